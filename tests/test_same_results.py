"""tools/same_results.py: the refactoring check finds a last-bit change and passes over timings only."""
import importlib.util
from pathlib import Path

import numpy as np
import xarray as xr

spec = importlib.util.spec_from_file_location("same_results", Path(__file__).parents[1] / "tools" / "same_results.py")
same_results = importlib.util.module_from_spec(spec)
spec.loader.exec_module(same_results)


def _tree(root: Path, x: float, us: float, table: str, err: float = 1e-9) -> Path:
    (root / "sweeps").mkdir(parents=True)
    xr.Dataset({"d": ("point", [0.2, x, np.nan]), "label": ("point", ["1:1", "2:1", "chaotic"]),
                "us_per_impact": ("point", [us, us, us], {"units": "µs"}),
                "cost": ("point", [us, us, us], {"wellposed": "timing"}),
                # a setting's name placed on its error-against-cost line: at (cost, error)
                "a0_text0_xy": ("xy", [us, err], {"wellposed": "magnitude"})}).to_netcdf(root / "sweeps" / "a.nc")
    (root / "t.csv").write_text(table)
    return root


def test_a_last_bit_a_table_and_a_missing_file_are_found_a_timing_is_not(tmp_path):
    base = _tree(tmp_path / "base", 0.3, 1.0, "a,b\n1,2\n")
    assert same_results.compare(base, _tree(tmp_path / "same", 0.3, 2.0, "a,b\n1,2\n")) == []
    moved = _tree(tmp_path / "moved", np.nextafter(0.3, 1.0), 1.0, "a,b\n1,3\n")
    assert same_results.compare(base, moved) == ["sweeps/a.nc: d: differs", "t.csv: text differs"]
    (moved / "sweeps" / "a.nc").unlink()
    assert same_results.compare(base, moved) == ["sweeps/a.nc: missing", "t.csv: text differs"]
    assert same_results.main([str(base), str(moved)]) == 1 and same_results.main([str(base), str(base)]) == 0


def test_a_label_on_an_error_against_cost_line_is_compared_by_its_error_alone(tmp_path):
    base = _tree(tmp_path / "base", 0.3, 1.0, "")
    assert same_results.compare(base, _tree(tmp_path / "faster", 0.3, 0.5, "")) == []
    moved = _tree(tmp_path / "moved", 0.3, 1.0, "", err=np.nextafter(1e-9, 1.0))
    assert same_results.compare(base, moved) == ["sweeps/a.nc: a0_text0_xy: differs"]
