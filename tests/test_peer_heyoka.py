"""heyoka as a benchmark peer against the 40-digit reference (vibroimpact.benchmarks.peer_heyoka)."""

import math

import numpy as np
import pytest

# ImportError, not only ModuleNotFoundError: an installed but unloadable heyoka skips too
hy = pytest.importorskip("heyoka", reason="heyoka is not importable (optional peer: pip install heyoka)",
                         exc_type=ImportError)

from vibroimpact.benchmarks import peer_heyoka as H  # noqa: E402
from vibroimpact.dynamics.params import Params  # noqa: E402
from vibroimpact.dynamics.reference import first_impact, trajectory  # noqa: E402

EPS = float(np.finfo(float).eps)


def _params(beta, d):
    return Params(d=d, gbar=0.1245 * 9.8 * math.sin(beta) / 5, r=0.5)


#: (beta, d, phi, v0): the 2:1 orbit of the benchmark, and the 3:1 orbit whose returns to the start
#: wall fall inside the first Taylor step (a restart exactly on the wall without cooldown misses them)
SCENES = {"2:1": (math.pi / 6, 0.16, 1.015, 0.1924), "3:1": (math.pi / 6, 0.138, 0.7342, 0.1845)}


@pytest.fixture(scope="module")
def references():
    out = {}
    for name, (beta, d, phi, v0) in SCENES.items():
        p = _params(beta, d)
        out[name] = (p, phi, v0, trajectory(p.d, p.gbar, p.r, phi, v0, 20))
    return out


def _states(n, seed):
    """Flights in the cylinder or just after an impact (on a wall, moving off it), as in test_impact_times."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        d, gbar, theta = rng.uniform(0.1, 0.5), rng.uniform(0.0, 0.6), rng.uniform(0, 2 * np.pi)
        if rng.random() < 0.5:
            wall = rng.choice([-1, 1])
            yield theta, wall * d / 2, -wall * rng.uniform(0.0, 1.0), d, gbar
        else:
            yield theta, rng.uniform(-d / 2, d / 2), rng.uniform(-1.0, 1.0), d, gbar


def test_available_and_compile_time_reported():
    assert H.available() and H.heyoka_version() == hy.__version__
    sec = H.compile_seconds(EPS)
    assert 0 < sec < 60 and H.integrator(EPS) is H.integrator(EPS)  # built once per tolerance


def test_flight_times_match_reference_at_machine_epsilon():
    checked = on_wall = 0
    for theta, z0, u, d, gbar in _states(40, seed=11):
        ref_tau, ref_wall, clearance = first_impact(theta, z0, u, d, gbar)
        if ref_wall == 0 or clearance < 1e-5:
            continue  # sampling could hide a tangency
        tau, wall, vm = H.heyoka_flight(theta, z0, u, d, gbar, EPS)
        assert wall == ref_wall
        assert abs(tau - float(ref_tau)) <= 1e-12
        assert vm * wall > 0  # moving into the wall it hits
        checked += 1
        on_wall += abs(z0) == d / 2
    assert checked >= 20 and on_wall >= 8


def test_return_to_the_start_wall_within_the_first_step_is_found():
    """A flight restarted exactly on the bottom wall that comes back to it after 0.25: heyoka's event
    root at tau = 0 must not hide it (see the module docstring)."""
    state = (0.2139147023420923, 0.18013448591993003, -0.15634664990358638,  # theta, z0 = d/2, u
             0.36026897183986006, 0.36390485438475745)  # d, gbar
    ref_tau, ref_wall, _ = first_impact(*state)
    assert ref_wall == 1
    tau, wall, _ = H.heyoka_flight(*state, EPS)
    assert wall == 1 and abs(tau - float(ref_tau)) <= 1e-12


@pytest.mark.parametrize("restart", ["cooldown", "offset"])
@pytest.mark.parametrize("scene", list(SCENES))
def test_run_follows_the_reference_for_20_impacts(references, scene, restart):
    p, phi, v0, ref = references[scene]
    run = H.run_heyoka(p, phi, v0, 20, tol=EPS, restart=restart)
    assert run.status == "ok" and len(run.t) == 20
    assert list(run.wall) == [w for _, w, _ in ref]
    assert np.max(np.abs(run.t - np.array([float(t) for t, _, _ in ref]))) <= 1e-10
    assert np.max(np.abs(run.v - np.array([float(v) for _, _, v in ref]))) <= 1e-10


def test_loose_tolerance_is_less_accurate(references):
    p, phi, v0, ref = references["2:1"]
    rt = np.array([float(t) for t, _, _ in ref])
    err = {}
    for tol in (EPS, 1e-6):
        run = H.run_heyoka(p, phi, v0, 20, tol=tol)
        assert list(run.wall) == [w for _, w, _ in ref]
        err[tol] = np.max(np.abs(run.t - rt))
    assert err[1e-6] > 100 * err[EPS] and err[1e-6] > 1e-10


def test_run_stops_at_t_end_and_reports_its_status():
    p = _params(math.pi / 6, 0.16)
    run = H.run_heyoka(p, 1.015, 0.1924, 10_000, tol=1e-10, t_end=5.0)
    assert run.status == "ok" and run.t[-2] < 5.0 <= run.t[-1] + 1e-12
    with pytest.raises(ValueError):
        H.run_heyoka(p, 1.015, 0.1924, 2, tol=1e-10, restart="bogus")


def test_stepping_cost_times_the_same_equations_as_the_event_loop():
    """The timed propagation (no events, no Python loop) solves the flight's equations: its end state
    after the whole span of the event run matches the closed form in 40 digits to 1e-9 relative, and
    the event loop's steps per impact are those of a run that took at least one step per impact (the
    last of three timed repeats: each starts again from the impact)."""
    import mpmath as mp

    from vibroimpact.dynamics.reference import gap, velocity

    beta, d, phi, v0 = SCENES["2:1"]
    p = _params(beta, d)
    out = H.stepping_cost(p, phi, v0, 200, tol=EPS, repeats=3)  # each repeat from the same start
    z, v = out["free_end"]
    u = -p.r * v0
    zref = gap(mp.mpf(phi), mp.mpf(p.d) / 2, mp.mpf(u), mp.mpf(p.gbar), 0)(mp.mpf(out["span"]))
    vref = velocity(mp.mpf(phi), mp.mpf(u), mp.mpf(p.gbar))(mp.mpf(out["span"]))
    assert abs(z - float(zref)) <= 1e-9 * abs(float(zref))
    assert abs(v - float(vref)) <= 1e-9 * max(1.0, abs(float(vref)))
    assert out["steps_per_impact"] >= 1.0
    assert out["timed_steps"] >= 200  # the last repeat, too, stepped over the whole span
    assert out["us_per_impact"] == pytest.approx(out["us_per_step"] * out["steps_per_impact"])
