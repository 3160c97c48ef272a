"""Lyapunov exponents of the impacting motion: the exact contraction identity, the multipliers of periodic
orbits, a two-trajectory estimate that uses no Jacobian, and the period-doubling route to chaos."""

import math

import numpy as np
import pytest
from conftest import CAPTIONS, gbar_of

import vibroimpact as vi
from vibroimpact.analysis.lyapunov import exponents_of_run
from vibroimpact.analysis.orbits import find_orbit
from vibroimpact.dynamics.flight import step_jacobian

#: The one allowance besides an estimate's own confidence interval: the exponents are means of
#: ~1e4 logarithms, each exact to rounding (~1e-16 relative) times the Jacobian's conditioning, which
#: is below 1e2 on every run here (no impact slower than 1e-3); sums of that many terms are exact to
#: ~1e-13 per impact.  1e-10 leaves three orders of magnitude and is far below any interval width.
ROUNDING = 1e-10

CHAOS = vi.Params(d=0.235, gbar=gbar_of(math.pi / 3), r=0.5)  # between the 1:1 cascade and the 2:1 (Fig 0)


def agrees(estimate, interval, reference):
    """An estimate agrees with a reference when the reference lies in its confidence interval (widened
    by rounding)."""
    lo, hi = interval
    return lo - ROUNDING <= reference <= hi + ROUNDING and lo <= estimate <= hi


def caption_params(name):
    beta, d, v, phi, *_ = CAPTIONS[name]
    return vi.Params(d=d, gbar=gbar_of(beta), r=0.5), phi, v


# ---- the contraction identity --------------------------------------------------------------------
@pytest.mark.parametrize("scene", ["chaos", "fig0b_a", "fig4_a", "fig0b_c", "start in flight"])
def test_the_exponents_sum_to_the_exact_phase_space_contraction(scene):
    """Each step's Jacobian has determinant r^2 Zdot_k / Zdot_{k+1}, so over N flights
    lambda_1 + lambda_2 = 2 ln r + ln|Zdot_0 / Zdot_N| / N, to rounding, on any run without sticking."""
    kw = {}
    if scene == "chaos":
        p, phi, v = CHAOS, 0.0, 0.5
    elif scene == "start in flight":
        p, phi, v, kw = CHAOS, 0.3, -0.2, {"Z0": 0.05}
    else:
        p, phi, v = caption_params(scene)
    n, transient = 6000, 500
    lam = vi.lyapunov(p, phi, v, n, transient=transient, **kw)
    run = vi.simulate(p, phi, v, n_impacts=n, **kw)
    assert lam.status == "ok" and lam.sticks == 0
    assert set(run.kind.values[transient:]) <= {0}  # impacts only: no stick interrupts
    N = lam.impacts
    vm = run.v_minus.values
    exact = 2 * math.log(p.r) + math.log(abs(vm[transient] / vm[transient + N])) / N
    assert abs(sum(lam.per_impact) - exact) <= ROUNDING, (sum(lam.per_impact), exact)
    # per unit time: the same, over the time the N flights span
    span = run.t.values[transient + N] - run.t.values[transient]
    assert sum(lam.per_time) == pytest.approx(exact * N / span, rel=1e-12)
    assert lam.mean_time == pytest.approx(span / N, rel=1e-12)


def test_one_step_jacobian_agrees_with_finite_differences_of_the_simulator():
    """The Jacobian of a flight (eqs. EntrP1-EntrP3) against central differences of the exact simulator's
    map from a bottom impact (its time and pre-impact velocity) to the next impact, at every bottom
    impact of a chaotic stretch (both walls follow)."""
    run = vi.simulate(CHAOS, 0.0, 0.5, n_impacts=400)
    t, vm, vp, ph, wall = (run[v].values for v in ("t", "v_minus", "v_plus", "phase", "wall"))
    h = 1e-7
    checked = 0
    for k in np.flatnonzero(wall[200:399] == 1) + 200:

        def step(dt, dv, k=k):
            nxt = vi.simulate(CHAOS, ph[k] + math.pi * dt, vm[k] + dv, n_impacts=2)
            return np.array([nxt.t.values[1] + dt, nxt.v_minus.values[1]])

        fd = np.column_stack([(step(h, 0) - step(-h, 0)) / (2 * h), (step(0, h) - step(0, -h)) / (2 * h)])
        J = np.array(step_jacobian(t[k + 1] - t[k], ph[k], vm[k], vm[k + 1], CHAOS.gbar + math.cos(ph[k + 1]),
                                   CHAOS.r)).reshape(2, 2)
        # central differences: error h^2 x third derivatives, and rounding 1e-16 / h
        np.testing.assert_allclose(J, fd, atol=1e-6 * max(1.0, np.abs(fd).max()))
        checked += 1
    assert checked >= 50


# ---- periodic orbits: the exponents are the multipliers' logarithms per impact -------------------
def _period_doubled_1_1():
    p = vi.Params(d=0.24, gbar=gbar_of(math.pi / 6), r=0.5)
    att = vi.identify_attractor(vi.simulate(p, 0.4, 0.6, n_impacts=20_000, stop_when_periodic=True, tol=1e-12),
                                tol=1e-12)
    b = att.cycle.where(att.cycle.wall == 1, drop=True)
    return find_orbit(p, "BTBT", float(b.phase[0]), float(b.v_minus[0]), k=2)


@pytest.mark.parametrize("scene", ["fig0b_a", "fig4_a", "fig0b_c", "period-doubled 1:1"])
def test_exponents_on_a_periodic_orbit_are_the_log_multipliers_per_impact(scene):
    """1:1 (a node), 2:1 (a focus: both exponents ln sqrt(det)), 3:1, and the period-doubled 1:1 (BTBT
    over two forcing periods): from a run started on the Newton-solved orbit, against ln|mu_i| / N from
    find_orbit's eigenvalues (the Newton solution's composed Jacobian, not the run's)."""
    if scene == "period-doubled 1:1":
        o = _period_doubled_1_1()
    else:
        word = {"fig0b_a": "BT", "fig4_a": "BBT", "fig0b_c": "BBBT"}[scene]
        p, phi, v = caption_params(scene)
        o = find_orbit(p, word, phi, v)
    assert o.stable and o.admissible
    lam = vi.lyapunov(o.params, o.phi, float(o.v_minus[0]), 20_000, transient=100)
    ref = np.sort(np.log(np.abs(o.eigenvalues)))[::-1] / o.n
    for i in range(2):
        assert agrees(lam.per_impact[i], lam.interval[i], ref[i]), (i, lam.per_impact[i], lam.interval[i], ref[i])
        # per unit time: N impacts span 2k
        assert agrees(lam.per_time[i], lam.interval_time[i], ref[i] * o.n / (2 * o.k))
        # an interval is centred on its estimate (batch means, Student's t)
        assert sum(lam.interval[i]) / 2 == pytest.approx(lam.per_impact[i], abs=ROUNDING)
    assert lam.status == "ok" and lam.slow_impacts == 0


# ---- chaos: against a two-trajectory estimate that uses no Jacobian ------------------------------
def benettin(params, phi, v0, *, transient, impacts, eps=1e-8, batches=20):
    """The largest exponent per impact from pairs of runs of the exact simulator (Benettin's method): at
    each bottom impact of a reference trajectory, a neighbour starts ``eps`` away in (t, Zdot-) along the
    separation carried so far, both are followed to the next bottom impact, the growth of their
    separation is logged, and the neighbour is renormalised.  Returns the mean and its interval (batch
    means, Student's t at 95 %)."""
    from scipy.stats import t as student

    run = vi.simulate(params, phi, v0, n_impacts=transient)
    kb = int(np.flatnonzero(run.wall.values == 1)[-1])  # start at the transient's last bottom impact
    ph, v = float(run.phase.values[kb]), float(run.v_minus.values[kb])
    direction = np.array([1.0, 1.0]) / math.sqrt(2)
    growth, steps = [], []
    done = 0
    while done < impacts:
        ref = vi.simulate(params, ph, v, n_impacts=8)
        j = 1 + int(np.argmax(ref.wall.values[1:] == 1))  # the next bottom impact
        assert ref.wall.values[j] == 1 and set(ref.kind.values[:j + 1]) == {0}
        dt, dv = eps * direction
        nb = vi.simulate(params, ph + math.pi * dt, v + dv, n_impacts=j + 1)
        assert list(nb.wall.values[:j + 1]) == list(ref.wall.values[:j + 1])  # the same walls, in order
        sep = np.array([nb.t.values[j] + dt - ref.t.values[j], nb.v_minus.values[j] - ref.v_minus.values[j]])
        norm = float(np.hypot(*sep))
        growth.append(math.log(norm / eps))
        steps.append(j)
        direction = sep / norm
        ph, v = float(ref.phase.values[j]), float(ref.v_minus.values[j])
        done += j
    growth, steps = np.array(growth), np.array(steps)
    m = len(growth) // batches
    per_batch = growth[:m * batches].reshape(batches, m).sum(1) / steps[:m * batches].reshape(batches, m).sum(1)
    half = student.ppf(0.975, batches - 1) * per_batch.std(ddof=1) / math.sqrt(batches)
    mean = growth.sum() / steps.sum()
    return mean, (mean - half, mean + half)


def test_largest_exponent_of_a_chaotic_motion_agrees_with_two_trajectories():
    """beta = pi/3, d = 0.235 (the paper's "apparently chaotic" window of Fig 0): the Jacobian estimate
    and Benettin's two-trajectory estimate from the exact simulator agree within their combined
    intervals, and both are positive: the motion is chaotic."""
    lam = vi.lyapunov(CHAOS, 0.0, 0.5, 22_000, transient=2000)
    ben, ben_ci = benettin(CHAOS, 0.0, 0.5, transient=2000, impacts=20_000)
    assert lam.interval[0][0] > 0 and ben_ci[0] > 0
    combined = math.hypot((lam.interval[0][1] - lam.interval[0][0]) / 2, (ben_ci[1] - ben_ci[0]) / 2)
    assert abs(lam.per_impact[0] - ben) <= combined, (lam.per_impact[0], lam.interval[0], ben, ben_ci)
    assert lam.status == "ok" and lam.sticks == 0


# ---- the period-doubling route ---------------------------------------------------------------------
def test_the_largest_exponent_touches_zero_from_below_at_a_period_doubling():
    """beta = pi/3, the 2:1 branch's period doubling B (located by continuation, multiplier -1): on the
    stable side (runs from the Newton-solved orbit) and on the period-doubled side (runs from the same
    start, transient discarded) lambda_1 is negative, its interval below 0, and it tends to 0 smoothly:
    extrapolated to B from either side (a quadratic in d - B through four points) it vanishes within
    the intervals."""
    p, phi, v = caption_params("fig0b_b")
    o = find_orbit(p, "BBT", phi, v)
    br = vi.continue_orbit(o, vary="d", d_range=(0.15, 0.19), step=1e-3)
    d_b = float(br.critical_d.values[br.critical_kind.values == "B"][0])
    assert d_b == pytest.approx(0.158, abs=5e-4)  # the paper: 2:1 stable for 0.158 < d < 0.22
    hs = np.array([2e-3, 1e-3, 5e-4, 2.5e-4])
    for side in (+1, -1):
        lams, halves = [], []
        for h in hs:
            q = vi.Params(d=d_b + side * h, gbar=p.gbar, r=p.r)
            if side > 0:
                oq = find_orbit(q, "BBT", o.phi, float(o.v_minus[0]))
                lam = vi.lyapunov(q, oq.phi, float(oq.v_minus[0]), 20_000, transient=100)
            else:
                lam = vi.lyapunov(q, o.phi, float(o.v_minus[0]), 60_000, transient=40_000)
            assert lam.interval[0][1] < 0, (side, h, lam.interval[0])
            lams.append(lam.per_impact[0])
            halves.append((lam.interval[0][1] - lam.interval[0][0]) / 2)
        _, slope, intercept = np.polyfit(hs, lams, 2)
        assert abs(intercept) <= max(halves), (side, intercept, halves)
        assert slope < 0 and np.all(np.diff(lams) > 0)  # closer to B, closer to 0


def test_the_largest_exponent_stays_at_most_zero_through_the_1_1_cascade_and_turns_positive_after_it():
    """beta = pi/3, d decreasing from the 1:1 (Fig 0): period 2, 4, 8, 16 (identified by the simulator's
    periodicity test, which uses no exponent), lambda_1 never significantly above 0, and touching 0 at
    each doubling; past the accumulation point (no period found) the interval lies above 0."""
    g = gbar_of(math.pi / 3)
    phi, v0 = CAPTIONS["fig0b_a"][3], CAPTIONS["fig0b_a"][2]
    periods, lams = {}, {}
    for d in np.round(np.arange(0.34, 0.2615, -0.002), 6):
        q = vi.Params(d=float(d), gbar=g, r=0.5)
        att = vi.identify_attractor(vi.simulate(q, phi, v0, n_impacts=40_000, stop_when_periodic=True, tol=1e-10),
                                    tol=1e-10)
        periods[d] = att.period if att.periodic else None
        lams[d] = vi.lyapunov(q, phi, v0, 40_000, transient=20_000)
    cascade = [d for d in periods if periods[d] is not None and d > 0.26]
    assert {periods[d] for d in cascade} >= {1, 2, 4, 8}  # forcing periods: the labels period-2 to -16 (in t)
    last = min(cascade)
    assert all(periods[d] is not None for d in periods if d >= last)  # no gap in the cascade
    for d in periods:
        lo, hi = lams[d].interval[0]
        if d >= last:
            assert lo <= 0, (d, periods[d], lams[d].interval[0])
            assert lams[d].per_impact[0] < 0 or hi > 0  # negative, or 0 within its interval
        else:
            assert lo > 0, (d, lams[d].interval[0])  # chaos past the accumulation point
    # at the doublings it comes close to 0: the largest value over the cascade's points
    assert max(lams[d].per_impact[0] for d in cascade) > -5e-3


# ---- what the result says, and bad input -----------------------------------------------------------
def test_a_sticking_run_gives_minus_infinity_for_lambda_2_and_says_why():
    """Fig 0b (a)'s 1:1 at a low incline force sticks each period: the map is constant across a stick."""
    p = vi.Params(d=0.38, gbar=0.9, r=0.5)
    lam = vi.lyapunov(p, 0.42, 0.87, 4000)
    assert lam.sticks > 0 and lam.per_impact[1] == -math.inf and "stick" in lam.status
    assert math.isfinite(lam.per_impact[0])


def test_a_run_that_rests_for_good_returns_minus_infinity_with_the_reason():
    p = vi.Params(d=0.2, gbar=1.5, r=0.5)
    with pytest.warns(UserWarning, match="never"):
        lam = vi.lyapunov(p, 0.0, 0.3, 1000)
    assert lam.per_impact == (-math.inf, -math.inf) and "for good" in lam.status
    assert lam.per_time == (-math.inf, -math.inf) and lam.interval == ((-math.inf, -math.inf),) * 2
    assert lam.interval_time == ((-math.inf, -math.inf),) * 2


def test_slow_impacts_are_counted():
    """Fig 4 (d) nearly grazes: the impacts slower than a stated speed are counted, against the run's own
    velocities (a speed just above its slowest impact counts them, one just below counts none)."""
    p, phi, v = caption_params("fig4_d")
    run = vi.simulate(p, phi, v, n_impacts=4000)
    speeds = np.abs(run.v_minus.values[401:])  # the impacts the flights after the transient reach
    slowest = speeds.min()
    above = vi.lyapunov(p, phi, v, 4000, transient=400, slow_speed=1.001 * slowest)
    below = vi.lyapunov(p, phi, v, 4000, transient=400, slow_speed=0.999 * slowest)
    assert above.slow_impacts == int((speeds[:above.impacts] < 1.001 * slowest).sum()) > 0
    assert below.slow_impacts == 0 and above.slow_speed == 1.001 * slowest


@pytest.mark.parametrize("kw, match", [
    ({"n_impacts": 100}, r"n_impacts = 100 is too few .* at least"),
    ({"n_impacts": 2000, "transient": 2000}, r"transient = 2000; allowed: an integer in \[0, n_impacts\)"),
    ({"n_impacts": 2000, "transient": -1}, r"transient = -1"),
    ({"n_impacts": 2000, "batches": 1}, r"batches = 1; allowed: an integer >= 2"),
    ({"n_impacts": 2000, "confidence": 1.0}, r"confidence = 1.0; allowed"),
    ({"n_impacts": 2.5}, r"n_impacts = 2.5; allowed: an integer"),
    ({"n_impacts": 2000, "Z0": 0.2}, r"Z0 = 0.2 is outside the cylinder; allowed: \|Z0\| <= d/2"),
])
def test_bad_input_is_refused_with_the_value_and_what_is_allowed(kw, match):
    n = kw.pop("n_impacts")
    with pytest.raises(ValueError, match=match):
        vi.lyapunov(CHAOS, 0.0, 0.5, n, **kw)


def test_a_recorded_run_too_short_for_an_interval_says_so():
    run = vi.simulate(CHAOS, 0.0, 0.5, n_impacts=150)
    lam = exponents_of_run(run, transient=10)
    assert math.isnan(lam.per_impact[0]) and "too few impacts" in lam.status


def test_the_fewest_impacts_for_an_interval_are_enough():
    """Batches of MIN_PER_BATCH flights give an interval; one flight fewer does not; and lyapunov accepts
    exactly the number of impacts it asks for."""
    from vibroimpact.analysis.lyapunov import MIN_PER_BATCH

    run = vi.simulate(CHAOS, 0.0, 0.5, n_impacts=10 + 2 * MIN_PER_BATCH + 1)
    assert set(run.kind.values) == {0}
    ok = exponents_of_run(run, transient=10, batches=2)
    assert ok.status == "ok" and ok.impacts == 2 * MIN_PER_BATCH and math.isfinite(ok.per_impact[0])
    short = exponents_of_run(run.isel(impact=slice(0, -1)), transient=10, batches=2)
    assert "too few impacts" in short.status
    lam = vi.lyapunov(CHAOS, 0.0, 0.5, 10 + 2 * MIN_PER_BATCH + 1, transient=10, batches=2)
    assert lam.status == "ok" and lam.impacts == 2 * MIN_PER_BATCH


@pytest.mark.parametrize("batches, quantile", [
    (2, lambda p: math.tan(math.pi * (p - 0.5))),  # Student's t with 1 degree of freedom: Cauchy
    (3, lambda p: (2 * p - 1) / math.sqrt(2 * p * (1 - p))),  # with 2: closed form
])
def test_the_interval_scales_with_student_s_quantile_of_its_batches(batches, quantile):
    """Over the same batches, the half-widths of two confidence levels are in the ratio of Student's t
    quantiles with batches - 1 degrees of freedom, here known in closed form."""
    run = vi.simulate(CHAOS, 0.0, 0.5, n_impacts=4000)
    half = {}
    for level in (0.9, 0.99):
        lam = exponents_of_run(run, transient=400, batches=batches, confidence=level)
        half[level] = [(hi - lo) / 2 for lo, hi in lam.interval]
    expect = quantile(0.995) / quantile(0.95)
    for i in (0, 1):
        assert half[0.99][i] / half[0.9][i] == pytest.approx(expect, rel=1e-12)


def test_the_guide_s_example_runs_and_finds_chaos():
    """The example of the documentation's chaos page, run as written."""
    import re
    from pathlib import Path

    page = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "chaos.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, re.S)
    assert len(blocks) == 1
    scope = {}
    exec(compile(blocks[0], "docs/guide/chaos.md", "exec"), scope)
    lam = scope["lam"]
    assert lam.interval[0][0] > 0 and lam.status == "ok" and lam.sticks == 0


@pytest.mark.parametrize("J", [
    [[0.5, 0.0], [0.0, 0.1]],                       # diagonal: 1
    [[40.0, -3.0e3], [0.5, -37.6]],                 # far from normal, real multipliers
    [[0.3, -0.8], [0.9, 0.2]],                      # a complex pair
    [[1.0, 1e-3], [1e-3, 0.999]],                   # nearly coalescing
])
def test_the_sensitivity_of_the_largest_multiplier_is_the_worst_first_order_change(J):
    """The componentwise condition of ln max|mu|, against finite differences of numpy's eigenvalues over
    every sign pattern of a relative perturbation of the entries (the first-order change is largest at
    one of them)."""
    from itertools import product

    from vibroimpact.analysis.lyapunov import multiplier_sensitivity

    J = np.array(J)
    top = lambda M: math.log(np.max(np.abs(np.linalg.eigvals(M))))
    h = 1e-7
    worst = max(abs(top(J * (1 + h * np.array(signs).reshape(2, 2))) - top(J)) / h
                for signs in product((-1.0, 1.0), repeat=4))
    assert multiplier_sensitivity(J) == pytest.approx(worst, rel=1e-4)
    if not J[0, 1] and not J[1, 0]:
        assert multiplier_sensitivity(J) == pytest.approx(1.0, rel=1e-12)


def test_the_sensitivity_of_a_cycle_s_multiplier_runs_through_each_factor_and_explains_its_spread():
    """Through a product of step Jacobians: against the worst first-order change found by perturbing each
    factor's entries (random sign patterns, finite differences of numpy's eigenvalues), which it bounds and
    nearly reaches; and on the pi/3 2:1 orbit the factors' product is the orbit's own Jacobian."""
    from vibroimpact.analysis.lyapunov import multiplier_sensitivity
    from vibroimpact.analysis.orbits import parse_word, step_jacobians

    o = vi.find_orbit(vi.Params(d=0.20, gbar=CHAOS.gbar, r=0.5), "BBT", phi=1.21, v0=0.2164)
    F = step_jacobians(o.z, parse_word(o.word), o.params.gbar, o.params.r)
    P = F[2] @ F[1] @ F[0]
    np.testing.assert_allclose(P, o.jacobian, rtol=1e-13, atol=1e-13)
    top = lambda fs: math.log(np.max(np.abs(np.linalg.eigvals(fs[2] @ fs[1] @ fs[0]))))
    rng = np.random.default_rng(7)
    h = 1e-7
    changes = [abs(top([f * (1 + h * rng.choice([-1.0, 1.0], size=(2, 2))) for f in F]) - top(F)) / h
               for _ in range(400)]
    s = multiplier_sensitivity(F)
    assert max(changes) <= s * (1 + 1e-4) and max(changes) > 0.5 * s


def test_newton_s_monodromy_is_the_product_of_the_tangent_map_s_steps_on_the_cycle():
    """One implementation of the impact map's derivative (flight.step_jacobian): the monodromy matrix of the
    Newton-solved 2:1 orbit (from its unknowns) equals the product of the steps the Lyapunov tangent pass
    applies along the simulated cycle (from the recorded impacts), to the agreement of the two orbits."""
    from vibroimpact.analysis.orbits import map_jacobian, parse_word
    from vibroimpact.dynamics import kernels as K

    p = vi.Params.from_physical(s=0.14 / 0.6225, beta=math.pi / 6)
    o = vi.find_orbit(p, "BBT", phi=5.855, v0=0.4185)
    n = o.walls.size
    run = vi.simulate(p, o.phi, float(o.v_minus[0]), n_impacts=n + 1)
    hit = K.hits(run.kind.values)
    t, phase, vm = (run[v].values[hit][: n + 1] for v in ("t", "phase", "v_minus"))
    assert np.allclose(vm[:n], o.v_minus, rtol=1e-9, atol=0)  # the simulated cycle is the Newton orbit's
    DP = np.eye(2)
    for k in range(n):
        j11, j12, j21, j22 = step_jacobian(t[k + 1] - t[k], phase[k], vm[k], vm[k + 1], p.gbar + math.cos(phase[k + 1]), p.r)
        DP = np.array([[j11, j12], [j21, j22]]) @ DP
    assert np.allclose(DP, map_jacobian(o.z, o.walls, p.gbar, p.r), rtol=1e-7, atol=1e-9)
    assert parse_word("BBT").tolist() == o.walls.tolist()
