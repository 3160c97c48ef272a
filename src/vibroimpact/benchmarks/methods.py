"""Simulation methods compared in the work-precision benchmark, behind one interface.

Every runner starts from a bottom impact at phase ``phi`` with pre-impact velocity ``v0`` (paper
convention) and returns :class:`Run`: the impacts after the first (time, wall, pre-impact velocity),
the status and the wall-clock time.

* ``exact``: the event-driven simulator (numba).
* ``python``: the same algorithm run as plain Python/NumPy (numba's JIT disabled in a subprocess).
* ``ivp-<method>``: scipy's solve_ivp (RK45, DOP853, LSODA, Radau) with terminal events on both
  walls, restarted after every impact — what most research codes do.
* ``rk4``: fixed-step classical Runge-Kutta; an impact is detected when a step ends beyond a wall
  and located by bisection on the step (re-taking one RK4 step of the bisected length).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
from collections import namedtuple
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..dynamics import impact as law
from ..dynamics import kernels as K
from ..dynamics.params import Params
from ..dynamics.runs import simulate

OK, STALLED, NO_IMPACT, CRASHED = "ok", "stalled", "no impact", "crashed"


@dataclass
class Run:
    t: np.ndarray
    wall: np.ndarray
    v: np.ndarray
    status: str
    seconds: float


# ---------------------------------------------------------------------------------------------
# exact (compiled) and the same algorithm in plain Python
# ---------------------------------------------------------------------------------------------


def run_exact(p: Params, phi, v0, n, t_end=math.inf):

    simulate(p, phi, v0, n_impacts=3)  # compiled outside the timing
    start = time.perf_counter()
    ds = simulate(p, phi, v0, n_impacts=n + 1, t_end=None if math.isinf(t_end) else t_end)
    sec = time.perf_counter() - start
    hit = K.hits(ds.kind.values[1:])
    status = OK if ds.sizes["impact"] == n + 1 or not math.isinf(t_end) else ds.attrs["status"]
    return Run(ds.t.values[1:][hit], ds.wall.values[1:][hit].astype(int), ds.v_minus.values[1:][hit], status, sec)


def run_python(p: Params, phi, v0, n, t_end=math.inf, timeout=600):
    """The exact algorithm with numba's JIT disabled, in a fresh interpreter (NUMBA_DISABLE_JIT=1)."""
    return run_python_many([(p, phi, v0, n, t_end)], timeout=timeout)[0]


def run_python_many(cases, timeout=600):
    """:func:`run_python` for several ``(params, phi, v0, n, t_end)`` in one fresh interpreter (its
    start-up and imports paid once); each run timed on its own."""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    args = json.dumps([dict(d=p.d, gbar=p.gbar, r=p.r, phi=phi, v0=v0, n=n, t_end=None if math.isinf(t_end) else t_end)
                       for p, phi, v0, n, t_end in cases])
    out = subprocess.run([sys.executable, "-m", "vibroimpact.benchmarks.methods", args], env=env, capture_output=True,
                         text=True, timeout=timeout, check=True)
    return [Run(np.array(res["t"]), np.array(res["wall"], dtype=int), np.array(res["v"]), res["status"], res["seconds"])
            for res in json.loads(out.stdout)]


def _python_worker(args):

    out = []
    for a in json.loads(args):
        p = Params(d=a["d"], gbar=a["gbar"], r=a["r"])
        start = time.perf_counter()
        ds = simulate(p, a["phi"], a["v0"], n_impacts=a["n"] + 1, t_end=a["t_end"])
        sec = time.perf_counter() - start
        hit = K.hits(ds.kind.values[1:])
        out.append(dict(t=ds.t.values[1:][hit].tolist(), wall=ds.wall.values[1:][hit].astype(int).tolist(),
                        v=ds.v_minus.values[1:][hit].tolist(), status=OK, seconds=sec))
    print(json.dumps(out))


# ---------------------------------------------------------------------------------------------
# solve_ivp with terminal events
# ---------------------------------------------------------------------------------------------


def ivp_flight(theta, z0, u, d, gbar, rtol, atol, method="DOP853", horizon=50.0, evals=None):
    """Next impact by solve_ivp with terminal events on both walls: (tau, wall, Zdot-) or (inf, 0, nan).
    ``evals``: a one-element list that counts the right-hand side's evaluations."""
    from scipy.integrate import solve_ivp  # here, not at the top: the jobs that only read datasets do not import it


    def rhs(t, y):
        if evals is not None:
            evals[0] += 1
        return (y[1], math.cos(theta + math.pi * t) + gbar)

    def bottom(t, y):
        return y[0] - d / 2

    def top(t, y):
        return y[0] + d / 2

    bottom.terminal = top.terminal = True
    bottom.direction, top.direction = 1.0, -1.0
    sol = solve_ivp(rhs, (0.0, horizon), [z0, u], method=method, rtol=rtol, atol=atol, events=(bottom, top))
    if sol.status == 1:
        if len(sol.t_events[0]):
            return sol.t_events[0][0], 1, sol.y_events[0][0][1]
        return sol.t_events[1][0], -1, sol.y_events[1][0][1]
    return math.inf, 0, math.nan


def flight_loop(flight, p: Params, phi, v0, n, *, t_end=math.inf, max_seconds=60.0, errors=(ValueError,),
                exhausted=None):
    """Chain flights from a bottom impact at phase ``phi`` with pre-impact velocity ``v0``: each flight
    ``flight(theta, z0, u, k)`` (``k`` flights done) gives ``(tau, wall, Zdot-)``, then Zdot+ = -r Zdot-.
    An exception of ``errors`` ends the run as crashed; ``max_seconds``, or ``exhausted()`` turning
    true (a budget of work, which unlike a time budget gives the same run on any machine), as stalled."""
    theta, z, u, t = phi, p.d / 2, law.rebound(v0, p.r), 0.0
    ts, ws, vs = [], [], []
    status = OK
    start = time.perf_counter()
    while len(ts) < n and t < t_end:
        if time.perf_counter() - start > max_seconds or (exhausted is not None and exhausted()):
            status = STALLED
            break
        try:
            tau, w, vm = flight(theta, z, u, len(ts))
        except errors as err:
            status = f"{CRASHED}: {err}"
            break
        if w == 0:
            status = NO_IMPACT
            break
        t += tau
        theta = (theta + math.pi * tau) % (2 * math.pi)
        z = w * p.d / 2
        u = law.rebound(vm, p.r)
        ts.append(t)
        ws.append(w)
        vs.append(vm)
    return Run(np.array(ts), np.array(ws, dtype=int), np.array(vs), status, time.perf_counter() - start)


def run_ivp(p: Params, phi, v0, n, *, method="DOP853", rtol=1e-12, atol=1e-12, t_end=math.inf, max_seconds=60.0,
            max_evals=None):
    """Event loop with solve_ivp: restart after each impact with Zdot+ = -r Zdot-; solve_ivp's event
    location raising ValueError (it gives up in chattering) ends the run as crashed.  ``max_evals``:
    stop (stalled) once the right-hand side has been evaluated that many times."""
    evals = [0]
    exhausted = None if max_evals is None else (lambda: evals[0] >= max_evals)
    return flight_loop(lambda th, z, u, _k: ivp_flight(th, z, u, p.d, p.gbar, rtol, atol, method, evals=evals), p, phi,
                       v0, n, t_end=t_end, max_seconds=max_seconds, exhausted=exhausted)


# ---------------------------------------------------------------------------------------------
# fixed-step RK4 with bisection on the step
# ---------------------------------------------------------------------------------------------


@njit(cache=True)
def _acc(theta, gbar, s):
    return math.cos(theta + math.pi * s) + gbar


@njit(cache=True)
def _rk4_step(theta, gbar, t, z, v, h):
    k1z, k1v = v, _acc(theta, gbar, t)
    k2z, k2v = v + 0.5 * h * k1v, _acc(theta, gbar, t + 0.5 * h)
    k3z, k3v = v + 0.5 * h * k2v, _acc(theta, gbar, t + 0.5 * h)
    k4z, k4v = v + h * k3v, _acc(theta, gbar, t + h)
    return z + h / 6 * (k1z + 2 * k2z + 2 * k3z + k4z), v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)


#: what bounds one RK4 flight: its step ``h``, the longest flight ``tau_max`` and the most steps ``max_steps``
FlightBudget = namedtuple("FlightBudget", ("h", "tau_max", "max_steps"))
#: an RK4 run: at most ``n`` impacts, steps of ``h``, up to time ``t_end`` and ``max_steps`` steps in all
RK4Run = namedtuple("RK4Run", ("n", "h", "t_end", "max_steps"))


@njit(cache=True)
def rk4_flight(theta, z0, u, model, budget):
    """One flight by fixed-step RK4 from (z0, u) at phase theta (``model``: :data:`~vibroimpact.dynamics.kernels.Model`;
    ``budget``: :data:`FlightBudget`): a step ending beyond a wall is an impact, located by bisection on the
    length of that step (re-taking one RK4 step from its start).

    Returns ``(tau, wall, Zdot-, steps)``; ``wall = 0`` when ``tau_max`` or ``max_steps`` came first.
    """
    d, gbar = model.d, model.gbar
    h, tau_max, max_steps = budget.h, budget.tau_max, budget.max_steps
    half = 0.5 * d
    z, v, t = z0, u, 0.0
    steps = 0
    while t < tau_max and steps < max_steps:
        zn, vn = _rk4_step(theta, gbar, t, z, v, h)
        steps += 1
        w = 1 if zn >= half and vn > 0 else (-1 if zn <= -half and vn < 0 else 0)
        if w != 0:
            lo, hi = 0.0, h
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                zm, _ = _rk4_step(theta, gbar, t, z, v, mid)
                if (zm - w * half) * w >= 0:
                    hi = mid
                else:
                    lo = mid
                if hi - lo < 1e-15 * max(1.0, t):
                    break
            _, v_hit = _rk4_step(theta, gbar, t, z, v, hi)
            return t + hi, w, v_hit, steps
        z, v, t = zn, vn, t + h
    return math.inf, 0, math.nan, steps


@njit(cache=True)
def _rk4_loop(model, phi, v0, run, out):
    """Chain RK4 flights from a bottom impact (``run``: :data:`RK4Run`; ``out``: the impact times, walls and
    pre-impact velocities written); returns (impacts, 1 if the step budget ran out)."""
    d, r = model.d, model.r
    n, h, t_end, max_steps = run.n, run.h, run.t_end, run.max_steps
    out_t, out_w, out_v = out
    half = 0.5 * d
    z, v, t = half, law.rebound(v0, r), 0.0
    k = 0
    steps = 0
    while k < n and t < t_end:
        theta = (phi + math.pi * t) % (2.0 * math.pi)
        tau, w, v_hit, used = rk4_flight(theta, z, v, model, FlightBudget(h, t_end - t, max_steps - steps))
        steps += used
        if w == 0:
            return k, 1 if steps >= max_steps else 0
        t += tau
        out_t[k] = t
        out_w[k] = w
        out_v[k] = v_hit
        k += 1
        z, v = w * half, law.rebound(v_hit, r)
    return k, 0


def run_rk4(p: Params, phi, v0, n, *, h=1e-3, t_end=math.inf, max_steps=50_000_000):
    out_t, out_w, out_v = np.zeros(n), np.zeros(n, np.int64), np.zeros(n)
    model = K.Model(float(p.d), float(p.gbar), float(p.r))
    _rk4_loop(model, phi, v0, RK4Run(2, h, math.inf, 10), (out_t[:2], out_w[:2], out_v[:2]))  # compile
    start = time.perf_counter()
    k, stalled = _rk4_loop(model, phi, v0, RK4Run(n, h, float(t_end), max_steps), (out_t, out_w, out_v))
    sec = time.perf_counter() - start
    return Run(out_t[:k], out_w[:k].astype(int), out_v[:k], STALLED if stalled else OK, sec)


if __name__ == "__main__":
    _python_worker(sys.argv[1])
