"""heyoka (Taylor integrator with event detection) as a peer of :mod:`vibroimpact.benchmarks.methods`.

One ``heyoka.taylor_adaptive`` integrator is compiled per tolerance and reused for every flight:
state ``[Z, Zdot]``, time ``tau`` (time since the flight's start), runtime parameters
``par[0] = theta``, ``par[1] = gbar``, ``par[2] = d``, so no flight recompiles.  Two terminal events:
``Z - d/2`` (bottom, positive direction) and ``Z + d/2`` (top, negative direction).  A flight resets the
integrator's time, state and parameters and calls ``propagate_until(horizon)``; the event's time and
state are read from the integrator, as :func:`methods.ivp_flight` reads them from solve_ivp.

Restarting exactly on a wall (every flight of a run starts at ``Z = +-d/2``; heyoka 7.13.2, measured)
------------------------------------------------------------------------------------------------------
* Naive restart (``reset_cooldowns()``, which heyoka's docs suggest after editing the state, or
  ``cooldown=0``): the start wall's event polynomial has a zero constant term.  heyoka reports that
  root at ``tau = 0`` twice (its special case for a zero at the lower end, then the root finder on
  the isolating interval ``[0, h)``, which returns the same exact zero) and loses the real return to
  that wall when it falls in the first Taylor step (h ~ 0.35 at eps): with a non-terminal event, a
  bottom start with u = -0.156 reports (0.0, -1) twice and not the crossing at 0.2529; started 1e-12
  inside the wall it reports the crossing.  The direction filter rejects tau = 0, so the ball passes
  through the wall.  Measured: of 212 random flights (d in [0.1, 0.5], gbar in [0, 0.6], |u| in 1e-9..1) that
  restart on a wall and return to it, 146 were missed (speeds up to 0.13); none on the other wall.
  In runs: 32 of 48 random 30-impact runs followed the exact simulator (44 with the fix; the other 4
  part from it where the exact simulator parts from the reference too, by chaos), the 3:1 scene fails
  at its first impact and the chattering scene at once (the 2:1 scene happens to pass).
* Used here (``restart="cooldown"``, default): the restart is a resume after the terminal event, so
  the cooldown heyoka puts on the event that fired is kept (no ``reset_cooldowns()`` between
  flights).  Roots within the cooldown are ignored and the bracket then starts after it, where the
  polynomial is nonzero: the return is found.  The events get an explicit cooldown ``COOLDOWN =
  1e-15``: the restart state is exact, so the only spurious root is exactly at 0 and any positive
  cooldown separates it.  heyoka's automatic cooldown ``10 g_eps / |Zdot-|`` (``g_eps ~ tol``) also
  works at eps, but at tol = 1e-6 it ignores returns slower than ~3e-3 (chattering is lost at |v| =
  2e-3 instead of 4e-15).  The first flight of a run (no event has fired yet) takes the offset step.
* Offset step (``restart="offset"``, and :func:`heyoka_flight`, which is stateless): clear the
  cooldowns; a flight starting exactly on a wall and moving off it first takes
  ``step(max_delta_t=delta)`` with ``delta = 10 eps (d/2) / |u|``, the time the state needs to leave
  the wall by ~10 ulps, then ``propagate_until``.  The 212 flights above: every return with |u| >
  1.4e-8 is found, times within 1.2e-14 where |Zdot-| > 1e-3 (the state is rounded after the short
  step; 1.4e-15 without it).  Cost: one extra step per flight, ~1.5-2.5x the per-impact time of
  ``"cooldown"`` in runs.

Chattering (Zeno) cannot be followed by any restart: the returns get shorter than the cooldown
(|v-| ~ 4e-12 at eps, once with a root-finding warning from heyoka) and the ball leaves through the
wall; the run ends with ``NO_IMPACT`` at the accumulation time (solve_ivp stalls there instead).
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..dynamics import impact as law
from ..dynamics.params import Params
from .methods import flight_loop

__all__ = ["available", "heyoka_version", "integrator", "compile_seconds", "heyoka_flight", "run_heyoka"]

EPS = float(np.finfo(float).eps)
#: Cooldown (in tau) of both terminal events: after an impact heyoka ignores that wall for this long
COOLDOWN = 1e-15
#: ``delta = OFFSET_ULPS * eps * (d/2) / |u|``: first step of a flight starting on a wall with no cooldown
OFFSET_ULPS = 10.0
RESTARTS = ("cooldown", "offset", "naive")

_CACHE: dict = {}  # (tol, cooldown) -> (integrator, compile seconds, state view, pars view)
#: Taylor steps taken by the event loop so far (read by :func:`stepping_cost`)
STEPS = [0]


def available() -> bool:
    """True when heyoka can be imported."""
    try:
        import heyoka  # noqa: F401
    except ImportError:
        return False
    return True


def heyoka_version() -> str | None:
    """heyoka's version string, or None when it is not installed."""
    if not available():
        return None
    import heyoka as hy

    return hy.__version__


def integrator(tol, cooldown=COOLDOWN):
    """The cached integrator for ``tol`` (compiled on first use; see :func:`compile_seconds`).

    ``cooldown`` of the wall events: a time, or a negative value for heyoka's automatic cooldown.
    """
    return _entry(tol, cooldown)[0]


def _entry(tol, cooldown):
    key = (float(tol), float(cooldown))
    if key not in _CACHE:
        import heyoka as hy

        start = time.perf_counter()
        z, v = hy.make_vars("Z", "V")
        events = [hy.t_event(z - 0.5 * hy.par[2], direction=hy.event_direction.positive, cooldown=key[1]),
                  hy.t_event(z + 0.5 * hy.par[2], direction=hy.event_direction.negative, cooldown=key[1])]
        ta = hy.taylor_adaptive([(z, v), (v, hy.cos(hy.par[0] + math.pi * hy.time) + hy.par[1])], [0.0, 0.0],
                                tol=key[0], pars=[0.0, 0.0, 1.0], t_events=events)
        # the views on the state and parameters stay valid: a scalar integrator never reallocates them
        _CACHE[key] = (ta, time.perf_counter() - start, ta.state, ta.pars)
    return _CACHE[key]


def compile_seconds(tol, cooldown=COOLDOWN) -> float:
    """Wall-clock seconds spent building the integrator for ``tol`` (builds it if needed).

    heyoka caches compiled code in memory and on disk (``heyoka.llvm_state.get_diskcache_path()``):
    a cold build costs far more than a cached one, so the build is timed apart from the runs.
    """
    return _entry(tol, cooldown)[1]


def _propagate(ta, state, pars, theta, z0, u, half, horizon, offset):
    """One flight on ``ta`` (``d`` and ``gbar`` already in ``pars``) from its current cooldowns:
    (tau, wall, Zdot-) or (inf, 0, nan).

    ``offset``: a flight starting exactly on a wall and moving off it first steps ``delta`` (module doc).
    """
    ta.time = 0.0
    state[0] = z0
    state[1] = u
    pars[0] = theta
    k = -1  # event index, from heyoka's outcome -(index + 1) of a stopping terminal event
    if offset and u != 0.0 and abs(z0) == half and (z0 > 0) != (u > 0):
        k = -int(ta.step(min(OFFSET_ULPS * EPS * half / abs(u), horizon))[0]) - 1
        STEPS[0] += 1
    if k != 0 and k != 1:
        res = ta.propagate_until(horizon)
        k = -int(res[0]) - 1
        STEPS[0] += int(res[3])
    if k == 0 or k == 1:
        return ta.time, 1 if k == 0 else -1, float(state[1])
    return math.inf, 0, math.nan


def heyoka_flight(theta, z0, u, d, gbar, tol, horizon=50.0, restart="offset"):
    """Next impact by heyoka with terminal events on both walls: (tau, wall, Zdot-) or (inf, 0, nan).

    A single flight has no previous event to cool down: the cooldowns are cleared and a start on a
    wall takes the offset step (``restart="naive"``: no offset, heyoka as is).
    """
    if restart not in ("offset", "naive"):
        raise ValueError(f"restart = {restart!r}; allowed: 'offset', 'naive'")
    ta, _, state, pars = _entry(tol, COOLDOWN)
    ta.reset_cooldowns()
    pars[1], pars[2] = gbar, d
    return _propagate(ta, state, pars, theta, z0, u, 0.5 * d, horizon, restart == "offset")


def run_heyoka(p: Params, phi, v0, n, *, tol, t_end=math.inf, max_seconds=60.0, horizon=50.0,
               restart="cooldown", cooldown=COOLDOWN):
    """Event loop with heyoka: restart a flight after each impact with Zdot+ = -r Zdot-.

    ``restart`` (module doc): ``"cooldown"`` keeps the cooldown heyoka sets at each impact across the
    restart (the first flight takes the offset step); ``"offset"`` clears it and takes the offset step
    every flight; ``"naive"`` clears it and nothing else.  The integrator is built before the clock
    starts; :func:`compile_seconds` gives that cost.
    """
    if restart not in RESTARTS:
        raise ValueError(f"restart = {restart!r}; allowed: {RESTARTS}")
    ta, _, state, pars = _entry(tol, cooldown)
    ta.reset_cooldowns()
    pars[1], pars[2] = p.gbar, p.d
    keep = restart == "cooldown"
    half = 0.5 * p.d

    def flight(theta, z, u, k):
        if not keep:
            ta.reset_cooldowns()
        return _propagate(ta, state, pars, theta, z, u, half, horizon, restart == "offset" or (keep and k == 0))

    return flight_loop(flight, p, phi, v0, n, t_end=t_end, max_seconds=max_seconds, errors=(ValueError, RuntimeError))


def stepping_timer(p: Params, phi, v0, n, *, tol):
    """:func:`stepping_cost` in two parts, so that its timed runs can be interleaved with other
    timings: returns ``(timed, result)``; ``timed()`` runs the propagation once from the same state and
    returns its seconds, ``result(seconds)`` the cost dictionary for the fastest of them."""
    import heyoka as hy

    ta_ev = integrator(tol)
    ta_ev.reset_cooldowns()
    STEPS[0] = 0
    run = run_heyoka(p, phi, v0, n, tol=tol)
    steps = STEPS[0]
    span = float(run.t[-1])
    z, v = hy.make_vars("Z", "V")
    ta = hy.taylor_adaptive([(z, v), (v, hy.cos(hy.par[0] + math.pi * hy.time) + hy.par[1])],
                            [0.5 * p.d, law.rebound(v0, p.r)],
                            tol=float(tol), pars=[phi, p.gbar])
    ta.propagate_until(1.0)  # touch the compiled code outside the clock
    last = {}

    def timed():
        ta.time = 0.0
        ta.state[:] = [0.5 * p.d, law.rebound(v0, p.r)]
        start = time.perf_counter()
        last["free"] = ta.propagate_until(span)
        return time.perf_counter() - start

    def result(seconds):
        timed_steps = int(last["free"][3])
        per_step = seconds / max(timed_steps, 1)
        return dict(us_per_impact=per_step * steps / len(run.t) * 1e6, steps_per_impact=steps / len(run.t),
                    us_per_step=per_step * 1e6, loop_us_per_impact=run.seconds / len(run.t) * 1e6,
                    span=span, free_end=(float(ta.state[0]), float(ta.state[1])), timed_steps=timed_steps)

    return timed, result


def stepping_cost(p: Params, phi, v0, n, *, tol, repeats: int = 1) -> dict:
    """heyoka's cost per impact without any Python in the loop: the seconds per Taylor step of one
    ``propagate_until`` over the time ``n`` impacts of :func:`run_heyoka` span (same equations and
    tolerance, no events), times the steps per impact that event loop took.  ``free_end``: the timed
    propagation's final (Z, Zdot) at ``span``, from a bottom impact at phase ``phi`` (Zdot+ the impact law's rebound of v0).

    This is the floor a user driving heyoka from C++ would approach; the propagation is timed
    ``repeats`` times from the same state and the fastest counts.  Returns ``us_per_impact``,
    ``steps_per_impact``, ``us_per_step``, the event loop's own ``loop_us_per_impact`` and the timed
    propagation's ``timed_steps``."""
    timed, result = stepping_timer(p, phi, v0, n, tol=tol)
    return result(min(timed() for _ in range(max(int(repeats), 1))))
