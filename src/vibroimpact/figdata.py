"""The arrays a figure draws, read back from the drawn figure, and their comparison with a reference.

:func:`figure_data` walks every axes of a matplotlib figure and keeps what is on it: the x and y of
each line, the points (and colour values) of each scatter, each image's array, with the axes'
title and labels and each artist's legend label.  Because it is read from the figure itself, not
from the code that drew it, the saved data is exactly what is plotted.  :func:`compare` checks
regenerated data against a committed reference (the figure regeneration check).
"""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import xarray as xr


def _units(label: str) -> str:
    """Units from an axis label ending in "(unit)", else "1" (non-dimensional)."""
    m = re.search(r"\(([^()]*)\)\s*$", label or "")
    return m.group(1) if m else "1"


def _float_array(values) -> np.ndarray:
    """Float array with masked entries as NaN."""
    a = np.ma.filled(np.ma.asarray(values, dtype=float), np.nan)
    return np.asarray(a, dtype=float)


def figure_data(fig, attrs: dict | None = None) -> xr.Dataset:
    """Every plotted array of ``fig`` as one dataset.

    Variables are named ``a<i>_<kind><j>_<part>``: axes ``i`` (in the figure's order), artist ``j``
    of a kind (``line``, ``points``, ``image``, ``text``) and its part (``x``, ``y``, ``c`` colour
    values, ``z`` image, ``xy`` a text's anchor).  Each carries ``axes_title``, ``axis_label`` and
    ``units`` (from the axis label), and ``label`` (the legend entry, or a text's string); lines
    also their ``marker`` and ``linestyle``.
    """
    data = {}
    for i, ax in enumerate(fig.get_axes()):
        title = " ".join(t for t in (ax.get_title("left"), ax.get_title(), ax.get_title("right")) if t)
        xlab, ylab = ax.get_xlabel(), ax.get_ylabel()

        def put(name, values, axis_label, label, title=title, **extra):
            arr = _float_array(values)
            dims = tuple(f"{name}_dim{k}" for k in range(arr.ndim))
            long_name = " / ".join(x for x in (title, label, axis_label) if x) or name
            data[name] = xr.Variable(dims, arr, {"axes_title": title, "axis_label": axis_label,
                                                 "units": _units(axis_label), "label": label or "",
                                                 "long_name": long_name, **extra})

        for j, line in enumerate(ax.get_lines()):
            label = line.get_label()
            # matplotlib's own names ("_child3") are dropped; "_name" (kept out of legends) is kept
            label = "" if label.startswith("_child") else label.lstrip("_")
            style = dict(marker=str(line.get_marker()), linestyle=str(line.get_linestyle()))
            put(f"a{i}_line{j}_x", line.get_xdata(), xlab, label, **style)
            put(f"a{i}_line{j}_y", line.get_ydata(), ylab, label, **style)
        for j, text in enumerate(ax.texts):  # annotations: names of marked points
            if text.get_text():
                x, y = text.xy if hasattr(text, "xy") else text.get_position()
                # a text placed in data coordinates moves with the axes' data (e.g. a timing)
                put(f"a{i}_text{j}_xy", [float(np.asarray(x, float)), float(np.asarray(y, float))],
                    f"position (x: {xlab}; y: {ylab})", text.get_text())
        k = 0
        for coll in ax.collections:
            offsets = coll.get_offsets()
            if offsets is None or len(offsets) == 0 or np.ndim(offsets) != 2:
                continue
            label = coll.get_label()
            label = "" if label.startswith("_") else label
            put(f"a{i}_points{k}_x", offsets[:, 0], xlab, label)
            put(f"a{i}_points{k}_y", offsets[:, 1], ylab, label)
            if coll.get_array() is not None:
                put(f"a{i}_points{k}_c", np.ravel(coll.get_array()), "colour value", label)
            k += 1
        for j, im in enumerate(ax.get_images()):
            put(f"a{i}_image{j}_z", im.get_array(), f"image over x: {xlab}; y: {ylab}", im.get_label())
    ds = xr.Dataset(data)
    ds.attrs.update(attrs or {})
    return ds


def compare(new: xr.Dataset, ref: xr.Dataset, *, rtol: float, atol: float, exclude=(), optional=()) -> pd.DataFrame:
    """One row per reference variable: ``variable``, ``axes``, ``max_difference``, ``status``.

    A variable passes when it is present with the reference's shape, NaN exactly where the
    reference is NaN, and ``|new - ref| <= atol + rtol |ref|`` elsewhere.  Variables whose axis label
    contains one of ``exclude`` (case-insensitive), or whose legend label or axes title contains one of
    ``optional`` (methods that need a system package, present on some machines only), are reported as
    ``excluded``, in the reference or only in the new data (e.g. timings,
    which are not results).  Variables only in ``new`` are reported as ``new`` (a figure that
    gained an artist fails until the reference is updated).
    """
    rows = []
    pats = [p.lower() for p in exclude]
    opts = [p.lower() for p in optional]

    def is_optional(var):
        a = var.attrs
        return any(p in (a.get("label", "") + " " + a.get("axes_title", "")).lower() for p in opts)

    for name in ref.data_vars:
        r = ref[name]
        row = {"variable": name, "axes": r.attrs.get("axes_title", ""), "axis_label": r.attrs.get("axis_label", ""),
               "max_difference": np.nan}
        if any(p in row["axis_label"].lower() for p in pats) or is_optional(r):
            rows.append(row | {"status": "excluded"})
            continue
        if name not in new:
            rows.append(row | {"status": "fail: missing"})
            continue
        a, b = np.asarray(new[name].values, float), np.asarray(r.values, float)
        if a.shape != b.shape:
            rows.append(row | {"status": f"fail: shape {a.shape} != reference {b.shape}"})
            continue
        nan_a, nan_b = np.isnan(a), np.isnan(b)
        if np.any(nan_a != nan_b):
            rows.append(row | {"status": f"fail: NaN at {int(np.sum(nan_a != nan_b))} other places"})
            continue
        ok = ~nan_b
        diff = np.abs(a[ok] - b[ok])
        row["max_difference"] = float(diff.max()) if diff.size else 0.0
        good = bool(np.all(diff <= atol + rtol * np.abs(b[ok])))
        rows.append(row | {"status": "pass" if good else "fail"})
    for name in sorted(set(new.data_vars) - set(ref.data_vars)):
        if is_optional(new[name]):
            rows.append({"variable": name, "axes": new[name].attrs.get("axes_title", ""),
                         "axis_label": new[name].attrs.get("axis_label", ""), "max_difference": np.nan,
                         "status": "excluded"})
            continue
        rows.append({"variable": name, "axes": new[name].attrs.get("axes_title", ""),
                     "axis_label": new[name].attrs.get("axis_label", ""), "max_difference": np.nan,
                     "status": "fail: new (not in the reference)"})
    return pd.DataFrame(rows, columns=["variable", "axes", "axis_label", "max_difference", "status"])


#: side of the perceptual hash (bits: its square)
HASH_SIZE = 16


def image_hash(png, hash_size: int = HASH_SIZE) -> str:
    """Perceptual hash (DCT of the grey image at 4 ``hash_size`` pixels a side, ImageHash's ``phash``)
    of a PNG file, as hex."""
    import imagehash
    from PIL import Image

    with Image.open(png) as im:
        return str(imagehash.phash(im, hash_size=hash_size))


def hash_distance(a: str, b: str) -> int:
    """Number of differing bits of two hashes from :func:`image_hash`."""
    import imagehash

    return int(imagehash.hex_to_hash(a) - imagehash.hex_to_hash(b))


def compare_image(new: xr.Dataset, ref: xr.Dataset, *, max_distance: int, draws_timings: bool = False) -> dict:
    """The image row of the regeneration check: the perceptual hashes stored with the new and the
    reference data (``png_phash``) differ in at most ``max_distance`` bits.  A figure that draws
    timings is ``excluded``: its markers move with the machine's speed, as its timing arrays do."""
    from .checks import IMAGE_ROW

    row = {"variable": IMAGE_ROW, "axes": "", "axis_label": "rendered PNG", "max_difference": np.nan}
    a, b = new.attrs.get("png_phash"), ref.attrs.get("png_phash")
    if a is None or b is None:
        return row | {"status": "fail: no image hash in the " + ("new data" if a is None else "reference")}
    row["max_difference"] = float(hash_distance(a, b))
    if draws_timings:
        return row | {"status": "excluded"}
    return row | {"status": "pass" if row["max_difference"] <= max_distance else "fail"}
