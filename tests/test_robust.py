"""Robust design under knocks (vibroimpact.analysis.robust): the critical shock of every attractor of a design map
against the single-motion call and the map's own outputs, the Pareto front and the robust choice against their
definitions, the basins a knock crosses against single runs, and the knocks config refused where it makes no
sense."""

import inspect
import math

import numpy as np
import pytest
import xarray as xr

import vibroimpact as vi
from vibroimpact.analysis.robust import mark_choices, pareto_front, point_params, robust_choice, table_choices
from vibroimpact.outputs.tables import knocks_markdown, knocks_table
from vibroimpact.outputs.workflow_config import ConfigError, check_knocks

BETA = math.pi / 6
SHOCK = dict(phases=8, refine=2)


@pytest.fixture(scope="module")
def km():
    """A small knock map at pi/6: the bistable band (s = 0.2245 m: 2:1 and 3:1), beyond G2 (0.23 m: the 2:1
    alone), and at pi/3 a chaotic length (d = 0.235) and the long cylinder (0.6 m: the 1:1 beside a
    stick-release cycle)."""
    phi, v0 = vi.start_states(16, distribution="box", seed=3)
    dm = vi.design_map("s", [0.2245, 0.23, 0.235 / vi.Params.from_physical(s=1.0, beta=math.pi / 3).d, 0.6], "beta",
                       [BETA, math.pi / 3], phi=phi, v0=v0)
    return vi.knock_map(dm, **SHOCK)


def test_each_shock_is_the_single_motion_call_s(km):
    """At every point and attractor with a shock, vi.critical_shock from the recorded bottom impact, at the point's
    parameters built anew, gives the same size, phase and motion reached."""
    dev = vi.Device()
    checked = 0
    for iy, ix, a in zip(*np.nonzero(np.isfinite(km["shock"].values)), strict=True):
        p = dev.params(s=float(km.s[ix]), beta=float(km.beta[iy]))
        sh = vi.critical_shock(p, float(km.impact_phase[iy, ix, a]), float(km.impact_v_minus[iy, ix, a]), **SHOCK)
        assert sh.size_si == km["shock"].values[iy, ix, a] and sh.reached == km["shock_reached"].values[iy, ix, a]
        assert sh.phase == km["shock_phase"].values[iy, ix, a]
        checked += 1
    assert checked >= 3


def test_the_motion_reached_delivers_the_map_s_output_for_it(km):
    """Where a knock drops a motion to another attractor of the same point, the reached motion's output (from the
    knocked run's own cycle) is the design map's output for that attractor (its Newton-solved cycle) to 1e-6."""
    pairs = 0
    for iy, ix, a in zip(*np.nonzero(np.isfinite(km["shock"].values)), strict=True):
        reached = km["shock_reached"].values[iy, ix, a]
        same = np.flatnonzero(km["label"].values[iy, ix] == reached)
        if same.size == 1:
            assert km["shock_reached_U_T"].values[iy, ix, a] == pytest.approx(km["U_T"].values[iy, ix, same[0]], rel=1e-6)
            pairs += 1
    assert pairs >= 2


def test_what_is_known_and_what_is_missing(km):
    """The lone 2:1 beyond G2 cannot be knocked off (inf, with the reason); the chaotic length has no shock, its
    reason says why; the highest-output attractor is the one of largest U_T; every attractor of the map is
    either knocked or has a reason."""
    (iy,) = np.flatnonzero(np.isclose(km.beta.values, BETA))
    assert km["top_label"].values[iy, 1] == "2:1 period-2" and np.isinf(km["top_shock"].values[iy, 1])
    assert "no velocity knock" in km["top_reason"].values[iy, 1]
    chaotic = km["label"].values == "chaotic"
    assert chaotic.any() and all("periodic motions" in r for r in km["shock_reason"].values[chaotic])
    present = km["label"].values != ""
    assert np.all(present <= (np.isfinite(km["shock"].values) | (km["shock_reason"].values != "")))
    u = np.where(km["share"].values >= km.attrs["min_share"], km["U_T"].values, -np.inf)
    assert np.array_equal(km["top"].values, np.argmax(u, axis=-1))
    # the top's label, output, shock and reason are those of that attractor at that point
    pairs = (("top_label", "label"), ("top_U_T", "U_T"), ("top_shock", "shock"), ("top_reason", "shock_reason"))
    for (iy, ix), a in np.ndenumerate(km["top"].values):
        for top, var in pairs:
            mine, its = km[top].values[iy, ix], km[var].values[iy, ix, a]
            assert mine == its or (isinstance(its, float) and math.isnan(its) and math.isnan(mine)), (iy, ix, top)


def test_units_and_descriptions(km):
    for v in ("shock", "shock_size", "shock_phase", "shock_reached_U_T", "top_U_T", "top_shock", "shock_runs"):
        assert km[v].attrs["units"] and km[v].attrs["long_name"]
    assert km["shock"].attrs["units"] == "m/s" == km.attrs["knock_unit"]


@pytest.mark.parametrize("kind, unit, component", [("velocity", "m/s", "velocity Zdot"),
                                                   ("position", "m", "position Z")])
def test_a_point_with_no_output_has_no_top_and_the_shock_names_its_component(km, kind, unit, component):
    """Two points of the map (one length, both inclines), each with a single attractor without a period (no
    shock is computed for it): the first carries an output, the second none (U_T NaN). The first's top is its
    attractor; the second has none (top = -1, no label, output or shock, and the reason). The shock's unit and
    description are those of the knock's kind."""
    dm = km.isel(s=[0]).copy(deep=True)
    assert dm.sizes["beta"] == 2
    dm["label"].values[...] = ""
    dm["label"].values[:, 0, 0] = "unsettled"
    dm["share"].values[...] = 0.0
    dm["share"].values[:, 0, 0] = 1.0
    dm["U_T"].values[...] = np.nan
    dm["U_T"].values[0, 0, 0] = 1000.0
    two = vi.knock_map(dm, kind=kind, **SHOCK)
    assert two["top"].values.tolist() == [[0], [-1]] and two["top_label"].values.tolist() == [["unsettled"], [""]]
    assert two["top_U_T"].values[0, 0] == 1000.0 and np.isnan(two["top_U_T"].values[1, 0])
    assert np.isnan(two["top_shock"].values).all() and np.isnan(two["shock"].values).all()
    assert "periodic motions only" in two["top_reason"].values[0, 0]
    assert two["top_reason"].values[1, 0] == "no attractor with an output"
    assert two["shock"].attrs["units"] == unit == two.attrs["knock_unit"]
    assert f"the ball's {component} that drops" in two["shock"].attrs["long_name"]


def test_the_top_is_among_the_motions_reached_by_at_least_min_share_of_the_starts(km):
    """A point with two motions without a period (no shock computed): the higher output reached by exactly
    ``min_share`` of the starts is the top (at least, as the top's description says); just below it, the other."""
    dm = km.isel(s=[0], beta=[0]).copy(deep=True)
    dm["label"].values[...] = ""
    dm["label"].values[0, 0, :2] = ["unsettled", "chaotic"]
    dm["share"].values[...] = 0.0
    dm["U_T"].values[...] = np.nan
    dm["U_T"].values[0, 0, :2] = [1000.0, 10.0]
    dm.attrs["min_share"] = 0.25
    for share, top in ((0.25, 0), (np.nextafter(0.25, 0.0), 1)):
        dm["share"].values[0, 0, :2] = [share, 1.0 - share]
        assert vi.knock_map(dm, **SHOCK)["top"].values.tolist() == [[top]], share


def test_the_pareto_front_is_what_no_design_beats():
    """On random designs (ties and infinite shocks included): no front point is beaten on both by any design,
    and every design off the front is beaten on both, or equalled, by a front point."""
    rng = np.random.default_rng(5)
    u = rng.integers(0, 8, 60).astype(float)
    s = np.where(rng.random(60) < 0.2, np.inf, rng.integers(0, 8, 60).astype(float))
    s[3] = np.nan
    front = set(pareto_front(u, s).tolist())
    ok = ~np.isnan(s)
    for i in np.flatnonzero(ok):
        beaten = ok & (u >= u[i]) & (s >= s[i]) & ((u > u[i]) | (s > s[i]))
        if i in front:
            assert not beaten.any()
        else:
            assert beaten.any() or any(u[j] == u[i] and s[j] == s[i] for j in front)
    assert 3 not in front


def _synthetic(u, s, labels):
    ny, nx = u.shape
    ds = xr.Dataset({"top_U_T": (("beta", "s"), u), "top_shock": (("beta", "s"), s),
                     "top_label": (("beta", "s"), labels)},
                    coords={"beta": np.arange(ny, dtype=float), "s": np.arange(nx, dtype=float) / 10})
    ds.attrs.update(x="s", y="beta", knock_unit="m/s", knock=1.0)
    return ds


def test_the_robust_choice_is_the_best_that_survives():
    """Against a direct search: the robust design has the largest output among shocks >= knock (inf survives,
    NaN is not a design), the best is the largest output of all; within a row, only that row counts."""
    rng = np.random.default_rng(7)
    u = rng.random((4, 6)) * 50e3
    s = rng.choice([0.1, 0.5, 1.0, 2.0, np.inf, np.nan], size=(4, 6))
    km = _synthetic(u, s, np.full((4, 6), "1:1 period-2"))
    for knock, row in ((1.0, None), (0.5, 2), (3.0, None), (1.0, 1)):
        ch = robust_choice(km, knock, row=row)
        rows = np.arange(4)[:, None] == (row if row is not None else np.arange(4)[:, None])
        known = ~np.isnan(s) & rows
        surv = known & (s >= knock)
        assert ch["survive"] == surv.sum() and ch["designs"] == known.sum()
        assert ch["best"]["U_T"] == u[known].max()
        assert (ch["robust"] is None) == (not surv.any())
        if surv.any():
            assert ch["robust"]["U_T"] == u[surv].max() and ch["robust"]["shock"] >= knock
    with pytest.raises(ValueError, match=r"knock = -1\.0; allowed: a finite size >= 0 \(in m/s\)"):
        robust_choice(km, -1.0)


def test_the_table_says_both_designs(km):
    """The knocks table: over the map and at each incline, the best design and the best that survives the knock;
    the surviving one's shock is at least the knock and its output at most the best's."""
    km = km.assign_attrs(knock=0.01)
    df = knocks_table(table_choices(km, 0.01, [BETA, math.pi / 3, 0.123]), km)
    assert list(df["among"]) == ["whole map", "whole map", BETA, BETA, math.pi / 3, math.pi / 3]
    robust = df[df.design == "survives the knock"]
    assert (robust.shock.fillna(np.inf) >= 0.01).all()
    for at in ("whole map", BETA):
        best, surv = df[(df["among"] == at) & (df.design == "best output")], df[(df["among"] == at) & (df.design != "best output")]
        assert float(surv.U_T.iloc[0]) <= float(best.U_T.iloc[0])
    md = knocks_markdown(df, km)
    assert "The knock: 0.01 m/s" in md and "| beta = π/6" in md and "∞" in md and "runs per motion" in md
    # the cost line: the job's seconds and its threads, one or more
    assert "took 12 s on 1 thread." in knocks_markdown(df, km.assign_attrs(workers=1), seconds=12.4)
    assert "took 7 s on 2 threads." in knocks_markdown(df, km.assign_attrs(workers=2), seconds=7.2)


def test_the_section_is_what_single_runs_reach(km):
    """At the long cylinder's 1:1 motion: the state the knock hits returns to it, the knocked state reaches the
    motion the shock names (vi.simulate from it); cells of the section reach the motions single runs do."""
    (iy,) = np.flatnonzero(np.isclose(km.beta.values, math.pi / 3))
    ix = int(np.flatnonzero(np.isclose(km.s.values, 0.6))[0])
    a = int(km["top"].values[iy, ix])
    p = point_params(km, iy, ix, vi.Device())
    phi, v0 = float(km.impact_phase[iy, ix, a]), float(km.impact_v_minus[iy, ix, a])
    sh = vi.critical_shock(p, phi, v0, **SHOCK)
    zs, vs = np.linspace(-p.d / 2, p.d / 2, 7), np.linspace(-1.0, 1.0, 5)
    sec = vi.knock_section(p, sh, phi, zs, vs)
    t0 = sec.attrs["t0"]

    def reached(z, v):
        return vi.identify_attractor(vi.simulate(p, phi, v, Z0=z, t0=t0, n_impacts=20_000)).label

    assert reached(sec.attrs["Z_knocked"], sec.attrs["Zdot_knocked"]) == sh.reached == sec.attrs["reached"]
    assert reached(sec.attrs["Z_state"], sec.attrs["Zdot_state"]) == sh.motion
    for j, k in ((0, 0), (2, 3), (4, 6), (1, 5)):
        assert sec.label.values[j, k] == reached(zs[k], vs[j])
    assert sec.attrs["phase"] == pytest.approx(sh.phase, abs=1e-12)
    # its runs are capped where the critical shock's knocked runs are, so that a state reaches what a knock to it does
    assert sec.attrs["max_periods"] == inspect.signature(vi.critical_shock).parameters["max_periods"].default
    with pytest.raises(ValueError, match=r"zs = .*allowed: \|Z\| <= d/2 = (\S+)$") as refused:
        vi.knock_section(p, sh, phi, [0.0, p.d], vs)
    assert float(refused.value.args[0].rsplit("= ", 1)[1]) == p.d / 2  # the bound it states is the wall's


def test_a_section_without_a_knock_is_at_the_start_s_phase_and_says_why():
    """Without a shock (None) or with one no admissible knock reaches (inf), the section is at the start's
    phase (t0 = 0), says why, and its cells reach what single runs from those states at t = 0 reach."""
    p = vi.Params(d=0.13975, gbar=0.12201)
    phi, v0 = 1.645, 0.05067
    zs, vs = np.array([-0.03, 0.03]), np.array([-0.4, 0.4])
    none = vi.knock_section(p, None, phi, zs, vs)
    reason = "no periodic motion to knock"
    assert (none.attrs["t0"], none.attrs["phase"], none.attrs["reason"]) == (0.0, phi, reason)
    assert "Z_knocked" not in none.attrs
    inf = vi.critical_shock(p, phi, v0, max_size=1e-5, phases=2, refine=0)
    assert inf.size == math.inf
    sec = vi.knock_section(p, inf, phi, zs, vs)
    assert (sec.attrs["t0"], sec.attrs["phase"], sec.attrs["reason"]) == (0.0, phi, inf.reason)
    assert math.isnan(sec.attrs["Z_knocked"]) and math.isnan(sec.attrs["Zdot_knocked"])
    assert np.array_equal(sec.label.values, none.label.values)
    for j, k in ((0, 0), (1, 1)):
        run = vi.simulate(p, phi, vs[j], Z0=zs[k], t0=0.0, n_impacts=20_000)
        assert sec.label.values[j, k] == vi.identify_attractor(run).label


@pytest.mark.parametrize("change, key", [
    (dict(map="nowhere"), "knocks.map = 'nowhere'"), (dict(kind="speed"), "knocks.kind = 'speed'"),
    (dict(knock=math.inf), "knocks.knock = inf"), (dict(section={"s": -0.5, "beta": 1.0}), "knocks.section"),
])
def test_a_knocks_config_that_makes_no_sense_is_refused(change, key):
    knocks = dict(map="s_beta", kind="velocity", knock=2.0, section={"s": 0.6, "beta": 1.0}) | change
    maps = {"s_beta": {"x": "s", "y": "beta"}, "d_gbar": {"x": "d", "y": "gbar"}}
    with pytest.raises(ConfigError, match="allowed") as err:
        check_knocks(knocks, maps, vi.Device())
    assert key in str(err.value)
    with pytest.raises(ConfigError, match="physical axes"):
        check_knocks(dict(knocks, map="d_gbar") if "map" not in change else knocks | {"map": "d_gbar"}, maps,
                     vi.Device())


def test_the_points_shared_among_threads_give_the_same_map(km):
    """workers=2 (two threads of one numba thread each: the serial kernel) gives every shock, reason and run count
    of one thread (its kernels in parallel), to the last bit: each knocked run is independent of the others."""
    two = vi.knock_map(km, workers=2, **SHOCK)
    for v in ("shock", "shock_size", "shock_phase", "shock_reached_U_T", "shock_runs", "shock_direction"):
        assert np.array_equal(two[v].values, km[v].values, equal_nan=True), v
    assert (two["shock_reason"].values == km["shock_reason"].values).all()
    with pytest.raises(ValueError, match=r"workers = 0; allowed: an integer >= 1"):
        vi.knock_map(km, workers=0)


def test_the_marked_designs_are_the_front_and_the_choice(km):
    """mark_choices flags what the figure draws: the Pareto front's points and the two designs robust_choice picks."""
    marked = mark_choices(km, 0.01)
    assert set(np.flatnonzero(marked["pareto"].values.ravel())) == set(
        pareto_front(km["top_U_T"].values, km["top_shock"].values).tolist())
    ch = robust_choice(km, 0.01)
    for flag in ("best", "robust"):
        (iy,), (ix,) = np.nonzero(marked[flag].values)
        assert (float(km.s[ix]), float(km.beta[iy])) == (ch[flag]["s"], ch[flag]["beta"])
    assert marked.attrs["knock"] == 0.01 and marked.attrs["shock_fine_span"] > 1
