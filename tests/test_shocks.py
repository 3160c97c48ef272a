"""The critical shock of a motion (vibroimpact.analysis.shocks): against an independent brute force as
Attractors.jl's MCSBruteForce defines it, the square-root law at a fold, the bracket it states, and its
errors."""

import math

import numpy as np
import pytest
from conftest import gbar_of

import vibroimpact as vi
from vibroimpact.analysis import shocks
from vibroimpact.analysis.shocks import critical_shock
from vibroimpact.analysis.windows import empty_windows
from vibroimpact.dynamics import kernels as K

BETA = math.pi / 6
GBAR = 0.12201  # the paper's incline pi/6 at 5 N
#: between G1 and G2 at pi/6: the 2:1 and the 3:1 coexist; a bottom impact of each (docs/guide/orbits.md)
BISTABLE = 0.13975
STARTS = {"2:1 period-2": (5.855, 0.4185), "3:1 period-2": (1.645, 0.05067)}
#: a long cylinder (s = 0.6 m) at pi/3: the 1:1 motion and a stick-release cycle on the bottom coexist; a start
#: at rest on the bottom reaching each
LONG = vi.Params.from_physical(s=0.6, beta=math.pi / 3)
ONE_ONE, STICKING = "1:1 period-2", "1:0 over 2 forcing periods with sticking"
LONG_STARTS = {ONE_ONE: (2 * math.pi / 3, 0.0), STICKING: (0.0, 0.0)}


def brute_force(params, phi, v0, kind, *, n_box, n_sphere, seed=0):
    """The minimal critical shock by random search, as Attractors.jl's ``MCSBruteForce``: ``n_box`` knocks
    uniform over the admissible box (knock time over one cycle, jump of ``Zdot`` in ``[-2 v_max, 2 v_max]``,
    ``v_max`` the cycle's largest impact speed, or new ``Z`` in ``(-d/2, d/2)``), then ``n_sphere`` knocks at random times of sizes
    uniform below the best so far (the shrinking sphere).  A knock leaves when the run after it (the public
    :func:`vibroimpact.simulate` and :func:`vibroimpact.identify_attractor`) settles on another motion.
    Returns the smallest leaving size and the runs used."""
    rng = np.random.default_rng(seed)
    ref = vi.simulate(params, phi, v0, n_impacts=4000)
    att = vi.identify_attractor(ref)
    t0, span = float(att.cycle.t[0]), 2.0 * att.period
    half = params.d / 2
    max_velocity = 2 * float(np.nanmax(np.abs(att.cycle.v_minus.values)))
    runs = 0

    def leaves(t, size):
        nonlocal runs
        tr = vi.trajectory(ref, [t])
        z, v = float(tr.Z[0]), float(tr.Zdot[0])
        if kind == "position":
            z += size
            if abs(z) >= half:
                return False
        else:
            v += size
        runs += 1
        after = vi.identify_attractor(vi.simulate(params, phi, v, Z0=z, t0=t, n_impacts=4000))
        return after.label != att.label

    best = math.inf
    for _ in range(n_box):
        t = t0 + span * rng.random()
        if kind == "position":
            size = rng.uniform(-half, half) - float(vi.trajectory(ref, [t]).Z[0])
        else:
            size = rng.uniform(-max_velocity, max_velocity)
        if abs(size) < best and leaves(t, size):
            best = abs(size)
    for _ in range(n_sphere):
        t, size = t0 + span * rng.random(), rng.choice((-1, 1)) * best * rng.random()
        if math.isfinite(best) and leaves(t, size):
            best = abs(size)
    return best, runs


CASES = [(vi.Params(d=BISTABLE, gbar=GBAR), m, STARTS) for m in sorted(STARTS)] + [
    (LONG, m, LONG_STARTS) for m in sorted(LONG_STARTS)]


@pytest.mark.parametrize("kind", ["velocity", "position"])
@pytest.mark.parametrize("p, motion, starts", CASES, ids=[f"d={c[0].d:.5g} {c[1]}" for c in CASES])
def test_never_larger_than_the_brute_force(p, motion, starts, kind):
    """In the 2:1/3:1 bistable band and on the long cylinder at pi/3, for each motion and each kind of knock,
    the shock is never larger than the brute force's (a knock the brute force saw leave) by more than the
    bracket's tolerance, and it reaches the other motion.  The runs each used are printed (``-s``): the brute
    force here is cut to 800 samples, Attractors.jl's default is 20 000."""
    phi, v0 = starts[motion]
    sh = critical_shock(p, phi, v0, kind=kind)
    assert sh.motion == motion and sh.reached != motion and sh.reached in starts
    bf, runs = brute_force(p, phi, v0, kind, n_box=400, n_sphere=400)
    print(f"{motion} {kind}: shock {sh.size:.6g} in {sh.simulations} runs; brute force {bf:.6g} in {runs} runs")
    assert sh.size <= bf * (1 + 1e-3) + sh.tolerance
    assert sh.simulations <= 2000  # ten times fewer than MCSBruteForce's default 20 000


@pytest.mark.parametrize("kind", ["velocity", "position"])
def test_the_stated_bracket_holds(kind):
    """The knock returned leaves, and the knock ``tolerance`` smaller at the same time and direction returns
    to the motion (both checked with the public simulator); the bracket is as narrow as asked."""
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    phi, v0 = STARTS["3:1 period-2"]
    sh = critical_shock(p, phi, v0, kind=kind, phases=8, refine=4, rtol=1e-3)
    assert 0 < sh.tolerance <= 1e-3 * sh.size
    t = (sh.phase - phi) % (2 * math.pi) / math.pi  # a time with that phase; the motion repeats each period
    t += 2.0 * math.ceil((40.0 - t) / 2.0)
    z, v = sh.state

    def label(size):
        zz, vv = (z + sh.direction * size, v) if kind == "position" else (z, v + sh.direction * size)
        return vi.identify_attractor(vi.simulate(p, phi, vv, Z0=zz, t0=t, n_impacts=4000)).label

    state = vi.trajectory(vi.simulate(p, phi, v0, n_impacts=4000), [t])
    assert (float(state.Z[0]), float(state.Zdot[0])) == pytest.approx(sh.state, abs=1e-7)
    assert label(sh.size) == sh.reached == "2:1 period-2"
    assert label(sh.size - 1.01 * sh.tolerance) == sh.motion == "3:1 period-2"
    assert sh.size_si == pytest.approx(sh.size * (p.scales or vi.Device().scales()).__dict__[
        "velocity" if kind == "velocity" else "length"])


def test_what_a_knock_does_to_the_long_cylinder():
    """The numbers the energy guide gives: at s = 0.6 m, beta = pi/3, the 1:1 motion (52.1 kV) is dropped to
    the stick-release cycle (4.9 kV) by a velocity knock of 1.31 m/s towards the bottom membrane just after it
    leaves it, or a jump of 131 mm; the stick-release cycle is lifted to the 1:1 by a knock of 0.084 m/s off
    the bottom membrane where it rests, or 2.2 mm."""
    one = critical_shock(LONG, *LONG_STARTS[ONE_ONE])
    assert (one.reached, round(one.U_T / 1e3, 1), round(one.reached_U_T / 1e3, 1)) == (STICKING, 52.1, 4.9)
    assert (round(one.size_si, 2), one.direction, round(one.delay, 2)) == (1.31, 1, 0.80)
    assert round(critical_shock(LONG, *LONG_STARTS[ONE_ONE], kind="position").size_si * 1e3) == 131
    up = critical_shock(LONG, *LONG_STARTS[STICKING])
    assert (up.reached, round(up.size_si, 3), up.direction) == (ONE_ONE, 0.084, -1)
    assert up.state[0] == pytest.approx(LONG.d / 2, abs=1e-6) and abs(up.state[1]) < 1e-4  # on the membrane
    assert round(critical_shock(LONG, *LONG_STARTS[STICKING], kind="position").size_si * 1e3, 1) == 2.2


@pytest.fixture(scope="module")
def fold():
    """The 3:1 orbit's fold G2 at pi/6, located by continuation."""
    p = vi.Params.from_physical(s=0.14 / vi.Params.from_physical(s=1.0, beta=BETA).d, beta=BETA)
    br = vi.continue_orbit(vi.find_orbit(p, "BBBT", 5.88, 0.3967), vary="s", d_range=(0.1395, 0.1425), step=5e-4)
    (g2,) = br.critical_d.values[br.critical_kind.values == "fold"]
    return float(g2), p.gbar


@pytest.mark.parametrize("kind", ["velocity", "position"])
def test_shock_shrinks_like_the_square_root_near_the_fold(fold, kind):
    """Approaching G2 the 3:1 motion's node meets its saddle: the knock that leaves it shrinks like
    sqrt(G2 - d), a log-log slope of 1/2 within three standard errors of the fit (with the law's first
    correction, a term in sqrt(G2 - d)), or the slope error the bisection's relative tolerance allows if
    larger."""
    g2, gbar = fold
    offsets = np.array([3.2e-4, 1.6e-4, 8e-5, 4e-5, 2e-5, 1e-5])
    sizes = []
    for off in offsets:
        q = vi.Params(d=g2 - off, gbar=gbar)
        o = vi.find_orbit(q, "BBBT", 5.88, 0.3967)
        sh = critical_shock(q, o.phi, float(o.v_minus[0]), kind=kind, max_periods=5000)
        assert sh.motion == "3:1 period-2" and sh.reached == "2:1 period-2"
        sizes.append(sh.size)
    # the square root and its first correction: log size = a log(G2 - d) + b + c sqrt(G2 - d)
    x = np.column_stack([np.log(offsets), np.ones_like(offsets), np.sqrt(offsets)])
    y = np.log(sizes)
    coef, res, *_ = np.linalg.lstsq(x, y, rcond=None)
    cov = np.linalg.inv(x.T @ x) * float(res[0]) / (len(y) - x.shape[1])
    slope, se = coef[0], math.sqrt(cov[0, 0])
    allowed = max(3 * se, 2 * 1e-3 / math.log(offsets.max() / offsets.min()))
    print(f"{kind}: slope {slope:.5f} +- {se:.5f}")
    assert abs(slope - 0.5) <= allowed


def test_no_admissible_knock_leaves_a_lone_motion():
    """Where the motion is the only attractor reachable within the knocks allowed, the shock is inf with the
    reason."""
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    sh = critical_shock(p, *STARTS["3:1 period-2"], max_size=1e-5, phases=4, refine=0)
    assert sh.size == math.inf and "no velocity knock" in sh.reason and sh.direction == 0
    assert sh.simulations > 8


@pytest.mark.parametrize("kind", ["velocity", "position"])
def test_a_shock_just_below_the_largest_admissible_knock_is_found(kind):
    """With ``max_size`` a tenth of a per cent above the critical shock, the leaving knocks lie in the scan's
    last step: the shock is still found (every ray is knocked at the largest admissible size), the same one,
    at the same time and in the same direction."""
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    free = critical_shock(p, *STARTS["3:1 period-2"], kind=kind, phases=2, refine=0)
    capped = critical_shock(p, *STARTS["3:1 period-2"], kind=kind, phases=2, refine=0, max_size=1.001 * free.size)
    assert capped.size <= 1.001 * free.size and capped.size == pytest.approx(free.size, rel=2e-3)
    assert (capped.delay, capped.direction, capped.reached) == (free.delay, free.direction, free.reached)


def test_a_knocked_run_that_does_not_repeat_in_time_has_left_without_an_output():
    """From the 3:1 orbit's own bottom impact (Newton-solved: the reference run repeats at once) with a cap of
    20 forcing periods, the knock that leaves is the uncapped call's (to the 2:1), but the run after it has no
    period yet: it reaches "no period found", with no output (NaN), beside the 3:1 motion's own."""
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    o = vi.find_orbit(p, "BBBT", 5.88, 0.3967)
    free = critical_shock(p, o.phi, float(o.v_minus[0]), phases=2, refine=0)
    capped = critical_shock(p, o.phi, float(o.v_minus[0]), phases=2, refine=0, max_periods=20)
    assert free.reached == "2:1 period-2" and capped.size == pytest.approx(free.size, rel=1e-9)
    assert capped.reached == "no period found" and math.isnan(capped.reached_U_T)
    assert capped.U_T == free.U_T and math.isfinite(capped.U_T)


def test_two_cycles_are_one_only_event_by_event():
    """A cycle is the same as itself, as itself with every phase a turn on or moved by half the tolerance, and
    as its events in another order; not with one event's phase or pre-impact velocity moved by twice the
    tolerance, nor with one event on the other wall, whatever the motion's label and events count say."""
    p, tol = vi.Params(d=BISTABLE, gbar=GBAR), 1e-6
    ref = vi.simulate(p, *STARTS["3:1 period-2"], stop_when_periodic=True, t_end=400.0)
    cyc = shocks._cycle(ref)
    assert cyc["t"].size == 4

    def moved(key, j, by):
        values = cyc[key].copy()
        values[j] = values[j] + by
        return cyc | {key: values}

    order = np.arange(4)[::-1]
    assert shocks._same(cyc, cyc, tol) and shocks._same(cyc | {"phase": cyc["phase"] + 2 * math.pi}, cyc, tol)
    assert shocks._same(cyc, {k: cyc[k][order] if k in ("t", "wall", "v_minus", "phase", "kind") else v
                              for k, v in cyc.items()}, tol)
    for j in range(4):
        assert shocks._same(moved("phase", j, tol / 2), cyc, tol) and shocks._same(moved("v_minus", j, -tol / 2), cyc, tol)
        for other in (moved("phase", j, 2 * tol), moved("v_minus", j, 2 * tol), moved("wall", j, -2 * cyc["wall"][j])):
            assert not shocks._same(other, cyc, tol) and not shocks._same(cyc, other, tol), j



def _per_run(knocks, win, ends):
    """The per-run reference of _Knocks.outcomes: each run's cycle (_window_cycle, cycle_class anew) and _same."""
    cycles = [shocks._window_cycle(win, k, int(ends.n[k]), int(ends.status[k]), int(ends.lag[k]))
              for k in range(ends.n.size)]
    left = np.array([c is None or not shocks._same(c, knocks.cycle, knocks.match_tol) for c in cycles])
    return left, [c for c, out in zip(cycles, left, strict=True) if out]


def _assert_outcomes_are_per_run(knocks, win, ends):
    left, reached = knocks.outcomes(win, ends)
    ref_left, ref_reached = _per_run(knocks, win, ends)
    assert np.array_equal(left, ref_left)
    assert len(reached) == len(ref_reached)
    for a, b in zip(reached, ref_reached, strict=True):
        assert (a is None) == (b is None)
        if a is not None:
            assert a["motion"] == b["motion"] and a["span"] == b["span"]
            for v in ("t", "wall", "v_minus", "phase", "kind"):
                assert np.array_equal(a[v], b[v], equal_nan=True), v
    return left, reached


@pytest.mark.parametrize("max_periods, reached", [(200, "2:1 period-2"), (20, None)])
def test_a_batch_of_knocked_runs_leaves_where_each_run_tested_alone_leaves(max_periods, reached):
    """_Knocks.outcomes (the compiled test of all runs' events at once, the motion looked up) against each run's
    cycle built and compared alone (_window_cycle, cycle_class, _same): the same runs leave, to the last bit, with
    the same cycles reached, over knocks of the 3:1 motion of sizes up to half the largest admissible one at
    times over its cycle (some return; some reach the 2:1, or no period within 20 forcing periods)."""
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    phi, v0 = STARTS["3:1 period-2"]
    ref = vi.simulate(p, phi, v0, stop_when_periodic=True, t_end=400.0)
    cycle = shocks._cycle(ref)
    knocks = shocks._Knocks(p, phi, max_periods, 1e-6, cycle)
    times = shocks._knock_times(cycle, 8)
    rays = shocks._rays(ref, times, "velocity", 2.0, p.d / 2, np.zeros(times.size, int))
    sizes = np.geomspace(1e-4, 1.0, 12)
    idx = np.repeat(np.arange(rays.t.size), sizes.size)
    z, v = rays.knocked(idx, np.tile(sizes, rays.t.size))
    left, cycles = _assert_outcomes_are_per_run(knocks, *knocks.runs(rays.t[idx], z, v))
    assert 10 < left.sum() < left.size - 10
    assert {None if c is None else c["motion"].label for c in cycles} == {reached}


def _windows(cycles, spans, ends):
    """A batch of windows whose runs end on ``cycles`` (dicts of events; each preceded by one event ``span``
    earlier than its last) with ``ends``: (status, lag) per run."""
    m, w = len(cycles), max(c["t"].size for c in cycles) + 2
    win = empty_windows(m, w)
    n = np.zeros(m, np.int64)
    for k, (c, span) in enumerate(zip(cycles, spans, strict=True)):
        n[k] = c["t"].size + 1
        win.t[k, 0] = c["t"][-1] - span
        for name, values in zip(("t", "wall", "v_minus", "phase", "kind"), (c[x] for x in
                                ("t", "wall", "v_minus", "phase", "kind")), strict=True):
            getattr(win, name)[k, 1:n[k]] = values
    status, lag = (np.array(x) for x in zip(*ends, strict=True))
    return win, K.WindowEnds(status.astype(np.int8), lag.astype(np.int64), n.copy(), n)


def test_the_batch_test_of_cycles_is_the_per_run_test_event_by_event():
    """The runs' cycles of test_two_cycles_are_one_only_event_by_event and more, in one batch: the same cycle, a
    turn on, reordered, moved by half the tolerance (back), by twice it, with an event on the other wall or of
    another kind, one event short, one more (a release: the same motion), over twice the span (another motion
    from the same events), without a period, with a NaN pre-impact velocity where the motion has one and where
    it has none: _Knocks.outcomes decides each as the per-run test does, and as stated."""
    p, tol = vi.Params(d=BISTABLE, gbar=GBAR), 1e-6
    cyc = shocks._cycle(vi.simulate(p, *STARTS["3:1 period-2"], stop_when_periodic=True, t_end=400.0))
    span, lag = cyc["span"], cyc["t"].size

    def moved(key, j, by, c=cyc):
        values = c[key].copy()
        values[j] = values[j] + by
        return c | {key: values}

    grazing = cyc["kind"].copy()
    grazing[1] = K.GRAZING
    nan_vm = moved("v_minus", 2, math.nan)
    cases = [  # (cycle, span, status, lag, leaves)
        (cyc, span, K.PERIODIC, lag, False),
        (cyc | {"phase": cyc["phase"] + 2 * math.pi}, span, K.PERIODIC, lag, False),
        ({k: cyc[k][::-1] if k in K.Window._fields else v for k, v in cyc.items()}, span, K.PERIODIC, lag,
         False),
        (moved("phase", 0, tol / 2), span, K.PERIODIC, lag, False),
        (moved("v_minus", 3, -tol / 2), span, K.PERIODIC, lag, False),
        (moved("phase", 1, 2 * tol), span, K.PERIODIC, lag, True),
        (moved("v_minus", 2, 2 * tol), span, K.PERIODIC, lag, True),
        (moved("wall", 0, -2 * cyc["wall"][0]), span, K.PERIODIC, lag, True),
        (cyc | {"kind": grazing}, span, K.PERIODIC, lag, True),
        ({k: cyc[k][1:] if k in K.Window._fields else v for k, v in cyc.items()}, span, K.PERIODIC, lag - 1,
         True),
        ({k: np.append(cyc[k], x) for k, x in zip(K.Window._fields, (cyc["t"][-1], 1, 0.0, cyc["phase"][-1],
                                                                      K.RELEASE), strict=True)}, span, K.PERIODIC,
         lag + 1, True),
        (cyc, 2 * span, K.PERIODIC, lag, True),
        (cyc, span, K.T_END, lag, True),
        (cyc, span, K.PERIODIC, 0, True),
        (nan_vm, span, K.PERIODIC, lag, True),
    ]
    knocks = shocks._Knocks(p, 1.645, 200, tol, cyc)
    win, ends = _windows([c[0] for c in cases], [c[1] for c in cases], [c[2:4] for c in cases])
    assert _assert_outcomes_are_per_run(knocks, win, ends)[0].tolist() == [c[4] for c in cases]
    knocks = shocks._Knocks(p, 1.645, 200, tol, nan_vm)  # a motion with a NaN pre-impact velocity
    win, ends = _windows([nan_vm, cyc], [span, span], [(K.PERIODIC, lag)] * 2)
    assert _assert_outcomes_are_per_run(knocks, win, ends)[0].tolist() == [False, True]

#: beta = pi/3, d = 0.235: the chaotic window between the 1:1 and the 2:1 (tests/test_attractor.py)
CHAOTIC = vi.Params(d=0.235, gbar=gbar_of(math.pi / 3), r=0.5)


@pytest.mark.parametrize("case", ["3:1 knocked", "chaotic, capped"])
def test_each_knocked_run_is_attractor_batch_s_run_from_its_state_in_flight(case):
    """The knocked runs are vi.attractor_batch's from the same states in flight, with its defaults (a period of at most
    64 events, a window of 65, at most 200 000 events; docs/guide/robustness.md), to the last bit: windows, statuses,
    periods and events simulated; over knocks of the 3:1 motion (some return, some reach the 2:1), and over runs in
    the chaotic window at pi/3 given a million forcing periods, which the cap on events cuts."""
    if case == "3:1 knocked":
        p, max_periods = vi.Params(d=BISTABLE, gbar=GBAR), 200
        phi, v0 = STARTS["3:1 period-2"]
        ref = vi.simulate(p, phi, v0, stop_when_periodic=True, t_end=400.0)
        cycle = shocks._cycle(ref)
        times = shocks._knock_times(cycle, 8)
        rays = shocks._rays(ref, times, "velocity", 2.0, p.d / 2, np.zeros(times.size, int))
        sizes = np.geomspace(1e-3, 1.0, 6)
        idx = np.repeat(np.arange(rays.t.size), sizes.size)
        t0, (z, v) = rays.t[idx], rays.knocked(idx, np.tile(sizes, rays.t.size))
    else:  # no motion to return to: the runs alone (runs() does not read the motion's cycle)
        p, max_periods, phi = CHAOTIC, 1e6, 0.4
        cycle = dict.fromkeys(K.Window._fields, np.zeros(0))
        t0, z, v = np.array([0.3, 1.1]), np.array([0.0, 0.05]), np.array([0.6, -0.3])
    win, ends = shocks._Knocks(p, phi, max_periods, 1e-6, cycle).runs(t0, z, v)
    ab = vi.attractor_batch(p.d, p.gbar, p.r, phi, v, t0=t0, Z0=z, max_periods=max_periods)
    for name in K.Window._fields:
        assert np.array_equal(getattr(win, name), ab[name].values, equal_nan=True), name
    assert np.array_equal(ends.status, ab.status.values) and np.array_equal(ends.total, ab.n_events.values)
    assert np.array_equal(np.where(ends.status == K.PERIODIC, ends.lag, 0), ab.period_events.values)
    if case == "3:1 knocked":
        assert {"3:1 period-2", "2:1 period-2"} <= set(ab.label.values.tolist())
    else:
        assert ab.n_events.values.tolist() == [200_000] * 2 and ab.period.values.tolist() == [0, 0]


@pytest.mark.parametrize("top, ratio", [(1.0, 1.1), (0.37, 1.5), (2.5e-3, 3.0)])
def test_the_scan_doubles_from_a_ten_thousandth_of_the_largest_knock_then_steps_by_the_ratio(top, ratio):
    """The scan's sizes as robustness.md states them: doubling from 1e-4 of the largest admissible knock (the first
    of them within a factor 2 above it), then by ``scan_ratio`` from a quarter of it up to it, ending on it."""
    sizes = np.array(shocks._scan_sizes(top, ratio))
    assert 1e-4 * top <= sizes[0] < 2e-4 * top and sizes[-1] == top
    coarse, fine = sizes[sizes < top / 4], sizes[sizes >= top / 4]
    assert np.allclose(coarse[1:] / coarse[:-1], 2.0, rtol=1e-12, atol=0)
    assert 2 * coarse[-1] == pytest.approx(top / 4, rel=1e-12) and fine[0] == pytest.approx(top / 4, rel=1e-12)
    steps = fine[1:] / fine[:-1]
    assert np.allclose(steps[:-1], ratio, rtol=1e-12, atol=0) and 1 < steps[-1] <= ratio * (1 + 1e-12)


def test_the_local_minima_are_read_around_the_circle():
    """The smallest local minima of the grid (no larger than either neighbour, the first and the last neighbours;
    infinite values never), smallest first and ties in order: against a loop over random grids with ties and
    infinities, and one by hand."""
    rng = np.random.default_rng(3)
    for _ in range(300):
        n = int(rng.integers(2, 12))
        v = rng.integers(0, 5, n).astype(float)
        v[rng.random(n) < 0.2] = math.inf
        minima = [i for i in range(n) if math.isfinite(v[i]) and v[i] <= v[i - 1] and v[i] <= v[(i + 1) % n]]
        assert shocks._local_minima(v, 3) == sorted(minima, key=lambda i: v[i])[:3], v
    assert shocks._local_minima([3.0, 1.0, 2.0, 0.0, 5.0], 3) == [3, 1]
    assert shocks._local_minima([0.5, 2.0, math.inf, 1.0, 4.0, 0.2], 2) == [5, 3]


def test_the_refinement_scans_from_an_eighth_to_twice_the_best_knock_so_far(monkeypatch):
    """Each golden-section step scans its new times from an eighth of the smallest knock found so far, then a
    quarter, then by ``scan_ratio`` from half of it up to twice it: the scans the refinement asks for, recorded,
    against the best that each step leaves; the shock is the smallest of them."""
    calls = []
    scan = shocks._scan

    def record(knocks, rays, idx, levels):
        calls.append(np.asarray(levels, dtype=float))
        return scan(knocks, rays, idx, levels)

    monkeypatch.setattr(shocks, "_scan", record)
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    sh = critical_shock(p, *STARTS["3:1 period-2"], phases=4, refine=3, scan_ratio=1.1)
    assert len(calls) == 1 + 1 + 3  # the grid, the first two golden-section points, one per step
    bests = []
    for levels in calls[1:]:
        best = levels[-1] / 2
        steps = 0.5 * best * 1.1 ** np.arange(int(math.log(4.0, 1.1)) + 1)
        assert np.array_equal(levels, [best / 8, best / 4, *steps, 2 * best])
        bests.append(best)
    assert all(a >= b for a, b in zip(bests, bests[1:], strict=False)) and sh.size <= bests[-1]


@pytest.mark.parametrize("kwargs, named", [
    (dict(kind="speed"), "kind = 'speed'"), (dict(phases=1), "phases = 1"), (dict(phases=2.5), "phases = 2.5"),
    (dict(rtol=0.0), "rtol = 0.0"), (dict(rtol=0.7), "rtol = 0.7"), (dict(max_size=-1.0), "max_size = -1.0"),
    (dict(max_size=0.0), "max_size = 0.0"),
    (dict(max_size=math.inf), "max_size = inf"), (dict(refine=-1), "refine = -1"),
])
def test_bad_input_is_named(kwargs, named):
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    with pytest.raises(ValueError, match="allowed") as err:
        critical_shock(p, *STARTS["3:1 period-2"], **kwargs)
    assert named in str(err.value)


def test_params_must_be_params():
    with pytest.raises(ValueError, match=r"params = \(0\.14, 0\.12\); allowed: a vibroimpact\.Params"):
        critical_shock((0.14, 0.12), 1.645, 0.05067)


def test_a_start_without_a_period_is_refused():
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    with pytest.raises(ValueError, match=r"\(phi, v0\) = \(1\.645, 0\.05067\); allowed: a start whose run repeats"):
        critical_shock(p, 1.645, 0.05067, max_periods=1)


def test_the_knock_time_is_refined_around_the_three_smallest_local_minima(monkeypatch):
    """The refinement's golden-section searches start around the three smallest local minima of the grid of knock
    times (the robustness page's and LOCAL_MINIMA's number): the count the search asks for, recorded."""
    asked = []
    minima = shocks._local_minima

    def record(values, n):
        asked.append(n)
        return minima(values, n)

    monkeypatch.setattr(shocks, "_local_minima", record)
    p = vi.Params(d=BISTABLE, gbar=GBAR)
    critical_shock(p, *STARTS["2:1 period-2"], phases=8, refine=1)
    assert asked == [3]
