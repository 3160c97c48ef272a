"""The event loop's building blocks against closed forms, and its sliding window against a plain run."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from conftest import TOL_T

import vibroimpact as vi
from vibroimpact.dynamics import kernels as K


def test_period_one_bouncing_orbit_is_the_closed_form():
    """Far from the top wall the ball bounces on the bottom once per forcing period.  Over one
    period the forcing averages out, so Zdot- = Zdot+ + 2 gbar with Zdot+ = -r Zdot-, hence
    Zdot- = 2 gbar / (1 + r); the flight returns to the wall when sin(phase) = pi gbar (1-r)/(1+r)
    (the displacement over the period, 2 Zdot+ + 2 gbar - 2 sin(phase) / pi, vanishes)."""
    gbar, r = 0.7, 0.5
    p = vi.Params(d=3.0, gbar=gbar, r=r)
    vm, phase = 2 * gbar / (1 + r), math.asin(math.pi * gbar * (1 - r) / (1 + r))
    ds = vi.simulate(p, phase + 1e-3, vm * 1.001, n_impacts=5000, stop_when_periodic=True)
    assert ds.attrs["status"] == "periodic" and ds.attrs["period_events"] == 1
    assert ds["wall"].values[-1] == 1 and ds["kind"].values[-1] == K.IMPACT
    assert abs(ds["v_minus"].values[-1] - vm) < 1e-8
    # of the two phases with that sine, the orbit that attracts meets the wall while the forcing
    # decelerates it (cos < 0)
    assert abs(ds["phase"].values[-1] - (math.pi - phase)) < 1e-8
    assert abs(ds["t"].values[-1] - ds["t"].values[-2] - 2.0) < 1e-8


def test_period_test_separates_motions_that_share_their_phases():
    """Events two forcing periods apart, all at one phase, with Zdot- alternating: the motion
    repeats after two events, not one (the velocities differ at lag one)."""
    n, tol = 12, 1e-9
    t = 2.0 * np.arange(n)
    wall = np.ones(n, np.int8)
    kind = np.zeros(n, np.int8)
    phase = np.full(n, 1.0)
    vm = np.where(np.arange(n) % 2 == 0, 0.5, 0.7)
    counts = np.zeros(9, np.int64)
    found = [K.period_update(i, K.Window(t, wall, vm, phase, kind), counts, tol) for i in range(n)]
    assert 1 not in found
    assert found[5] == 2  # events 2..5 each repeat the event two before: two full cycles
    # the same events with one velocity: period one after two repetitions
    counts[:] = 0
    found = [K.period_update(i, K.Window(t, wall, np.full(n, 0.5), phase, kind), counts, tol) for i in range(n)]
    assert found[2] == 1
    # phases either side of 0 = 2 pi are the same phase
    counts[:] = 0
    wrap = np.where(np.arange(n) % 2 == 0, 1e-12, 2 * np.pi - 1e-12)
    found = [K.period_update(i, K.Window(t, wall, np.full(n, 0.5), wrap, kind), counts, tol) for i in range(n)]
    assert found[2] == 1
    # the longest period looked for is the counters' last lag: period 2 with lags up to 2
    short = np.zeros(3, np.int64)
    found = [K.period_update(i, K.Window(t, wall, vm, phase, kind), short, tol) for i in range(n)]
    assert found[5] == 2


@settings(max_examples=200, deadline=None, derandomize=True)
@given(pmax=st.integers(1, 6), seed=st.integers(0, 2**32 - 1), tol=st.sampled_from([1e-9, 1e-3]))
def test_the_event_loop_s_shortcut_of_the_period_test_leaves_the_counters_as_the_test_does(pmax, seed, tol):
    """The event loop calls :func:`period_update` only where :func:`no_lag_matches` is False, which otherwise does
    the update's work itself: over events that repeat often (walls, kinds, speeds and phases from a few values,
    speeds moved by less or more than ``tol``, NaN speeds, times near whole forcing periods), where the shortcut is
    taken the update finds no period and leaves the counters exactly as the shortcut does; where it is not, the
    shortcut leaves them untouched."""
    rng = np.random.default_rng(seed)
    n = 40
    wall = rng.choice(np.array([-1, 1], np.int8), n)
    kind = rng.choice(np.array([0, 0, 0, 2], np.int8), n)
    vm = rng.choice([0.5, 0.7, 0.0, math.nan], n) + rng.choice([0.0, 0.0, 0.3, 0.7, 1.5, 3.0], n) * tol
    phase = rng.choice([1.0, 2.0], n)
    t = 2.0 * np.cumsum(rng.integers(1, 3, n)) + rng.choice([0.0, 0.3 * tol], n)
    events = K.Window(t, wall, vm, phase, kind)
    counts = np.full(pmax + 1, 7, np.int64)  # counters of lags not yet looked at keep their values
    for i in range(n):
        short = counts.copy()
        found = K.period_update(i, events, counts, tol)
        if K.no_lag_matches(i, vm, short, tol):
            assert found == 0 and np.array_equal(short, counts), (i, found, short, counts)
        else:
            assert K.velocity_repeats(i, vm, pmax, tol)


def _period_update_lag_by_lag(i, events, counts, tol):
    """The period test as :func:`~vibroimpact.dynamics.kernels.period_update` states it, one lag after the other in
    plain Python: each lag's wall, kind, speed, phase and time compared, its counter counted up or reset, the
    smallest lag with two full cycles (and no shorter period still converging) returned."""
    t, wall, vm, phase, kind = events
    found = 0
    for p in range(1, min(len(counts) - 1, i) + 1):
        j = i - p
        same_speed = abs(vm[i] - vm[j]) <= tol or (math.isnan(vm[i]) and math.isnan(vm[j]))
        dphase = abs(phase[i] - phase[j]) % (2 * math.pi)
        lag = t[i] - t[j]
        k = math.floor(lag / 2.0 + 0.5)
        if (wall[i] == wall[j] and kind[i] == kind[j] and same_speed and min(dphase, 2 * math.pi - dphase) <= tol
                and k >= 1 and abs(lag - 2.0 * k) <= tol * max(1.0, lag)):
            counts[p] += 1
            if found == 0 and counts[p] >= 2 * p:
                if K._no_shorter_period(i, p, vm, phase, tol):
                    found = p
                else:
                    counts[p] = 0
        else:
            counts[p] = 0
    return found


@settings(max_examples=200, deadline=None, derandomize=True)
@given(pmax=st.one_of(st.integers(1, 8), st.sampled_from([63, 64, 65, 130])), q=st.integers(1, 5),
       seed=st.integers(0, 2**32 - 1), tol=st.sampled_from([1e-9, 1e-3, 2.0**-10]))
def test_the_period_test_counts_each_lag_as_one_lag_at_a_time_does(pmax, q, seed, tol):
    """:func:`~vibroimpact.dynamics.kernels.period_update` against the test as stated, written one lag at a time in
    plain Python: the same period found and the same counters after every event, over motions repeating a pattern
    of ``q`` events (walls, kinds, speeds among them NaN, phases near 0 = 2 pi, time lags near whole forcing periods,
    zero among them), each event moved by less or more than ``tol`` now and then (by exactly ``tol`` too, where it is
    a power of two: a speed that far still repeats), and some converging alternately (a shorter period not yet
    decided)."""
    rng = np.random.default_rng(seed)
    n = 60 if pmax < 60 else 2 * pmax + 20  # the longest lags (the test takes them 64 at a time) counted up as well
    pick = lambda values: np.resize(rng.choice(values, q), n)  # noqa: E731
    wall, kind = pick(np.array([-1, 1], np.int8)), pick(np.array([0, 0, 2], np.int8))
    vm = pick(np.array([0.5, 0.7, 0.0, math.nan])) + rng.choice([0.0] * 8 + [0.3, 1.0, 1.5, 3.0], n) * tol
    vm += rng.choice([0.0, 1.0]) * 3.0 * tol * (-0.99) ** np.arange(n)  # alternating: lag-2q first
    phase = pick(np.array([1.0, 1e-3 * tol, 2 * math.pi - 1e-3 * tol])) + rng.choice([0.0] * 8 + [2.0], n) * tol
    t = 2.0 * np.cumsum(pick(np.array([0, 1, 2]))) + rng.choice([0.0] * 8 + [0.3, 3.0], n) * tol
    events = K.Window(t, wall, vm, phase, kind)
    counts = np.full(pmax + 1, 7, np.int64)  # counters of lags not yet looked at keep their values
    expected = counts.copy()
    found = []
    for i in range(n):
        want = _period_update_lag_by_lag(i, events, expected, tol)
        found.append(K.period_update(i, events, counts, tol))
        assert found[-1] == want and np.array_equal(counts, expected), (i, found[-1], want, counts, expected)


def test_a_batch_on_threads_runs_in_a_forked_child_too():
    """A process forked after a batch ran on the threads' pool (multiprocessing's default start on Linux) runs
    batches there too, the same runs: the child starts pools of its own (the parent's threads do not exist in
    it; a block handed to them would wait for ever)."""
    import multiprocessing

    import numba

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba has one thread here: no pool to fork")
    d = np.array([0.3, 0.235, 0.2, 0.25])
    first = vi.simulate_batch(d, 0.2, 0.5, 0.4, 0.6, n_impacts=50)  # the pool started in this process
    ctx = multiprocessing.get_context("fork")
    with ctx.Pool(1) as pool:
        res = pool.apply_async(_batch_times, (d,))
        again = res.get(timeout=120)
    assert np.array_equal(again, first["t"].values, equal_nan=True)


def _batch_times(d):
    return vi.simulate_batch(d, 0.2, 0.5, 0.4, 0.6, n_impacts=50)["t"].values


def test_a_period_one_motion_converging_alternately_is_not_taken_for_period_two():
    """A period-1 motion with its eigenvalue near -1 (-0.9999) converges alternately: its lag-2 residuals (2e-10)
    fall below tol = 1e-9 long before its lag-1 residuals (2e-6), which stay below sqrt(tol): not decided yet, so
    no period is reported (not period 2, which every lag-2 match alone would give); a genuine period 2, whose
    lag-1 splitting exceeds sqrt(tol), is (test above)."""
    n, tol = 12, 1e-9
    t = 2.0 * np.arange(n)
    wall, kind, phase = np.ones(n, np.int8), np.zeros(n, np.int8), np.full(n, 1.0)
    vm = 0.5 + 1e-6 * (-0.9999) ** np.arange(n)
    counts = np.zeros(9, np.int64)
    found = [K.period_update(i, K.Window(t, wall, vm, phase, kind), counts, tol) for i in range(n)]
    assert found == [0] * n
    assert np.abs(vm[2:] - vm[:-2]).max() < tol < np.abs(vm[1:] - vm[:-1]).min() < math.sqrt(tol)  # as stated


def test_a_lag_split_by_exactly_the_root_of_tol_is_decided():
    """The shorter-period check holds a period back while a divisor's residuals are below sqrt(tol); a split of
    exactly sqrt(tol) (a power of two here, so exact) is decided: the period stands.  A split just below is not."""
    tol = 2.0**-20  # sqrt(tol) = 2**-10
    n = 12
    phase = np.full(n, 1.0)
    for split, decided in ((2.0**-10, True), (2.0**-10 - 2.0**-30, False)):
        vm = 0.5 + split * (np.arange(n) % 2)
        assert abs(vm[1] - vm[0]) == split
        assert K._no_shorter_period(n - 1, 2, vm, phase, tol) is decided


@pytest.mark.parametrize("gbar", [0.2, 0.9])
def test_chattering_sum_applies_exactly_where_the_acceleration_stays_within_the_drift_bound(gbar):
    """At phase 0 (cosine 1, sine 0) the acceleration into the bottom, cos(pi t) + gbar, falls by 1 - cos(pi tau) over the
    sequence: the sum is used if and only if that is at most CHATTER_DRIFT of it (closed form at a
    maximum of the forcing, where the rule's bound is attained to second order)."""
    r, a = 0.5, 1.0 + gbar
    applied, refused = 0, 0
    for u in np.geomspace(1e-7, 1e-4, 60):
        tau = 2 * u / ((1 - r) * a)
        change = (1 - math.cos(math.pi * tau)) / a
        got = K._accumulation_time(1.0, 0.0, u, 1, K.Model(1.0, gbar, r), 1e-3)
        if change < K.CHATTER_DRIFT * (1 - 1e-6):
            assert got == pytest.approx(tau, rel=1e-15)
            applied += 1
        elif change > K.CHATTER_DRIFT * (1 + 1e-6):
            assert got < 0
            refused += 1
    assert applied > 5 and refused > 5
    # away from the wall (acceleration pulling off it) and above v_chatter: never summed
    assert K._accumulation_time(-1.0, 0.0, 1e-8, 1, K.Model(1.0, 0.2, r), 1e-3) < 0
    assert K._accumulation_time(1.0, 0.0, 2e-3, 1, K.Model(1.0, gbar, r), 1e-3) < 0
    # a rebound at v_chatter or faster is never summed, even where the drift bound holds: the same speed is summed
    # under a larger v_chatter
    u = 2e-6
    assert (1 - math.cos(math.pi * 2 * u / ((1 - r) * a))) / a < K.CHATTER_DRIFT
    assert K._accumulation_time(1.0, 0.0, u, 1, K.Model(1.0, gbar, r), 1e-3) == pytest.approx(2 * u / ((1 - r) * a), rel=1e-15)
    assert K._accumulation_time(1.0, 0.0, u, 1, K.Model(1.0, gbar, r), u) < 0


def test_a_flight_that_never_reaches_a_wall_ends_the_run_with_no_impact():
    """gbar = 0, at rest at the centre at phase 0: Z = (1 - cos(pi t)) / pi^2 stays in [0, 0.21],
    inside walls at +-0.5."""
    p = vi.Params(d=1.0, gbar=0.0, r=0.5)
    ds = vi.simulate(p, 0.0, 0.0, Z0=0.0, n_impacts=5)
    assert ds.attrs["status"] == "no_impact" and ds.sizes["impact"] == 1
    ds = vi.simulate(p, 0.0, 0.0, Z0=0.0, t_end=50.0)
    assert ds.attrs["status"] == "t_end"


def _window(d, gbar, r, phi, v0, *, max_events, pmax, cap, window, tol=1e-9):
    win = K.Window(np.full(window, np.nan), np.zeros(window, np.int8), np.full(window, np.nan),
                   np.full(window, np.nan), np.zeros(window, np.int8))
    limits = K.WindowSettings(max_events=max_events, t_end=math.inf, v_chatter=1e-9, tol=tol, pmax=pmax, cap=cap)
    st, lag, total, n = K.run_window(K.Model(d, gbar, r), phi, v0, limits, win)
    return win, K.STATUS_NAMES[st], lag, total, n


@pytest.mark.parametrize("d, gbar, pmax, expected", [
    (0.3, 0.7, 8, "n_events"),       # chattering into sticking and release, period longer than pmax
    # the same where the acceleration at the bottom's release rounds to just into the wall (cos(2 pi - alpha) < -gbar
    # by an ulp): a run resumed after a release must not take the ball at rest there for one after an impact
    (0.3, 0.608, 8, "n_events"),
    (0.3, 0.5, 8, "periodic"),       # 4 events per period, found after ~50 events
    (0.3, 0.5, 4, "periodic"),       # the same with pmax = the period: the last lag is looked at
    (0.235, 0.21216, 8, "n_events"),  # chaotic (beta = pi/3)
])
def test_sliding_window_run_equals_one_long_run(d, gbar, pmax, expected):
    """run_window keeps only a small buffer and resumes from its last event again and again; the
    events, their count and the detected period equal one run that keeps everything."""
    max_events, phi, v0 = 3000, 0.3, 0.5
    keep = 3 * pmax + 1
    win, status, lag, total, n = _window(d, gbar, 0.5, phi, v0, max_events=max_events, pmax=pmax,
                                         cap=keep + 3, window=keep)
    ref = vi.simulate(vi.Params(d=d, gbar=gbar, r=0.5), phi, v0, n_impacts=max_events,
                      stop_when_periodic=True, max_period_events=pmax)
    assert status == ref.attrs["status"] == expected
    assert total == ref.sizes["impact"] > keep + 3 and lag == ref.attrs["period_events"]
    assert n == keep
    tail = ref.isel(impact=slice(-n, None))
    np.testing.assert_allclose(win[0][:n], tail["t"].values, rtol=TOL_T, atol=0)
    np.testing.assert_array_equal(win[1][:n], tail["wall"].values)
    np.testing.assert_array_equal(win[4][:n], tail["kind"].values)
    np.testing.assert_allclose(win[2][:n], tail["v_minus"].values, rtol=0, atol=TOL_T)
    np.testing.assert_allclose(win[3][:n], tail["phase"].values, rtol=0, atol=TOL_T)
    if gbar in (0.7, 0.608):
        kinds = ref["kind"].values
        assert (kinds == K.STICK).sum() > 40 and (kinds == K.RELEASE).sum() > 40


def test_batch_runs_equal_single_runs_event_for_event():
    """simulate_batch and attractor_batch (parallel) against simulate, including the event count."""
    from vibroimpact.analysis.windows import attractor_batch

    d = np.array([0.3, 0.235, 0.2])
    gbar = np.array([0.9, 0.21216, 0.0311])
    b = vi.simulate_batch(d, gbar, 0.5, 0.4, 0.6, n_impacts=400, stop_when_periodic=True, max_period_events=1)
    att = attractor_batch(d, gbar, 0.5, 0.4, 0.6, max_periods=100, window=65, pmax=64)
    for k in range(3):
        p = vi.Params(d=d[k], gbar=gbar[k], r=0.5)
        one = vi.simulate(p, 0.4, 0.6, n_impacts=400, stop_when_periodic=True, max_period_events=1)
        n = int(b["n_events"].values[k])
        assert n == one.sizes["impact"]
        np.testing.assert_array_equal(b["t"].values[k, :n], one["t"].values)
        long = vi.simulate(p, 0.4, 0.6, t_end=200.0, stop_when_periodic=True, max_period_events=64)
        assert int(att["n_events"].values[k]) == long.sizes["impact"]
        assert K.STATUS_NAMES[int(att["status"].values[k])] == long.attrs["status"]


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_a_batch_s_runs_are_shared_among_the_threads_each_once(monkeypatch, threads):
    """kernels.shared splits a batch's runs [0, m) into blocks, each given to the kernel once: together they
    hold every run once, in order; one block per thread, all of equal size but the last (the calling thread takes
    the first); one block, in the calling thread, on one thread or for one run; none for no runs.  Run with a Python kernel that notes its blocks and thread, the
    number of numba's threads set as a user's setting would."""
    import threading

    import numba

    monkeypatch.setattr(numba, "get_num_threads", lambda: threads)
    for m in (0, 1, 2, 3, 4, 5, 7, 8, 9, 100, 1001):
        seen = []

        def kernel(span, note):
            lo, hi = span
            assert isinstance(lo, np.int64) and isinstance(hi, np.int64)  # one compiled specialisation
            note.append((int(lo), int(hi), threading.get_ident()))

        K.shared(kernel, m, seen)
        blocks = sorted(b[:2] for b in seen)
        assert [k for lo, hi in blocks for k in range(lo, hi)] == list(range(m)), (threads, m, blocks)
        sizes = [hi - lo for lo, hi in blocks]
        assert len(set(sizes[:-1])) <= 1 and sizes[0] == -(-m // threads) if m else not blocks
        if threads == 1 or m <= 1:
            assert blocks == ([(0, m)] if m else []) and {b[2] for b in seen} <= {threading.get_ident()}
        else:
            assert len(blocks) == -(-m // -(-m // threads)) >= 2, (threads, m, blocks)  # min(m, threads) or fewer
            main = threading.get_ident()  # the first block in this thread, the others on the pool's threads
            assert [b[2] == main for b in sorted(seen)] == [True] + [False] * (len(blocks) - 1)


def test_acceleration_zero_comes_with_the_sign_of_the_sine_there():
    """events.accel_zero: the next time after tau where cos(theta + pi t) = -gbar, with no zero in
    between, and the sign of sin(theta + pi t) there (+1 at the phase alpha, -1 at 2 pi - alpha); the
    piece ends take their sine and cosine from it, without a trigonometric call."""
    from vibroimpact.dynamics.events import accel_zero, next_accel_zero

    rng = np.random.default_rng(11)
    for _ in range(400):
        theta, tau, gbar = rng.uniform(0, 2 * math.pi), rng.uniform(0, 3), rng.uniform(0, 0.95)
        alpha = math.acos(-gbar)
        t, sgn = accel_zero(tau, theta, alpha)
        psi = theta + math.pi * t
        assert t > tau and math.cos(psi) == pytest.approx(-gbar, abs=1e-12)
        assert sgn == math.copysign(1.0, math.sin(psi))
        # no zero of cos + gbar strictly between tau and t
        s = np.linspace(tau, t, 200)[1:-1]
        f = np.cos(theta + math.pi * s) + gbar
        assert np.all(f[:-1] * f[1:] > 0)
        assert next_accel_zero(tau, theta, alpha) == t  # the time alone, as the grazing search uses it


def test_a_hit_is_defined_once_and_used_everywhere():
    """An event reaches a wall when it is an impact or a grazing contact: kernels.is_hit (compiled) and
    kernels.hits (arrays) agree with the kinds' names, and no other module spells the rule out again."""
    import re

    from conftest import ROOT

    from vibroimpact.dynamics import kernels as K

    kinds = np.arange(len(K.KIND_NAMES), dtype=np.int8)
    expected = [name in ("impact", "grazing") for name in K.KIND_NAMES]
    assert K.hits(kinds).tolist() == expected == [bool(K.is_hit(k)) for k in kinds]
    spelled = re.compile(r"kind\W[^\n]*(IMPACT[^\n]*GRAZING|<=\s*(1|K\.GRAZING)\b|isin\([^)]*\(0, 1\))")
    again = [f"{f.relative_to(ROOT)}:{i}" for f in (ROOT / "src" / "vibroimpact").rglob("*.py") if f.name != "kernels.py"
             for i, line in enumerate(f.read_text().splitlines(), 1) if spelled.search(line)]
    assert not again, again


def test_a_batch_run_with_no_period_stops_after_max_periods_forcing_periods():
    """attractor_batch stops a run without a period after max_periods forcing periods (200 by default, 2 time
    units each): the chaotic run at beta = pi/3, d = 0.235 ends within one event of t = 400 (30 with
    max_periods = 15)."""
    from vibroimpact.analysis.windows import attractor_batch

    g = 0.1245 * 9.8 * math.sin(math.pi / 3) / 5.0
    for kw, t_end in (({}, 400.0), ({"max_periods": 15}, 30.0)):
        ab = attractor_batch(0.235, g, 0.5, 0.42, 0.87, **kw)
        assert ab.label.values[0] == "no period found"
        last = float(np.nanmax(ab.t.values[0]))
        assert t_end - 2.0 < last <= t_end, (kw, last)


@pytest.mark.parametrize("d, gbar, phi, v0", [(0.16, 0.12201, 1.015, 0.1924), (0.235, 0.21216, 0.4, 0.6),
                                              (0.3, 0.9, 0.4, 0.6)])
def test_every_recorded_flight_is_the_event_finders_to_the_last_bit(d, gbar, phi, v0):
    """The event loop compiles the event finder into itself (``flight_impact`` is inlined): every impact it
    records after an impact is the one ``flight_impact``, called on its own, finds from the recorded post-impact
    state (time, phase, wall and pre-impact velocity, bit for bit), on a 2:1, a chaotic and a chattering run."""
    from vibroimpact.dynamics.events import flight_impact

    run = vi.simulate(vi.Params(d=d, gbar=gbar, r=0.5), phi, v0, n_impacts=600)
    t, phase, z, vp, vm, wall = (run[k].values for k in ("t", "phase", "z", "v_plus", "v_minus", "wall"))
    hit = K.hits(run["kind"].values)
    alpha = math.acos(-gbar)
    checked = 0
    for i in np.flatnonzero(hit[1:] & hit[:-1]) + 1:
        th = phase[i - 1]
        tau, w, v = flight_impact(th, math.cos(th), math.sin(th), alpha, z[i - 1], vp[i - 1], d, gbar, math.inf)
        assert (t[i - 1] + tau, (th + math.pi * tau) % (2 * math.pi), w, v) == (t[i], phase[i], wall[i], vm[i])
        checked += 1
    assert checked > 300
