"""Design under multistability (vibroimpact.analysis.design): shares, outputs and the tolerance analysis against
the basins, the analytic orbits, a run with more starts, closed forms and synthetic curves."""

import math

import numpy as np
import pytest
import xarray as xr
import yaml
from conftest import ROOT

import vibroimpact as vi
from vibroimpact.analysis.basins import basins
from vibroimpact.analysis.design import (
    best_designs,
    box_minimum,
    curve_margin,
    design_map,
    merge_chunks,
    share_interval,
    start_states,
    summarise,
    tolerance_analysis,
)
from vibroimpact.analysis.energy import Membrane, orbit_energy
from vibroimpact.analysis.orbits import find_orbit
from vibroimpact.dynamics.params import Params
from vibroimpact.outputs.workflow_config import check_design

CFG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
PH = CFG["physics"]
MB = Membrane(**CFG["membrane"])
#: the config's device (its physics and membrane, as the workflow builds it)
DEV = vi.Device.from_config(PH, CFG["membrane"])
BETA = math.pi / 6
#: relative agreement of a simulated periodic output with the analytic orbit's: the periodicity
#: tolerance of the attractor identification (1e-9), as the issue of this check states
REL = 1e-9


def s_of_d(d, F=PH["F"]):
    """The length giving the non-dimensional gap d at the physics' force."""
    return d * F * math.pi**2 / (PH["M"] * PH["omega"] ** 2)


def point(d, phi, v0, **kw):
    """A one-point design map at incline pi/6 and the physics' force."""
    return design_map("s", [s_of_d(d)], "beta", [BETA], phi=phi, v0=v0, device=DEV, F=PH["F"], progress=False, **kw).isel(s=0, beta=0)


def attractors(p):
    n = int((p["label"] != "").sum())
    return [(str(p.label.values[k]), float(p.share[k]), float(p.U_T[k]), float(p.share_low[k]),
             float(p.share_high[k])) for k in range(n)]


def test_shares_equal_those_of_the_basins_over_the_same_starts():
    """At the bistable point of the basins figure (beta = pi/6, d = 0.14), over the basins' grid of first
    impacts: each label's share of the starts is its share of the basins."""
    spec = CFG["basins"]["figBiS"]
    phis = np.linspace(0, 2 * math.pi, 45, endpoint=False)
    v0s = np.linspace(*spec["v0_range"], 30)
    params = Params.from_physical(s=s_of_d(spec["d"]), beta=spec["beta"], M=PH["M"], F=PH["F"], omega=PH["omega"],
                                  r=PH["r"], g=PH["g"])
    b = basins(params, phis, v0s, max_periods=200, progress=False)
    P, V = np.meshgrid(phis, v0s, indexing="ij")
    p = point(spec["d"], P.ravel(), V.ravel())
    labels, counts = np.unique(b.label.values, return_counts=True)
    assert len(labels) >= 2  # the point is bistable: the check compares two shares
    found = {}
    for lab, share, *_ in attractors(p):
        found[lab] = found.get(lab, 0.0) + share
    assert found == pytest.approx({str(k): c / b.label.size for k, c in zip(labels, counts, strict=True)}, abs=1e-15)


def test_where_one_analytic_orbit_is_the_only_attractor_E_U_T_is_its_output():
    """At d = 0.40 (beta = pi/6) every start at rest reaches the 1:1 orbit: E[U_T] equals the output of
    the Newton-solved orbit (from the caption's guess near Fig 0b (a)) to 1e-9."""
    phi, v0 = start_states(64, seed=3)
    p = point(0.40, phi, v0)
    assert [a[0] for a in attractors(p)] == ["1:1 period-2"] and float(p.share[0]) == 1.0
    params = Params.from_physical(s=s_of_d(0.40), beta=BETA, M=PH["M"], F=PH["F"], omega=PH["omega"], r=PH["r"],
                                  g=PH["g"])
    orbit = find_orbit(params, "BT", CFG["branches"]["words"]["BT"]["phi"], CFG["branches"]["words"]["BT"]["v0"])
    exact = orbit_energy(orbit, DEV)
    assert float(p.E_U_T) == pytest.approx(exact["U_T"], rel=REL)
    assert float(p.E_U_I) == pytest.approx(exact["U_I"], rel=REL)
    assert float(p.worst_U_T) == float(p.E_U_T) and not bool(p.multistable)


def test_inside_G1_G2_the_two_attractors_are_the_analytic_2to1_and_3to1_orbits():
    """At d = 0.14 (beta = pi/6, between G1 and G2) the device switched on at rest reaches two motions:
    the 2:1 and the 3:1 orbits of Fig BiS (e), (f), solved by Newton from the captions' guesses; each
    attractor's output and its last bottom impact are the orbit's."""
    phi, v0 = start_states(64, seed=1)
    p = point(0.14, phi, v0)
    got = {a[0]: (k, a) for k, a in enumerate(attractors(p))}
    assert set(got) == {"2:1 period-2", "3:1 period-2"} and bool(p.multistable)
    params = Params.from_physical(s=s_of_d(0.14), beta=BETA, M=PH["M"], F=PH["F"], omega=PH["omega"], r=PH["r"],
                                  g=PH["g"])
    for label, word, cap in (("2:1 period-2", "BBT", "figBiS_e"), ("3:1 period-2", "BBBT", "figBiS_f")):
        c = CFG["captions"][cap]
        orbit = find_orbit(params, word, c["phi"], c["v0"])
        k, (_, share, u_t, *_) = got[label]
        assert u_t == pytest.approx(orbit_energy(orbit, DEV)["U_T"], rel=REL)
        bottom = np.asarray(orbit.walls) == 1
        phases, vms = np.asarray(orbit.phase)[bottom] % (2 * math.pi), np.asarray(orbit.v_minus)[bottom]
        dist = np.hypot(np.angle(np.exp(1j * (phases - float(p.impact_phase[k])))), vms - float(p.impact_v_minus[k]))
        assert dist.min() < 1e-7
    e = sum(a[1] * a[2] for a in attractors(p))
    assert float(p.E_U_T) == pytest.approx(e, rel=1e-15)
    assert float(p.worst_U_T) == min(a[2] for a in attractors(p))


def test_the_share_interval_contains_the_share_of_a_run_with_16x_more_starts():
    small = point(0.14, *start_states(64, seed=1))
    big = point(0.14, *start_states(1024, seed=2))
    big_share = {a[0]: a[1] for a in attractors(big)}
    for lab, share, _, low, high in attractors(small):
        assert low <= big_share[lab] <= high, (lab, share, low, high, big_share[lab])
        assert low < share < high


def test_share_interval_is_clopper_pearson():
    """Closed forms at the ends: k = 0 gives [0, 1 - (a/2)^(1/n)], k = n gives [(a/2)^(1/n), 1]."""
    n, a = 64, 0.05
    assert share_interval(0, n, 1 - a) == pytest.approx((0.0, 1 - (a / 2) ** (1 / n)), rel=1e-10)
    assert share_interval(n, n, 1 - a) == pytest.approx(((a / 2) ** (1 / n), 1.0), rel=1e-10)
    lo, hi = share_interval(16, 64, 0.95)
    assert lo < 0.25 < hi and hi - lo < share_interval(16, 64, 0.99)[1] - share_interval(16, 64, 0.99)[0]


def test_start_states_are_seeded_and_in_their_distribution():
    phi, v0 = start_states(500, seed=7)
    assert (v0 == 0).all() and (phi >= 0).all() and (phi < 2 * math.pi).all()
    assert abs(phi.mean() - math.pi) < 0.3  # uniform: mean pi, standard error 0.08
    again = start_states(500, seed=7)
    assert np.array_equal(phi, again[0]) and not np.array_equal(phi, start_states(500, seed=8)[0])
    phi, v0 = start_states(200, distribution="box", seed=1, phi_range=(1.0, 2.0), v0_range=(0.1, 0.3))
    assert (phi >= 1).all() and (phi < 2).all() and (v0 >= 0.1).all() and (v0 < 0.3).all()


@pytest.mark.parametrize("kw, words", [
    (dict(n=4), ["starts", "4", ">= 8"]),
    (dict(n=64, distribution="uniform"), ["distribution", "uniform", "rest or box"]),
    (dict(n=64, distribution="box", v0_range=(0.5, 0.5)), ["v0_range", "0.5", "lo < hi"]),
    (dict(n=64, distribution="box", phi_range=(2.0, 1.0)), ["phi_range", "2.0", "lo < hi"]),
])
def test_bad_start_states_are_refused(kw, words):
    n = kw.pop("n")
    with pytest.raises(ValueError) as err:
        start_states(n, **kw)
    for w in words:
        assert w in str(err.value)


def _design_cfg():
    return {q: dict(v["design"]) for q, v in CFG["resolution"].items()}


@pytest.mark.parametrize("edit, words", [
    (lambda d, p: d["tolerance"].update(s=-0.01), ["design.tolerance.s", "-0.01", ">= 0"]),
    (lambda d, p: d["tolerance"].update(s=0.0, beta=0.0), ["design.tolerance (s_beta)", "box is empty"]),
    (lambda d, p: d["tolerance"].update(F=1.5), ["design.tolerance.F", "1.5", "< 1"]),
    (lambda d, p: p["draft"].update(starts=4), ["resolution.draft.design.starts", "4", ">= 8"]),
    (lambda d, p: p["paper"].update(chunks=500), ["resolution.paper.design.chunks", "500", "grid rows"]),
    (lambda d, p: p["draft"].update(grid=[1, 5]), ["resolution.draft.design.grid", "[1, 5]", "each >= 2"]),
    (lambda d, p: d.update(maps=["s_gamma"]), ["design.maps", "s_gamma", "a regime map of `maps`"]),
    (lambda d, p: d.update(confidence=1.0), ["design.confidence", "1.0", "(0, 1)"]),
    (lambda d, p: d.update(table_betas=[0.01]), ["design.table_betas", "0.01", "beta range"]),
    (lambda d, p: d["starts"].update(distribution="box", v0_range=[0.8, 0.2]), ["v0_range", "0.8", "lo < hi"]),
])
def test_bad_design_config_is_refused_naming_the_key(edit, words):
    import copy

    design, presets = copy.deepcopy(CFG["design"]), _design_cfg()
    check_design(design, presets, CFG["maps"])  # the shipped config passes
    smallest = copy.deepcopy(presets)
    smallest["draft"].update(grid=[2, 2], starts=8, chunks=2)
    check_design(design, smallest, CFG["maps"])  # and so do the smallest allowed values
    edit(design, presets)
    with pytest.raises(ValueError) as err:
        check_design(design, presets, CFG["maps"])
    for w in words:
        assert w in str(err.value), str(err.value)


def test_curve_margin_against_closed_forms():
    # a vertical segment x = 1, y in [-1, 1]; boxes of half-widths (0.05, 0.1)
    seg = ([1.0], [-1.0], [1.0], [1.0])
    m, i = curve_margin([0.9, 1.2, 1.0], [0.0, 0.5, 1.3], [0.05] * 3, [0.1] * 3, *seg)
    assert m == pytest.approx([2.0, 4.0, 3.0]) and list(i) == [0, 0, 0]
    # a diagonal y = x from (0, 0) to (1, 1), a square box of half-width w at (0.5, 0): the scaled box first
    # touches the line at its corner (0.5 - w m, w m), so 0.5 - w m = w m: m = 0.25 / w
    m, _ = curve_margin([0.5], [0.0], [0.1], [0.1], [0.0], [0.0], [1.0], [1.0])
    assert m[0] == pytest.approx(2.5)
    # a zero half-width in y: the box is a horizontal segment; only a curve crossing its line counts
    m, _ = curve_margin([0.0, 0.0], [0.5, 1.5], [0.1, 0.1], [0.0, 0.0], [0.3], [0.0], [0.3], [1.0])
    assert m[0] == pytest.approx(3.0) and m[1] == math.inf
    # and in x: the box is a vertical segment, met by a horizontal curve where it crosses x = 0.5 (0.3 / 0.1 boxes up)
    m, _ = curve_margin([0.5, 1.5], [0.0, 0.0], [0.0, 0.0], [0.1, 0.1], [0.0], [0.3], [1.0], [0.3])
    assert m[0] == pytest.approx(3.0) and m[1] == math.inf
    # the nearest of several segments, and none at all
    m, i = curve_margin([0.0], [0.0], [1.0], [1.0], [5.0, 2.0], [0.0, 0.0], [5.0, 2.0], [1.0, 1.0])
    assert m[0] == pytest.approx(2.0) and i[0] == 1
    m, i = curve_margin([0.0], [0.0], [1.0], [1.0], [], [], [], [])
    assert m[0] == math.inf and i[0] == -1


def test_box_minimum_sees_the_grid_points_bracketing_the_box():
    xs, ys = np.arange(5.0), np.arange(3.0)
    field = np.arange(15.0).reshape(3, 5)
    field[1, 3] = -1.0
    h0, h = np.zeros((3, 5)), np.full((3, 5), 0.5)
    out, inside = box_minimum(field, xs, ys, h0, h0)
    assert np.array_equal(out, field) and inside.all()  # a box of width 0 is the point itself
    out, inside = box_minimum(field, xs, ys, h, h0)  # half a cell in x: the two neighbours in the row
    assert out[1, 2] == -1 and out[1, 4] == -1 and out[1, 1] == 5 and out[0, 2] == 1
    assert not inside[0, 0] and inside[0, 2] and not inside[2, 4]
    field[2, 2] = np.nan
    out, _ = box_minimum(field, xs, ys, h0, h)
    assert np.isnan(out[1, 2]) and np.isnan(out[2, 2]) and out[0, 2] == 2


def _synthetic(E, xs, ys, share=None):
    """A design dataset over (beta, s) with one attractor per point of output E."""
    ny, nx = E.shape
    share = np.ones((ny, nx, 1)) if share is None else share
    ds = xr.Dataset({"label": (("beta", "s", "attractor"), np.full(share.shape, "1:1 period-2")),
                     "share": (("beta", "s", "attractor"), share),
                     "U_T": (("beta", "s", "attractor"), np.repeat(E[..., None], share.shape[-1], -1)),
                     "U_I": (("beta", "s", "attractor"), np.repeat(E[..., None], share.shape[-1], -1)),
                     "d": (("beta", "s"), np.ones((ny, nx)))},
                    coords={"s": xs, "beta": ys}, attrs=dict(x="s", y="beta", min_share=0.01, F=5.0))
    return summarise(ds)


def test_expected_and_worst_output_from_shares():
    share = np.array([[[0.5, 0.495, 0.005]]])
    ds = _synthetic(np.ones((1, 1)), [0.5], [0.5], share)
    ds["U_T"][:] = [[[10.0, 20.0, 1.0]]]
    ds = summarise(ds.drop_vars(["E_U_T", "worst_U_T"]))
    assert float(ds.E_U_T[0, 0]) == pytest.approx(0.5 * 10 + 0.495 * 20 + 0.005 * 1)
    assert float(ds.worst_U_T[0, 0]) == 10.0  # the 0.5 % attractor does not count
    assert int(ds.n_attractors[0, 0]) == 2 and bool(ds.multistable[0, 0])
    # an attractor whose output is not known (U_T NaN) adds nothing to the expected output
    ds["U_T"][:] = [[[10.0, np.nan, 1.0]]]
    ds = summarise(ds.drop_vars(["E_U_T", "worst_U_T"]))
    assert float(ds.E_U_T[0, 0]) == pytest.approx(0.5 * 10 + 0.005 * 1)


def test_tolerance_analysis_and_best_design_on_a_synthetic_plane():
    """A curve at s = 0.504 over all beta: designs within 1 % of it are not robust (margin <= 1); a second
    curve is admissible only at one end, so it does not count; the best robust design per row maximises
    the lowest E over its box within the budget."""
    xs = np.linspace(0.3, 0.8, 51)  # spacing 0.01
    ys = np.array([0.1, 0.2])
    E = np.tile(xs, (2, 1)) * 100
    E[0, 40] = 1.0  # s = 0.70: a dip; its neighbours' boxes see it
    ds = _synthetic(E, xs, ys)
    curves = xr.Dataset({"s": ("point", [0.504, 0.504, 0.6, 0.6]), "beta": ("point", [0.0, 1.0, 0.0, 1.0]),
                         "curve_index": ("point", [0, 0, 1, 1]), "admissible": ("point", [True, True, True, False]),
                         "curve_kind": ("curve", ["fold", "B"]), "curve_word": ("curve", ["BBT", "BT"])},
                        attrs={"params": "s beta", "kinds": "fold B"})
    out = tolerance_analysis(ds, curves, {"s": 0.01, "F": 0.05, "beta": 0.0})
    m = out.margin.values[0]
    assert m[xs.searchsorted(0.6)] == pytest.approx(0.096 / 0.006)  # the curve at 0.6 is not admissible
    assert m[xs.searchsorted(0.5)] == pytest.approx(0.8) and m[xs.searchsorted(0.51)] == pytest.approx(0.006 / 0.0051)
    robust = out.robust.values[0]
    near = np.abs(xs - 0.504) <= 0.01 * xs
    assert near.sum() == 1 and not robust[near].any() and robust[~near].all()
    assert out.nearest_curve.values[0, 0] == "fold of BBT"
    # a curve through the best row's top designs: the best robust design avoids its boxes
    crossing = curves.copy(deep=True)
    crossing["s"][:] = [0.504, 0.504, 0.705, 0.705]
    crossing["admissible"][:] = True
    top = best_designs(tolerance_analysis(ds, crossing, {"s": 0.01}), {"s": 0.71}, per="beta")
    assert top[1]["s"] == pytest.approx(0.69) and not top[1]["longest"]["robust"]
    best = best_designs(out, {"s": 0.71}, per="beta")
    # row 0: the boxes of s = 0.69, 0.70 and 0.71 see the dip at 0.70, so the best is 0.68; row 1 has no dip
    assert best[0]["s"] == pytest.approx(0.68) and best[1]["s"] == pytest.approx(0.71)
    assert best[0]["box_min_E_U_T"] == pytest.approx(67.0) and best[0]["longest"]["s"] == pytest.approx(0.71)
    E2 = E.copy()
    E2[:, 39:] = 0.0  # nothing from s = 0.69 on: the box of 0.68 sees 0.69
    best = best_designs(tolerance_analysis(_synthetic(E2, xs, ys), curves, {"s": 0.01}), {"s": 0.8}, per="beta")
    assert best[0]["s"] == pytest.approx(0.67) and best[0]["box_min_E_U_T"] == pytest.approx(66.0)
    assert not best_designs(out, {"s": 0.3}, per="beta")[0]["found"]  # 0.30: its box leaves the grid
    with pytest.raises(ValueError, match="box is empty"):
        tolerance_analysis(ds, curves, {"s": 0.0, "beta": 0.0})
    # a tolerance in beta only (0.01 rad): the box is a vertical segment, and only s = 0.504 meets the curve
    only_beta = tolerance_analysis(ds, curves, {"s": 0.0, "beta": 0.01})
    assert only_beta.margin.values[0, xs.searchsorted(0.6)] == math.inf and int((~only_beta.robust.values).sum()) == 0
    # over the whole map (per=None): one best design, without a "longest" beside it
    whole = best_designs(out, {"s": 0.71})
    assert len(whole) == 1 and whole[0]["s"] == pytest.approx(0.71) and whole[0]["beta"] == 0.2
    assert "longest" not in whole[0]


def test_a_beta_axis_gets_a_row_for_each_table_incline():
    from vibroimpact.analysis.design import grid_axes

    spec = {"x": "s", "x_range": [0.2, 0.7], "y": "beta", "y_range": [0.05, math.pi / 2]}
    xs, ys = grid_axes(spec, [6, 4], table_betas=[math.pi / 6, math.pi / 2, 0.01])
    assert xs.size == 6 and ys.size == 5 and (np.diff(ys) > 0).all()
    assert math.pi / 6 in ys and 0.01 not in ys  # outside the map's range: no row
    _, ys = grid_axes({**spec, "y": "F", "y_range": [3.0, 22.0]}, [6, 4], table_betas=[math.pi / 6])
    assert ys.size == 4


def test_chunks_merge_into_the_whole_map():
    phi, v0 = start_states(8, seed=5)
    kw = dict(phi=phi, v0=v0, device=DEV, F=PH["F"],
              progress=False, max_periods=100)
    xs, ys = np.linspace(0.2, 0.7, 4), np.array([0.3, 0.6, 1.0, 1.4])
    whole = design_map("s", xs, "beta", ys, **kw)
    parts = merge_chunks([design_map("s", xs, "beta", ys[a], **kw) for a in (slice(0, 1), slice(1, 4))])
    for v in whole.data_vars:
        xr.testing.assert_identical(whole[v], parts[v])
    assert parts.attrs["events"] == whole.attrs["events"]


def test_the_longest_device_at_pi_3_mostly_switches_on_into_a_motion_that_never_reaches_the_top():
    """At beta = pi/3, s = 0.72 m (the sweeps' best design) most starts at rest settle on a motion with
    sticking that never hits the top membrane, beside the 1:1: the design point says so, and the event
    simulator (a second code path) run from the same starts over 2000 forcing periods agrees start by start."""
    from vibroimpact.dynamics.runs import simulate

    phi, v0 = start_states(16, seed=16)
    p = design_map("s", [0.72], "beta", [math.pi / 3], phi=phi, v0=v0, device=DEV, F=PH["F"], progress=False).isel(s=0, beta=0)
    atts = attractors(p)
    assert len(atts) == 2 and atts[0][0].endswith("with sticking") and int(p.n_top[0]) == 0 and int(p.n_top[1]) > 0
    params = Params.from_physical(s=0.72, beta=math.pi / 3, M=PH["M"], F=PH["F"], omega=PH["omega"], r=PH["r"], g=PH["g"])
    never_top = 0
    for ph in phi:
        ev = simulate(params, float(ph), 0.0, t_end=4000.0)
        late = ev.t.values > 2000.0
        never_top += int(not (ev.wall.values[late] == -1).any())
    assert never_top == int(p["count"][0])
    assert float(p.E_U_T) < 0.5 * float(p.U_T[1])  # the output expected from switch-on is far below the 1:1's


def test_a_device_too_weakly_driven_to_lift_the_ball_rests_and_delivers_nothing():
    """||F|| = 0.5 N at beta = pi/2: gbar = M g / F > 1, the forcing never lifts the ball off the bottom
    membrane from any start, so one attractor, at rest, with U_T = 0 and no U_I."""
    from vibroimpact.analysis.design import AT_REST

    phi, v0 = start_states(8, distribution="box", seed=2, v0_range=(0.0, 0.5))
    p = design_map("s", [0.5], "F", [0.5], phi=phi, v0=v0, device=DEV, beta=math.pi / 2, progress=False).isel(s=0, F=0)
    assert float(p.gbar) > 1
    assert attractors(p) == [(AT_REST, 1.0, 0.0, pytest.approx(share_interval(8, 8, 0.95)[0]), 1.0)]
    assert float(p.E_U_T) == 0.0 and np.isnan(float(p.E_U_I)) and float(p.worst_U_T) == 0.0


def test_a_chaotic_attractor_is_named_so_and_delivers_its_long_run_average():
    """An attractor with no period (beta = pi/3, d = 0.235) is split by its largest exponent (chaotic) and
    gets the long run's averages with standard errors, which agree with an independent long run from
    another start within Z_CRIT combined standard errors (a statistic of a chaotic motion, not a pointwise
    value)."""
    from vibroimpact.analysis.design import PointAttractor, _settle_attractor
    from vibroimpact.analysis.energy import LONG_BATCHES, batch_averages
    from vibroimpact.analysis.motions import APERIODIC
    from vibroimpact.analysis.settled import LONG_IMPACTS, long_run
    from vibroimpact.outputs.figcheck import Z_CRIT

    gbar = PH["M"] * 9.8 * math.sin(math.pi / 3) / PH["F"]
    att = PointAttractor(label=APERIODIC, runs=np.arange(1), count=1, share=1.0, low=0.0, high=1.0, U_T=math.nan,
                         U_I=math.nan, u_t_runs=np.zeros(1), u_i_runs=np.zeros(1), impact=(0.42, 0.87), period=0)
    _settle_attractor(att, None, 0, 0.235, gbar, 0.5, PH["F"], DEV)
    assert att.label == "chaotic" and not att.settled
    assert att.U_T_se > 0 and att.U_I_se > 0
    other = long_run(0.235, gbar, 0.5, 0.0, 0.5, impacts=LONG_IMPACTS)
    u_i, se_i, u_t, se_t = batch_averages(other, PH["F"], DEV, batches=LONG_BATCHES)
    assert abs(att.U_T - u_t) < Z_CRIT * math.hypot(att.U_T_se, se_t)
    assert abs(att.U_I - u_i) < Z_CRIT * math.hypot(att.U_I_se, se_i)
    assert abs(att.U_T - u_t) > 1e-9 * u_t  # two different runs: not the same numbers


def test_the_standard_error_of_the_expected_output_adds_the_starts_and_the_runs_spread():
    """E_U_T's standard error over n starts: sqrt(sum share (U_T - E)^2 / n + sum share^2 U_T_se^2), here with a
    settled attractor (share 0.6, U_T 10) and one with no period (share 0.4, U_T 20 +- 2) over 10 starts:
    sqrt(2.4 + 0.64)."""
    ds = _synthetic(np.ones((1, 1)), [0.5], [0.5], np.array([[[0.6, 0.4]]]))
    ds["U_T"][:] = [[[10.0, 20.0]]]
    ds["U_T_se"] = (("beta", "s", "attractor"), [[[math.nan, 2.0]]])
    ds["settled"] = (("beta", "s", "attractor"), [[[True, False]]])
    ds.attrs["starts"] = 10
    ds = summarise(ds.drop_vars(["E_U_T", "worst_U_T"]))
    assert float(ds.E_U_T[0, 0]) == pytest.approx(14.0, rel=1e-15)
    assert float(ds.E_U_T_se[0, 0]) == pytest.approx(math.sqrt(2.4 + 0.64), rel=1e-14)


def test_a_box_reaching_past_the_grid_in_one_parameter_is_not_inside_it():
    """box_minimum's box_in_grid: a tolerance box in beta only (half a cell) lies inside the grid at the middle
    row and reaches past it at the first and the last row."""
    xs, ys = np.arange(5.0), np.arange(3.0)
    h0, h = np.zeros((3, 5)), np.full((3, 5), 0.5)
    _, inside = box_minimum(np.arange(15.0).reshape(3, 5), xs, ys, h0, h)
    assert inside[1].all() and not inside[0].any() and not inside[2].any()


def test_a_tolerance_analysis_with_no_admissible_curve_segment_is_robust_everywhere():
    """Curves in the map's plane without a single admissible segment (one point each): no margin to any curve
    (infinite), every design robust, no nearest curve named."""
    ds = _synthetic(np.arange(6.0).reshape(2, 3), [0.2, 0.3, 0.4], [0.5, 0.6])
    curves = xr.Dataset({"curve_index": ("point", [0, 1]), "s": ("point", [0.25, 0.35]),
                         "beta": ("point", [0.55, 0.55]), "admissible": ("point", [True, True]),
                         "curve_kind": ("curve", ["fold", "grazing"]), "curve_word": ("curve", ["BBT", "BBT"])},
                        attrs={"params": "s beta", "kinds": "fold grazing"})
    out = tolerance_analysis(ds, curves, {"s": 0.01})
    assert np.isinf(out.margin.values).all() and out.robust.values.all()
    assert set(out.nearest_curve.values.ravel()) == {""}
    # and without curves (None), with a box of both widths: the same, with no curve kinds recorded
    out = tolerance_analysis(ds, None, {"s": 0.01, "beta": 0.01})
    assert np.isinf(out.margin.values).all() and out.robust.values.all()
    assert set(out.nearest_curve.values.ravel()) == {""} and out.attrs["curve_kinds"] == ""


def test_a_design_map_s_runs_are_attractor_batch_s_unless_told_otherwise(monkeypatch):
    """design_map documents its transient and period test as attractor_batch's: by default its runs get
    attractor_batch's own defaults (read from its signature), and the values given otherwise."""
    import inspect

    import vibroimpact.analysis.design as D
    from vibroimpact.analysis import windows

    given = []
    batch = D.attractor_batch

    def recording(*args, **kw):
        given.append((kw["max_periods"], kw["tol"]))
        return batch(*args, **kw)

    monkeypatch.setattr(D, "attractor_batch", recording)
    phi, v0 = start_states(8, distribution="box", seed=0)
    defaults = inspect.signature(windows.attractor_batch).parameters
    design_map("s", [0.5], "beta", [math.pi / 6], phi=phi, v0=v0, progress=False)
    assert given and set(given) == {(defaults["max_periods"].default, defaults["tol"].default)}
    given.clear()
    design_map("s", [0.5], "beta", [math.pi / 6], phi=phi, v0=v0, progress=False, max_periods=50, tol=1e-7)
    assert given and set(given) == {(50, 1e-7)}


def test_chunks_without_settled_outputs_merge_into_the_whole_map():
    """Chunks of rows whose attractors carry no 'settled' flag (a map written without long runs, or by hand) merge
    into the map of all their rows, its per-point summary recomputed."""
    xs, ys = np.array([0.3, 0.4, 0.5]), np.array([0.1, 0.2, 0.3])
    E = np.arange(9.0).reshape(3, 3)
    whole = _synthetic(E, xs, ys)
    chunks = [_synthetic(E[rows], xs, ys[rows]).assign_attrs(events=10) for rows in (slice(0, 1), slice(1, 3))]
    assert "settled" not in chunks[0]
    merged = merge_chunks(chunks)
    assert merged.attrs["events"] == 20
    for v in ("E_U_T", "worst_U_T", "n_attractors", "E_U_T_se"):
        np.testing.assert_array_equal(merged[v].values, whole[v].values)
