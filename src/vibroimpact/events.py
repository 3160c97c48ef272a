"""Guaranteed location of the next impact (docs/model.md).

Why it cannot miss: ``Z'' = cos(pi t + phi) + gbar`` vanishes at explicitly known phases
(``cos = -gbar``), so ``Zdot`` is monotone between them and has at most one root there; that root
is bracketed and found.  Between consecutive roots of ``Zdot`` (and the zeros of ``Z''``), ``Z`` is
monotone, so it meets a wall at most once and only if the wall value lies between ``Z`` at the
ends.  Every crossing, including a tangential (grazing) contact at an extremum, is therefore
bracketed; no step size is involved.  A near miss is decided by the sign of the gap at the
extremum, evaluated in double-double arithmetic when it is within 1e-12 of the wall.

Roots are found by Newton's method safeguarded by bisection (``rtsafe``).  A crossing with small
impact velocity is ill-conditioned in time (``dt = dZ / Zdot``), so it is polished by Newton steps
on the double-double gap.
"""

import math

from numba import njit

from .flight import PI, TWO_PI, acceleration, displacement, gap_dd, velocity

#: Below this |Zdot-| an impact time is polished in double-double arithmetic.
POLISH_SPEED = 1e-3
#: Within this distance of a wall a near-extremum hit/miss decision is made in double-double.
DD_MARGIN = 1e-12


@njit(cache=True)
def next_accel_zero(tau, theta, alpha):
    """Smallest local time > ``tau`` where ``cos(theta + pi t) = -gbar`` (``alpha = arccos(-gbar)``)."""
    psi = theta + PI * tau
    base = math.floor(psi / TWO_PI) * TWO_PI
    for cand in (base + alpha, base + TWO_PI - alpha, base + TWO_PI + alpha):
        if cand > psi:
            t = (cand - theta) / PI
            if t > tau:
                return t
    return (base + TWO_PI * 2 - alpha - theta) / PI


@njit(cache=True)
def _eval(which, tau, c, s, z0w, u, gbar):
    """which=0: (Zdot, Z''); which=1: (Z - wall, Zdot)."""
    if which == 0:
        return velocity(tau, c, s, u, gbar), acceleration(tau, c, s, gbar)
    return z0w + displacement(tau, c, s, u, gbar), velocity(tau, c, s, u, gbar)


@njit(cache=True)
def _rtsafe(which, lo, hi, flo, fhi, c, s, z0w, u, gbar):
    """Root of a monotone function on [lo, hi] with f(lo), f(hi) of opposite sign (or zero)."""
    if flo == 0.0:
        return lo
    if fhi == 0.0:
        return hi
    # orient so that f(xl) < 0 < f(xh)
    if flo < 0.0:
        xl, xh = lo, hi
    else:
        xl, xh = hi, lo
    x = 0.5 * (lo + hi)
    dxold = abs(hi - lo)
    dx = dxold
    f, df = _eval(which, x, c, s, z0w, u, gbar)
    for _ in range(200):
        if ((x - xh) * df - f) * ((x - xl) * df - f) > 0.0 or abs(2.0 * f) > abs(dxold * df):
            dxold = dx
            dx = 0.5 * (xh - xl)
            x = xl + dx
        else:
            dxold = dx
            dx = f / df
            x -= dx
        if abs(dx) <= 2.2e-16 * max(abs(x), 1e-300) or abs(xh - xl) <= 4.4e-16 * max(abs(x), 1e-300):
            return x
        f, df = _eval(which, x, c, s, z0w, u, gbar)
        if f == 0.0:
            return x
        if f < 0.0:
            xl = x
        else:
            xh = x
    return x


@njit(cache=True)
def _gap_sign_dd(tau, theta, z0w, u, gbar, g):
    """Gap at an extremum, re-evaluated in double-double when it is within DD_MARGIN of zero."""
    if abs(g) < DD_MARGIN:
        return gap_dd(tau, theta, z0w, u, gbar)
    return g


@njit(cache=True)
def _polish(tau, lo, hi, theta, c, s, z0w, u, gbar):
    """Newton steps on the double-double gap, kept inside [lo, hi]."""
    for _ in range(3):
        v = velocity(tau, c, s, u, gbar)
        if v == 0.0:
            break
        g = gap_dd(tau, theta, z0w, u, gbar)
        step = g / v
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
    half = 0.5 * d
    theta = theta % TWO_PI
    c = math.cos(theta)
    s = math.sin(theta)
    has_zeros = gbar < 1.0
    alpha = math.acos(-gbar) if has_zeros else 0.0
    z0b = z0 - half  # gap to the bottom wall (exact 0 when starting there)
    z0t = z0 + half  # gap to the top wall
    ta = 0.0
    va = u
    for _ in range(100000):
        if ta >= tau_max:
            return math.inf, 0
        if has_zeros:
            tb = next_accel_zero(ta, theta, alpha)
        else:
            tb = ta + 2.0
        last = False
        if tb >= tau_max:
            tb = tau_max
            last = True
        vb = velocity(tb, c, s, u, gbar)
        # split at the root of Zdot (Zdot is monotone on [ta, tb])
        n_sub = 1
        te = tb
        if (va < 0.0 and vb > 0.0) or (va > 0.0 and vb < 0.0):
            te = _rtsafe(0, ta, tb, va, vb, c, s, 0.0, u, gbar)
            n_sub = 2
        p = ta
        vp = va
        for k in range(n_sub):
            q = te if k == 0 else tb
            vq = velocity(q, c, s, u, gbar) if k == 0 else vb
            # direction of Z on the monotone piece [p, q]
            if k == 0 and n_sub == 2:
                up = va > 0.0
            elif k == 1:
                up = vb > 0.0
            else:
                up = (vp + vq) > 0.0
            if up:
                gq = z0b + displacement(q, c, s, u, gbar)
                if gq >= -DD_MARGIN:
                    if k == 0 and n_sub == 2 or vq == 0.0:
                        gq = _gap_sign_dd(q, theta, z0b, u, gbar, gq)
                    if gq >= 0.0:
                        gp = z0b + displacement(p, c, s, u, gbar) if p > 0.0 else z0b
                        if gp > 0.0:
                            gp = 0.0
                        t = _rtsafe(1, p, q, gp, gq, c, s, z0b, u, gbar)
                        if abs(velocity(t, c, s, u, gbar)) < POLISH_SPEED:
                            t = _polish(t, p, q, theta, c, s, z0b, u, gbar)
                        return t, 1
            else:
                gq = z0t + displacement(q, c, s, u, gbar)
                if gq <= DD_MARGIN:
                    if k == 0 and n_sub == 2 or vq == 0.0:
                        gq = _gap_sign_dd(q, theta, z0t, u, gbar, gq)
                    if gq <= 0.0:
                        gp = z0t + displacement(p, c, s, u, gbar) if p > 0.0 else z0t
                        if gp < 0.0:
                            gp = 0.0
                        t = _rtsafe(1, p, q, gp, gq, c, s, z0t, u, gbar)
                        if abs(velocity(t, c, s, u, gbar)) < POLISH_SPEED:
                            t = _polish(t, p, q, theta, c, s, z0t, u, gbar)
                        return t, -1
            p = q
            vp = vq
        if last:
            return math.inf, 0
        ta = tb
        va = vb
    return math.inf, 0
