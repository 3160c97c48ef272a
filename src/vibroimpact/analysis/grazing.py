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
    n = walls.shape[0]
    theta = z[0]
    tau = z[1:n + 1]
    v = z[n + 1:]
    clearance = math.inf
    reason = ""
    for j in range(n):
        jn = (j + 1) % n
        speed = walls[j] * v[j]
        clearance = min(clearance, speed)
        if speed <= 0 and not reason:
            reason = f"impact {j} ({'B' if walls[j] == 1 else 'T'}): pre-impact velocity {v[j]:.3g} does not point into its wall"
        z0 = walls[j] * 0.5 * d
        u = law.rebound(v[j], r)
        clearance = min(clearance, interior_clearance(theta, z0, u, d, gbar, tau[j]))
        if not reason and speed > 0:
            t_hit, w_hit = next_impact(theta, z0, u, d, gbar, tau[j] * (1 + 1e-9) + 1e-12)
            if w_hit == 0 or w_hit != walls[jn] or abs(t_hit - tau[j]) > 1e-8 * max(1.0, tau[j]):
                where = "no wall" if w_hit == 0 else ("the bottom" if w_hit == 1 else "the top")
                reason = f"flight {j}: the ball meets {where} at tau={t_hit:.6g} before the orbit's impact at {tau[j]:.6g}"
        theta = (theta + PI * tau[j]) % TWO_PI
    return (not reason), reason, float(clearance)


__all__ = ["admissibility", "interior_clearance"]
