"""Independent high-precision reference for impact times (mpmath, 40 digits).

Uses the paper's form of the flight (eq. ``z_t``: F1, F2 of the phase), not the package's
rewritten form, and locates roots by dense sampling plus bracketed refinement, not by the
package's monotone-segment algorithm.  The one thing it shares with the package is the impact law
(:mod:`~vibroimpact.dynamics.impact`), in its Python form.
"""

import math

import mpmath as mp
import numpy as np

from . import impact as law

mp.mp.dps = 40
PI = mp.pi


def rebound(v, r):
    """The impact law's :func:`~vibroimpact.dynamics.impact.rebound` on mpmath's numbers."""
    return law.rebound.py_func(v, r)


def rebound_slope(v, r):
    """The impact law's :func:`~vibroimpact.dynamics.impact.rebound_slope` on mpmath's numbers."""
    return law.rebound_slope.py_func(v, r)


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
    u = rebound(mp.mpf(v0), r)
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
        u = rebound(v, r)
        out.append((t, wall, v))
    return out


def _bracketed_root(f, lo, hi):
    """Root of f in [lo, hi] (a sign change): Anderson-Bjorck, or bisection where it stalls."""
    try:
        return mp.findroot(f, (mp.mpf(lo), mp.mpf(hi)), solver="anderson")
    except ValueError:
        return mp.findroot(f, (mp.mpf(lo), mp.mpf(hi)), solver="bisect", verify=False)


# ---------------------------------------------------------------------------------------------
# Chattering bounce by bounce (no accumulation rule): the reference for sticking and release
# ---------------------------------------------------------------------------------------------


def _first_crossing(fns, fns_float, tau_min, horizon, per_decade=8, step=1e-3):
    """First ``tau`` in ``(0, horizon]`` where one of ``fns`` (mpmath callables, positive at the
    start) becomes ``<= 0``; ``(tau, index)`` or ``(inf, -1)``.

    Sampled on a logarithmic grid from ``tau_min`` to 1e-2 in mpmath (short chattering flights need
    the extra digits), then on a linear grid of ``step`` in floats (``fns_float``: the same
    functions on NumPy arrays); the bracketing pair of samples is refined in mpmath.
    """
    lo = mp.mpf(0)
    if tau_min < 1e-2:
        n = max(2, int(math.ceil(per_decade * math.log10(1e-2 / tau_min))))
        for x in np.logspace(math.log10(tau_min), -2, n):
            x = mp.mpf(x)
            for k, f in enumerate(fns):
                if f(x) <= 0:
                    return _bracketed_root(f, lo, x), k
            lo = x
    grid = np.arange(float(lo) + step, horizon + step, step)
    vals = np.array([f(grid) for f in fns_float])
    hit = np.flatnonzero((vals <= 0).any(axis=0))
    if hit.size == 0:
        return mp.inf, -1
    i = hit[0]
    k = int(np.flatnonzero(vals[:, i] <= 0)[0])
    a = grid[i - 1] if i > 0 else lo
    # the float samples can misjudge a value within rounding of zero: confirm the bracket in mpmath
    a = mp.mpf(a)
    if fns[k](a) <= 0:
        a = lo
    return _bracketed_root(fns[k], a, mp.mpf(grid[i])), k


def _displacement_mp(theta, u, gbar):
    """Z(tau) - Z(0) of a flight in the paper's form (eq. ``z_t``), in mpmath."""
    F1_0, cos0 = mp.sin(theta) / PI, mp.cos(theta)
    return lambda tau: u * tau + gbar / 2 * tau**2 - (mp.cos(theta + PI * tau) - cos0) / PI**2 - F1_0 * tau


def _displacement_float(theta, u, gbar):
    th, uf, gf = float(theta), float(u), float(gbar)
    return lambda tau: uf * tau + gf / 2 * tau**2 - (np.cos(th + np.pi * tau) - np.cos(th)) / np.pi**2 - np.sin(th) / np.pi * tau


def _slow_restitution(u, r):
    """The impact law's restitution in the limit of slow impacts, ``-rebound_slope(0)`` (``r`` itself for a
    constant restitution), on ``u``'s number type: the ratio of the geometric sum of the last bounces of a
    chattering sequence, exact for a constant restitution and to first order in ``|u|`` otherwise."""
    return -rebound_slope(0 * u, r)


def bounce_by_bounce(theta0, z0, u0, d, gbar, r, *, t_end, v_rest=1e-25, dps=60, max_events=2000, horizon=12.0):
    """Events of the motion from ``(theta0, z0, u0)`` until ``t_end``, every bounce of every chattering
    sequence chained as an exact flight in ``dps``-digit arithmetic: no accumulation rule.

    A chattering sequence is ended only when the rebound speed is below ``v_rest`` (1e-25): the
    remaining bounces then last less than ``2 v_rest / ((1 - r) a)`` (``r`` the restitution of slow impacts,
    :func:`_slow_restitution`), far below any tolerance.  The ball then rests on the wall until the relative acceleration stops pushing it in (a root of
    ``w (cos(theta) + gbar)`` found by sampling, not by a formula) and leaves with zero velocity.

    Returns a list of ``(kind, t, wall, Zdot-)`` with ``kind`` in ``"impact", "stick", "release"``
    (mpmath numbers), times measured from the start.
    """
    with mp.workdps(dps):
        d, gbar, r = mp.mpf(d), mp.mpf(gbar), mp.mpf(r)
        theta, z, u, t = mp.mpf(theta0), mp.mpf(z0), mp.mpf(u0), mp.mpf(0)
        half = d / 2
        out = []
        released = False  # just released: the acceleration is zero there and turns away from the wall
        while t < t_end and len(out) < max_events:
            wall = 1 if z == half else (-1 if z == -half else 0)
            push = wall * (mp.cos(theta) + gbar)
            if wall and push > 0 and abs(u) < v_rest and not released:
                rho = _slow_restitution(u, r)
                t += 2 * abs(u) / ((1 - rho) * push)
                theta += PI * 2 * abs(u) / ((1 - rho) * push)
                out.append(("stick", t, wall, mp.mpf(0)))
                th = theta
                tau, _ = _first_crossing([lambda x: wall * (mp.cos(th + PI * x) + gbar)],
                                         [lambda x: wall * (np.cos(float(th) + np.pi * x) + float(gbar))],
                                         1e-30, horizon)
                if tau == mp.inf:
                    return out  # never released (gbar >= 1 on the bottom)
                # a root rounded to the near side leaves a push of ~10^-dps, which would start a new
                # chattering sequence of that size: step past it (10^(10 - dps) in time)
                while wall * (mp.cos(th + PI * tau) + gbar) > 0:
                    tau += mp.mpf(10) ** (10 - dps)
                t += tau
                theta += PI * tau
                u = mp.mpf(0)
                out.append(("release", t, wall, mp.mpf(0)))
                released = True
                continue
            released = False
            disp, disp_f = _displacement_mp(theta, u, gbar), _displacement_float(theta, u, gbar)
            # inside gaps: to the bottom (d/2 - Z) and to the top (Z + d/2), both positive in flight
            fns = [lambda x: half - z - disp(x), lambda x: z + half + disp(x)]
            fns_f = [lambda x: float(half - z) - disp_f(x), lambda x: float(z + half) + disp_f(x)]
            # a flight leaving a wall with speed |u| cannot return before |u| / (1 + gbar); one from rest
            # (released) moves away as tau^3: sampling starts where that is far above the rounding
            tau_min = (float(abs(u)) / (1 + float(gbar)) if u != 0 else 1e-8) if wall else 1e-12
            tau, k = _first_crossing(fns, fns_f, tau_min, horizon)
            if tau == mp.inf:
                return out
            w = 1 if k == 0 else -1
            v = velocity(theta, u, gbar)(tau)
            t += tau
            theta += PI * tau
            z = w * half
            u = rebound(v, r)
            out.append(("impact", t, w, v))
        return out
