"""Guaranteed location of the next impact (docs/model.md).

Why it cannot miss: ``Z'' = cos(pi t + phi) + gbar`` vanishes at explicitly known phases
(``cos = -gbar``), so ``Zdot`` is monotone between them and has at most one root there; that root
is bracketed and found.  Between consecutive roots of ``Zdot`` (and the zeros of ``Z''``), ``Z`` is
monotone, so it meets a wall at most once and only if the wall value lies between ``Z`` at the
ends.  Every crossing, including a tangential (grazing) contact at an extremum, is therefore
bracketed; no step size is involved.  A near miss is decided by the sign of the gap at the
extremum, evaluated in double-double arithmetic when it is within 1e-12 of the wall.

Roots are found by Halley's method safeguarded by bisection (``rtsafe``'s safeguards).  A crossing
with small impact velocity is ill-conditioned in time (``dt = dZ / Zdot``), so it is polished on the
double-double gap by steps that solve its local quadratic.

Cost: every point is evaluated once for its displacement, velocity, acceleration and jerk from one
sine and cosine of half the angle travelled (:func:`~vibroimpact.flight.state3`); within a root
search each new point takes them from the previous one by angle addition; at a zero of the
acceleration they follow from ``cos = -gbar`` by angle subtraction.  The event loop carries the
phase's cosine and sine.  About 7-9 trigonometric calls per impact (``vibroimpact.bench.kernel_profile``).
"""

import math

from numba import njit

from .flight import PI, TWO_PI, gap_dd, half_angle_near, state3, state_from_half, state_from_sc, velocity

#: Below this |Zdot-| an impact time is polished in double-double arithmetic.
POLISH_SPEED = 1e-3
#: Within this distance of a wall a near-extremum hit/miss decision is made in double-double.
DD_MARGIN = 1e-12


@njit(cache=True)
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


@njit(cache=True)
def next_accel_zero(tau, theta, alpha):
    """Smallest local time > ``tau`` where ``cos(theta + pi t) = -gbar`` (``alpha = arccos(-gbar)``)."""
    return accel_zero(tau, theta, alpha)[0]


@njit(cache=True)
def _rtsafe(which, lo, hi, flo, fhi, c, s, z0w, u, gbar):
    """Root of a monotone function on [lo, hi] with f(lo), f(hi) of opposite sign (or zero):
    ``which=0`` Zdot, ``which=1`` the gap ``Z - wall`` (``z0w`` its value at the flight's start).

    Halley's method (third order: the second derivative comes with the same evaluation) from the
    bracket's midpoint, safeguarded as rtsafe is: bisection where even Newton's step would not halve
    the bracket (a flat f) and where Halley's step leaves it.  After the first point, the sine and
    cosine at each new point come from the previous point's by angle addition while the steps are
    small (:func:`~vibroimpact.flight.half_angle_near`).

    Returns ``(x, disp, vel)``: the root and the displacement and velocity there, from the last
    evaluated point by Taylor's formula (its distance to the root is at rounding level, or the
    bracket's width of a few ulps), so no further evaluation is needed."""
    if flo == 0.0 or fhi == 0.0:
        x = lo if flo == 0.0 else hi
        disp, vel, _, _ = state3(x, c, s, u, gbar)
        return x, disp, vel
    # orient so that f(xl) < 0 < f(xh)
    if flo < 0.0:
        xl, xh = lo, hi
    else:
        xl, xh = hi, lo
    x = 0.5 * (lo + hi)
    dxold = abs(hi - lo)
    dx = dxold
    half = 0.5 * PI * x
    sh = math.sin(half)
    ch = math.cos(half)
    disp, vel, acc, jerk = state_from_half(x, sh, ch, c, s, u, gbar)
    xe = x
    for _ in range(200):
        if which == 0:
            f, df, d2f = vel, acc, jerk
        else:
            f, df, d2f = z0w + disp, vel, acc
        if f == 0.0:
            return x, disp, vel
        if f < 0.0:
            xl = x
        else:
            xh = x
        den = 2.0 * df * df - f * d2f
        step = 2.0 * f * df / den if den != 0.0 else 0.0
        xn = x - step
        if den == 0.0 or abs(2.0 * f) > abs(dxold * df) or (xn - xh) * (xn - xl) > 0.0:
            dxold = dx
            dx = 0.5 * (xh - xl)
            x = xl + dx
        else:
            dxold = dx
            dx = step
            x = xn
        if abs(dx) <= 2.2e-16 * max(abs(x), 1e-300) or abs(xh - xl) <= 4.4e-16 * max(abs(x), 1e-300):
            h = x - xe
            return x, disp + h * (vel + 0.5 * h * acc), vel + h * (acc + 0.5 * h * jerk)
        sh, ch = half_angle_near(x, xe, sh, ch)
        disp, vel, acc, jerk = state_from_half(x, sh, ch, c, s, u, gbar)
        xe = x
    return x, disp, vel


@njit(cache=True)
def _gap_sign_dd(tau, theta, z0w, u, gbar, g):
    """Gap at an extremum, re-evaluated in double-double when it is within DD_MARGIN of zero."""
    if abs(g) < DD_MARGIN:
        return gap_dd(tau, theta, z0w, u, gbar)
    return g


@njit(cache=True)
def _polish(tau, lo, hi, theta, c, s, z0w, u, gbar):
    """Steps on the double-double gap, kept inside [lo, hi]: each solves the local quadratic
    ``g + v h + a h^2 / 2 = 0`` for the root nearest to ``tau``, which converges fast even where the
    impact is slow (a Newton step ``g / v`` only halves the error there once ``|h| > |v / a|``)."""
    for _ in range(6):
        _, v, a, _ = state3(tau, c, s, u, gbar)
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


@njit(cache=True)
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


@njit(cache=True)
def flight_impact(theta, c, s, alpha, z0, u, d, gbar, tau_max):
    """:func:`next_impact` for the event loop: the start phase ``theta`` in [0, 2 pi) with its cosine
    ``c`` and sine ``s``, and ``alpha = arccos(-gbar)`` (any value when ``gbar >= 1``), computed once
    by the caller; returns ``(tau, wall, Zdot-)`` (``(inf, 0, nan)`` if no impact).

    Every point is evaluated once, for its displacement, velocity and acceleration together
    (:func:`~vibroimpact.flight.state3`)."""
    half = 0.5 * d
    has_zeros = gbar < 1.0
    sa = math.sqrt(1.0 - gbar * gbar) if has_zeros else 0.0  # sin(alpha)
    z0b = z0 - half  # gap to the bottom wall (exact 0 when starting there)
    z0t = z0 + half  # gap to the top wall
    ta = 0.0
    va = u
    da = 0.0
    for _ in range(100000):
        if ta >= tau_max:
            return math.inf, 0, math.nan
        sgn = 0.0
        if has_zeros:
            tb, sgn = accel_zero(ta, theta, alpha)
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
            db, vb, _, _ = state_from_sc(tb, sp * c + gbar * s, 1.0 - cx, c, s, u, gbar)
        else:
            db, vb, _, _ = state3(tb, c, s, u, gbar)
        # split at the root of Zdot (Zdot is monotone on [ta, tb])
        n_sub = 1
        te = tb
        de = db
        ve = vb
        if (va < 0.0 and vb > 0.0) or (va > 0.0 and vb < 0.0):
            te, de, ve = _rtsafe(0, ta, tb, va, vb, c, s, 0.0, u, gbar)
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
                    t, _, v = _rtsafe(1, p, q, gp, gq, c, s, z0w, u, gbar)
                    if abs(v) < POLISH_SPEED:
                        t = _polish(t, p, q, theta, c, s, z0w, u, gbar)
                        v = velocity(t, c, s, u, gbar)
                    return t, 1 if up else -1, v
            p = q
            vp = vq
            dp = dq
        if last:
            return math.inf, 0, math.nan
        ta = tb
        va = vb
        da = db
    return math.inf, 0, math.nan
