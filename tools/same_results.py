"""Are two result trees the same to the last bit?  For a change that must not move any number (a refactoring).

    python tools/same_results.py BASE NEW          # e.g. a copy of results/ made before the change, and results/

Every netCDF file under BASE is compared with the file of the same path under NEW, variable by variable and
coordinate by coordinate, bit for bit (NaN equal to NaN in the same place); every CSV and Markdown table as
text.  What a timing produces is passed over: a variable the figure data mark as timed (``wellposed`` or
``provenance`` ``"timing"``), a variable in µs, ms or ns or whose name says it is a time taken (``*seconds*``,
``elapsed*``, ``*wall*``, ``us_per*``), the x of a label placed on an error-against-cost line (a text's anchor
under the figure check's ``magnitude`` rule: its x is a cost, its y the error it names), and the ``benchmarks/``
files.  Prints each difference and exits 1 if there is one,
or a file of BASE is missing under NEW.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import xarray as xr

TIMED_NAME = re.compile(r"(seconds|^elapsed|wall|_time_s$|us_per|_us$)")
TIMED_UNITS = ("µs", "us", "ms", "ns", "s per impact")


def timed(var: xr.DataArray, name: str) -> bool:
    """Whether a variable is what a timing produces (its value is never reproducible)."""
    return ("timing" in (var.attrs.get("wellposed"), var.attrs.get("provenance"))
            or var.attrs.get("units") in TIMED_UNITS or bool(TIMED_NAME.search(str(name))))


def untimed(var: xr.DataArray, name: str) -> np.ndarray:
    """A variable's values less what a timing produces in them: the error coordinate alone of a label placed on an
    error-against-cost line (as the figure check's ``magnitude`` rule compares it)."""
    if name.endswith("_xy") and var.attrs.get("wellposed") == "magnitude":
        return var.values[1:]
    return var.values


def same_array(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal shape and dtype kind, and equal bits (NaN where NaN) for numbers; equal values otherwise."""
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return False
    if a.dtype.kind in "fc" and b.dtype.kind in "fc":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a.astype(str) if a.dtype.kind in "OUS" else a,
                               b.astype(str) if b.dtype.kind in "OUS" else b))


def compare_nc(base: Path, new: Path) -> list[str]:
    """The variables and coordinates that differ between two netCDF files (timed ones passed over)."""
    out = []
    with xr.open_dataset(base, decode_times=False) as a, xr.open_dataset(new, decode_times=False) as b:
        names = set(a.variables) | set(b.variables)
        for name in sorted(names, key=str):
            if name not in a.variables or name not in b.variables:
                out.append(f"{name}: only in {'base' if name in a.variables else 'new'}")
                continue
            if timed(a[name], name):
                continue
            if not same_array(untimed(a[name], name), untimed(b[name], name)):
                out.append(f"{name}: differs")
    return out


def compare(base: Path, new: Path) -> list[str]:
    """Every difference between two result trees, as ``path: what``."""
    diffs = []
    for f in sorted(base.rglob("*")):
        rel = f.relative_to(base)
        if not f.is_file() or "benchmarks" in rel.parts or f.suffix not in (".nc", ".csv", ".md"):
            continue
        g = new / rel
        if not g.is_file():
            diffs.append(f"{rel}: missing")
        elif f.suffix == ".nc":
            diffs += [f"{rel}: {d}" for d in compare_nc(f, g)]
        elif f.read_bytes() != g.read_bytes():
            diffs.append(f"{rel}: text differs")
    return diffs


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print(__doc__)
        return 2
    diffs = compare(Path(argv[0]), Path(argv[1]))
    for line in diffs or ["same to the last bit (timings passed over)"]:
        print(line, flush=True)
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
