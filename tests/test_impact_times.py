"""Impact times against an independent 40-digit reference (agree to 1e-12 in t)."""

import math

import mpmath as mp
import numpy as np
import pytest
from conftest import TOL_T

import vibroimpact as vi
from vibroimpact.dynamics.events import next_impact
from vibroimpact.dynamics.reference import _bracketed_root, first_impact, gap, grazing_state, velocity


def random_states(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        d = rng.uniform(0.1, 0.5)
        gbar = rng.uniform(0.0, 0.6)
        theta = rng.uniform(0, 2 * np.pi)
        if rng.random() < 0.5:  # just after a bottom or top impact, moving away from the wall
            wall = rng.choice([-1, 1])
            z0 = wall * d / 2
            u = -wall * rng.uniform(0.0, 1.0)
        else:
            z0 = rng.uniform(-d / 2, d / 2)
            u = rng.uniform(-1.0, 1.0)
        yield theta, z0, u, d, gbar


def test_impact_times_match_high_precision_reference_at_random_states():
    checked = 0
    for theta, z0, u, d, gbar in random_states(60, seed=1):
        ref_tau, ref_wall, clearance = first_impact(theta, z0, u, d, gbar)
        if ref_wall == 0 or clearance < 1e-5:
            continue  # sampling could hide a tangency here: near-grazing states have their own test
        tau, wall = next_impact(theta, z0, u, d, gbar, math.inf)
        assert wall == ref_wall
        assert abs(tau - float(ref_tau)) < TOL_T
        checked += 1
    assert checked >= 40


@pytest.mark.parametrize("wall", [1, -1])
@pytest.mark.parametrize("eps", [1e-4, 1e-6, 1e-8, 1e-10, -1e-14, -1e-12, -1e-10, -1e-8, -1e-6, -1e-4])
def test_near_grazing_impact_is_never_missed_nor_invented(wall, eps):
    """An extremum passing eps inside a wall (eps > 0) is no impact; crossing it by |eps| is.  At
    eps = -1e-14 the impact speed is ~1e-7: a time found from the double-precision gap alone would be
    off by ~1e-10, so this also checks the double-double polish."""
    d, gbar = 0.3, 0.2
    rng = np.random.default_rng(abs(hash((wall, eps))) % 2**32)
    for _ in range(5):
        # the extremum must be a maximum at the bottom (Z'' < 0) or a minimum at the top (Z'' > 0)
        while True:
            theta_e = rng.uniform(0, 2 * np.pi)
            if wall * (math.cos(theta_e) + gbar) < -0.2:
                break
        tau_e = rng.uniform(0.05, 0.3)
        th0, z0, u0 = grazing_state(theta_e, tau_e, d, gbar, wall, eps)
        assert abs(z0) < d / 2
        tau, w = next_impact(th0, z0, u0, d, gbar, math.inf)
        f = gap(th0, z0, u0, gbar, wall * d / 2)
        if eps < 0:
            # the reference crossing lies between tau_e - 2 sqrt(2|eps|/|Z''|) and tau_e
            width = 4 * math.sqrt(abs(eps))
            ref = mp.findroot(f, (mp.mpf(tau_e) - width, mp.mpf(tau_e)), solver="anderson")
            assert w == wall
            assert abs(tau - float(ref)) < TOL_T
        else:
            # no impact at the extremum: the next impact comes later, found by the reference
            assert tau > tau_e + 1e-3 or w != wall
            ref_tau, ref_wall, _ = first_impact(th0, z0, u0, d, gbar)
            assert w == ref_wall
            assert abs(tau - float(ref_tau)) < TOL_T


@pytest.mark.parametrize("wall, phases", [(1, (2.6, 3.6)), (-1, (-0.5, 0.5))])
def test_tangency_at_rounding_level_is_decided_by_the_exact_sign(wall, phases):
    """A state rounded from an exactly tangent flight passes ~1e-17 inside or outside the wall; the
    hit/miss decision must follow the sign of the exact (40-digit) gap at the extremum, on both
    walls (a maximum at the bottom, a minimum at the top)."""
    from vibroimpact.dynamics.reference import velocity

    d, gbar = 0.3, 0.2
    outcomes = set()
    for theta_e in np.linspace(*phases, 15):
        th0, z0, u0 = grazing_state(theta_e % (2 * np.pi), 0.2, d, gbar, wall, 0.0)
        te = mp.findroot(velocity(th0, u0, gbar), mp.mpf(0.2))
        exact_gap = gap(th0, z0, u0, gbar, wall * d / 2)(te)
        if abs(exact_gap) < 1e-28:
            continue
        ds = vi.simulate(vi.Params(d=d, gbar=gbar, r=0.5), th0, u0, Z0=z0, n_impacts=2)
        hit = bool(abs(ds["t"].values[1] - float(te)) < 1e-6)
        assert hit == (wall * exact_gap > 0)
        if hit:
            assert ds["wall"].values[1] == wall and abs(ds["v_minus"].values[1]) < 1e-7
        outcomes.add(hit)
    assert outcomes == {True, False}


@pytest.mark.parametrize("wall", [1, -1])
@pytest.mark.parametrize("dist", [1e-3, 1e-5, 1e-7])
def test_impact_just_after_the_start_matches_the_reference(wall, dist):
    """A flight starting ``dist`` from a wall and moving into it: impact times of 1e-7 .. 1e-2, where
    the root finder's stopping rule must be relative to the (small) root, not to 1."""
    d, gbar = 0.3, 0.2
    rng = np.random.default_rng(7)
    for _ in range(4):
        theta = rng.uniform(0, 2 * np.pi)
        u = wall * rng.uniform(0.05, 1.0)
        z0 = wall * (d / 2 - dist)
        horizon = 20 * dist / abs(u)  # the flight reaches the wall after ~dist / |u|
        ref_tau, ref_wall, _ = first_impact(theta, z0, u, d, gbar, horizon=horizon, step=horizon / 4000)
        tau, w = next_impact(theta, z0, u, d, gbar, math.inf)
        assert w == ref_wall == wall
        assert abs(tau - float(ref_tau)) < TOL_T * float(ref_tau)


def test_impact_times_with_gbar_at_least_one_match_the_reference():
    """gbar >= 1: the acceleration never vanishes, so the flight has no inflection phases and is
    split into fixed pieces instead; the ball always comes back down."""
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(20):
        d, gbar = rng.uniform(0.1, 0.5), rng.uniform(1.0, 1.5)
        theta, z0, u = rng.uniform(0, 2 * np.pi), rng.uniform(-d / 2, d / 2), rng.uniform(-1.0, 1.0)
        ref_tau, ref_wall, clearance = first_impact(theta, z0, u, d, gbar)
        if clearance < 1e-5:
            continue
        tau, wall = next_impact(theta, z0, u, d, gbar, math.inf)
        assert wall == ref_wall
        assert abs(tau - float(ref_tau)) < TOL_T
        checked += 1
    assert checked >= 15


def test_simulate_impact_times_match_reference_along_a_run():
    """Each flight of a simulated run, restarted from its recorded post-impact state, agrees: the
    impact's wall, time and arrival velocity (the reference's velocity at its impact time)."""
    p = vi.Params(d=0.25, gbar=0.15, r=0.5)
    ds = vi.simulate(p, 0.7, 0.6, n_impacts=25)
    t, phase, z, vp, vm, kind = (ds[k].values for k in ("t", "phase", "z", "v_plus", "v_minus", "kind"))
    for j in range(len(t) - 1):
        if kind[j] != 0:
            continue
        ref_tau, ref_wall, clearance = first_impact(phase[j], z[j], vp[j], p.d, p.gbar)
        if clearance < 1e-5:
            continue
        assert ds["wall"].values[j + 1] == ref_wall
        assert abs((t[j + 1] - t[j]) - float(ref_tau)) < TOL_T * max(1.0, t[j + 1])
        assert abs(vm[j + 1] - float(velocity(phase[j], vp[j], p.gbar)(ref_tau))) < TOL_T


def test_no_flight_time_left_means_no_impact():
    """A run that reaches t_end exactly asks for the next impact with tau_max = 0: none."""
    for theta, z0, u, d, gbar in random_states(20, seed=4):
        assert next_impact(theta, z0, u, d, gbar, 0.0) == (math.inf, 0)
        tau, wall = next_impact(theta, z0, u, d, gbar, 1e-3)
        assert (wall == 0) == math.isinf(tau) and (math.isinf(tau) or tau <= 1e-3)


@pytest.mark.parametrize("theta, z0, u, wall", [
    (5.84485605970136, -0.010965417079968481, -0.558450165385619, -1),
])
def test_crossing_at_impact_speed_1e_9_matches_the_reference(theta, z0, u, wall):
    """Flights that cross a wall at |Zdot-| ~ 1e-9 (an extremum ~1e-18 beyond it): the time is
    ill-conditioned (1e-16 / 1e-9) unless the root finder keeps its bracket and the gap is polished
    in double-double; found while auditing the root finder with a wider probe than these tests."""
    d, gbar = 0.3, 0.2
    tau, w = next_impact(theta, z0, u, d, gbar, math.inf)
    f = gap(theta, z0, u, gbar, wall * d / 2)
    te = mp.findroot(velocity(theta, u, gbar), mp.mpf(tau))  # the extremum, ~1e-18 beyond the wall
    assert wall * f(te) > 0
    ref = _bracketed_root(f, mp.mpf(tau) - mp.mpf("1e-6"), te)
    assert w == wall
    assert abs(tau - float(ref)) < TOL_T
    assert abs(float(velocity(theta, u, gbar)(ref))) < 1e-8
    assert abs(tau - float(ref)) < 1e-15 * 100  # far better than TOL_T: the double-double polish

@pytest.mark.parametrize("theta, wall, gbar", [(0.3, 1, 1.2), (1.7, 1, 1.0), (math.pi, -1, 0.2), (4.0, -1, 0.0)])
def test_at_rest_on_a_wall_pushed_into_it_is_an_impact_now(theta, wall, gbar):
    """At rest on a wall with the relative acceleration into it (w Z'' > 0): contact at once, with
    zero velocity (the polish must stop where the velocity is exactly zero)."""
    d = 0.3
    assert wall * (math.cos(theta) + gbar) > 0
    assert next_impact(theta, wall * d / 2, 0.0, d, gbar, math.inf) == (0.0, wall)


@pytest.mark.parametrize("start", ["on_wall_slow", "on_wall", "inside"])
def test_every_shortcut_of_the_event_finder_matches_the_reference(start):
    """The finder skips an extremum its tangents keep off a wall, looks where the tangents meet when
    they do not, and divides out the start's root on a flight that returns to the wall it left.
    Flights of each kind (a wall left slowly, so that it returns within one piece; a wall left at
    any speed; a start inside) against the reference: same wall, same time to TOL_T."""
    rng = np.random.default_rng({"on_wall_slow": 11, "on_wall": 12, "inside": 13}[start])
    n = 800 if start == "on_wall_slow" else 400  # a slow start samples close to its wall: fewer kept
    checked = 0
    for _ in range(n):
        d = rng.uniform(0.1, 0.5)
        gbar = rng.uniform(0.0, 0.6)
        theta = rng.uniform(0, 2 * np.pi)
        if start == "inside":
            z0, u = rng.uniform(-d / 2, d / 2), rng.uniform(-1.0, 1.0)
        else:
            wall = rng.choice([-1, 1])
            z0 = wall * d / 2
            u = -wall * (10 ** rng.uniform(-6, -1) if start == "on_wall_slow" else rng.uniform(0.0, 1.0))
        ref_tau, ref_wall, clearance = first_impact(theta, z0, u, d, gbar)
        if ref_tau < 1e-3:  # a flight shorter than a few sampling steps: sample it finely
            ref_tau, ref_wall, clearance = first_impact(theta, z0, u, d, gbar, horizon=2e-3, step=1e-8)
            clearance = math.inf  # a return within 1e-3 has no extremum near the other wall
        if ref_wall == 0 or clearance < 1e-5:
            continue  # near-grazing states have their own tests
        tau, wall_found = next_impact(theta, z0, u, d, gbar, math.inf)
        assert wall_found == ref_wall, (theta, z0, u, d, gbar)
        assert abs(tau - float(ref_tau)) < TOL_T * max(1.0, float(ref_tau)), (theta, z0, u, d, gbar)
        checked += 1
    assert checked >= 150


@pytest.mark.parametrize("wall", [1, -1])
@pytest.mark.parametrize("eps", [-1e-5, -1e-7, -1e-9])
def test_a_hit_just_after_the_start_past_a_tight_tangent_bound_is_found(wall, eps):
    """The extremum is skipped only when the tangents at the ends of its piece keep it off the wall.
    A flight that starts just before its extremum, which crosses the wall by |eps|, has a piece short
    enough that the bound lies within ~1e-4 of the extremum: a bound that were not an upper bound, or
    a skip margin of the order of the crossing, would miss the hit."""
    d, gbar = 0.3, 0.2
    rng = np.random.default_rng(abs(hash((wall, eps, "tight"))) % 2**32)
    for _ in range(5):
        while True:
            theta_e = rng.uniform(0, 2 * np.pi)
            if -0.3 < wall * (math.cos(theta_e) + gbar) < -0.1:
                break
        # start after the last time the flight was beyond the wall (|Z''| > 0.1 there)
        tau_e = 0.002 + rng.uniform(1.5, 2.0) * math.sqrt(2 * abs(eps) / 0.1)
        th0, z0, u0 = grazing_state(theta_e, tau_e, d, gbar, wall, eps)
        assert abs(z0) < d / 2
        tau, w = next_impact(th0, z0, u0, d, gbar, math.inf)
        f = gap(th0, z0, u0, gbar, wall * d / 2)
        width = 4 * math.sqrt(abs(eps))
        ref = mp.findroot(f, (max(mp.mpf(tau_e) - width, mp.mpf(0)), mp.mpf(tau_e)), solver="anderson")
        assert w == wall
        assert abs(tau - float(ref)) < TOL_T


def test_a_short_step_propagates_the_state_as_the_closed_form():
    """Within a root search a point near the last is propagated from it by Taylor polynomials
    (``state_step``) instead of sines and cosines. From states at random phases, steps from 1e-12 up
    to the largest allowed (``NEAR_STEP``), both directions: displacement, velocity, acceleration and
    jerk against the 40-digit closed form, to TOL_T."""
    from vibroimpact.dynamics.flight import NEAR_STEP, kinematics, state_step

    rng = np.random.default_rng(7)
    for _ in range(200):
        theta, u, gbar, tau = rng.uniform(0, 2 * np.pi), rng.uniform(-1, 1), rng.uniform(0, 1.2), rng.uniform(0, 2)
        h = rng.choice([-1, 1]) * min(10 ** rng.uniform(-12, 0), 0.999 * NEAR_STEP / np.pi)
        got = state_step(h, *kinematics(tau, math.cos(theta), math.sin(theta), u, gbar), gbar)
        th, x = mp.mpf(theta), mp.pi * (mp.mpf(tau) + mp.mpf(h))
        ref = (u * (x / mp.pi) + gbar * (x / mp.pi) ** 2 / 2 - (mp.cos(th + x) - mp.cos(th) + x * mp.sin(th)) / mp.pi**2,
               u + gbar * x / mp.pi + (mp.sin(th + x) - mp.sin(th)) / mp.pi,
               mp.cos(th + x) + gbar,
               -mp.pi * mp.sin(th + x))
        for name, a, b in zip(("displacement", "velocity", "acceleration", "jerk"), got, ref, strict=True):
            assert abs(a - float(b)) < TOL_T, (name, theta, u, gbar, tau, h)
