"""Numerical sweeps: hysteresis, located transitions, agreement with the analytic orbits, basins, maps."""

import math

import numpy as np
import pytest
import xarray as xr

import vibroimpact as vi
from vibroimpact.analysis import windows
from vibroimpact.analysis.basins import basins
from vibroimpact.analysis.bistability import bistable_intervals
from vibroimpact.analysis.continuation import continue_orbit
from vibroimpact.analysis.grids import parameter_grid
from vibroimpact.analysis.motions import (
    APERIODIC,
    NO_PERIOD_LABELS,
    Motion,
    no_period,
    no_period_label,
    transition_kind,
)
from vibroimpact.analysis.orbits import find_orbit
from vibroimpact.analysis.regime_maps import regime_map
from vibroimpact.analysis.sweeps import sweep
from vibroimpact.analysis.transitions import locate_transitions

K_S = 0.1245 * (5 * math.pi) ** 2 / (5 * math.pi**2)  # d = K_S s at the paper's force
G1_ANALYTIC = 0.1376002140  # tests/test_orbits.py: 2:1 grazing point (beta = pi/6)
G2_ANALYTIC = 0.1419540498  # 3:1 fold


@pytest.fixture(scope="module")
def pi6():
    sw = sweep("s", np.linspace(0.125, 0.16, 36) / K_S, beta=math.pi / 6, phi=5.855, v0=0.4185)
    return sw, locate_transitions(sw, xtol=1e-9)


def test_sweep_dataset_shape_and_hysteresis(pi6):
    sw, _ = pi6
    assert list(sw.direction.values) == ["up", "down"]
    assert np.all(np.diff(sw.d.values) > 0)
    np.testing.assert_allclose(sw.d.values, sw.s.values * K_S, rtol=1e-12)
    up, down = sw.label.values
    # hysteresis: at d = 0.14 the up sweep is on 3:1, the down sweep on 2:1
    i = int(np.argmin(np.abs(sw.d.values - 0.14)))
    assert (up[i], down[i]) == ("3:1 period-2", "2:1 period-2")
    for var in ("v_minus", "phase", "t", "wall", "label", "period", "n_bottom", "n_top", "n_events"):
        assert var in sw and "long_name" in sw[var].attrs
    # each direction starts from the given impact; every later point from the last bottom impact of
    # the attractor before it
    for k, first, step in ((0, 0, 1), (1, sw.sizes["point"] - 1, -1)):
        assert (float(sw.start_phi[k, first]), float(sw.start_v0[k, first])) == (5.855, 0.4185)
        prev = sw.isel(direction=k, point=first)
        m = int(np.isfinite(prev.t.values).sum())
        j = max(i for i in range(m) if prev.wall.values[i] == 1 and prev.kind.values[i] == 0 and prev.v_minus.values[i] > 0)
        assert float(sw.start_v0[k, first + step]) == float(prev.v_minus.values[j])
        assert float(sw.start_phi[k, first + step]) == float(prev.phase.values[j])


def test_transitions_G1_and_G2_located_and_agree_with_the_analytic_points(pi6):
    sw, tr = pi6
    down = tr.where(tr.direction == "down", drop=True)
    up = tr.where(tr.direction == "up", drop=True)
    (g1,) = down.d.values
    (g2,) = up.d.values
    assert str(down.kind.values[0]) == "grazing: extra bottom impact"
    assert (str(down.before.values[0]), str(down.after.values[0])) == ("2:1 period-2", "3:1 period-2")
    assert str(up.after.values[0]) == "2:1 period-2"
    assert abs(g1 - G1_ANALYTIC) < 1e-6 and abs(g2 - G2_ANALYTIC) < 1e-6
    # the paper's simulated values: G1 = 0.1378, G2 = 0.1419
    assert g1 == pytest.approx(0.1378, abs=3e-4) and g2 == pytest.approx(0.1419, abs=1e-4)
    iv = bistable_intervals(sw, tr)
    assert iv.sizes["interval"] == 1
    assert float(iv.d_lo[0]) == pytest.approx(g1, abs=1e-12) and float(iv.d_hi[0]) == pytest.approx(g2, abs=1e-12)
    assert (str(iv.label_up.values[0]), str(iv.label_down.values[0])) == ("3:1 period-2", "2:1 period-2")


def analytic_ends(sw, beta):
    """Grazing point of the 3:1 orbit (where it gains a bottom impact: the down sweep's end) and
    fold of the 4:1 orbit (the up sweep's end), by continuation of the orbits the sweeps settle on."""
    ends = {}
    for k_dir, word, kind in [(0, "BBBBT", "fold"), (1, "BBBT", "grazing")]:
        label = f"{len(word) - 1}:1 period-2"
        i = int(np.flatnonzero(sw.label.values[k_dir] == label)[-1 if k_dir == 0 else 0])
        ev = sw.isel(direction=k_dir, point=i)
        m, n = int(np.isfinite(ev.t.values).sum()), int(ev.period_events)
        w, ph, vm = (ev[v].values[m - n:m] for v in ("wall", "phase", "v_minus"))
        b = next(j for j in range(n) if w[j] == 1 and w[j - 1] == -1)
        o = find_orbit(vi.Params.from_physical(s=float(sw.s[i]), beta=beta), word, ph[b], vm[b])
        br = continue_orbit(o, vary="s", d_range=(0.115, 0.13), step=2e-4)
        crit = br.critical_d.values[br.critical_kind.values == kind]
        ends[kind] = float(crit[np.argmin(np.abs(crit - float(sw.d[i])))])
    return ends["grazing"], ends["fold"]


@pytest.mark.parametrize("beta, lo, hi, n, found_by", [
    # beta = pi/3: 3:1 grazes at 0.12238, 4:1 folds at 0.12511: the interval spans 3 grid steps and
    # its two ends are far from the one grid point where the sweeps disagree
    (math.pi / 3, 0.119, 0.127, 5, "sweeps differ"),
    (math.pi / 3, 0.119, 0.127, 9, "sweeps differ"),
    # beta = pi/4 (3:1 grazes at 0.12179, 4:1 folds at 0.12315): no grid point inside, both sweeps
    # jump between the same grid points, and only the located ends see the loop
    (math.pi / 4, 0.1155, 0.1275, 5, "transitions only"),
])
def test_bistable_interval_ends_are_the_bounding_transitions(beta, lo, hi, n, found_by):
    """The lower end is the down sweep's transition (3:1 gains a bottom impact at its grazing point),
    the upper end the up sweep's (4:1 ends at its fold): both agree with continuation of the orbits."""
    sw = sweep("s", np.linspace(lo, hi, n) / K_S, beta=beta, phi=0.42, v0=0.87)
    tr = locate_transitions(sw, xtol=1e-9)
    assert set(tr.status.values) == {"refined"}
    (iv,) = [bistable_intervals(sw, tr).isel(interval=k) for k in range(1)]
    grazing, fold = analytic_ends(sw, beta)
    assert fold - grazing > 1e-3  # a wide interval: at least one grid step here
    assert str(iv.found_by.values) == found_by
    assert (str(iv.label_up.values), str(iv.label_down.values)) == ("4:1 period-2", "3:1 period-2")
    assert (str(iv.lo_source.values), str(iv.hi_source.values)) == ("located", "located")
    assert abs(float(iv.d_lo) - grazing) < 1e-6 and abs(float(iv.d_hi) - fold) < 1e-6


def synthetic(up, down, d, transitions):
    sw = xr.Dataset({"label": (("direction", "point"), np.array([up, down]))}, coords={"d": ("point", d)})
    cols = list(zip(*transitions, strict=True))
    tr = xr.Dataset({"direction": ("transition", list(cols[0])), "d": ("transition", np.array(cols[1])),
                     "d_width": ("transition", np.full(len(transitions), 1e-8)),
                     "before": ("transition", list(cols[2])), "after": ("transition", list(cols[3]))})
    return sw, tr


def test_bistable_interval_with_an_aperiodic_side_ends_on_the_grid():
    d = np.array([0.1, 0.2, 0.3, 0.4])
    gone = APERIODIC
    sw, tr = synthetic(["A", "A", "A", "B"], ["A", gone, gone, "B"], d, [("up", 0.35, "A", "B")])
    (row,) = bistable_intervals(sw, tr).to_dataframe().itertuples()
    assert (row.d_lo, row.lo_source, row.d_lo_width) == (pytest.approx(0.15), "grid", pytest.approx(0.1))
    assert (row.d_hi, row.hi_source) == (0.35, "located")


def test_bistable_interval_with_an_aperiodic_upper_side_ends_on_the_grid():
    d = np.array([0.1, 0.2, 0.3, 0.4])
    gone = APERIODIC
    sw, tr = synthetic(["A", "B", "B", gone], ["A", "A", "A", gone], d, [("down", 0.15, "A", "B")])
    (row,) = bistable_intervals(sw, tr).to_dataframe().itertuples()
    assert (row.d_lo, row.lo_source) == (0.15, "located")
    assert (row.d_hi, row.hi_source, row.d_hi_width) == (pytest.approx(0.35), "grid", pytest.approx(0.1))


def test_bistable_interval_of_non_positive_width_is_recorded_not_raised():
    d = np.array([0.1, 0.2, 0.3, 0.4])
    # both motions said to end exactly at the grid point where the sweeps differ: no interval is left; the sweep's
    # job goes on, the dataset naming the interval left out and why
    sw, tr = synthetic(["A", "A", "A", "B"], ["A", "A", "B", "B"], d, [("up", 0.3, "A", "B"), ("down", 0.3, "B", "A")])
    out = bistable_intervals(sw, tr)
    assert out.sizes["interval"] == 0
    assert out.attrs["inconsistent_intervals"] == ("intervals of non-positive width, left out (the located transitions "
                                                   "are inconsistent): d_lo = 0.3 >= d_hi = 0.3 (up sweep 'A', down "
                                                   "sweep 'B')")


def test_bistable_interval_reaching_the_range_end_is_open_there():
    d = np.array([0.1, 0.2, 0.3, 0.4])
    sw, tr = synthetic(["A", "A", "A", "A"], ["A", "A", "B", "B"], d, [("down", 0.25, "B", "A")])
    (row,) = bistable_intervals(sw, tr).to_dataframe().itertuples()
    assert (row.d_lo, row.lo_source, row.d_lo_width) == (0.25, "located", 1e-8)
    assert (row.d_hi, row.hi_source) == (0.4, "range end") and math.isnan(row.d_hi_width)
    sw, tr = synthetic(["B", "B", "A", "A"], ["A", "A", "A", "A"], d, [("up", 0.25, "B", "A")])
    (row,) = bistable_intervals(sw, tr).to_dataframe().itertuples()
    assert (row.d_lo, row.lo_source, row.d_hi, row.hi_source) == (0.1, "range end", 0.25, "located")
    assert (row.label_up, row.label_down) == ("B", "A")


def test_no_bistability_gives_an_empty_table():
    d = np.array([0.1, 0.2, 0.3, 0.4])
    sw, tr = synthetic(["A", "A", "B", "B"], ["A", "A", "B", "B"], d, [("up", 0.25, "A", "B"), ("down", 0.25, "B", "A")])
    iv = bistable_intervals(sw, tr)
    assert iv.sizes["interval"] == 0
    assert set(iv.data_vars) >= {"d_lo", "d_hi", "d_lo_width", "d_hi_width", "label_up", "label_down"}


@pytest.mark.parametrize("before, after, kind", [
    ("2:1 period-2", "3:1 period-2", "grazing: extra bottom impact"),
    ("3:1 period-2", "2:1 period-2", "bottom impact lost"),
    ("1:1 period-2", "1:2 period-2", "grazing: extra top impact"),
    ("1:2 period-2", "1:1 period-2", "top impact lost"),
    ("2:2 period-2", "2:1 period-2", "top impact lost"),
    ("1:1 period-2", "1:1 period-4", "period doubling"),
    ("1:1 period-4", "1:1 period-2", "period halving"),
    ("1:1 period-2", "1:1 period-6", "period change"),
    ("2:1 period-2", "4:2 period-4", "other"),
    ("2:1 period-2", "3:2 period-2", "other"),
    ("2:1 period-2", "no period found", "period lost (no period found)"),
    ("no period found", "2:1 period-2", "period found"),
    ("no period found", "no period found", "none"),
    ("2:1 period-2", "chaotic", "period lost (chaotic)"),
    ("1:1 period-2", "quasi-periodic", "period lost (quasi-periodic)"),
    ("unsettled", "1:1 period-4", "period found"),
    ("chaotic", "quasi-periodic", "none"),
    ("2:0 period-2 with sticking", "2:1 period-2", "other"),
])
def test_transition_kinds(before, after, kind):
    """Each motion given by its parts (bottom and top impacts over its period, sticking), its label checked."""
    assert MOTIONS[before].label == before and MOTIONS[after].label == after
    assert transition_kind(MOTIONS[before], MOTIONS[after]) == kind


MOTIONS = {
    "2:1 period-2": Motion(period=1, bottom=2, top=1), "3:1 period-2": Motion(period=1, bottom=3, top=1),
    "1:1 period-2": Motion(period=1, bottom=1, top=1), "1:2 period-2": Motion(period=1, bottom=1, top=2),
    "2:2 period-2": Motion(period=1, bottom=2, top=2), "3:2 period-2": Motion(period=1, bottom=3, top=2),
    "1:1 period-4": Motion(period=2, bottom=2, top=2), "1:1 period-6": Motion(period=3, bottom=3, top=3),
    "4:2 period-4": Motion(period=2, bottom=8, top=4),
    "2:0 period-2 with sticking": Motion(period=1, bottom=2, top=0, sticking=True),
    **{label: Motion(kind=label) for label in NO_PERIOD_LABELS},
}


def test_bad_window_is_rejected_before_running():
    with pytest.raises(ValueError, match="window = 64; allowed: >= pmax \\+ 1 = 65"):
        sweep("s", [0.3], beta=math.pi / 6, window=64)
    with pytest.raises(ValueError, match="window = 10"):
        windows.attractor_batch(0.2, 0.1, 0.5, 0.0, 0.5, window=10, pmax=16)
    with pytest.raises(ValueError, match="axes"):
        regime_map("s", [0.3], "s", [0.4])


def test_swept_points_agree_with_the_analytic_orbit(pi6):
    """Where a stable analytic 2:1 orbit exists, the sweep's attractor equals it to 1e-8."""
    sw, _ = pi6
    down = sw.sel(direction="down")
    checked = 0
    for i in np.flatnonzero(down.label.values == "2:1 period-2"):
        n = int(down.period_events[i])
        ev = down.isel(point=i)
        m = int(np.isfinite(ev.t.values).sum())
        vm, ph, wall = ev.v_minus.values[m - n:m], ev.phase.values[m - n:m], ev.wall.values[m - n:m]
        b = int(np.flatnonzero(wall == 1)[0])
        p = vi.Params(d=float(down.d[i]), gbar=float(down.gbar[i]), r=0.5)
        o = find_orbit(p, "BBT", ph[b], vm[b])
        assert np.min(np.abs(o.v_minus[:, None] - vm[None, :]), axis=1).max() < 1e-8
        checked += 1
    assert checked >= 15


def test_period_doubling_of_1to1_located_near_the_analytic_point():
    """beta = pi/3: 1:1 period-2 above d_B = 0.324189 (analytic), period-doubled below."""
    sw = sweep("s", np.linspace(0.28, 0.36, 9) / K_S, beta=math.pi / 3, phi=0.42, v0=0.87)
    assert sw.label.values[0, 0] == "1:1 period-4" and sw.label.values[1, -1] == "1:1 period-2"
    tr = locate_transitions(sw, xtol=1e-8)
    for d in tr.d.values:
        assert abs(d - 0.3241885) < 2e-4  # convergence within the allowed transient limits this
    assert set(tr.before.values) == {"1:1 period-4", "1:1 period-2"}


def test_force_sweep_grid():
    d, gbar, s, F = parameter_grid("F", [6.0, 12.0, 22.0], beta=math.pi / 2, s=0.85)
    np.testing.assert_allclose(d * F, 0.85 * K_S * 5.0, rtol=1e-12)
    np.testing.assert_allclose(gbar * F, 0.1245 * 9.8, rtol=1e-12)
    assert np.all(s == 0.85)
    with pytest.raises(ValueError, match="vary"):
        parameter_grid("x", [1.0], beta=1.0)
    with pytest.raises(ValueError, match="F = "):
        parameter_grid("F", [0.0], beta=1.0)


def test_basins_at_the_bistable_point_hold_both_motions():
    p = vi.Params.from_physical(s=0.14 / K_S, beta=math.pi / 6)
    b = basins(p, np.linspace(0, 2 * np.pi, 24, endpoint=False), np.linspace(0.05, 1.0, 16))
    assert b.attractor.shape == (24, 16)
    labels = set(np.unique(b.label.values))
    assert {"2:1 period-2", "3:1 period-2"} <= labels
    assert "legend" in b.attractor.attrs


def test_regime_map_over_length_and_incline():
    m = regime_map("s", np.linspace(0.2, 0.7, 6), "beta", [math.pi / 6, math.pi / 3])
    assert m.label.dims == ("beta", "s") and m.label.shape == (2, 6)
    p = vi.Params.from_physical(s=0.7, beta=math.pi / 3)
    assert float(m.d.sel(beta=math.pi / 3, s=0.7)) == pytest.approx(p.d)
    # long cylinders give the 1:1 motion, short ones asymmetric n:1 motions (paper Fig 0)
    assert str(m.label.sel(beta=math.pi / 3, s=0.7).values) == "1:1 period-2"
    assert str(m.label.sel(beta=math.pi / 6, s=0.2).values).startswith(("3:1", "4:1"))
    # the paper's defaults fill the third parameter: F = 5 N here, beta = pi/6 for an (s, F) map
    m2 = regime_map("s", [0.3], "F", [5.0], max_periods=20)
    p = vi.Params.from_physical(s=0.3, F=5.0, beta=math.pi / 6)
    assert (float(m2.d[0, 0]), float(m2.gbar[0, 0])) == (pytest.approx(p.d, rel=1e-12), pytest.approx(p.gbar, rel=1e-12))


def test_regime_map_on_non_dimensional_axes_runs_the_parameters_it_names():
    """On (d, gbar) each point is the attractor of Params(d, gbar, r) itself: at the 2:1 scene
    (d = 0.16, gbar of beta = pi/6) the 2:1 period-2 motion, as the physical map finds it there; d mixed
    with a physical axis is refused."""
    import math


    g = 0.1245 * 9.8 * math.sin(math.pi / 6) / 5.0
    m = regime_map("d", [0.16, 0.40], "gbar", [g], phi=1.015, v0=0.1924)
    assert list(m.label.values[0]) == ["2:1 period-2", "1:1 period-2"]
    assert m.attrs["r"] == 0.5 and "s" not in m.attrs and m.d.attrs["units"] == "1"
    k = 0.1245 * (5 * math.pi) ** 2 / (5.0 * math.pi**2)  # d = k s at F = 5 N
    phys = regime_map("s", [0.16 / k, 0.40 / k], "beta", [math.pi / 6], phi=1.015, v0=0.1924)
    assert list(phys.label.values[0]) == list(m.label.values[0])
    r_map = regime_map("d", [0.16], "r", [0.5], phi=1.015, v0=0.1924, beta=math.pi / 6)
    assert abs(float(r_map.gbar.values[0, 0]) - g) < 1e-15
    with pytest.raises(ValueError, match="'d' is non-dimensional"):
        regime_map("d", [0.16], "s", [0.3])


@pytest.mark.parametrize("status, low, high, sticks, label", [
    ("aperiodic", 0.01, 0.3, 0, "chaotic"),
    ("aperiodic", 0.0, 0.3, 0, "quasi-periodic"),  # an interval touching 0 cannot tell chaos from a torus
    ("aperiodic", -0.01, 0.01, 0, "quasi-periodic"),
    ("aperiodic", -0.3, 0.0, 0, "quasi-periodic"),
    ("aperiodic", -0.3, -0.01, 0, "unsettled"),
    ("aperiodic", 0.01, 0.3, 2, "unsettled"),  # sticks again and again: eventually periodic
    ("aperiodic", -np.inf, -np.inf, 0, "no period found"),
    ("aperiodic", np.nan, np.nan, 0, "no period found"),
    ("aperiodic", 0.01, np.inf, 0, "no period found"),
    ("settles", np.nan, np.nan, 0, "unsettled"),
    ("stuck", np.nan, np.nan, 0, "unsettled"),
    ("not run", np.nan, np.nan, 0, "no period found"),
    ("no restart", 0.01, 0.3, 0, "no period found"),
])
def test_a_motion_with_no_period_is_named_by_the_interval_of_its_largest_exponent(status, low, high, sticks, label):
    assert no_period_label(status, low, high, sticks) == label


def test_every_label_of_a_motion_with_no_period_is_one():
    assert list(no_period(["chaotic", "quasi-periodic", "unsettled", "no period found", "2:1 period-2",
                                  "1:1 period-2 with sticking"])) == [True] * 4 + [False] * 2


@pytest.fixture(scope="module")
def across_chaos():
    """pi/3 from the 2:1 period-2 orbit (d = 0.20) into the chaotic window of Fig 0 (a) (d = 0.235, the
    chaotic scene of the benchmarks) and on to the period-doubled 1:1 orbit (d = 0.30)."""
    return sweep("s", np.array([0.20, 0.235, 0.30]) / K_S, beta=math.pi / 3, phi=0.42, v0=0.87, long_impacts=4000)


def test_a_sweep_gives_lambda_1_exact_on_solved_cycles_and_estimated_on_the_chaotic_point(across_chaos):
    """Each point's lambda_1: on a Newton-solved cycle the log of its largest multiplier per impact (and per
    unit time over its period), which the tangent estimate of a run from the cycle (vibroimpact.lyapunov,
    another method) confirms within its interval; on the chaotic point the long run's estimate, positive,
    whose interval meets that of an independent run of 22 000 impacts from another start."""
    sw = across_chaos
    lab = sw.label.values.astype(str)
    assert list(lab[0]) == ["2:1 period-2", "chaotic", "1:1 period-4"]
    assert (lab[1] == lab[0]).all()
    for i in (0, 2):
        pt = sw.isel(direction=0, point=i)
        assert str(pt.lyap1_source.values) == "multipliers of the Newton-solved cycle"
        lam1 = float(pt.lyap1)
        assert lam1 < 0 and float(pt.lyap1_low) == lam1 == float(pt.lyap1_high)
        n = int(pt.period_events)
        assert float(pt.lyap1_time) == pytest.approx(lam1 * n / (2 * int(pt.period)), rel=1e-12)
        p = vi.Params(d=float(pt.d), gbar=float(pt.gbar), r=0.5)
        est = vi.lyapunov(p, float(pt.cycle_phase[0]), float(pt.cycle_v_minus[0]), 4000, transient=400)
        lo, hi = est.interval[0]
        assert lo <= lam1 <= hi and hi - lo < 0.05 * abs(lam1)
    chaos = sw.isel(direction=0, point=1)
    assert float(chaos.lyap1_low) > 0 and "long run of 4000 impacts" == str(chaos.lyap1_source.values)
    assert float(chaos.lyap1_time) == pytest.approx(float(chaos.lyap1) * 4000 / 4000, rel=0.6)
    ref = vi.lyapunov(vi.Params(d=0.235, gbar=float(chaos.gbar), r=0.5), 0.0, 0.5, 22_000, transient=2000)
    assert float(chaos.lyap1_low) <= ref.interval[0][1] and ref.interval[0][0] <= float(chaos.lyap1_high)


def test_a_located_loss_of_period_names_what_follows_by_its_long_run(across_chaos):
    """The 2:1 period-2 orbit of pi/3 is lost near d = 0.22007 going up; a hair beyond it the motion is
    intermittent (lambda_1 about 0.02 over 40 000 impacts, 0.1 at 1e-5 beyond): the 4000 impacts of the
    continuation tell it from a torus or not, but never call it periodic, unsettled or unknown."""
    tr = locate_transitions(across_chaos.isel(point=[0, 1]), xtol=1e-6)
    up = tr.where(tr.direction == "up", drop=True)
    after = [str(a) for a in up.after.values]
    assert len(after) == 1 and after[0] in ("chaotic", "quasi-periodic")
    assert list(up.kind.values) == [f"period lost ({after[0]})"]
    assert float(up.d[0]) == pytest.approx(0.22007, abs=1e-5)


def test_a_regime_map_splits_its_cells_with_no_period():
    m = regime_map("s", np.array([0.235, 0.30]) / K_S, "beta", [math.pi / 3], phi=0.42, v0=0.87)
    assert list(m.label.values[0]) == ["chaotic", "1:1 period-4"]
    assert 0 < float(m.lyap1_low[0, 0]) < float(m.lyap1[0, 0]) < float(m.lyap1_high[0, 0])
    assert np.isnan(m.lyap1.values[0, 1])  # a periodic cell has no long run


def test_without_a_long_run_a_motion_with_no_period_keeps_its_label_and_says_why_it_has_no_exponent():
    sw = sweep("s", [0.235 / K_S], beta=math.pi / 3, phi=0.42, v0=0.87, long_impacts=0)
    assert set(sw.label.values.ravel()) == {"no period found"}
    assert np.isnan(sw.lyap1.values).all()
    assert set(sw.lyap1_source.values.ravel()) == {"not estimated: no long run (long_impacts = 0)"}


def test_transitions_are_followed_with_the_sweep_s_own_window_and_longest_period(monkeypatch):
    """locate_transitions follows each motion with the window and longest period the sweep identified it
    with (recorded in the sweep), not with the defaults."""
    import vibroimpact.analysis.transitions as S

    sw = vi.sweep("s", [0.219, 0.2245, 0.23], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=0,
                  window=41, pmax=20)
    assert (sw.attrs["window"], sw.attrs["pmax"]) == (41, 20)
    seen = set()
    run_one = S.run_window

    def spy(*args):
        seen.add(args[-2:])
        return run_one(*args)

    monkeypatch.setattr(S, "run_window", spy)
    tr = vi.locate_transitions(sw, xtol=1e-5)
    assert seen == {(41, 20)} and list(tr.status.values) == ["refined", "refined"]


def test_a_force_sweep_s_transitions_are_followed_on_its_own_parameter_line(monkeypatch):
    """Along a force sweep d and gbar both change (gbar / d is constant): every run of the refinement lies on
    the sweep's line through its points; a sweep written without its window and longest period is followed
    with the sweep's defaults (65 events, 64)."""
    import vibroimpact.analysis.transitions as S

    sw = vi.sweep("F", [4.8, 5.0, 5.2], beta=math.pi / 6, s=0.2245, phi=5.855, v0=0.4185, long_impacts=0)
    ratio = sw.gbar.values / sw.d.values
    assert np.ptp(ratio) < 1e-12 * ratio[0] and len(set(sw.label.values.ravel())) > 1
    seen, run_one = [], S.run_window

    def spy(d, gbar, *args):
        seen.append((d, gbar, args[-2:]))
        return run_one(d, gbar, *args)

    monkeypatch.setattr(S, "run_window", spy)
    old = sw.copy()
    for a in ("window", "pmax"):
        old.attrs.pop(a)
    tr = vi.locate_transitions(old, xtol=1e-5)
    assert tr.sizes["transition"] > 0 and seen
    d, gbar = np.array([x[0] for x in seen]), np.array([x[1] for x in seen])
    np.testing.assert_allclose(gbar, ratio[0] * d, rtol=1e-12)
    assert {x[2] for x in seen} == {(65, 64)}


def test_a_hysteresis_loop_between_grid_points_reads_the_nearest_neighbour_below():
    """Both sweeps agree on every grid point (C, A, A, B, B) but jump between the same two points: up from A to B
    at 0.35, down from B to A at 0.25.  The loop [0.25, 0.35] is bistable ("transitions only"): the down sweep
    below its lower end follows A at its nearest grid point (0.2), whatever it follows further down (C at 0.1)."""
    d = np.array([0.1, 0.2, 0.3, 0.4, 0.5])
    labels = ["C", "A", "A", "B", "B"]
    sw, tr = synthetic(labels, labels, d, [("up", 0.35, "A", "B"), ("down", 0.25, "B", "A")])
    (row,) = bistable_intervals(sw, tr).to_dataframe().itertuples()
    assert (row.d_lo, row.d_hi, row.label_up, row.label_down, row.found_by) == (0.25, 0.35, "A", "B",
                                                                                 "transitions only")


def test_a_sweep_starts_and_caps_its_runs_as_documented():
    """sweep's defaults: the first point starts from a bottom impact at phase 0 with pre-impact speed 0.5
    (recorded as the start), and a run is capped at 200 000 events: a point that chatters (r = 0.9, gbar =
    0.9, d = 0.3) runs 32 911 events without finding a period, far beyond one buffer of 4096."""
    dev = vi.Device().replace(r=0.9)
    F = dev.M * dev.g / 0.9
    s = 0.3 / dev.params(1.0, math.pi / 2, F=F).d
    sw = vi.sweep("F", [F], beta=math.pi / 2, s=s, device=dev, long_impacts=0)
    assert (sw.attrs["first_phi"], sw.attrs["first_v0"]) == (0.0, 0.5)
    assert sw.start_phi.values[0, 0] == 0.0 and sw.start_v0.values[0, 0] == 0.5
    assert np.allclose(sw.gbar.values, 0.9) and np.allclose(sw.d.values, 0.3)
    assert 4096 < int(sw.n_events.values[0, 0]) <= 200_000


def test_the_follow_runs_take_the_documented_caps_unless_given_others(pi6, monkeypatch):
    """Each run that follows an attractor towards its change lasts at most 20 000 forcing periods and 2 000 000
    events by default (locate_transitions' documentation), and the caps given otherwise."""
    import vibroimpact.analysis.transitions as T

    seen = []
    run = T.run_window

    def recording(d, gbar, r, phi, v0, max_periods, max_events, *rest):
        seen.append((max_periods, max_events))
        return run(d, gbar, r, phi, v0, max_periods, max_events, *rest)

    monkeypatch.setattr(T, "run_window", recording)
    sw, _ = pi6
    near_g1 = sw.isel(point=[13, 14])  # d = 0.138, 0.139: going down the sweep leaves the 2:1 motion here
    locate_transitions(near_g1, xtol=1e-4)
    assert seen and set(seen) == {(20_000, 2_000_000)}
    seen.clear()
    locate_transitions(near_g1, xtol=1e-4, max_periods=500, max_events=12_345)
    assert seen and set(seen) == {(500, 12_345)}


def test_the_shortest_period_looked_for_is_one_event():
    """pmax = 1 (a period of one event, with a window of two) is allowed and runs; pmax = 0 is refused naming the
    key.  The 1:1 motion (two events a cycle) is then not identified, and is with pmax = 2."""
    with pytest.raises(ValueError, match="pmax = 0; allowed: an integer >= 1"):
        windows.attractor_batch(0.5, 0.1, 0.5, 1.0, 0.3, window=2, pmax=0)
    one = windows.attractor_batch(0.5, 0.1, 0.5, 1.0, 0.3, window=2, pmax=1, max_periods=2000)
    two = windows.attractor_batch(0.5, 0.1, 0.5, 1.0, 0.3, window=3, pmax=2, max_periods=2000)
    assert int(one.period_events[0]) == 0 and str(one.label.values[0]) == "no period found"
    assert int(two.period_events[0]) == 2 and str(two.label.values[0]) == "1:1 period-2"


def test_the_next_start_is_the_window_s_last_bottom_impact_not_another_bottom_event():
    """A sweep's next point and a located transition's next trial start from the last bottom impact of the window
    (wall +1, kind impact, moving into the wall): not from a later stick, release or grazing contact on the bottom,
    nor from a top impact; None where the window holds no bottom impact."""
    from vibroimpact.dynamics import kernels as K

    # events: bottom impact, top impact, bottom grazing contact, bottom stick, bottom release
    t = np.array([0.0, 0.7, 1.3, 1.9, 2.4])
    wall = np.array([1, -1, 1, 1, 1], np.int8)
    vm = np.array([0.31, -0.25, 2e-10, 0.0, 0.0])
    phase = np.array([0.4, 2.6, 4.5, 6.0, 1.2])
    kind = np.array([K.IMPACT, K.IMPACT, K.GRAZING, K.STICK, K.RELEASE], np.int8)
    assert windows.last_bottom_impact(t, wall, vm, phase, kind, 5) == (0.4, 0.31)
    assert windows.last_bottom_impact(t[1:], wall[1:], vm[1:], phase[1:], kind[1:], 4) is None
