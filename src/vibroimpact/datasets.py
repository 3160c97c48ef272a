"""One place for every variable's units and descriptions; datasets are built through it."""

from __future__ import annotations

import datetime as _dt
import json
import os
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import xarray as xr

from ._version import __version__

#: name -> (units, long_name, description): every variable the datasets share, declared once in the
#: package's ``variables.toml`` (a table of data, read here)
VARIABLES: dict[str, tuple[str, str, str]] = {
    name: tuple(row) for name, row in tomllib.loads((Path(__file__).parent / "variables.toml").read_text("utf-8")).items()
}

#: index dimensions: name -> what one index is
INDEX = {
    "point": "point (of the branch or curve, by arclength; of the sweep, by d)", "impact": "impact of one period",
    "event": "event", "critical": "critical or grazing point", "curve": "curve of the set",
    "crossing": "crossing of two curves", "boundary": "simulated boundary of the map", "transition": "located transition",
    "interval": "bistable interval", "eig": "eigenvalue of DP", "sim": "simulated point", "run": "run",
    "line": "line of the plane followed with d decreasing",
}
#: prefixes whose variable is another variable at a located place: prefix -> where
AT = {"critical_": "at the critical point", "event_": "where the curve meets another set",
      "crossing_": "where the two curves cross"}


def annotate(ds: xr.Dataset) -> xr.Dataset:
    """Attach units (where numeric), long_name and description to every known variable and coordinate
    (CF style: strings and labels get a long_name only), to the index dimensions, and to a variable
    named ``<prefix><known name>`` (:data:`AT`) from the known one; what a builder set stays."""
    for name in list(ds.variables):
        attrs = ds[name].attrs
        entry = VARIABLES.get(name)
        if entry is None and name in INDEX:
            entry = ("1", f"index of the {INDEX[name]}", "")
        if entry is None:
            for prefix, where in AT.items():
                base = VARIABLES.get(name[len(prefix):]) if name.startswith(prefix) else None
                if base is not None:
                    entry = (base[0], f"{base[1]} {where}", "")
                    break
        if entry is None:
            continue
        units, long_name, description = entry
        if units and ds[name].dtype.kind in "fiub":
            attrs.setdefault("units", units)
        attrs.setdefault("long_name", long_name)
        if description:
            attrs.setdefault("description", description)
    return ds


def provenance(**config) -> dict:
    """Global attributes: package version, creation time and the configuration that made the data."""
    return {
        "vibroimpact_version": __version__,
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "config": json.dumps(config, sort_keys=True, default=_jsonable),
    }


def _jsonable(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)


def write_netcdf(ds: xr.Dataset, path, *, fmt: str = "NETCDF4") -> None:
    """Write atomically (temporary file then rename): never a partial file; annotated first
    (:func:`annotate`).  ``fmt="NETCDF3_64BIT"`` suits many small float variables (a figure's data: a
    third of the size); it is written by scipy's engine, which writes the header once, where the netCDF4
    library rewrites it for every variable (the difference grows with the number of variables; the same
    dataset read back).  NETCDF4 files are written by the netCDF4 engine.  A dataset with more than one
    empty dimension (a figure that draws nothing in some panels) is written as NETCDF4: the classic format
    reads a zero length as its one unlimited dimension, and the netCDF library refuses a file with several."""

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    annotate(ds)  # every dataset written carries units and long names (CF style)
    if fmt.startswith("NETCDF3") and sum(size == 0 for size in ds.sizes.values()) > 1:
        fmt = "NETCDF4"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".part")
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="scipy" if fmt.startswith("NETCDF3") else "netcdf4", format=fmt)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def _codes(labels: np.ndarray):
    """Integer codes for labels, most frequent first; returns (codes, legend)."""
    uniq, counts = np.unique(labels, return_counts=True)
    legend = list(uniq[np.argsort(-counts, kind="stable")])
    lookup = {lab: i for i, lab in enumerate(legend)}
    return np.vectorize(lookup.__getitem__, otypes=[np.int16])(labels), legend


def attractor_codes(ds: xr.Dataset, dims) -> xr.Dataset:
    """``ds`` with the integer ``attractor`` of each cell on ``dims``: an index into its labels, most frequent
    first, listed in the variable's ``legend`` attribute and as JSON in the dataset's."""
    codes, legend = _codes(ds["label"].values)
    ds["attractor"] = (dims, codes, {"units": "1", "long_name": "attractor class (index into the legend)",
                                      "legend": "; ".join(f"{i}: {lab}" for i, lab in enumerate(legend))})
    ds.attrs["legend"] = json_list(legend)
    return ds


def json_list(items):
    """The items as a JSON list of strings (a netCDF attribute)."""
    return json.dumps([str(x) for x in items])
