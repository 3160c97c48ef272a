"""Independent high-precision reference for impact times (mpmath, 40 digits).

Uses the paper's form of the flight (eq. ``z_t``: F1, F2 of the phase), not the package's
rewritten form, and locates roots by dense sampling plus bracketed refinement, not by the
package's monotone-segment algorithm.
"""

import math

import mpmath as mp
import numpy as np

mp.mp.dps = 40
PI = mp.pi


def gap(theta, z0, u, gbar, wall_z):
    theta, z0, u, gbar, wall_z = (mp.mpf(x) for x in (theta, z0, u, gbar, wall_z))
    F1_0 = mp.sin(theta) / PI
    F2_0 = -mp.cos(theta) / PI**2

    def f(tau):
        tau = mp.mpf(tau)
        return (z0 + u * tau + gbar / 2 * tau**2 - mp.cos(theta + PI * tau) / PI**2 - F2_0 - F1_0 * tau) - wall_z

    return f


def velocity(theta, u, gbar):
    theta, u, gbar = (mp.mpf(x) for x in (theta, u, gbar))
    return lambda tau: u + gbar * tau + (mp.sin(theta + PI * tau) - mp.sin(theta)) / PI


def first_impact(theta, z0, u, d, gbar, horizon=12.0, step=2e-4):
    """First crossing of a wall by sampling then refining in mpmath. Returns (tau, wall, min_clearance).

    ``min_clearance`` is the closest sampled approach to a wall before the crossing, so a caller can
    discard states whose sampling could hide a tangency.  The state may be given as floats or as
    mpmath numbers: the sampling rounds it to floats, the refinement uses it as given.
    """
    tau = np.arange(0.0, horizon, step)[1:]
    th, zf, uf, gf, df = float(theta), float(z0), float(u), float(gbar), float(d)
    z = zf + uf * tau + gf / 2 * tau**2 - (np.cos(th + np.pi * tau) - np.cos(th)) / np.pi**2 - np.sin(th) / np.pi * tau
    above = z >= df / 2
    below = z <= -df / 2
    hit = np.flatnonzero(above | below)
    if hit.size == 0:
        return math.inf, 0, float(np.min(df / 2 - np.abs(z)))
    k = hit[0]
    wall = 1 if above[k] else -1
    clearance = float(np.min(df / 2 - np.abs(z[:k]))) if k > 0 else math.inf
    lo = tau[k - 1] if k > 0 else 0.0
    f = gap(theta, z0, u, gbar, wall * d / 2)
    return _bracketed_root(f, lo, tau[k]), wall, clearance


def grazing_state(theta_e, tau_e, d, gbar, wall, eps):
    """A state (theta0, z0, u0) whose flight has an extremum at tau_e with Z = wall*(d/2 - eps).

    ``eps > 0``: passes inside the wall by eps (a near miss); ``eps < 0``: crosses it by |eps|.
    Built backwards from the extremum in mpmath and rounded to doubles.
    """
    th_e = mp.mpf(theta_e)
    th0 = th_e - PI * mp.mpf(tau_e)
    g = mp.mpf(gbar)
    te = mp.mpf(tau_e)
    u0 = -(g * te + (mp.sin(th_e) - mp.sin(th0)) / PI)
    ze = wall * (mp.mpf(d) / 2 - mp.mpf(eps))
    disp = u0 * te + g / 2 * te**2 - (mp.cos(th_e) - mp.cos(th0)) / PI**2 - mp.sin(th0) / PI * te
    z0 = ze - disp
    return float(th0 % (2 * PI)), float(z0), float(u0)


def trajectory(d, gbar, r, phi, v0, n, horizon=12.0, step=2e-4):
    """The first ``n`` impacts after a bottom impact at phase ``phi`` with pre-impact velocity ``v0``
    (paper convention), chained in 40-digit arithmetic: ``(t, wall, Zdot-)`` as mpf lists.

    Each flight is bracketed by dense float sampling and refined in mpmath from the mpmath state, so
    rounding does not accumulate along the run; the package's impact location is not used.
    """
    d, gbar, r = mp.mpf(d), mp.mpf(gbar), mp.mpf(r)
    theta = mp.mpf(phi)
    z0 = d / 2
    u = -r * mp.mpf(v0)
    t = mp.mpf(0)
    out = []
    for _ in range(n):
        tau, wall, _ = first_impact(theta, z0, u, d, gbar, horizon, step)
        if wall == 0:
            break
        v = velocity(theta, u, gbar)(tau)
        t += tau
        theta = theta + PI * tau
        z0 = wall * d / 2
        u = -r * v
        out.append((t, wall, v))
    return out


def _bracketed_root(f, lo, hi):
    """Root of f in [lo, hi] (a sign change): Anderson-Bjorck, or bisection where it stalls."""
    try:
        return mp.findroot(f, (mp.mpf(lo), mp.mpf(hi)), solver="anderson")
    except ValueError:
        return mp.findroot(f, (mp.mpf(lo), mp.mpf(hi)), solver="bisect", verify=False)
