"""Admissibility of periodic orbits and the test functions whose zeros are grazing points.

An orbit solved from its impact maps is a physical motion only if (i) every pre-impact velocity
points into its wall and (ii) every flight stays strictly inside ``|Z| < d/2`` between its impacts.
(ii) is checked with the simulator's guaranteed impact location: the first impact of each flight
must be the orbit's next impact.  Its margin is the *clearance*: the distance from the nearer wall
of every interior extremum of ``Z`` (maxima against the bottom, minima against the top).  Grazing
points are where a clearance or an impact velocity reaches zero (docs/guide/model.md).
"""

from __future__ import annotations

import math

from numba import njit

from ..dynamics import impact as law
from ..dynamics.events import ROOT_VELOCITY, next_accel_zero, next_impact, rtsafe
from ..dynamics.flight import PI, TWO_PI, displacement, velocity


@njit(cache=True, error_model="numpy")
def interior_clearance(theta, z0, u, d, gbar, tau_end):
    """Smallest distance to a wall of the interior extrema of one flight on ``(0, tau_end)``.

    A maximum counts against the bottom wall (``d/2 - Z``), a minimum against the top (``Z + d/2``).
    Returns ``inf`` when the flight has no interior extremum.
    """
    theta = theta % TWO_PI
    c = math.cos(theta)
    s = math.sin(theta)
    has_zeros = gbar < 1.0
    alpha = math.acos(-gbar) if has_zeros else 0.0
    best = math.inf
    ta = 0.0
    va = u
    while ta < tau_end:
        tb = next_accel_zero(ta, theta, alpha) if has_zeros else ta + 2.0
        if tb > tau_end:
            tb = tau_end
        vb = velocity(tb, c, s, u, gbar)
        if (va < 0.0 and vb > 0.0) or (va > 0.0 and vb < 0.0):
            te = rtsafe(ROOT_VELOCITY, ta, tb, va, vb, math.nan, math.nan, c, s, 0.0, u, gbar)[0]
            if 0.0 < te < tau_end:
                ze = z0 + displacement(te, c, s, u, gbar)
                gap = 0.5 * d - ze if va > 0.0 else ze + 0.5 * d
                best = min(best, gap)
        ta = tb
        va = vb
    return best


def admissibility(z, walls, d, gbar, r):
    """``(admissible, reason, clearance)`` of the orbit with unknown vector ``z``.

    ``clearance`` is the smallest of the interior clearances and of the impact speeds (``w_j v_j``),
    so that it is positive for an admissible orbit and changes sign at a grazing point.
    """
    clearance, kind, j, t_hit, w_hit = _flights_admissible(z, walls, d, gbar, r)
    reason = ""
    if kind == 1:
        v = z[walls.shape[0] + 1 + j]
        reason = f"impact {j} ({'B' if walls[j] == 1 else 'T'}): pre-impact velocity {v:.3g} does not point into its wall"
    elif kind == 2:
        where = "no wall" if w_hit == 0 else ("the bottom" if w_hit == 1 else "the top")
        reason = f"flight {j}: the ball meets {where} at tau={t_hit:.6g} before the orbit's impact at {z[1 + j]:.6g}"
    return (not reason), reason, float(clearance)


@njit(cache=True, error_model="numpy")
def _flights_admissible(z, walls, d, gbar, r):
    """The flights' check of :func:`admissibility`, compiled (a continuation checks every point it accepts): the
    clearance, and what makes the orbit inadmissible first (``kind`` 0: nothing; 1: impact ``j``'s velocity
    does not point into its wall; 2: flight ``j`` meets wall ``w_hit`` at ``t_hit``, not the orbit's next
    impact).  Every operation in the interpreted loop's order (``min`` and ``max`` as Python's: the first
    argument unless the second is smaller, larger): the same results to the last bit."""
    n = walls.shape[0]
    theta = z[0]
    clearance = math.inf
    kind, jbad, t_bad, w_bad = 0, -1, 0.0, 0
    for j in range(n):
        jn = (j + 1) % n
        tau_j, v_j = z[1 + j], z[n + 1 + j]
        speed = walls[j] * v_j
        if speed < clearance:
            clearance = speed
        if speed <= 0 and kind == 0:
            kind, jbad = 1, j
        z0 = walls[j] * 0.5 * d
        u = law.rebound(v_j, r)
        inner = interior_clearance(theta, z0, u, d, gbar, tau_j)
        if inner < clearance:
            clearance = inner
        if kind == 0 and speed > 0:
            t_hit, w_hit = next_impact(theta, z0, u, d, gbar, tau_j * (1 + 1e-9) + 1e-12)
            scale = tau_j if tau_j > 1.0 else 1.0
            if w_hit == 0 or w_hit != walls[jn] or abs(t_hit - tau_j) > 1e-8 * scale:
                kind, jbad, t_bad, w_bad = 2, j, t_hit, w_hit
        theta = (theta + PI * tau_j) % TWO_PI
    return clearance, kind, jbad, t_bad, w_bad


__all__ = ["admissibility", "interior_clearance"]
