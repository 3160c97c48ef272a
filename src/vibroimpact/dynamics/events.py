"""Guaranteed location of the next impact (docs/guide/model.md).

Why it cannot miss: ``Z'' = cos(pi t + phi) + gbar`` vanishes at explicitly known phases
(``cos = -gbar``), so ``Zdot`` is monotone between them and has at most one root there; that root
is bracketed and found.  Between consecutive roots of ``Zdot`` (and the zeros of ``Z''``), ``Z`` is
monotone, so it meets a wall at most once and only if the wall value lies between ``Z`` at the
ends.  Every crossing, including a tangential (grazing) contact at an extremum, is therefore
bracketed; no step size is involved.  A near miss is decided by the sign of the gap at the
extremum, evaluated in double-double arithmetic when it is within 1e-12 of the wall.

Roots are found by Householder's third-order method (the point's first three derivatives come with
it) safeguarded by bisection (``rtsafe``'s safeguards), started at the secant point moved by one
Newton step on the cubic Hermite interpolant of the end values and slopes.  A crossing with small impact
velocity is ill-conditioned in time (``dt = dZ / Zdot``), so it is polished on the double-double gap
by steps that solve its local quadratic.

Shortcuts that keep the guarantee: ``Z`` is convex or concave between zeros of ``Z''``, so an
extremum lies below the tangents at both ends of its piece.  Where the tangents meet short of the
wall the ball moves to, the extremum is not located at all; the only possible hit is then on the way
back, where the gap has one root on the piece (a flight that returns to the wall it left has a root
at its start too: the chord slope ``(Z(x) - Z(0)) / x``, monotone, has only the impact).  Where the
tangents meet past the wall, the gap there is evaluated; past the wall by more than ``DD_MARGIN``,
it brackets the hit without the extremum.

Cost: every point is evaluated once for its displacement, velocity, acceleration and jerk from one
sine and cosine of half the angle travelled (:func:`~vibroimpact.dynamics.flight.kinematics`); within a root
search each new point within a short step of the last takes them from it by Taylor polynomials
(:func:`~vibroimpact.dynamics.flight.state_step`, no trigonometric call); at a zero of the acceleration they
follow from ``cos = -gbar`` by angle subtraction.  The event loop carries the phase's cosine and
sine.  About 3.7-4.6 points and 4-5.3 trigonometric calls per impact
(``vibroimpact.benchmarks.bench.kernel_profile``).  Compiled with numba's ``numpy`` error model: no check per
division (every divisor here is nonzero by construction or tested first).
"""

import math

import numpy as np
from numba import njit

from .flight import (
    INV_PI,
    NEAR_STEP,
    PI,
    TWO_PI,
    gap_dd,
    kinematics,
    state_from_sc,
    state_step,
    velocity,
)

#: Below this |Zdot-| an impact time is polished in double-double arithmetic.
POLISH_SPEED = 1e-3
#: Within this distance of a wall a near-extremum hit/miss decision is made in double-double.
DD_MARGIN = 1e-12
#: An arrival speed below this is rounding (the velocity is a sum of terms of order 1, each rounded
#: to ~1e-16): a hit found with such a speed pointing out of its wall arrives at zero speed.
ZERO_SPEED = 1e-15


@njit(cache=True, error_model="numpy")
def accel_zero(tau, theta, alpha):
    """Smallest local time ``t > tau`` where ``cos(theta + pi t) = -gbar`` (``alpha = arccos(-gbar)``),
    and the sign of ``sin(theta + pi t)`` there: +1 at the phase ``alpha``, -1 at ``2 pi - alpha``."""
    psi = theta + PI * tau
    base = math.floor(psi / TWO_PI) * TWO_PI
    for k in range(3):
        cand = base + (alpha, TWO_PI - alpha, TWO_PI + alpha)[k]
        if cand > psi:
            t = (cand - theta) / PI
            if t > tau:
                return t, (1.0, -1.0, 1.0)[k]
    return (base + TWO_PI * 2 - alpha - theta) / PI, -1.0


@njit(cache=True, error_model="numpy")
def next_accel_zero(tau, theta, alpha):
    """Smallest local time > ``tau`` where ``cos(theta + pi t) = -gbar`` (``alpha = arccos(-gbar)``)."""
    return accel_zero(tau, theta, alpha)[0]


@njit(cache=True, error_model="numpy")
def _hermite_start(lo, hi, flo, fhi, dflo, dfhi):
    """Start for a root search on [lo, hi]: one Newton step on the cubic Hermite interpolant of f
    (values and slopes at both ends, all known there) from the secant point; the secant point when
    that step leaves the interval.  One step measured fastest: 4.0 points per impact on the 2:1 scene
    against 4.3 with four steps on the cubic, each of which costs about as much as a true evaluation."""
    h = hi - lo
    m0 = h * dflo
    m1 = h * dfhi
    dl = fhi - flo
    a2 = 3.0 * dl - 2.0 * m0 - m1
    a3 = m0 + m1 - 2.0 * dl
    x = flo / (flo - fhi)
    hv = flo + x * (m0 + x * (a2 + x * a3))
    dh = m0 + x * (2.0 * a2 + 3.0 * x * a3)
    if dh != 0.0:
        xn = x - hv / dh
        if xn > 0.0 and xn < 1.0:
            x = xn
    if not (x > 0.0 and x < 1.0):
        x = 0.5
    return lo + x * h


@njit(cache=True, error_model="numpy")
def _done(step, x, df, d2f, d3f):
    """Is the root within rounding of ``x - step``?  Halley's error after the step would be about
    ``K step^3`` with ``K = (f''/2f')^2 + |f'''/6f'|``; stop when that is below 1e-17 of ``|x|``.
    The fourth-order step actually taken leaves less (``O(step^4)``), so the test is conservative."""
    if abs(step) <= 2.2e-16 * max(abs(x), 1e-300):
        return True
    if df == 0.0 or abs(step) > 1e-4:
        return False
    # K |step|^3 <= 1e-17 |x| multiplied through by f'^2: no division
    return (0.25 * d2f * d2f + abs(d3f * df) * (1.0 / 6.0)) * step * step * abs(step) <= 1e-17 * max(abs(x), 1e-300) * df * df


#: :func:`rtsafe`'s ``which``: the root of the velocity, of the gap to a wall, of the chord slope of a
#: flight that returns to the wall it left. NumPy integers, not Python ones: numba types a Python integer
#: passed to a call (written out or named as a global) as a literal and compiles the callee once per value;
#: each copy of the search cost about a second of a first run's compile, for no measurable speed.
ROOT_VELOCITY, ROOT_GAP, ROOT_CHORD = np.int64(0), np.int64(1), np.int64(2)


@njit(cache=True, error_model="numpy")
def rtsafe(which, lo, hi, flo, fhi, dflo, dfhi, c, s, z0w, u, gbar):
    """Root of a monotone function on [lo, hi] with f(lo), f(hi) of opposite sign (or zero):
    ``which`` :data:`ROOT_VELOCITY` Zdot, :data:`ROOT_GAP` the gap ``Z - wall`` (``z0w`` its value at the
    flight's start), :data:`ROOT_CHORD` the slope ``(Z(x) - Z(0)) / x`` of a flight that starts on the wall it
    returns to;
    ``dflo``, ``dfhi`` its slopes at the ends (NaN if unknown: the search starts at the midpoint).

    Householder's third-order method (fourth-order convergence: the second and third derivatives
    come with the same evaluation) from the secant point moved by one Newton step on the cubic
    Hermite interpolant (:func:`_hermite_start`), safeguarded as rtsafe is: bisection where even
    Newton's step would not halve the bracket (a flat f) and where the step leaves it.  It stops when
    the last step leaves an error at rounding level (:func:`_done`).  After the first point, each new
    point within a short step of the last is propagated from it by Taylor polynomials, with no
    trigonometric call (:func:`~vibroimpact.dynamics.flight.state_step`).

    Returns ``(x, disp, vel)``: the root and the displacement and velocity there, from the last
    evaluated point by Taylor's formula (its distance to the root is below 1e-5, or the bracket's
    width of a few ulps), so no further evaluation is needed."""
    if flo == 0.0 or fhi == 0.0:
        x = lo if flo == 0.0 else hi
        disp, vel, _, _ = kinematics(x, c, s, u, gbar)
        return x, disp, vel
    # orient so that f(xl) < 0 < f(xh)
    if flo < 0.0:
        xl, xh = lo, hi
    else:
        xl, xh = hi, lo
    if dflo == dflo and dfhi == dfhi:
        x = _hermite_start(lo, hi, flo, fhi, dflo, dfhi)
    else:
        x = 0.5 * (lo + hi)
    dxold = abs(hi - lo)
    dx = dxold
    disp, vel, acc, jerk = kinematics(x, c, s, u, gbar)
    xe = x
    for _ in range(200):
        if which == 0:
            f, df, d2f, d3f = vel, acc, jerk, -PI * PI * (acc - gbar)
        elif which == 1:
            f, df, d2f, d3f = z0w + disp, vel, acc, jerk
        else:
            f = disp / x
            df = (vel - f) / x
            d2f = (acc - 2.0 * df) / x
            d3f = (jerk - 3.0 * d2f) / x
        if f == 0.0:
            return x, disp, vel
        if f < 0.0:
            xl = x
        else:
            xh = x
        # Householder's third-order step (fourth-order convergence: the third derivative comes with
        # the point as well)
        num = 2.0 * df * df - f * d2f
        den = 3.0 * df * num - f * (3.0 * df * d2f - f * d3f)
        step = 3.0 * f * num / den if den != 0.0 else 0.0
        xn = x - step
        if den == 0.0 or abs(2.0 * f) > abs(dxold * df) or (xn - xh) * (xn - xl) > 0.0:
            dxold = dx
            dx = 0.5 * (xh - xl)
            x = xl + dx
            fast = False
        else:
            dxold = dx
            dx = step
            x = xn
            fast = True
        if (fast and _done(dx, x, df, d2f, d3f)) or abs(xh - xl) <= 4.4e-16 * max(abs(x), 1e-300):
            h = x - xe
            return x, disp + h * (vel + 0.5 * h * acc), vel + h * (acc + 0.5 * h * jerk)
        h = x - xe
        if abs(PI * h) < NEAR_STEP:
            disp, vel, acc, jerk = state_step(h, disp, vel, acc, jerk, gbar)
        else:
            disp, vel, acc, jerk = kinematics(x, c, s, u, gbar)
        xe = x
    return x, disp, vel


#: A flight's extremum is skipped without locating it when the tangent bound keeps it this far
#: from the wall it moves to (far above the bound's rounding error, about 1e-15).
SKIP_MARGIN = 1e-9


@njit(cache=True, error_model="numpy")
def _gap_sign_dd(tau, theta, z0w, u, gbar, g):
    """Gap at an extremum, re-evaluated in double-double when it is within DD_MARGIN of zero."""
    if abs(g) < DD_MARGIN:
        return gap_dd(tau, theta, z0w, u, gbar)
    return g


@njit(cache=True, error_model="numpy")
def _polish(tau, lo, hi, theta, c, s, z0w, u, gbar):
    """Steps on the double-double gap, kept inside [lo, hi]: each solves the local quadratic
    ``g + v h + a h^2 / 2 = 0`` for the root nearest to ``tau``, which converges fast even where the
    impact is slow (a Newton step ``g / v`` only halves the error there once ``|h| > |v / a|``)."""
    for _ in range(6):
        _, v, a, _ = kinematics(tau, c, s, u, gbar)
        g = gap_dd(tau, theta, z0w, u, gbar)
        disc = v * v - 2.0 * a * g
        if disc > 0.0 and v != 0.0:
            step = 2.0 * g / (v + math.copysign(math.sqrt(disc), v))
        elif v != 0.0:
            step = g / v
        else:
            break
        new = tau - step
        if new < lo:
            new = lo
        elif new > hi:
            new = hi
        if new == tau:
            break
        tau = new
    return tau


@njit(cache=True, error_model="numpy", inline="always")
def _finish_hit(t, v, lo, hi, theta, c, s, z0w, u, gbar, sg):
    """Finish a hit: ``(t, wall, Zdot-)`` of the hit on the wall on side ``sg`` (+1 bottom) at ``t`` with velocity
    ``v``, polished in double-double when the impact is slow (:func:`_polish`)."""
    if abs(v) < POLISH_SPEED:
        t = _polish(t, lo, hi, theta, c, s, z0w, u, gbar)
        v = velocity(t, c, s, u, gbar)
        if sg * v < 0.0 and abs(v) < ZERO_SPEED:
            # a crossing into the wall (bracketed as one) whose speed is below the velocity's
            # rounding error: it arrives at zero speed, not out of the wall
            v = 0.0
    return t, 1 if sg > 0.0 else -1, v


@njit(cache=True, error_model="numpy")
def next_impact(theta, z0, u, d, gbar, tau_max):
    """First impact of the flight that starts at phase ``theta``, position ``z0``, velocity ``u``.

    Parameters
    ----------
    theta : float
        Forcing phase ``pi t + phi`` at the flight's start (any real; reduced internally).
    z0, u : float
        Position (``|z0| <= d/2``) and velocity at the start.
    d, gbar : float
        Model parameters.
    tau_max : float
        Give up after this flight time (may be ``inf`` when ``gbar > 0``).

    Returns
    -------
    tau : float
        Flight time to the impact (``inf`` if none before ``tau_max``).
    wall : int
        +1 bottom (``Z = d/2``), -1 top (``Z = -d/2``), 0 none.
    """
    theta = theta % TWO_PI
    alpha = math.acos(-gbar) if gbar < 1.0 else 0.0
    tau, wall, _ = flight_impact(theta, math.cos(theta), math.sin(theta), alpha, z0, u, d, gbar, tau_max)
    return tau, wall


@njit(cache=True, error_model="numpy", inline="always")
def flight_impact(theta, c, s, alpha, z0, u, d, gbar, tau_max):
    """:func:`next_impact` for the event loop: the start phase ``theta`` in [0, 2 pi) with its cosine
    ``c`` and sine ``s``, and ``alpha = arccos(-gbar)`` (any value when ``gbar >= 1``), computed once
    by the caller; returns ``(tau, wall, Zdot-)`` (``(inf, 0, nan)`` if no impact).

    Every point is evaluated once, for its displacement, velocity and acceleration together
    (:func:`~vibroimpact.dynamics.flight.kinematics`).  Compiled into its callers (``inline="always"``:
    the event loop of :mod:`~vibroimpact.dynamics.kernels` and :func:`next_impact`), which spares the
    event loop a call per flight; the operations are the same, and so are the results to the last bit
    (inlining :func:`rtsafe` as well measured no faster)."""
    half = 0.5 * d
    has_zeros = gbar < 1.0
    sa = math.sqrt(1.0 - gbar * gbar) if has_zeros else 0.0  # sin(alpha)
    z0b = z0 - half  # gap to the bottom wall (exact 0 when starting there)
    z0t = z0 + half  # gap to the top wall
    ta = 0.0
    va = u
    da = 0.0
    aa = c + gbar
    # index of the next zero of the acceleration (theta is in [0, 2 pi))
    nz = 0 if alpha > theta else (1 if TWO_PI - alpha > theta else 2)
    for _ in range(100000):
        if ta >= tau_max:
            return math.inf, 0, math.nan
        sgn = 0.0
        if has_zeros:
            # the acceleration's zeros in order: phases alpha, 2 pi - alpha, 2 pi + alpha, ...
            tb = ((nz // 2) * TWO_PI + (alpha if nz % 2 == 0 else TWO_PI - alpha) - theta) * INV_PI
            sgn = 1.0 if nz % 2 == 0 else -1.0
            nz += 1
        else:
            tb = ta + 2.0
        last = False
        if tb >= tau_max:
            tb = tau_max
            last = True
        if sgn != 0.0 and not last and PI * tb >= 0.25:
            # at a zero of the acceleration cos(theta + pi tb) = -gbar is known, and so is the sine:
            # x = pi tb by angle subtraction, no trigonometric call (away from the flight's start,
            # where 1 - cos x would lose digits)
            sp = sgn * sa
            cx = -gbar * c + sp * s
            db, vb, ab, jb = state_from_sc(tb, sp * c + gbar * s, 1.0 - cx, c, s, u, gbar)
        else:
            db, vb, ab, jb = kinematics(tb, c, s, u, gbar)
        # split at the root of Zdot (Zdot is monotone on [ta, tb])
        n_sub = 1
        te = tb
        de = db
        ve = vb
        if (va < 0.0 and vb > 0.0) or (va > 0.0 and vb < 0.0):
            # Z is convex or concave on [ta, tb] (Z'' keeps its sign): its extremum lies below the
            # tangents at both ends, so where they meet short of the wall it moves to, it cannot
            # reach that wall; then the only possible hit is on the way back, at the other wall
            sg1 = 1.0 if va > 0.0 else -1.0
            z0w1 = z0b if va > 0.0 else z0t
            ts = ((db - da) + va * ta - vb * tb) / (va - vb)
            skip = ta <= ts and ts <= tb and sg1 * (z0w1 + da + va * (ts - ta)) < -SKIP_MARGIN
            z0w2 = z0t if va > 0.0 else z0b
            if skip and ta == 0.0 and z0w2 == 0.0:
                # the flight leaves the wall it returns to: Z(x) - Z(0) is convex or concave with a
                # root at 0, so its chord slope from 0 is monotone, and its one root is the impact
                if -sg1 * db >= 0.0:
                    g1 = db / tb
                    t, _, v = rtsafe(ROOT_CHORD, 0.0, tb, u, g1, 0.5 * (c + gbar), (vb - g1) / tb, c, s, 0.0,
                                     u, gbar)
                    return _finish_hit(t, v, ta, tb, theta, c, s, z0w2, u, gbar, -sg1)
            elif skip and sg1 * (z0w2 + da) > 0.0:
                # a convex or concave gap of opposite signs at the ends has one root between them
                if -sg1 * (z0w2 + db) >= 0.0:
                    t, _, v = rtsafe(ROOT_GAP, ta, tb, z0w2 + da, z0w2 + db, va, vb, c, s, z0w2, u, gbar)
                    return _finish_hit(t, v, ta, tb, theta, c, s, z0w2, u, gbar, -sg1)
            else:
                skip = False
                if ta <= ts and ts <= tb and sg1 * (z0w1 + da) < 0.0:
                    # the bound is inconclusive: look where the tangents meet; past the wall there,
                    # the gap (convex or concave, of opposite signs at ta and ts) has one root between
                    ds_, vs_, _, _ = kinematics(ts, c, s, u, gbar)
                    if sg1 * (z0w1 + ds_) > DD_MARGIN:
                        t, _, v = rtsafe(ROOT_GAP, ta, ts, z0w1 + da, z0w1 + ds_, va, vs_, c, s, z0w1, u,
                                         gbar)
                        return _finish_hit(t, v, ta, ts, theta, c, s, z0w1, u, gbar, sg1)
            if skip:
                n_sub = 0  # no piece can reach a wall: on to the next one
            else:
                te, de, ve = rtsafe(ROOT_VELOCITY, ta, tb, va, vb, aa, ab, c, s, 0.0, u, gbar)
                n_sub = 2
        p = ta
        vp = va
        dp = da
        for k in range(n_sub):
            if k == 0:
                q, vq, dq = te, ve, de
            else:
                q, vq, dq = tb, vb, db
            # direction of Z on the monotone piece [p, q]
            if k == 0 and n_sub == 2:
                up = va > 0.0
            elif k == 1:
                up = vb > 0.0
            else:
                up = (vp + vq) > 0.0
            z0w = z0b if up else z0t
            sgn = 1.0 if up else -1.0
            gq = z0w + dq
            if sgn * gq >= -DD_MARGIN:
                if k == 0 and n_sub == 2 or vq == 0.0:
                    gq = _gap_sign_dd(q, theta, z0w, u, gbar, gq)
                if sgn * gq >= 0.0:
                    gp = z0w + dp if p > 0.0 else z0w
                    if sgn * gp > 0.0:
                        gp = 0.0
                    t, _, v = rtsafe(ROOT_GAP, p, q, gp, gq, vp, vq, c, s, z0w, u, gbar)
                    return _finish_hit(t, v, p, q, theta, c, s, z0w, u, gbar, sgn)
            p = q
            vp = vq
            dp = dq
        if last:
            return math.inf, 0, math.nan
        ta = tb
        va = vb
        da = db
        aa = ab
    return math.inf, 0, math.nan
