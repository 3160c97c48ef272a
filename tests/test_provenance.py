"""The figure check's rule follows from what produced an array (vibroimpact.outputs.figcheck.PROVENANCE), not from
one machine's measurement: an array that rides on a chaotic run, a statistic, a method's error or a timing is
never compared pointwise.  Held here against what the test finds itself: which scene's start is chaotic (the
largest Lyapunov exponent of its run), which axes draw timings (their units), which arrays moved when the figures
were recomputed under another libm and other OpenBLAS kernels, and a work-precision chart redrawn with the
chaotic scene's errors and every timing moved as another machine moves them."""

import math
import re

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from conftest import ROOT

import vibroimpact as vi
from vibroimpact.benchmarks.workprecision import SCENES
from vibroimpact.dynamics.device import PAPER
from vibroimpact.outputs.checks import IMAGE_ROW
from vibroimpact.outputs.figcheck import MAGNITUDE_DECADES, NOT_POINTWISE, PROVENANCE
from vibroimpact.outputs.figdata import compare, figure_data
from vibroimpact.outputs.plots import fig_work_precision

REFERENCES = ROOT / "reference" / "figures"
FIGURES = sorted(p.stem for p in REFERENCES.glob("*.nc"))
#: a unit of time at the end of an axis label: what a timing is drawn in
TIME_UNIT = re.compile(r"\((µs|us|ms|s)\)\s*$")


def _arrays(ds):
    return {k: v for k, v in ds.data_vars.items() if v.attrs.get("role") != "wellposed"}


def _chaotic(beta, d, phi, v0):
    """Whether a start settles on chaos: no period, and the largest Lyapunov exponent's interval above 0."""
    p = vi.Params(d=d, gbar=PAPER.gbar(beta), r=PAPER.r)  # the paper's device
    if vi.identify_attractor(vi.simulate(p, phi=phi, v0=v0, n_impacts=4000)).periodic:
        return False
    (low, _), _ = vi.lyapunov(p, phi, v0, n_impacts=20_000).interval
    return low > 0


@pytest.fixture(scope="module")
def chaotic_scenes():
    return {name for name, scene in SCENES.items() if _chaotic(*scene)}


@pytest.mark.parametrize("fig", FIGURES)
def test_every_array_declares_a_known_provenance_and_none_that_forbids_pointwise_is_compared_so(fig):
    ds = xr.load_dataset(REFERENCES / f"{fig}.nc")
    for name, v in _arrays(ds).items():
        prov, rule = v.attrs.get("provenance", "exact"), v.attrs.get("wellposed", "strict")
        assert prov in PROVENANCE, (name, prov)
        assert not (prov in NOT_POINTWISE and rule == "strict"), name
        assert (rule == "timing") == (prov == "timing"), (name, rule, prov)


@pytest.mark.parametrize("fig", FIGURES)
def test_what_is_drawn_in_a_unit_of_time_is_declared_a_timing(fig):
    """A wall-clock time is the machine's speed: every array along an axis in seconds is a timing, and no
    other is (a text placed at a timing names its error coordinate)."""
    ds = xr.load_dataset(REFERENCES / f"{fig}.nc")
    for name, v in _arrays(ds).items():
        part = name.rsplit("_", 1)[-1]
        if part in ("x", "y") and TIME_UNIT.search(v.attrs.get("axis_label", "")):
            assert v.attrs.get("wellposed") == "timing", name
        if v.attrs.get("wellposed") == "timing":
            assert part in ("x", "y", "z") and (part == "z" or TIME_UNIT.search(v.attrs["axis_label"])), name


def test_every_panel_of_a_chaotic_scene_is_declared_a_chaotic_run(chaotic_scenes):
    """The work-precision scene whose start the test finds chaotic (by its own run's Lyapunov exponent) is the
    one whose panel declares its errors a chaotic run's; the other scenes' errors are the methods' own, and
    all of them are compared as orders of magnitude."""
    assert chaotic_scenes == {"chaotic"}
    ds = xr.load_dataset(REFERENCES / "work_precision.nc")
    seen = set()
    for name, v in _arrays(ds).items():
        scene = v.attrs["axes_title"].removesuffix(" motion")
        if v.attrs.get("wellposed") in (None, "timing") or scene not in SCENES:
            continue  # the frame's reference line, the costs
        seen.add(scene)
        assert v.attrs["provenance"] == ("chaotic run" if scene in chaotic_scenes else "method error"), name
        assert v.attrs["wellposed"] == "magnitude" and v.attrs["wp_floor"] > 0, name
    assert seen == set(SCENES)


def test_the_failure_map_declares_its_outcomes_a_chaotic_run_s(chaotic_scenes):
    """Its last case follows the chaotic scene's start (found chaotic here): its outcomes are compared as
    outcomes, allowed to differ only where a start one ulp away changed them."""
    assert "chaotic" in chaotic_scenes
    ds = xr.load_dataset(REFERENCES / "failure_map.nc")
    image = [n for n in _arrays(ds) if "_image" in n]
    assert image and all(ds[n].attrs["wellposed"] == "outcome" and ds[n].attrs["provenance"] == "chaotic run"
                         for n in image)
    assert all(f"{n.rsplit('_', 1)[0]}_wp_sensitive" in ds for n in image)


def test_every_array_that_moved_on_another_machine_declares_a_rule_that_passes_it():
    """The committed conditioning (the figures recomputed under another libm, OpenBLAS's kernels of other CPUs
    and inputs moved by ulps): every array that moved beyond the strict tolerance declares a rule, and every
    declared rule passed every perturbed copy, so the check passes on each such machine."""
    table = pd.read_csv(REFERENCES / "conditioning.csv", keep_default_na=False)
    data = table[table.variable != IMAGE_ROW]
    assert set(data.figure) == set(FIGURES)
    moved = data[data.conditioning == "ill-conditioned"]
    assert len(moved) and (moved.rule != "strict").all(), moved[moved.rule == "strict"]
    assert set(data.judged) <= {"pass", "excluded"}, data[~data.judged.isin(["pass", "excluded"])]
    summary = pd.read_csv(REFERENCES / "conditioning_summary.csv")
    blas = {p for p in summary.perturbation if p.startswith("OpenBLAS ")}
    assert len(blas) >= 2 and {"libm", "mass +2 ulp"} <= set(summary.perturbation)
    assert (summary.failed == 0).all()
    for fig in FIGURES:  # the table names each array of the committed figure data
        assert set(data.variable[data.figure == fig]) == set(_arrays(xr.load_dataset(REFERENCES / f"{fig}.nc")))


def _wp(err_scale=None, time_scale=1.0):
    """A work-precision dataset of two scenes (a periodic one and the chaotic one), two methods."""
    scenes, solvers = ["2:1", "chaotic"], ["exact (numba)", "solve_ivp DOP853 rtol=1e-09", "solve_ivp DOP853 rtol=1e-11"]
    err = np.array([[9e-16, 5e-15], [1.2e-9, 1.2e-9], [7.8e-12, 7.5145e-11]])
    if err_scale is not None:
        err = err * err_scale
    cost = np.array([[0.25, 0.24], [1000.0, 1600.0], [1400.0, 1700.0]]) * time_scale
    return xr.Dataset(
        {"err_t": (("solver", "scene"), err), "us_per_impact": (("solver", "scene"), cost),
         "family": ("solver", ["exact", "ivp-DOP853", "ivp-DOP853"]), "setting": ("solver", [np.nan, 1e-9, 1e-11]),
         "t_window": ("scene", [13.0, 15.0]), "scene_motion": ("scene", ["2:1 period-2", "chaotic"])},
        coords={"solver": solvers, "scene": scenes})


def test_a_work_precision_chart_moved_as_another_machine_moves_it_passes_and_a_changed_method_fails():
    """Redrawn from its dataset with every timing three times slower, the chaotic scene's errors moved in their
    fourth digit (another BLAS kernel summing in another order: 7.5145e-11 -> 7.5193e-11) and the exact
    method's rounding-level errors redrawn at other ulp counts, the chart passes its check; the same chart with
    one method ten times less accurate does not."""
    ref = figure_data(fig_work_precision(_wp()))
    moved = np.array([[4.0, 2.0], [1.0, 1.0 + 4e-4], [1.0, 7.5193 / 7.5145]])
    df = compare(figure_data(fig_work_precision(_wp(moved, time_scale=3.0))), ref, rtol=1e-9, atol=1e-12)
    assert set(df.status) == {"pass", "excluded"}, df[~df.status.isin(["pass", "excluded"])]
    assert set(df.rule[df.status == "excluded"]) == {"timing"}
    worse = np.ones((3, 2))
    worse[2, 0] = 1.2 * 10 ** MAGNITUDE_DECADES
    df = compare(figure_data(fig_work_precision(_wp(worse))), ref, rtol=1e-9, atol=1e-12).set_index("variable")
    assert (df.status == "fail").sum() >= 1 and set(df.provenance[df.status == "fail"]) == {"method error"}
    assert math.isclose(float(df.max_difference[df.status == "fail"].max()), math.log10(12), rel_tol=1e-9)
