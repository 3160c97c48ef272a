"""Lyapunov exponents of the impacting motion, from the exact linearisation of the impact map.

The state at impact ``k`` is ``(t_k, Zdot_k)``: its time and pre-impact velocity.  The flight from
impact ``k`` (phase ``theta_k = pi t_k + phi``, post-impact velocity ``u_k = -r Zdot_k``) ends where its
displacement reaches the next wall, so its duration ``tau`` is defined implicitly, and the map to
``(t_{k+1}, Zdot_{k+1})`` has the Jacobian (the paper's appendix, eqs. ``EntrP1``-``EntrP3``, for any
pair of walls; ``v'`` and ``a'`` the velocity and acceleration at the next impact)::

    dtau       = (-pi dZ/dtheta dt_k + r tau dZdot_k) / v'
    dt_{k+1}   = dt_k + dtau
    dZdot_{k+1} = a' dtau + pi dZdot/dtheta dt_k - r dZdot_k

with determinant ``r^2 Zdot_k / Zdot_{k+1}``.  :func:`lyapunov` multiplies these Jacobians along a run
of the exact simulator (:func:`~vibroimpact.simulate`), re-orthonormalising (QR) at every impact in a
numba kernel, and gives both exponents per impact and per unit time with confidence intervals from batch
means, the transient discarded.

Two cases need words.  A stick (the ball chatters into rest on a wall, then leaves it at the release
phase, where the acceleration turns away from the wall) maps every nearby state to the same release: the
map across it is constant, of rank 0, so both directions collapse there and the second exponent is
``-inf``; the first is measured on the stretches of flight between sticks (the tangent basis restarts
after each), and the result says how many sticks it crossed.  An impact at small speed makes the
Jacobian large (``1 / v'``: the square-root singularity of grazing); the result counts the impacts slower
than ``slow_speed`` the estimate passed through.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..dynamics import impact as law
from ..dynamics import kernels as K
from ..dynamics.flight import step_jacobian
from ..dynamics.params import Params
from ..dynamics.runs import simulate

__all__ = ["Lyapunov", "lyapunov", "tangent_pass", "exponents_of_run", "multiplier_sensitivity", "MIN_PER_BATCH"]

#: fewest impacts per batch of the confidence interval
MIN_PER_BATCH = 10


#: a running product of stretch factors is folded into its logarithm beyond this range (one ``log`` per
#: hundreds of impacts instead of two per impact; far from overflow)
_FOLD = 1e150


#: how :func:`tangent_pass` accumulates: from the flight leaving event ``first`` on, in ``batches`` batches,
#: counting the impacts slower than ``slow_speed``
TangentSettings = namedtuple("TangentSettings", ("first", "batches", "slow_speed"))


@njit(cache=True, error_model="numpy")
def tangent_pass(events, model, settings, logs, counts):
    """Multiply the Jacobians of a run's flights (``events``, :data:`~vibroimpact.dynamics.kernels.Window`; the
    constants ``model``, :data:`~vibroimpact.dynamics.kernels.Model`), re-orthonormalising (QR) at every
    impact; accumulate from the flight leaving event ``settings.first`` on (:data:`TangentSettings`).

    In the plane the QR step needs only the first direction ``q``: ``R11 = |J q|``, ``q <- J q / R11``,
    and ``R22 = |det J| / R11`` (the second direction is ``q``'s normal).  The direction is carried from
    the run's start, so it has aligned with the expanding one by the end of the transient.  ``logs``
    (``(batches, 2)``, zeroed) receives per batch the sums of ``log R11`` and ``log R22``; ``counts``:
    ``[flights, sticks, slow impacts, flights per batch, time spanned]``.  A flight is counted from an
    impact (or grazing contact) to the next; a stick restarts the direction (the map across it is
    constant).
    """
    t, vm, phase, kind = events.t, events.v_minus, events.phase, events.kind
    _, gbar, r = model
    first, batches, slow_speed = settings
    n = t.shape[0]
    steps = 0
    for k in range(first, n - 1):
        if K.is_hit(kind[k]) and K.is_hit(kind[k + 1]):
            steps += 1
    per = steps // batches
    counts[3] = per
    q1, q2 = 1.0, 0.0
    done = 0
    sticks = 0
    slow = 0
    t0 = 0.0
    t1 = 0.0
    p1 = 1.0  # running products of R11 and R22 within the batch
    p2 = 1.0
    for k in range(n - 1):
        a, b = kind[k], kind[k + 1]
        if k >= first and b == K.STICK:
            sticks += 1
        if not (K.is_hit(a) and K.is_hit(b)):
            if b == K.STICK or a == K.RELEASE:  # across a stick the map is constant: restart
                q1, q2 = 1.0, 0.0
            continue
        if k >= first and done >= per * batches:
            break
        v1 = vm[k + 1]
        j11, j12, j21, j22 = step_jacobian(t[k + 1] - t[k], phase[k], vm[k], v1, gbar + math.cos(phase[k + 1]), r)
        m1 = j11 * q1 + j12 * q2
        m2 = j21 * q1 + j22 * q2
        r11 = math.sqrt(m1 * m1 + m2 * m2)
        q1, q2 = m1 / r11, m2 / r11
        if k < first:
            continue
        p1 *= r11
        p2 *= abs(j11 * j22 - j12 * j21) / r11
        batch = done // per
        if p1 > _FOLD or p1 < 1.0 / _FOLD:
            logs[batch, 0] += math.log(p1)
            p1 = 1.0
        if p2 > _FOLD or p2 < 1.0 / _FOLD:
            logs[batch, 1] += math.log(p2)
            p2 = 1.0
        if abs(v1) < slow_speed:
            slow += 1
        if done == 0:
            t0 = t[k]
        t1 = t[k + 1]
        done += 1
        if done % per == 0:  # the batch ends
            logs[batch, 0] += math.log(p1)
            logs[batch, 1] += math.log(p2)
            p1 = 1.0
            p2 = 1.0
    counts[0] = done
    counts[1] = sticks
    counts[2] = slow
    counts[4] = t1 - t0


# a record a call returns: its fields are Attributes, not Parameters (no one constructs it)
@dataclass(frozen=True)
class Lyapunov:  # numpydoc ignore=PR01
    """Both Lyapunov exponents of a run of the impact map (:func:`lyapunov`).

    Attributes
    ----------
    per_impact : (float, float)
        ``lambda_1 >= lambda_2``, per impact (natural logarithm).
    per_time : (float, float)
        The same per unit of non-dimensional time t (forcing period 2).
    interval : ((float, float), (float, float))
        Confidence intervals of ``lambda_1`` and ``lambda_2`` per impact (batch means, Student's t).
    interval_time : ((float, float), (float, float))
        The same per unit time.
    confidence : float
        Their level.
    impacts : int
        Flights whose Jacobians entered the exponents (after the transient).
    transient : int
        Events discarded before.
    mean_time : float
        Mean time per impact over them.
    sticks : int
        Sticks crossed: the map is constant across each (rank 0), ``lambda_2 = -inf``, and ``lambda_1`` is
        measured on the stretches of flight between them.
    slow_impacts : int
        Impacts slower than ``slow_speed`` (near grazing: the Jacobian grows as ``1 / |Zdot-|``).
    slow_speed : float
        That speed.
    status : str
        ``"ok"``, or why the exponents are not finite (sticks, a run that rests for good).

    Examples
    --------
    On the stable 2:1 orbit of Figure 7 (a) (3 impacts a forcing period, multipliers a complex pair of
    modulus ``r^3``) both exponents are ``ln(r^3) / 3 = ln r`` per impact, and they add up to ``2 ln r``
    (each impact contracts areas by ``r^2``), up to boundary terms of order ``1 / impacts``:

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
    >>> lam = vi.lyapunov(p, 1.015, 0.1924, 2000)
    >>> lam.status, [round(x, 3) for x in lam.per_impact], round(math.log(0.5), 3)
    ('ok', [-0.693, -0.693], -0.693)
    >>> round(sum(lam.per_impact), 3), round(2 * math.log(0.5), 3), round(lam.mean_time, 3)   # 2 / 3
    (-1.386, -1.386, 0.667)
    """

    per_impact: tuple
    per_time: tuple
    interval: tuple
    interval_time: tuple
    confidence: float
    impacts: int
    transient: int
    mean_time: float
    sticks: int
    slow_impacts: int
    slow_speed: float
    status: str


def t_quantile(p: float, df: int) -> float:
    """Student's t quantile ``p`` with ``df`` degrees of freedom, for the batch-means intervals: scipy's
    ``stdtrit``, which ``scipy.stats.t.ppf`` calls (importing ``scipy.stats`` costs about a second a process;
    ``scipy.special`` is imported here, where it is needed, so that a job that only reads datasets does not pay it)."""
    from scipy.special import stdtrit

    return float(stdtrit(df, p))


def exponents_of_run(run, *, transient: int, batches: int = 20, slow_speed: float = 1e-3,
                     confidence: float = 0.95) -> Lyapunov:
    """The exponents of a recorded run (:func:`~vibroimpact.simulate`'s dataset), its first ``transient``
    events discarded.

    Parameters
    ----------
    run : xarray.Dataset
        A run of :func:`~vibroimpact.simulate`.
    transient : int
        Events discarded before the exponents are accumulated (the tangent basis aligns over them).
    batches : int
        Batches of the confidence interval (at least 2, each of at least :data:`MIN_PER_BATCH` impacts).
    slow_speed : float
        Impacts slower than this are counted (near grazing).
    confidence : float
        Level of the intervals.

    Returns
    -------
    Lyapunov
        The exponents with their intervals and what the run passed through.
    """
    events = K.Window(*(run[v].values for v in ("t", "wall", "v_minus", "phase")), run["kind"].values.astype(np.int8))
    model = K.Model(float(run.attrs.get("d", math.nan)), float(run.attrs["gbar"]), float(run.attrs["r"]))
    return exponents_of_events(events, model, str(run.attrs.get("status")), transient=transient, batches=batches,
                                slow_speed=slow_speed, confidence=confidence)


def exponents_of_events(events, model, run_status, *, transient, batches, slow_speed, confidence) -> Lyapunov:
    """:func:`exponents_of_run` of a run's events (:data:`~vibroimpact.dynamics.kernels.Window`), constants
    (:data:`~vibroimpact.dynamics.kernels.Model`) and status name (``run_status``)."""
    logs = np.zeros((batches, 2))
    counts = np.zeros(5)
    tangent_pass(events, model, TangentSettings(int(transient), int(batches), float(slow_speed)), logs, counts)
    done, sticks, slow, per, span = int(counts[0]), int(counts[1]), int(counts[2]), int(counts[3]), float(counts[4])
    nan2 = (math.nan, math.nan)
    if per < MIN_PER_BATCH:
        status = (f"too few impacts for an interval: {done} flights between impacts after the transient, "
                  f"fewer than {batches} batches of {MIN_PER_BATCH}")
        if run_status == "stuck_forever":
            status = "rests on the bottom wall for good: no impacts, the motion is a fixed point (exponents -inf)"
            return Lyapunov((-math.inf, -math.inf), (-math.inf, -math.inf), ((-math.inf,) * 2,) * 2,
                            ((-math.inf,) * 2,) * 2, confidence, done, int(transient), math.nan, sticks, slow,
                            float(slow_speed), status)
        return Lyapunov(nan2, nan2, (nan2, nan2), (nan2, nan2), confidence, done, int(transient), math.nan, sticks,
                        slow, float(slow_speed), status)
    b = logs / per  # per batch, per impact
    mean = b.mean(axis=0)
    half = t_quantile(0.5 + confidence / 2, batches - 1) * b.std(axis=0, ddof=1) / math.sqrt(batches)
    dt = span / done
    lam = (float(mean[0]), float(mean[1]) if sticks == 0 else -math.inf)
    ci = ((float(mean[0] - half[0]), float(mean[0] + half[0])),
          (float(mean[1] - half[1]), float(mean[1] + half[1])) if sticks == 0 else (-math.inf, -math.inf))
    status = "ok" if sticks == 0 else (f"{sticks} sticks: across each the map is constant (rank 0), so lambda_2 = -inf; "
                                        "lambda_1 is measured on the flights between them (a motion that sticks again and again is "
                                        "eventually periodic: each release starts from the same state)")
    return Lyapunov(lam, tuple(x / dt for x in lam), ci, tuple(tuple(x / dt for x in c) for c in ci), confidence,
                    done, int(transient), dt, sticks, slow, float(slow_speed), status)


def lyapunov(params: Params, phi: float, v0: float, n_impacts: int = 20_000, *, transient: int | None = None,
             batches: int = 20, slow_speed: float = 1e-3, confidence: float = 0.95, Z0: float | None = None,
             t0: float = 0.0) -> Lyapunov:
    """Both Lyapunov exponents of the impacting motion from a start, per impact and per unit time.

    The Jacobians of the impact-to-impact map (eqs. ``EntrP1``-``EntrP3``) along a run of the exact
    simulator, multiplied with QR re-orthonormalisation at every impact (:func:`tangent_pass`, numba);
    confidence intervals from ``batches`` batch means (Student's t).

    Parameters
    ----------
    params : Params
        The parameters.
    phi, v0 : float
        The start: a bottom impact at phase ``phi`` with pre-impact velocity ``v0`` (paper convention),
        or with ``Z0``, the state ``Z(t0) = Z0``, ``Zdot(t0) = v0`` in flight.
    n_impacts : int
        Events simulated, the transient included.
    transient : int, optional
        Events discarded first (default: a tenth of ``n_impacts``).
    batches : int
        Batches of the confidence intervals (at least 2).
    slow_speed : float
        Impacts slower than this are counted (the Jacobian grows as ``1 / |Zdot-|`` near grazing).
    confidence : float
        Level of the intervals, in (0, 1).
    Z0 : float, optional
        Start in flight at this position (``|Z0| <= d/2``).
    t0 : float
        Time of the start.

    Returns
    -------
    Lyapunov
        ``per_impact``, ``per_time``, their intervals, and what the run passed through (sticks, slow
        impacts); a run that rests for good has exponents ``-inf`` with the reason.

    Raises
    ------
    ValueError
        Too few impacts for an interval, a transient as long as the run, a start outside the cylinder, or
        a bad ``batches`` or ``confidence``.

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)          # a stable 2:1 orbit
    >>> lam = vi.lyapunov(p, 1.015, 0.1924, 4000)
    >>> lam.per_impact[0] < 0 and lam.status
    'ok'
    """

    if isinstance(n_impacts, bool) or not isinstance(n_impacts, (int, np.integer)) or n_impacts < 1:
        raise ValueError(f"n_impacts = {n_impacts!r}; allowed: an integer >= 1")
    if isinstance(batches, bool) or not isinstance(batches, (int, np.integer)) or batches < 2:
        raise ValueError(f"batches = {batches!r}; allowed: an integer >= 2")
    if not 0 < confidence < 1:
        raise ValueError(f"confidence = {confidence!r}; allowed: a level in (0, 1), e.g. 0.95")
    transient = int(n_impacts) // 10 if transient is None else transient
    if isinstance(transient, bool) or not isinstance(transient, (int, np.integer)) or not 0 <= transient < n_impacts:
        raise ValueError(f"transient = {transient!r}; allowed: an integer in [0, n_impacts) = [0, {n_impacts})")
    needed = int(transient) + batches * MIN_PER_BATCH + 1
    if n_impacts < needed:
        raise ValueError(f"n_impacts = {n_impacts!r} is too few for an interval; allowed: at least transient + "
                         f"batches x {MIN_PER_BATCH} + 1 = {needed} (transient {transient}, batches {batches})")
    run = simulate(params, phi, v0, n_impacts=int(n_impacts), Z0=Z0, t0=t0)
    return exponents_of_run(run, transient=int(transient), batches=batches, slow_speed=slow_speed,
                            confidence=confidence)


def multiplier_sensitivity(factors) -> float:
    """How much ``ln max|mu|`` of a product of 2x2 Jacobians ``F_N ... F_1`` (a cycle's map over one period,
    ``factors`` in order of application; a single matrix is a product of one) moves per unit of
    componentwise relative perturbation of the factors' entries, to first order.

    With ``x``, ``y`` the right and left eigenvectors of the product ``P`` for its eigenvalue ``mu`` of
    largest modulus, ``A_k`` the factors after ``F_k`` and ``B_k`` those before:
    ``sum_k |y^T A_k| |F_k| |B_k x| / (|y^T x| |mu|)`` (the componentwise condition number of an
    eigenvalue, through each factor).  Large where the product is far from normal (its entries much larger
    than its eigenvalues) or two multipliers nearly coalesce.  A complex pair has
    ``|mu|^2 = prod_k det F_k``: ``sum_k (|a_k d_k| + |b_k c_k|) / |det F_k|``."""
    F = [np.asarray(f, dtype=float) for f in (factors if np.ndim(factors) == 3 else [factors])]
    P = np.eye(2)
    for f in F:
        P = f @ P
    w, V = np.linalg.eig(P)
    k = int(np.argmax(np.abs(w)))
    if abs(w[k].imag) > 0:
        return float(sum((abs(f[0, 0] * f[1, 1]) + abs(f[0, 1] * f[1, 0])) / abs(f[0, 0] * f[1, 1] - f[0, 1] * f[1, 0])
                         for f in F))
    wl, U = np.linalg.eig(P.T)
    x, y = V[:, k].real, U[:, int(np.argmin(np.abs(wl - w[k])))].real
    total, before = 0.0, [x]
    for f in F[:-1]:
        before.append(f @ before[-1])  # B_k x, k = 1 .. N
    after = y.copy()  # y^T A_k, from the last factor back
    for kf in range(len(F) - 1, -1, -1):
        total += np.abs(after) @ np.abs(F[kf]) @ np.abs(before[kf])
        after = after @ F[kf]
    return float(total / (abs(y @ x) * abs(w[k])))
