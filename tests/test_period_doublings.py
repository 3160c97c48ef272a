"""Period doublings among the located transitions: near a flip the detector gives up under critical slowing, short
of the bifurcation, and records a period lost; such a transition is named a period doubling and placed at the
flip, checked against the flip found by an independent method (Newton's method on the orbit and its eigenvalue
-1, solved for d by bisection) and against the bracket the two sweeps give without any branch."""

import math

import numpy as np
import pytest
import xarray as xr
from conftest import ROOT
from scipy.optimize import brentq

import vibroimpact as vi
from vibroimpact.analysis.transitions import PERIOD_DOUBLING, period_doublings
from vibroimpact.outputs.tables import transitions_markdown

K_S = 0.6225  # d = K_S s at the paper's force
BETA = math.pi / 3
#: transients of the small sweeps here (forcing periods): short, so that critical slowing is wide and fast to run
MAX_PERIODS = 2000
TOL = 1e-9  # the sweep's periodicity tolerance (its default)


def newton_flip(lo: float, hi: float) -> tuple[float, float]:
    """The 2:1 orbit's flip at beta = pi/3 by Newton's method at each d and bisection in d on its real eigenvalue
    + 1 (no continuation, no test function of the branch code), and d lambda / d d there (central difference)."""
    gbar = vi.Params.from_physical(s=1.0, beta=BETA).gbar
    guess = [1.0, 0.2]

    def lam(d):
        o = vi.find_orbit(vi.Params(d=d, gbar=gbar, r=0.5), "BBT", *guess)
        real = o.eigenvalues[np.abs(np.imag(o.eigenvalues)) < 1e-12].real
        return float(real[np.argmin(np.abs(real + 1))])

    b = brentq(lambda d: lam(d) + 1, lo, hi, xtol=1e-14, rtol=4 * np.finfo(float).eps)
    h = 1e-6
    return b, (lam(b + h) - lam(b - h)) / (2 * h)


@pytest.fixture(scope="module")
def across_flip():
    """A length sweep at beta = pi/3 over the 2:1 period doubling (2:1 period-4 below, 2:1 period-2 above), its
    located transitions, and the 2:1 branch continued over it."""
    sw = vi.sweep("s", np.array([0.156, 0.158, 0.160]) / K_S, beta=BETA, phi=1.0, v0=0.2, max_periods=MAX_PERIODS,
                  long_impacts=0)
    tr = vi.locate_transitions(sw, xtol=1e-7, max_periods=MAX_PERIODS)
    p = vi.Params.from_physical(s=0.17 / K_S, beta=BETA)
    br = vi.continue_orbit(vi.find_orbit(p, "BBT", 1.0, 0.2), vary="s", d_range=(0.155, 0.171), step=1e-3)
    return sw, tr, br


def test_the_sweep_loses_its_period_short_of_the_flip_on_both_sides(across_flip):
    """What the naming corrects: both directions' detectors give up before the flip, each on its own side."""
    sw, tr, _ = across_flip
    b, _ = newton_flip(0.157, 0.159)
    assert sw.label.values[:, 0].tolist() == ["2:1 period-4"] * 2 and sw.label.values[:, -1].tolist() == [
        "2:1 period-2"] * 2
    up, down = (tr.isel(transition=np.flatnonzero(tr.direction.values == k)[0]) for k in ("up", "down"))
    assert str(up.before.values) == "2:1 period-4" and float(up.d) < b
    assert str(down.before.values) == "2:1 period-2" and float(down.d) > b
    assert all(str(k).startswith("period lost") for k in tr.kind.values)


def test_a_period_lost_short_of_a_flip_is_a_period_doubling_at_the_newton_flip(across_flip):
    """Named a period doubling, placed at the branch's B, which is the flip Newton's method finds to the
    continuation's refinement (1e-13 in d, ten times that for the bisection's conditioning); the uncertainty covers
    where each detector gave up; past the flip each sweep's next motion is the other side's."""
    sw, tr, br = across_flip
    b, _ = newton_flip(0.157, 0.159)
    pd = period_doublings(tr, sw, [br])
    assert pd.kind.values.tolist() == [PERIOD_DOUBLING] * 2
    np.testing.assert_allclose(pd.bifurcation_d.values, b, rtol=0, atol=1e-12)
    assert pd.bifurcation_source.values.tolist() == ["2:1 period-2"] * 2
    for k in range(pd.sizes["transition"]):
        r = pd.isel(transition=k)
        gave_up = float(r.d) + (0.5 if str(r.direction.values) == "up" else -0.5) * float(r.d_width)
        assert abs(gave_up - b) <= float(r.bifurcation_d_width) / 2
    beyond = dict(zip(pd.direction.values.tolist(), pd.beyond.values.tolist(), strict=True))
    assert beyond == {"up": "2:1 period-2", "down": "2:1 period-4"}
    # a transition whose bracket holds the flip: the uncertainty is the bracket, which covers where it gave up
    down = int(np.flatnonzero(tr.direction.values == "down")[0])
    inside = tr.copy(deep=True)
    inside["d"].values[down], inside["d_width"].values[down] = b, 1e-5
    r = period_doublings(inside, sw, [br]).isel(transition=down)
    assert str(r.kind.values) == PERIOD_DOUBLING and float(r.bifurcation_d_width) == pytest.approx(1e-5, rel=1e-6)
    # what the detector found is kept
    xr.testing.assert_equal(pd[["d", "d_width", "before", "after"]], tr[["d", "d_width", "before", "after"]])


def test_the_detector_gives_up_within_the_predicted_critical_slowing(across_flip):
    """The half-width delta = k ln(1/tol) / (|d lambda / d d| max_periods), with the multiplier's slope from Newton's
    orbits (not the branch), bounds how far from the flip each detector gave up; it is what the naming uses."""
    sw, tr, br = across_flip
    b, slope = newton_flip(0.157, 0.159)
    delta = math.log(1 / TOL) / (abs(slope) * MAX_PERIODS)
    pd = period_doublings(tr, sw, [br])
    np.testing.assert_allclose(pd.slowing_width.values / 2, delta, rtol=0.05)  # the branch's chord against the tangent
    assert np.all(np.abs(tr.d.values - b) < delta)


def test_without_a_branch_the_two_sweeps_bracket_the_flip(across_flip):
    """An independent location: with no branch, between where one motion was last and the other first identified;
    the Newton flip lies in that bracket."""
    sw, tr, br = across_flip
    b, _ = newton_flip(0.157, 0.159)
    pd = period_doublings(tr, sw, [])
    assert pd.kind.values.tolist() == [PERIOD_DOUBLING] * 2 and set(pd.bifurcation_source.values) == {"sweeps"}
    xr.testing.assert_identical(period_doublings(period_doublings(tr, sw, [br]), sw, []), pd)  # named afresh
    assert np.all(np.abs(pd.bifurcation_d.values - b) <= pd.bifurcation_d_width.values / 2)
    assert np.all(pd.bifurcation_d_width.values < 5e-4)
    # the up sweep's loss moved below the grid point 0.158 (no period found there): still a flip between; with that
    # point chaotic, no flip's slowing
    up = int(np.flatnonzero(tr.direction.values == "up")[0])
    wider = tr.copy(deep=True)
    wider["d"].values[up] = 0.1579
    assert sw.d.values[1] == pytest.approx(0.158) and set(sw.label.values[:, 1]) == {"no period found"}
    assert period_doublings(wider, sw, []).kind.values.tolist() == [PERIOD_DOUBLING] * 2
    chaotic = sw.copy(deep=True)
    chaotic["label"].values[:, 1] = "chaotic"
    assert all(str(k).startswith("period lost") for k in period_doublings(wider, chaotic, []).kind.values)


def test_a_branch_on_another_line_of_parameters_is_not_used(across_flip):
    """The 2:1 branch at a force 0.02 % larger has its flip 1.4e-5 lower in d, within the critical slowing of both
    transitions and ahead of both, but it is another device: the transitions are placed by the sweeps alone."""
    sw, tr, _ = across_flip
    p = vi.Params.from_physical(s=0.17 / K_S, beta=BETA, F=5.001)
    other = vi.continue_orbit(vi.find_orbit(p, "BBT", 1.0, 0.2), vary="s", d_range=(0.155, 0.171), step=1e-3)
    b = float(other.critical_d.values[other.critical_kind.values == "B"][0])
    assert np.all(np.abs(tr.d.values - b) < 3e-4) and tr.d.values.min() < b < tr.d.values.max()
    pd = period_doublings(tr, sw, [other])
    assert set(pd.bifurcation_source.values) == {"sweeps"}


def _with_row(tr, **row):
    """``tr`` with one more located transition."""
    extra = xr.Dataset({k: ("transition", [v]) for k, v in row.items()},
                       coords={"transition": [int(tr.transition.max()) + 1]})
    return xr.concat([tr, extra], dim="transition", data_vars="all", combine_attrs="override")


def test_a_flip_behind_the_transition_beyond_the_slowing_or_past_another_motion_is_not_its_flip(across_flip):
    """The branch's flip places a transition only when it lies ahead of it in the sweep's direction, within the
    critical slowing, with no other motion identified between, and the motion the detector found there is not
    chaos."""
    sw, tr, br = across_flip
    down = int(np.flatnonzero(tr.direction.values == "down")[0])
    # the directions reversed: each flip is behind its transition
    flipped = tr.assign(direction=("transition", np.where(tr.direction.values == "up", "down", "up")))
    assert "2:1 period-2" not in period_doublings(flipped, sw, [br]).bifurcation_source.values
    # the down sweep's loss moved to 3 slowing half-widths above the flip (still below the next grid point, 0.160):
    # too far for slowing to explain
    b = float(br.critical_d.values[br.critical_kind.values == "B"][0])
    delta = float(period_doublings(tr, sw, [br]).slowing_width.values[down]) / 2
    far = tr.copy(deep=True)
    far["d"].values[down] = b + 3 * delta
    assert b + 3 * delta < 0.160
    assert str(period_doublings(far, sw, [br]).bifurcation_source.values[down]) != "2:1 period-2"
    # a 3:1 motion identified by the up sweep between the down sweep's loss and the flip
    x = float(tr.d.values[down])
    other = _with_row(tr, direction="up", d=0.5 * (b + x), d_width=1e-7, before="3:1 period-2", after="2:1 period-2",
                      kind="bottom impact lost", status="refined")
    assert str(period_doublings(other, sw, [br]).kind.values[down]).startswith("period lost")
    # lost into chaos (lambda_1 > 0), not the slowing near the flip (lambda_1 -> 0)
    chaos = tr.copy(deep=True)
    chaos["after"].values[down] = "chaotic"
    assert str(period_doublings(chaos, sw, [br]).kind.values[down]) == "period lost (chaotic)"


def test_a_period_lost_at_a_fold_stays_a_period_lost():
    """At the 2:1 fold (beta = pi/3, d = 0.2200675) the up sweep loses the 2:1 motion with no flip near: neither the
    2:1 branch (its B is at 0.158) nor the sweeps make it a period doubling."""
    sw = vi.sweep("s", np.array([0.219, 0.221]) / K_S, beta=BETA, phi=1.0, v0=0.2, max_periods=MAX_PERIODS,
                  long_impacts=0)
    tr = vi.locate_transitions(sw, xtol=1e-7, max_periods=MAX_PERIODS)
    p = vi.Params.from_physical(s=0.17 / K_S, beta=BETA)
    br = vi.continue_orbit(vi.find_orbit(p, "BBT", 1.0, 0.2), vary="s", d_range=(0.155, 0.2205), step=1e-3)
    assert {"B", "fold"} <= set(br.critical_kind.values)
    assert tr.sizes["transition"] == 1 and str(tr.kind.values[0]).startswith("period lost")
    for branches in ([br], []):
        pd = period_doublings(tr, sw, branches)
        assert str(pd.kind.values[0]).startswith("period lost") and np.isnan(pd.bifurcation_d.values[0])


def test_the_transitions_table_gives_a_period_doubling_at_its_flip(across_flip):
    """The table's d is the flip, "to" the motion past it, and the status says where the detector gave up."""
    sw, tr, br = across_flip
    table = transitions_markdown({"s": period_doublings(tr, sw, [br])})
    b = float(br.critical_d.values[br.critical_kind.values == "B"][0])
    down = next(line for line in table.splitlines() if line.startswith("| s | down"))
    cells = [c.strip() for c in down.strip("|").split("|")]
    assert cells[2] == f"{b:.7f}" and cells[4:7] == ["2:1 period-2", "2:1 period-4", PERIOD_DOUBLING]
    assert f"gave up at {float(tr.d.values[tr.direction.values == 'down'][0]):.7f}" in cells[7]
    assert "B of the 2:1 period-2 branch" in cells[7]


def _results_sweeps():
    import glob

    import yaml

    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    for name, sc in cfg["sweeps"]["scenes"].items():
        key = f"beta-{sc['beta']:.4f}_r-{cfg['physics']['r']:.4f}"
        f = ROOT / "results" / "sweeps" / key / f"{name}-transitions.nc"
        if f.exists():
            brs = sorted(glob.glob(str(ROOT / "results" / "branches" / key / f"orbit-*_vary-{sc['vary']}.nc")))
            yield name, xr.load_dataset(ROOT / "results" / "sweeps" / key / f"{name}.nc"), xr.load_dataset(f), [
                xr.load_dataset(b) for b in brs]


def test_the_workflow_s_period_doublings_sit_at_the_branches_flips():
    """In this checkout's results (skipped where the workflow has not run): every period doubling placed by a branch
    is at one of its B points, the detector gave up within its slowing, and the sweeps alone, without the branch,
    bracket it."""
    found = list(_results_sweeps())
    if not found or "bifurcation_d" not in found[0][2]:
        pytest.skip("no located transitions with period doublings in results/: run the default target")
    n = 0
    for name, sw, tr, brs in found:
        alone = period_doublings(tr, sw, [])  # named afresh, without the branches
        for k in np.flatnonzero(tr.bifurcation_source.values.astype(str) != ""):
            r = tr.isel(transition=k)
            if str(r.bifurcation_source.values) == "sweeps":
                continue
            flips = [float(b) for br in brs for kind, b in zip(br.critical_kind.values, br.critical_d.values,
                                                                  strict=True) if kind == "B"]
            assert min(abs(f - float(r.bifurcation_d)) for f in flips) == 0, (name, k)
            assert abs(float(r.d) - float(r.bifurcation_d)) <= float(r.slowing_width) / 2, (name, k)
            a = alone.isel(transition=k)
            assert str(a.kind.values) == PERIOD_DOUBLING, (name, k)
            assert abs(float(a.bifurcation_d) - float(r.bifurcation_d)) <= float(a.bifurcation_d_width) / 2, (name, k)
            n += 1
    assert n >= 8


def test_a_two_point_sweep_along_a_force_line_finds_the_flips_on_its_line():
    """The line of parameters a sweep follows is fitted through its points from two points on: along a force line
    (d and gbar both vary, gbar affine in d) a sweep of two points keeps a branch's flip on that line and leaves out
    one on another line.  The branch here is written by hand: a real eigenvalue linear in d, crossing -1 at
    b = 0.15 with slope -20, so the half-width of critical slowing is k ln(1/tol) / (20 max_periods)."""
    from vibroimpact.analysis.motion_names import orbit_motion
    from vibroimpact.analysis.transitions import _flips

    d = np.array([0.14, 0.15, 0.16])
    lam = -1.0 - 20.0 * (d - 0.15)

    def branch(intercept):
        ds = xr.Dataset({"d": ("point", d), "eig_real": (("point", "eig"), np.stack([lam, np.full(3, 0.1)], axis=1)),
                         "eig_imag": (("point", "eig"), np.zeros((3, 2))),
                         "critical_kind": ("critical", np.array(["B"])), "critical_d": ("critical", np.array([0.15])),
                         "critical_admissible": ("critical", np.array([True]))})
        ds.attrs.update(r=0.5, k=1, word="BBT", gbar_intercept=intercept, gbar_slope=-1.5)
        return ds

    for points in (np.array([0.10, 0.20]), np.array([0.10, 0.15, 0.20])):
        sw = xr.Dataset({"d": ("point", points), "gbar": ("point", 0.45 - 1.5 * points)}, attrs={"r": 0.5})
        flips = _flips(sw, [branch(0.45), branch(0.46)], TOL, MAX_PERIODS)
        assert len(flips) == 1, (points, flips)
        b, motion, delta = flips[0]
        assert b == 0.15 and motion == orbit_motion("BBT", 1)
        assert delta == pytest.approx(math.log(1 / TOL) / (20.0 * MAX_PERIODS), rel=1e-12)
