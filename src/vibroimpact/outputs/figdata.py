"""The arrays a figure draws, read back from the drawn figure, and their comparison with a reference.

:func:`figure_data` walks every axes of a matplotlib figure and keeps what is on it: the x and y of
each line, the points (and colour values) of each scatter, each image's array, with the axes'
title and labels and each artist's legend label.  Because it is read from the figure itself, not
from the code that drew it, the saved data is exactly what is plotted.  :func:`compare` checks
regenerated data against a committed reference (the figure regeneration check).
"""

from __future__ import annotations

import re
import weakref

import numpy as np
import pandas as pd
import xarray as xr

from . import figcheck as fc
from .checks import IMAGE_ROW

#: what each drawn artist records for the check (:func:`record_wellposed`), kept beside the figure rather than on
#: matplotlib's objects; an artist's entry goes with the artist
WELLPOSED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()

def record_wellposed(artist, rule: str, *, provenance: str | None = None, timed=(), **fields):
    """Record what is well-posed about ``artist``'s arrays: ``rule`` (one of
    :data:`vibroimpact.outputs.figcheck.RULES`) and its fields, and ``provenance`` (what produced the arrays, one
    of :data:`vibroimpact.outputs.figcheck.PROVENANCE`; by default the rule's, :data:`~vibroimpact.outputs.figcheck.DEFAULT_PROVENANCE`).  ``timed``: the parts of the
    artist (``"x"``, ``"y"``, ``"xy"``) that are timings, recorded with the rule ``timing`` (not compared).
    :func:`figure_data` saves all of it beside the arrays.  Returns the artist.

    Raises
    ------
    ValueError
        For an unknown rule or provenance, or a part of ``timed`` an artist does not have.
    """
    if rule not in fc.RULES:
        raise ValueError(f"rule = {rule!r}; allowed: {', '.join(fc.RULES)}")
    provenance = provenance or fc.DEFAULT_PROVENANCE[rule]
    if provenance not in fc.PROVENANCE:
        raise ValueError(f"provenance = {provenance!r}; allowed: {', '.join(fc.PROVENANCE)}")
    bad = set(timed) - {"x", "y", "xy", "c"}
    if bad:
        raise ValueError(f"timed = {sorted(timed)!r}; allowed: the parts x, y, xy, c")
    WELLPOSED[artist] = {"rule": rule, "provenance": provenance, "timed": tuple(timed), **fields}
    return artist


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
    from matplotlib.collections import QuadMesh  # here: a figure's check (compare) draws nothing, and loads no matplotlib

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

        def wellposed(artist, base, names):
            """What the artist carries for the check (:func:`record_wellposed`): the rule and the provenance on
            its variables ``names`` (the rule ``timing`` on its timed parts), per-element fields as
            ``<base>_wp_<field>``, scalars as attributes."""
            wp = WELLPOSED.get(artist)
            if not wp:
                return
            scalars = {f"wp_{k}": v for k, v in wp.items() if np.ndim(v) == 0 and k not in ("rule", "provenance")}
            for name in names:
                timed = name.rsplit("_", 1)[-1] in wp["timed"]
                data[name].attrs.update(wellposed="timing" if timed else wp["rule"],
                                        provenance="timing" if timed else wp["provenance"], **scalars)
            for key, v in wp.items():
                if np.ndim(v) == 0 or key == "timed":
                    continue
                v = np.asarray(v)
                arr = v.astype(str) if v.dtype.kind in "UOS" else v.astype(np.int8) if v.dtype == bool else v.astype(float)
                data[f"{base}_wp_{key}"] = xr.Variable((f"{base}_wp_dim0",), arr, {
                    "long_name": f"what the check compares where {base} is not well-posed pointwise: {key}",
                    "units": "1", "role": "wellposed"})

        for j, line in enumerate(ax.get_lines()):
            label = line.get_label()
            # matplotlib's own names ("_child3") are dropped; "_name" (kept out of legends) is kept
            label = "" if label.startswith("_child") else label.lstrip("_")
            style = dict(marker=str(line.get_marker()), linestyle=str(line.get_linestyle()))
            # a coordinate in axes fraction (a line across the axes, axhline's x) is no value of its axis
            in_data = line.get_transform().contains_branch_seperately(ax.transData)
            for part, values, lab, data_coords in (("x", line.get_xdata(), xlab, in_data[0]),
                                                  ("y", line.get_ydata(), ylab, in_data[1])):
                put(f"a{i}_line{j}_{part}", values, lab if data_coords else "axes fraction", label, **style)
            wellposed(line, f"a{i}_line{j}", [f"a{i}_line{j}_x", f"a{i}_line{j}_y"])
        for j, text in enumerate(ax.texts):  # annotations: names of marked points
            if text.get_text():
                x, y = text.xy if hasattr(text, "xy") else text.get_position()
                # a text placed in data coordinates moves with the axes' data (e.g. a timing)
                put(f"a{i}_text{j}_xy", [float(np.asarray(x, float)), float(np.asarray(y, float))],
                    f"position (x: {xlab}; y: {ylab})", text.get_text())
                wellposed(text, f"a{i}_text{j}", [f"a{i}_text{j}_xy"])
        k = 0
        for coll in ax.collections:
            if isinstance(coll, QuadMesh):  # a map: its cells' centres, in the order of its values
                corners = coll.get_coordinates()
                offsets = 0.25 * (corners[:-1, :-1] + corners[1:, :-1] + corners[:-1, 1:] + corners[1:, 1:]).reshape(-1, 2)
            else:
                offsets = coll.get_offsets()
            if offsets is None or len(offsets) == 0 or np.ndim(offsets) != 2:
                continue
            label = coll.get_label()
            label = "" if label.startswith("_") else label
            put(f"a{i}_points{k}_x", offsets[:, 0], xlab, label)
            put(f"a{i}_points{k}_y", offsets[:, 1], ylab, label)
            names = [f"a{i}_points{k}_x", f"a{i}_points{k}_y"]
            if coll.get_array() is not None:
                put(f"a{i}_points{k}_c", np.ravel(coll.get_array()), "colour value", label)
                names.append(f"a{i}_points{k}_c")
            wellposed(coll, f"a{i}_points{k}", names)
            k += 1
        for j, im in enumerate(ax.get_images()):
            put(f"a{i}_image{j}_z", im.get_array(), f"image over x: {xlab}; y: {ylab}", im.get_label())
            wellposed(im, f"a{i}_image{j}", [f"a{i}_image{j}_z"])
    ds = xr.Dataset(data)
    ds.attrs.update(attrs or {})
    return ds


class _Variables:
    """A dataset's variables by name, as the comparisons read them (``values``, ``attrs``, ``shape``, ``size``;
    ``data_vars``, ``in``): xarray's Variables, without building a DataArray at every look-up (which took most
    of a figure check's time)."""

    def __init__(self, ds: xr.Dataset):
        self.data_vars, self._vars = ds.data_vars, ds.variables

    def __getitem__(self, name):
        return self._vars[name]

    def __contains__(self, name):
        return name in self._vars


def compare(new: xr.Dataset, ref: xr.Dataset, *, rtol: float, atol: float, optional=()) -> pd.DataFrame:
    """One row per reference variable: ``variable``, ``axes``, ``axis_label``, ``rule``, ``provenance``,
    ``max_difference``, ``status`` and ``detail``.

    Each variable is compared by the rule its figure declared when drawing it (attribute ``wellposed``,
    :func:`record_wellposed`; :mod:`vibroimpact.outputs.figcheck`), whatever one machine measured: a value that
    rides on a chaotic run, a step-size decision or a timing is never compared pointwise.  A variable that
    declares no rule is compared pointwise (``rule`` ``"strict"``): it passes when it is present with the
    reference's shape, NaN exactly where the reference is NaN, and ``|new - ref| <= atol + rtol |ref|``
    elsewhere.  A timing (rule ``timing``) is ``excluded``.  Variables whose legend label or axes title
    contains one of ``optional`` (methods that need a system package, present on some machines only) are
    ``excluded``, in the reference or only in the new data.  Variables only in ``new`` are reported as
    ``new`` (a figure that gained an artist fails until the reference is updated); a variable whose declared
    rule differs from the reference's fails.
    """

    rows = []
    opts = [p.lower() for p in optional]
    cache = {}
    new, ref = _Variables(new), _Variables(ref)

    def is_optional(var):
        a = var.attrs
        return any(p in (a.get("label", "") + " " + a.get("axes_title", "")).lower() for p in opts)

    def aux(var):
        return var.attrs.get("role") == "wellposed"

    for name in ref.data_vars:
        r = ref[name]
        if aux(r):
            continue
        rule = r.attrs.get("wellposed", "strict")
        row = {"variable": name, "axes": r.attrs.get("axes_title", ""), "axis_label": r.attrs.get("axis_label", ""),
               "rule": rule, "provenance": r.attrs.get("provenance", "exact"), "max_difference": np.nan, "detail": ""}
        if is_optional(r):
            rows.append(row | {"rule": "excluded", "status": "excluded", "detail": "an optional peer"})
            continue
        if name not in new:
            if r.attrs.get("wp_sensitive"):  # a glyph of a cell whose outcome the last bit decides
                rows.append(row | {"status": "pass", "detail": "a sensitive cell's mark, absent here"})
            else:
                rows.append(row | {"status": "fail: missing"})
            continue
        if new[name].attrs.get("wellposed", "strict") != rule:
            rows.append(row | {"status": f"fail: declares rule {new[name].attrs.get('wellposed', 'strict')!r}, "
                                         f"the reference {rule!r}"})
            continue
        if rule != "strict":
            ok, diff, detail = fc.judge(rule, new, ref, name, rtol=rtol, atol=atol, cache=cache)
            status = "excluded" if rule == "timing" else "pass" if ok else "fail"
            rows.append(row | {"max_difference": diff, "detail": detail, "status": status})
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
        if aux(new[name]):
            continue
        rows.append({"variable": name, "axes": new[name].attrs.get("axes_title", ""),
                     "axis_label": new[name].attrs.get("axis_label", ""),
                     "rule": new[name].attrs.get("wellposed", "strict"),
                     "provenance": new[name].attrs.get("provenance", "exact"), "max_difference": np.nan,
                     "detail": "", "status": "excluded" if is_optional(new[name]) else
                     "pass" if new[name].attrs.get("wp_sensitive") else "fail: new (not in the reference)"})
    return pd.DataFrame(rows, columns=["variable", "axes", "axis_label", "rule", "provenance", "max_difference",
                                       "status", "detail"])


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

    row = {"variable": IMAGE_ROW, "axes": "", "axis_label": "rendered PNG", "max_difference": np.nan}
    a, b = new.attrs.get("png_phash"), ref.attrs.get("png_phash")
    if a is None or b is None:
        return row | {"status": "fail: no image hash in the " + ("new data" if a is None else "reference")}
    row["max_difference"] = float(hash_distance(a, b))
    if draws_timings:
        return row | {"status": "excluded"}
    return row | {"status": "pass" if row["max_difference"] <= max_distance else "fail"}


#: the fewest bits a change of the drawn data changes the hash by: a single sample read on the other side of
#: an impact's jump moved Figures 3 and 8 by 2 bits, and so did rounding-level changes of Figures 7 and 3
#: under the conditioning's perturbations (antialiased edges shift one grey level)
ONE_POINT_BITS = 2


def image_allowance(conditioning, figure: str, default: int) -> tuple[int, str]:
    """How many bits the image of ``figure`` may differ by, and why.

    Agg with the locked matplotlib and its own fonts draws the same data to the same pixels, but data that
    differ at rounding level can move an antialiased edge by one grey level, and ill-conditioned points
    legitimately move: twice the largest distance measured under the conditioning's perturbations, and at
    least :data:`ONE_POINT_BITS` (``default`` where no conditioning was measured)."""

    if conditioning is None or not len(conditioning):
        return default, f"image: <= {default} bits (no conditioning measured)"
    rows = conditioning[conditioning.figure == figure]
    ill = rows[(rows.variable != IMAGE_ROW) & (rows.conditioning == "ill-conditioned")]
    img = rows[rows.variable == IMAGE_ROW]
    bits = int(img.spread.iloc[0]) if len(img) and np.isfinite(img.spread.iloc[0]) else 0
    allowed = max(2 * bits, ONE_POINT_BITS, default)
    return allowed, (f"image: <= {allowed} bits (twice the {bits} measured, at least {ONE_POINT_BITS}; "
                     f"{len(ill)} ill-conditioned arrays)")
