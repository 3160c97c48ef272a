"""benchmarks/bench_kernel.py: the kernel's cost per impact beside a baseline commit's, and its kept record."""
import importlib.util
import io
import math
import sys

import pandas as pd
import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))  # the script imports its neighbours
spec = importlib.util.spec_from_file_location("bench_kernel", ROOT / "benchmarks" / "bench_kernel.py")
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)

NAN = math.nan


def _run(us, finder=NAN):
    return {"2:1": {"us_per_impact": us, "finder_us_per_impact": finder, "trig_floor_us_per_impact": 0.04,
                    "heyoka_stepping_us_per_impact": 0.6},
            "chaotic": {"us_per_impact": us + 0.01, "finder_us_per_impact": finder, "trig_floor_us_per_impact": 0.05,
                        "heyoka_stepping_us_per_impact": 0.8}}


def test_each_measure_is_the_fastest_of_the_rounds_and_a_side_without_it_keeps_nan():
    best = bench.fastest([_run(0.15, NAN), _run(0.12, 0.11), _run(0.13, 0.09)])
    assert best["2:1"]["us_per_impact"] == 0.12 and best["chaotic"]["us_per_impact"] == pytest.approx(0.13)
    assert best["2:1"]["finder_us_per_impact"] == 0.09
    assert math.isnan(bench.fastest([_run(0.15), _run(0.14)])["2:1"]["finder_us_per_impact"])


def test_the_sides_alternate_and_the_ratio_is_to_the_baseline_s_same_scene(monkeypatch, tmp_path):
    order, costs = [], {"base": iter([0.20, 0.16]), "this": iter([0.09, 0.10])}
    monkeypatch.setattr(bench, "baseline_copy", lambda rev, d: (d / "base").mkdir() or d / "base")
    monkeypatch.setattr(bench, "scratch_copy", lambda d: (d / "this").mkdir() or d / "this")
    monkeypatch.setattr(bench, "profile", lambda tree, cache: order.append(tree.name) or _run(next(costs[tree.name])))
    df = bench.main("7f6254a", rounds=2)
    assert order == ["base", "this", "base", "this"]
    assert list(df["tree"]) == ["baseline (7f6254a)"] * 2 + ["this tree"] * 2
    assert list(df["µs per impact"]) == pytest.approx([0.16, 0.17, 0.09, 0.10])
    assert list(df["ratio to the baseline"]) == [1.0, 1.0, 0.56, 0.59]
    assert list(df[f"≤ {bench.GOAL} µs"]) == [False, False, True, True]


def test_a_side_s_own_profile_is_run_from_its_own_files(tmp_path):
    """`profile` runs the tree's own package: a tree whose kernel_profile returns known numbers gives them back."""
    pkg = tmp_path / "tree" / "src" / "vibroimpact" / "benchmarks"
    pkg.mkdir(parents=True)
    for d in (pkg.parent, pkg):
        (d / "__init__.py").write_text("")
    (pkg / "bench.py").write_text(
        "import xarray as xr\n"
        "def kernel_profile():\n"
        "    return xr.Dataset({'us_per_impact': ('scene', [0.5, 0.25])}, coords={'scene': ['2:1', 'chaotic']})\n")
    got = bench.profile(tmp_path / "tree", tmp_path / "numba")
    assert got["2:1"]["us_per_impact"] == 0.5 and got["chaotic"]["us_per_impact"] == 0.25
    assert math.isnan(got["2:1"]["finder_us_per_impact"])


def test_the_kept_record_holds_both_sides_and_this_tree_s_bounds():
    """The kept record: both sides on both scenes, the ratio that of the costs, the goal column the cost's, and this
    tree's bounds below its cost (its sines and cosines below the event finder alone, which is below the kernel)."""
    text = (ROOT / "reference" / "bench_kernel.md").read_text()
    df = pd.read_table(io.StringIO(text.split("\n\n")[0]), sep="|", skipinitialspace=True).iloc[1:, 1:-1]
    df.columns = [c.strip() for c in df.columns]
    df = df.apply(lambda c: c.str.strip())
    assert [t.split()[0] for t in df["tree"]] == ["baseline", "baseline", "this", "this"]
    us = df["µs per impact"].astype(float).to_numpy()
    assert list(df["ratio to the baseline"].astype(float)) == pytest.approx(
        [1.0, 1.0, us[2] / us[0], us[3] / us[1]], abs=0.006)
    assert list(df[f"≤ {bench.GOAL} µs"] == "True") == list(us <= bench.GOAL)
    this = df[df["tree"] == "this tree"]
    trig, finder = (this[c].astype(float).to_numpy() for c in ("sines and cosines alone, µs", "event finder alone, µs"))
    assert (trig < finder).all() and (finder < us[2:]).all()
    assert "Machine:" in text and "Command: `python benchmarks/bench_kernel.py" in text
