"""Closed-form flight between impacts (docs/guide/model.md, paper eqs. ``zdot_t``, ``z_t``).

A flight starts at local time ``tau = 0`` with forcing phase ``theta = pi t_j + phi``, position
``z0`` and velocity ``u``.  With ``x = pi tau``

    Zdot(tau) - u  = gbar tau + (cos(theta) sin(x) - sin(theta) (1 - cos x)) / pi
    Z(tau) - z0    = u tau + gbar tau^2 / 2 + (cos(theta) (1 - cos x) + sin(theta) (sin x - x)) / pi^2

This is ``z_t`` with ``F2(t) - F2(t_j) - F1(t_j)(t - t_j)`` rewritten so that no two large terms
cancel: ``1 - cos x`` and ``sin x - x`` are evaluated without cancellation, so the displacement is
relatively accurate however short the flight (chattering).  The phase is carried from impact to
impact instead of absolute time, which keeps ``pi t + phi`` exact to rounding on long runs.

``*_dd`` functions evaluate the gap to a wall in double-double arithmetic (about 32 digits); they
polish impact times where a near-grazing impact makes the time ill-conditioned (|Zdot-| small).

Every function here is an ordinary compiled function: LLVM inlines it into the kernels that call it when it
optimizes their linked code, with the same results to the last bit. numba's own inlining (``inline="always"``)
would type it again at every call site: the first ``vi.simulate`` on an empty cache compiled in about 12 s
with it and 7 s without, and ran no faster.
"""

import math

from numba import njit

from . import impact as law

PI = math.pi
INV_PI = 1.0 / math.pi
INV_PI2 = 1.0 / (math.pi * math.pi)
TWO_PI = 2.0 * math.pi


@njit(cache=True, error_model="numpy")
def one_minus_cos(x):
    """1 - cos x without cancellation."""
    s = math.sin(0.5 * x)
    return 2.0 * s * s


@njit(cache=True, error_model="numpy")
def x_minus_sin_series(x, x2):
    """``x - sin x`` by its Taylor series to the x^11 term, ``x2 = x * x`` (relative truncation below 3e-18
    for ``|x| < 0.25``); the one series the flights use, for ``sin x - x`` with its sign changed (exact)."""
    return x * x2 * (1.0 / 6.0) * (1.0 - x2 * (1.0 / 20.0) * (1.0 - x2 * (1.0 / 42.0) * (1.0 - x2 * (1.0 / 72.0) * (1.0 - x2 * (1.0 / 110.0)))))


@njit(cache=True, error_model="numpy")
def sin_minus_x(x):
    """sin x - x without cancellation (Taylor series for |x| < 0.25)."""
    if abs(x) < 0.25:
        return -x_minus_sin_series(x, x * x)
    return math.sin(x) - x


@njit(cache=True, error_model="numpy")
def _theta_partials(c, s, omc, smx, sx):
    """d/dtheta of the displacement and of the velocity, from the flight's trigonometric terms."""
    return (-s * omc + c * smx) * INV_PI2, (-s * sx - c * omc) * INV_PI


@njit(cache=True, error_model="numpy")
def flight_partials(tau, theta, u, gbar):
    """Displacement ``Z(tau) - Z(0)``, velocity and acceleration at ``tau`` of a flight from forcing phase
    ``theta`` with velocity ``u``, and the displacement's and velocity's derivatives in ``theta``: what the
    periodic orbits' equations and their Jacobian need (eqs. ``zj_p1``, ``zdotj_p1``)."""
    x = PI * tau
    c, s = math.cos(theta), math.sin(theta)
    omc, smx = one_minus_cos(x), sin_minus_x(x)
    sx = math.sin(x)
    disp = u * tau + 0.5 * gbar * tau * tau + (c * omc + s * smx) * INV_PI2
    vel = u + gbar * tau + (c * sx - s * omc) * INV_PI
    acc = math.cos(theta + x) + gbar
    disp_th, vel_th = _theta_partials(c, s, omc, smx, sx)
    return disp, vel, acc, disp_th, vel_th


@njit(cache=True, error_model="numpy")
def step_jacobian(tau, theta, v, v_next, acc_next, r):
    """The 2x2 Jacobian ``(j11, j12, j21, j22)`` of one flight's map ``(t, Zdot-) -> (t', Zdot'-)`` (the
    paper's eqs. EntrP1-EntrP3): a flight of time ``tau`` from phase ``theta`` after the rebound of an impact
    at velocity ``v`` (restitution ``r``, the impact law's :func:`~vibroimpact.dynamics.impact.rebound`),
    arriving with velocity ``v_next`` and acceleration ``acc_next``.  The one implementation of the impact
    map's derivative: the periodic orbits' monodromy matrix is the product of these steps, and the Lyapunov
    exponents' tangent map applies them along a run.

    With ``u = rebound(v)`` and ``k = du/dv`` (:func:`~vibroimpact.dynamics.impact.rebound_slope`), the
    flight time from ``disp(tau; theta, u) = const`` moves by ``dtau = (-pi dZ/dtheta dt - k tau dv) / v'``
    and the arrival velocity by ``a' dtau + pi dZdot/dtheta dt + k dv``."""
    x = PI * tau
    c, s = math.cos(theta), math.sin(theta)
    disp_th, vel_th = _theta_partials(c, s, one_minus_cos(x), sin_minus_x(x), math.sin(x))
    k = law.rebound_slope(v, r)
    dtau_dt = -PI * disp_th / v_next
    dtau_dv = -k * tau / v_next
    return 1.0 + dtau_dt, dtau_dv, acc_next * dtau_dt + PI * vel_th, acc_next * dtau_dv + k


@njit(cache=True, error_model="numpy")
def displacement(tau, c, s, u, gbar):
    """Z(tau) - Z(0) for a flight with cos/sin of the start phase ``c``, ``s``."""
    x = PI * tau
    return u * tau + 0.5 * gbar * tau * tau + (c * one_minus_cos(x) + s * sin_minus_x(x)) * INV_PI2


@njit(cache=True, error_model="numpy")
def velocity(tau, c, s, u, gbar):
    """Zdot(tau)."""
    x = PI * tau
    return u + gbar * tau + (c * math.sin(x) - s * one_minus_cos(x)) * INV_PI


@njit(cache=True, error_model="numpy")
def acceleration(tau, c, s, gbar):
    """Z''(tau) = cos(theta + pi tau) + gbar."""
    x = PI * tau
    return c * math.cos(x) - s * math.sin(x) + gbar


@njit(cache=True, error_model="numpy")
def state_from_sc(tau, sx, omc, c, s, u, gbar):
    """Displacement ``Z(tau) - Z(0)``, velocity, acceleration and jerk of a flight from ``sin x`` and
    ``1 - cos x`` of the forcing angle travelled, ``x = pi tau``."""
    x = PI * tau
    if abs(x) < 0.25:
        smx = -x_minus_sin_series(x, x * x)
    else:
        smx = sx - x
    cx = 1.0 - omc
    disp = u * tau + 0.5 * gbar * tau * tau + (c * omc + s * smx) * INV_PI2
    vel = u + gbar * tau + (c * sx - s * omc) * INV_PI
    acc = c * cx - s * sx + gbar
    jerk = -PI * (s * cx + c * sx)
    return disp, vel, acc, jerk


@njit(cache=True, error_model="numpy")
def state_from_half(tau, sh, ch, c, s, u, gbar):
    """:func:`state_from_sc` from the sine ``sh`` and cosine ``ch`` of half the angle travelled
    (``sin x = 2 sh ch``, ``1 - cos x = 2 sh^2``: no cancellation however short the flight)."""
    return state_from_sc(tau, 2.0 * sh * ch, 2.0 * sh * sh, c, s, u, gbar)


@njit(cache=True, error_model="numpy")
def kinematics(tau, c, s, u, gbar):
    """Displacement, velocity, acceleration and jerk at ``tau`` (:func:`state_from_half`) for one
    sine and one cosine, where separate formulas would take four to six trigonometric calls."""
    half = 0.5 * PI * tau
    return state_from_half(tau, math.sin(half), math.cos(half), c, s, u, gbar)


#: below this angle step ``pi h``, :func:`state_step` uses Taylor polynomials instead of sin/cos
NEAR_STEP = 0.1


@njit(cache=True, error_model="numpy")
def state_step(h, disp, vel, acc, jerk, gbar):
    """Displacement, velocity, acceleration and jerk at ``tau + h`` from their values at ``tau``, for
    a step with ``|pi h| < NEAR_STEP``: the acceleration less ``gbar`` is a pure harmonic, so

        acc(tau + h) - gbar = (acc - gbar) cos w + jerk sin(w) / pi,     w = pi h,

    and velocity and displacement are its integrals; ``sin w``, ``1 - cos w`` and ``w - sin w`` come
    from their Taylor series (relative truncation below 3e-18 for ``|w| < NEAR_STEP``), so no
    trigonometric call and no cancellation.  Replaces sin and cos at the points of a root search after
    the first, whose steps are short."""
    w = PI * h
    w2 = w * w
    sw = w * (1.0 - w2 * (1.0 / 6.0) * (1.0 - w2 * (1.0 / 20.0) * (1.0 - w2 * (1.0 / 42.0) * (1.0 - w2 * (1.0 / 72.0)))))
    omc = w2 * 0.5 * (1.0 - w2 * (1.0 / 12.0) * (1.0 - w2 * (1.0 / 30.0) * (1.0 - w2 * (1.0 / 56.0)
                                                                               * (1.0 - w2 * (1.0 / 90.0)))))
    wms = x_minus_sin_series(w, w2)
    a = acc - gbar
    jp = jerk * INV_PI
    disp1 = disp + vel * h + 0.5 * gbar * h * h + (a * omc + jp * wms) * INV_PI2
    vel1 = vel + gbar * h + (a * sw + jp * omc) * INV_PI
    acc1 = gbar + a - a * omc + jp * sw
    jerk1 = jerk - jerk * omc - PI * a * sw
    return disp1, vel1, acc1, jerk1


# --------------------------------------------------------------------------------------------
# Double-double arithmetic (Dekker / Knuth error-free transformations), for the gap only.
# --------------------------------------------------------------------------------------------

_SPLIT = 134217729.0  # 2^27 + 1


@njit(cache=True, error_model="numpy")
def _two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@njit(cache=True, error_model="numpy")
def _quick_two_sum(a, b):
    s = a + b
    return s, b - (s - a)


@njit(cache=True, error_model="numpy")
def _two_prod(a, b):
    p = a * b
    t = _SPLIT * a
    ah = t - (t - a)
    al = a - ah
    t = _SPLIT * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@njit(cache=True, error_model="numpy")
def dd_add(ah, al, bh, bl):
    s, e = _two_sum(ah, bh)
    t, f = _two_sum(al, bl)
    e += t
    s, e = _quick_two_sum(s, e)
    e += f
    return _quick_two_sum(s, e)


@njit(cache=True, error_model="numpy")
def dd_mul(ah, al, bh, bl):
    p, e = _two_prod(ah, bh)
    e += ah * bl + al * bh
    return _quick_two_sum(p, e)


# pi and pi/2 to double-double precision
PI_HI = 3.141592653589793
PI_LO = 1.2246467991473532e-16
PI2_HI = 9.869604401089358  # pi^2
PI2_LO = 6.265295508739711e-16
HALF_PI_HI = 1.5707963267948966
HALF_PI_LO = 6.123233995736766e-17


@njit(cache=True, error_model="numpy")
def dd_div_int(ah, al, n):
    """Double-double divided by an integer-valued double."""
    q = ah / n
    p, e = _two_prod(q, n)
    r = ((ah - p) - e + al) / n
    return _quick_two_sum(q, r)


@njit(cache=True, error_model="numpy")
def _dd_sincos_reduced(rh, rl):
    """sin and cos of a double-double |r| <= pi/4 by Taylor series (27 terms)."""
    r2h, r2l = dd_mul(rh, rl, rh, rl)
    # sin: r - r^3/3! + ...   cos: 1 - r^2/2! + ...
    sh, sl = rh, rl
    th, tl = rh, rl
    ch, cl = 1.0, 0.0
    uh, ul = 1.0, 0.0
    for k in range(1, 15):
        # term_cos_k = term_cos_{k-1} * (-r^2) / ((2k-1)(2k))
        uh, ul = dd_mul(uh, ul, -r2h, -r2l)
        uh, ul = dd_div_int(uh, ul, float((2 * k - 1) * (2 * k)))
        ch, cl = dd_add(ch, cl, uh, ul)
        th, tl = dd_mul(th, tl, -r2h, -r2l)
        th, tl = dd_div_int(th, tl, float((2 * k) * (2 * k + 1)))
        sh, sl = dd_add(sh, sl, th, tl)
    return sh, sl, ch, cl


@njit(cache=True, error_model="numpy")
def dd_sincos(xh, xl):
    """sin and cos of a double-double argument (|x| up to ~1e6) to ~1e-30 absolute."""
    k = math.floor(xh / HALF_PI_HI + 0.5)
    ph, pl = dd_mul(HALF_PI_HI, HALF_PI_LO, -k, 0.0)
    rh, rl = dd_add(xh, xl, ph, pl)
    sh, sl, ch, cl = _dd_sincos_reduced(rh, rl)
    q = int(k) % 4
    if q == 0:
        return sh, sl, ch, cl
    if q == 1:
        return ch, cl, -sh, -sl
    if q == 2:
        return -sh, -sl, -ch, -cl
    return -ch, -cl, sh, sl


@njit(cache=True, error_model="numpy")
def gap_dd(tau, theta, z0_minus_wall, u, gbar):
    """(Z(tau) - wall) in double-double, rounded to double: accurate to ~1e-30 absolute.

    Exact for the double inputs ``tau, theta, z0_minus_wall, u, gbar``.
    """
    xh, xl = dd_mul(PI_HI, PI_LO, tau, 0.0)
    s_t, s_tl, c_t, c_tl = dd_sincos(theta, 0.0)
    # 1 - cos x = 2 sin^2(x/2)
    s2h, s2l, _, _ = dd_sincos(0.5 * xh, 0.5 * xl)
    omc_h, omc_l = dd_mul(s2h, s2l, s2h, s2l)
    omc_h, omc_l = 2.0 * omc_h, 2.0 * omc_l
    sxh, sxl, _, _ = dd_sincos(xh, xl)
    smx_h, smx_l = dd_add(sxh, sxl, -xh, -xl)
    a_h, a_l = dd_mul(c_t, c_tl, omc_h, omc_l)
    b_h, b_l = dd_mul(s_t, s_tl, smx_h, smx_l)
    f_h, f_l = dd_add(a_h, a_l, b_h, b_l)
    # divide by pi^2: one Newton correction of the double quotient
    q = f_h / PI2_HI
    ph, pl = dd_mul(q, 0.0, PI2_HI, PI2_LO)
    rh, rl = dd_add(f_h, f_l, -ph, -pl)
    qh, ql = _quick_two_sum(q, (rh + rl) / PI2_HI)
    ut_h, ut_l = _two_prod(u, tau)
    g_h, g_l = _two_prod(gbar, tau)
    g_h, g_l = dd_mul(g_h, g_l, 0.5 * tau, 0.0)
    acc_h, acc_l = dd_add(z0_minus_wall, 0.0, ut_h, ut_l)
    acc_h, acc_l = dd_add(acc_h, acc_l, g_h, g_l)
    acc_h, acc_l = dd_add(acc_h, acc_l, qh, ql)
    return acc_h + acc_l
