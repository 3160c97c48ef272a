"""Siconos as a benchmark peer (vibroimpact.benchmarks.peer_siconos, src/vibroimpact/_siconos/siconos_peer.py).

Skipped as a whole unless the system interpreter imports Debian's python3-siconos
(``tools/install_siconos.sh``).  Compared with the 40-digit reference (vibroimpact.dynamics.reference).
"""

import math
import random

import numpy as np
import pytest
from conftest import flight_state, gbar_of

from vibroimpact.benchmarks import peer_siconos as ps
from vibroimpact.dynamics.params import Params
from vibroimpact.dynamics.reference import first_impact, trajectory, velocity

if not ps.available():
    pytest.skip(f"Siconos peer unavailable: {ps.unavailable_reason()}", allow_module_level=True)

#: LSODAR tolerance of the event-driven checks (rtol = atol).
TOL = 1e-10
#: LSODAR keeps each step's local error below ~TOL (|Z| < 1 here, so rtol*|Z| + atol <= 2 TOL); the
#: global error of such a tolerance-controlled integrator is typically 1-100 times the local
#: tolerance per unit of integrated time, hence a position error <= C TOL (1 + tau) with C = 100,
#: which the root finder turns into a time error divided by the crossing speed |Zdot-|.
C_LSODAR = 100.0

#: Fig 4a: the periodic 2:1 orbit (beta = pi/6, d = 0.16, r = 0.5, phi = 1.015, v0 = 0.1924).
SCENE_21 = (Params(d=0.16, gbar=gbar_of(math.pi / 6), r=0.5), 1.015, 0.1924)


def lsodar_bound(tau, v):
    """Allowed impact-time error of one event-driven flight of length ``tau`` ending at speed ``v``."""
    return C_LSODAR * TOL * (1.0 + tau) / abs(v)


def ordinary_flights(k=10, seed=7):
    """``k`` flights from a wall, away from it, with a transversal first impact (|Zdot-| >= 0.1) and no
    extremum of Z within 5 % of d of a wall before it (far from grazing); with their reference impact."""
    rng = random.Random(seed)
    out = []
    while len(out) < k:
        d, gbar = rng.uniform(0.1, 0.4), rng.uniform(0.0, 0.3)
        theta, side = rng.uniform(0.0, 2 * math.pi), rng.choice((1, -1))
        z0, u = side * d / 2, -side * rng.uniform(0.05, 0.4)
        tau, wall, _ = first_impact(theta, z0, u, d, gbar)
        if wall == 0:
            continue
        v = float(velocity(theta, u, gbar)(tau))
        s = np.linspace(0.0, float(tau), 4001)
        z, zdot = flight_state(theta, z0, u, gbar, s)
        turn = np.flatnonzero(np.sign(zdot[1:]) != np.sign(zdot[:-1]))
        if abs(v) < 0.1 or any(d / 2 - abs(z[i]) < 0.05 * d for i in turn):
            continue
        out.append(((theta, z0, u, d, gbar), float(tau), wall, v))
    return out


def test_version():
    assert ps.version().startswith("4.")


def test_event_driven_flights_match_reference():
    flights = ordinary_flights()
    res = ps.siconos_flights([f for f, *_ in flights], "event-driven", tol=TOL)
    for (f, tau, wall, v), got in zip(flights, res, strict=True):
        assert got.status == "ok", (f, got)
        assert got.wall == wall, (f, got)
        assert abs(got.tau - tau) <= lsodar_bound(tau, v), (f, got.tau, tau, lsodar_bound(tau, v))


def test_event_driven_run_2to1():
    """Chained flights on the stable 2:1 orbit: the per-flight bounds add up (no amplification)."""
    p, phi, v0 = SCENE_21
    ref = trajectory(p.d, p.gbar, p.r, phi, v0, 10)
    run = ps.run_siconos(p, phi, v0, 10, method="event-driven", tol=TOL)
    assert run.status == "ok" and len(run.t) == 10
    assert run.wall.tolist() == [w for _, w, _ in ref]
    t_prev, allowed = 0.0, 0.0
    for k, (t, _, v) in enumerate(ref):
        allowed += lsodar_bound(float(t) - t_prev, float(v))
        t_prev = float(t)
        assert abs(run.t[k] - float(t)) <= allowed, (k, run.t[k], float(t), allowed)


def test_moreau_jean_run_2to1():
    """Moreau-Jean at h = 1e-4: the walls of the first 10 impacts, and times within 3h: the reported
    time is the end of the step holding the impulse (up to h late) and the first-order scheme's own
    error is O(h), kept bounded on this stable orbit (the largest seen is 2.5h, at the 6th impact)."""
    p, phi, v0 = SCENE_21
    h = 1e-4
    ref = trajectory(p.d, p.gbar, p.r, phi, v0, 10)
    run = ps.run_siconos(p, phi, v0, 10, method="moreau-jean", h=h)
    assert run.status == "ok" and len(run.t) == 10
    assert run.wall.tolist() == [w for _, w, _ in ref]
    err = np.abs(run.t - np.array([float(t) for t, _, _ in ref]))
    assert err.max() <= 3 * h, err


def test_plugin_and_python_forcing_agree():
    """The compiled forcing plugin and the Python override evaluate the same double expression with
    the same libm cosine, so the runs agree to the last bit."""
    if ps.plugin_path()[0] is None:
        pytest.skip(f"forcing plugin not built: {ps.plugin_path()[1]}")
    p, phi, v0 = SCENE_21
    a = ps.run_siconos(p, phi, v0, 6, method="event-driven", force="plugin")
    b = ps.run_siconos(p, phi, v0, 6, method="event-driven", force="python")
    assert (a.force, b.force) == ("plugin", "python")
    assert a.status == b.status == "ok"
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_array_equal(a.v, b.v)


def test_run_contract_t_end_and_stall():
    p, phi, v0 = SCENE_21
    run = ps.run_siconos(p, phi, v0, 10**6, method="event-driven", t_end=4.7)
    assert run.status == "ok" and len(run.t) == 6 and run.t[-1] <= 4.7  # 3 impacts per period 2
    slow = ps.run_siconos(p, phi, v0, 10**6, method="moreau-jean", h=1e-6, max_seconds=0.5)
    assert slow.status == "stalled" and 0.5 <= slow.seconds < 5.0


def test_unavailable_interpreter_gives_the_install_hint(monkeypatch):
    monkeypatch.setenv(ps.ENV_PYTHON, "/nonexistent/python3")
    assert not ps.available()
    hint = r"python3-siconos not installed \(tools/install_siconos.sh\)"
    with pytest.raises(ps.SiconosUnavailable, match=hint):
        ps.run_siconos(SCENE_21[0], 1.015, 0.1924, 3, method="event-driven")
