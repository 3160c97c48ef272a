"""Periodic impact orbits from impact maps, for any word of walls (paper §3, eqs. ``zdotj_p1``,
``zj_p1``; stability: eq. ``Lin2`` and the appendix).

A word such as ``"BBT"`` lists the walls of the impacts over ``k`` forcing periods (``k`` given, or
1).  Impact ``j`` happens at wall ``w_j`` with pre-impact velocity ``v_j``; the flight from impact
``j`` to ``j + 1`` (cyclically) lasts ``tau_j`` and starts at phase ``theta_j = theta_0 + pi sum_{i<j}
tau_i`` with the impact law's rebound velocity (``-r v_j``, :mod:`~vibroimpact.dynamics.impact`).
Each flight gives a position condition (eq. ``zj_p1``: it ends on wall ``w_{j+1}``) and a velocity
relation (eq. ``zdotj_p1``); periodicity adds ``sum tau_j = 2k``.  The ``2N + 1`` equations in ``(theta_0, tau, v)`` are solved by Newton's method with an analytic
Jacobian.

The equations know nothing of the walls between impacts: :func:`admissibility` checks every flight
against the exact simulator (its first impact must be the orbit's next one) and measures the
clearance of every interior extremum from the walls.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..dynamics import impact as law
from ..dynamics import kernels as K
from ..dynamics.flight import (
    PI,
    TWO_PI,
    flight_partials,
    step_jacobian,
)
from ..dynamics.params import Params
from ..dynamics.runs import events_dataset, simulate
from .grazing import admissibility

__all__ = ["Orbit", "OrbitError", "find_orbit", "parse_word", "solve_orbit"]

WALLS = {"B": 1, "T": -1}


class OrbitError(RuntimeError):
    """Newton's method did not converge, or the guess does not follow the word.

    Parameters
    ----------
    *args
        The message, saying which of the two happened and at which guess.

    Examples
    --------
    At d = 0.14 the start (5.855, 0.4185) lies on the 2:1 orbit ``"BBT"``, not on a 1:1 ``"BT"``:

    >>> import vibroimpact as vi
    >>> try:
    ...     vi.find_orbit(vi.Params(d=0.14, gbar=0.0949), "BT", 5.855, 0.4185)
    ... except vi.OrbitError as e:
    ...     print(e)
    the guess (phi=5.855, v0=0.4185) follows 'BB', not a rotation of 'BT'
    """


def parse_word(word: str) -> np.ndarray:
    """``"BBT"`` -> array([1, 1, -1]); rejects anything but B and T, and words without a B."""
    if not isinstance(word, str) or not word or set(word) - set(WALLS):
        raise ValueError(f"word = {word!r}; allowed: a non-empty string of 'B' (bottom) and 'T' (top)")
    if "B" not in word:
        raise ValueError(f"word = {word!r}: an orbit in the paper's convention needs a bottom impact 'B'")
    return np.array([WALLS[c] for c in word], dtype=np.int64)


# --------------------------------------------------------------------------------------------
# One flight: displacement, velocity and their partial derivatives (closed form, docs/guide/model.md)
# --------------------------------------------------------------------------------------------


def residual_and_jacobian(z, walls, d, gbar, r, k):
    """Equations of the orbit in unknowns z = (theta_0, tau_0..tau_{N-1}, v_0..v_{N-1})."""
    n = walls.shape[0]
    F = np.empty(2 * n + 1)
    J = np.zeros((2 * n + 1, 2 * n + 1))
    _flight_rows(z, walls, d, gbar, r, F, J)
    F[2 * n] = z[1:n + 1].sum() - 2.0 * k  # numpy's sum (pairwise), as the periodicity row has always been summed
    J[2 * n, 1:n + 1] = 1.0
    return F, J


@njit(cache=True, error_model="numpy")
def _flight_rows(z, walls, d, gbar, r, F, J):
    """The two rows of each flight in :func:`residual_and_jacobian`, written into ``F`` and the zeroed ``J``:
    compiled, with every operation in the order the interpreted loop took (the same results to the last bit;
    tests/test_orbits.py compares them), because a continuation evaluates them at every corrector step."""
    n = walls.shape[0]
    theta = z[0]
    for j in range(n):
        jn = (j + 1) % n
        tau_j, v_j = z[1 + j], z[n + 1 + j]
        u = law.rebound(v_j, r)
        du = law.rebound_slope(v_j, r)
        disp, vel, acc, disp_th, vel_th = flight_partials(tau_j, theta, u, gbar)
        # position: w_j d/2 + disp = w_{j+1} d/2   (eq. zj_p1)
        F[2 * j] = disp - (walls[jn] - walls[j]) * 0.5 * d
        # velocity: v_{j+1} = vel               (eq. zdotj_p1)
        F[2 * j + 1] = vel - z[n + 1 + jn]
        _flight_row(J, 2 * j, j, n, disp_th, vel, du * tau_j)
        _flight_row(J, 2 * j + 1, j, n, vel_th, acc, du * 1.0)
        J[2 * j + 1, n + 1 + jn] -= 1.0
        theta += PI * tau_j


@njit(cache=True, error_model="numpy")
def _flight_row(J, row, j, n, f_th, f_tau, f_v):
    """One row of flight ``j``: its derivatives in theta_0 and (through theta_j) the earlier flight times, in its
    own flight time and in its start velocity."""
    J[row, 0] += f_th
    for i in range(j):  # theta_j depends on the earlier flight times
        J[row, 1 + i] += PI * f_th
    J[row, 1 + j] += f_tau
    J[row, n + 1 + j] += f_v


#: a residual this many machine epsilons of the unknowns' scale is rounding: the equations' terms are of
#: order one (positions up to d/2, velocities and flight times of order one) and each residual sums a few
#: of them, so no step can lower it further
ROUNDING_RESIDUAL = 64 * np.finfo(float).eps


def solve_orbit(z0, walls, d, gbar, r, k, *, tol=1e-13, max_iter=50):
    """Newton's method on the orbit equations from the guess ``z0``; returns the solution vector.

    Converged when a full step is below ``tol`` (relative) with a residual below 1e-11, or as soon as the
    residual is at rounding level (:data:`ROUNDING_RESIDUAL` times the unknowns' scale): near a fold the
    Jacobian is nearly singular and rounding alone keeps the step above ``tol``."""
    z = np.array(z0, dtype=float)
    n = walls.shape[0]
    for it in range(max_iter):
        F, J = residual_and_jacobian(z, walls, d, gbar, r, k)
        if np.max(np.abs(F)) <= ROUNDING_RESIDUAL * max(1.0, float(np.max(np.abs(z)))):
            z[0] %= TWO_PI
            return z
        try:
            step = np.linalg.solve(J, -F)
        except np.linalg.LinAlgError as err:
            raise OrbitError(f"singular Jacobian at iteration {it}") from err
        # keep flight times positive: damp a step that would make one negative
        tau, dtau = z[1:n + 1], step[1:n + 1]
        lam = 1.0
        neg = dtau < 0
        if np.any(neg):
            lam = min(1.0, 0.9 * float(np.min(tau[neg] / -dtau[neg])))
        z = z + lam * step
        if lam == 1.0 and np.max(np.abs(step)) < tol * max(1.0, np.max(np.abs(z))):
            F, _ = residual_and_jacobian(z, walls, d, gbar, r, k)
            if np.max(np.abs(F)) < 1e-11:
                z[0] %= TWO_PI
                return z
    raise OrbitError(f"Newton did not converge in {max_iter} iterations (residual {np.max(np.abs(F)):.2e})")


# --------------------------------------------------------------------------------------------
# Linear stability: the composed impact map (paper eq. Lin2 and appendix, any word)
# --------------------------------------------------------------------------------------------


def map_jacobian(z, walls, gbar, r):
    """2x2 Jacobian of the map (t_k, Zdot_k) -> (t_{k+N}, Zdot_{k+N}) over one period (eq. Lin2).

    Each flight's map is defined implicitly by its position condition ``disp(tau; theta_j, u_j) =
    const`` with ``theta_j = pi t_j + phi`` and ``u_j = -r Zdot_j`` (the impact law's rebound).  Differentiating it (the
    appendix's eqs. EntrP1-EntrP3, for any pair of walls), with ``v'`` and ``a'`` the velocity and
    acceleration at the next impact:

        dtau = (-pi dZ/dtheta dt_j + r tau dZdot_j) / v'
        t'   = t_j + tau,      Zdot' = Zdot(tau; theta_j, u_j)
        dZdot' = a' dtau + pi dZdot/dtheta dt_j - r dZdot_j
    """
    DP = np.eye(2)
    for F in step_jacobians(z, walls, gbar, r):
        DP = F @ DP
    return DP


def step_jacobians(z, walls, gbar, r):
    """The factors of :func:`map_jacobian`: the 2x2 Jacobian of each flight's map (t_j, Zdot_j) ->
    (t_{j+1}, Zdot_{j+1}) over one period, in order."""
    n = walls.shape[0]
    theta = z[0]
    tau = z[1:n + 1]
    v = z[n + 1:]
    out = []
    for j in range(n):
        u = law.rebound(v[j], r)
        _, vel, acc, _, _ = flight_partials(tau[j], theta, u, gbar)
        # implicit flight time: disp(tau; theta_j, u_j) = const, theta_j = pi t_j + phi, u_j = rebound(v_j)
        j11, j12, j21, j22 = step_jacobian(tau[j], theta, v[j], vel, acc, r)
        out.append(np.array([[j11, j12], [j21, j22]]))
        theta += PI * tau[j]
    return out


# --------------------------------------------------------------------------------------------
# The orbit object
# --------------------------------------------------------------------------------------------


# a record a call returns: its fields are Attributes, not Parameters (no one constructs it)
@dataclass
class Orbit:  # numpydoc ignore=PR01
    """A periodic impact orbit (:func:`find_orbit`).

    Impact ``j`` (``j = 0 .. N-1``) is at wall ``wall[j]`` at time ``t[j]`` (``t[0] = 0``) with phase
    ``phase[j] = mod(pi t_j + phi, 2 pi)`` and pre-impact velocity ``v_minus[j]``; ``dt[j] = t_j -
    t_{j-1}`` is the flight arriving at it (cyclically, paper's ``Delta t``).  ``jacobian`` is the
    2x2 linearised map over one period in ``(t, Zdot)`` at impact 0 (paper eq. ``Lin2``).

    Attributes
    ----------
    params : Params
        The parameters it is solved at.
    word : str
        The walls of one period, ``"B"`` and ``"T"``.
    k : int
        Forcing periods per orbit period.
    z : numpy.ndarray
        The unknowns of the orbit equations (``theta_0``, flight times, pre-impact velocities).
    jacobian : numpy.ndarray
        The linearised map over one period (eq. ``Lin2``).
    eigenvalues : numpy.ndarray
        Its eigenvalues.
    admissible : bool
        Whether every flight stays between the walls and meets the next impact's wall first.
    reason : str
        Why it is not admissible ("" where it is).
    clearance : float
        Least distance of an interior extremum of a flight from the walls.

    Examples
    --------
    The 2:1 orbit: its flights add up to one forcing period (2 time units), and the determinant of its map
    is ``r^(2N)`` for ``N`` impacts (each impact contracts areas by ``r^2``):

    >>> import vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params(d=0.14, gbar=0.0949, r=0.5), "BBT", 5.855, 0.4185)
    >>> o.walls.tolist(), o.k, round(float(o.dt.sum()), 12)
    ([1, 1, -1], 1, 2.0)
    >>> round(o.det, 12), 0.5**6, o.stable, o.stability, o.admissible
    (0.015625, 0.015625, True, 'stable focus', True)
    """

    params: Params
    word: str
    k: int
    z: np.ndarray = field(repr=False)
    jacobian: np.ndarray = field(repr=False)
    eigenvalues: np.ndarray
    admissible: bool
    reason: str
    clearance: float

    @property
    def walls(self):
        return parse_word(self.word)

    @property
    def n(self):
        return len(self.word)

    @property
    def tau(self):
        return self.z[1:self.n + 1]

    @property
    def v_minus(self):
        return self.z[self.n + 1:]

    @property
    def t(self):
        return np.concatenate([[0.0], np.cumsum(self.tau)[:-1]])

    @property
    def phase(self):
        return (self.z[0] + PI * self.t) % TWO_PI

    @property
    def dt(self):
        return np.roll(self.tau, 1)

    @property
    def phi(self):
        """Phase of impact 0 (the paper's phi with t0 = 0)."""
        return float(self.z[0])

    @property
    def trace(self):
        return float(np.trace(self.jacobian))

    @property
    def det(self):
        J = self.jacobian
        return float(np.linalg.det(J)) if np.all(np.isfinite(J)) else math.nan

    @property
    def discriminant(self):
        """Delta = Tr^2 - 4 Det (paper eq. Lambda)."""
        return self.trace**2 - 4.0 * self.det

    @property
    def stable(self):
        return bool(np.max(np.abs(self.eigenvalues)) < 1.0)

    @property
    def stability(self):
        """'stable node', 'unstable focus', ... (paper Table 1); 'saddle' when one |lambda| > 1 > other."""
        mods = np.abs(self.eigenvalues)
        if not np.all(np.isfinite(mods)):
            return "undefined (zero-speed impact)"
        kind = "focus" if self.discriminant < 0 else "node"
        if np.all(mods < 1):
            return f"stable {kind}"
        if np.all(mods > 1):
            return f"unstable {kind}"
        return "saddle"


def _assemble(params, word, k, z):
    walls = parse_word(word)
    with np.errstate(divide="ignore", invalid="ignore"):
        J = map_jacobian(z, walls, params.gbar, params.r)
    # an impact at exactly zero speed (on a grazing curve) makes the map's Jacobian infinite (it grows as
    # 1 / v): no eigenvalues there, NaN rather than an error
    ev = np.linalg.eigvals(J) if np.all(np.isfinite(J)) else np.full(2, complex(math.nan, math.nan))

    ok, reason, clearance = admissibility(z, walls, params.d, params.gbar, params.r)
    return Orbit(params=params, word=word, k=k, z=z, jacobian=J, eigenvalues=ev, admissible=ok,
                 reason=reason, clearance=clearance)


def orbit_from_vector(params: Params, word: str, k: int, z) -> Orbit:
    """Build an :class:`Orbit` from an already solved unknown vector."""
    return _assemble(params, word, k, np.asarray(z, dtype=float))


def orbit_run(orbit: Orbit, periods: int = 1):
    """The orbit's impacts over ``periods`` periods as a run like :func:`~vibroimpact.simulate`'s.

    The run is for :func:`~vibroimpact.trajectory`: the exact state along the orbit, with no simulation.
    At a grazing point the loop touches a wall, and whether a simulator registers that touch as an impact
    is decided by rounding; the Newton orbit's flights (paper eqs. ``zdotj_p1``, ``zj_p1``) are the orbit
    itself.

    Parameters
    ----------
    orbit : Orbit
        From :func:`~vibroimpact.find_orbit`.
    periods : int
        Periods of the orbit to lay out (at least 1).

    Returns
    -------
    xarray.Dataset
        Events ``t``, ``wall``, ``v_minus``, ``v_plus``, ``phase``, ``z``, ``kind`` along ``impact``,
        ``t = 0`` at impact 0 and the last event the return to it.

    Examples
    --------
    Two periods of the 2:1 orbit: its impacts recur after 2 time units, on the walls ``Z = +-d/2``:

    >>> import vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params(d=0.14, gbar=0.0949, r=0.5), "BBT", 5.855, 0.4185)
    >>> run = vi.orbit_run(o, periods=2)
    >>> run.wall.values.tolist(), run.t.values[[0, 3, 6]].round(9).tolist()
    ([1, 1, -1, 1, 1, -1, 1], [0.0, 2.0, 4.0])
    >>> run.z.values.round(9).tolist()[:3], bool(abs(run.v_minus[3] - run.v_minus[0]) < 1e-9)
    ([0.07, 0.07, -0.07], True)
    """

    if int(periods) < 1:
        raise ValueError(f"periods = {periods!r}; allowed: an integer >= 1")
    n, m = orbit.n, orbit.n * int(periods) + 1
    idx = np.arange(m) % n
    t = np.concatenate([orbit.t + 2.0 * orbit.k * p for p in range(int(periods))] + [[2.0 * orbit.k * int(periods)]])
    walls = orbit.walls[idx]
    vm = orbit.v_minus[idx]
    bufs = K.EventBuffers(t=t, wall=walls.astype(np.int8), v_minus=vm, v_plus=law.rebound(vm, orbit.params.r),
                          phase=orbit.phase[idx], kind=np.full(m, K.IMPACT, np.int8), z=0.5 * orbit.params.d * walls)
    ds = events_dataset(bufs, m)
    ds.attrs.update(d=orbit.params.d, gbar=orbit.params.gbar, r=orbit.params.r, phi=orbit.phi,
                    v0=float(orbit.v_minus[0]), t0=0.0, start=f"periodic orbit {orbit.word} (k = {orbit.k})",
                    status="n_events", t_valid=float(t[-1]))
    return ds


def find_orbit(params: Params, word: str, phi: float, v0: float, *, k: int = 1) -> Orbit:
    """Solve the periodic orbit ``word`` (over ``k`` forcing periods) near a guess.

    The guess is in the paper's convention: a bottom impact at phase ``phi`` with pre-impact
    velocity ``v0`` (e.g. a caption, or an impact of a simulated attractor).  The exact simulator
    follows it for ``len(word)`` impacts; the walls it meets must be a rotation of ``word`` starting
    with this bottom impact, and its flight times and velocities are Newton's starting point.

    Parameters
    ----------
    params : Params
        Non-dimensional parameters ``d``, ``gbar``, ``r`` (from ``Params.from_physical`` when the
        orbit is to be continued in ``s`` or ``F``).
    word : str
        Walls met over one period, ``"B"`` (bottom) and ``"T"`` (top), e.g. ``"BBT"`` for 2:1.
    phi, v0 : float
        Guess: phase (rad) and pre-impact velocity of a bottom impact on the orbit.
    k : int
        Forcing periods per orbit period.

    Returns
    -------
    Orbit
        The orbit: impacts (``wall``, ``t``, ``phase``, ``v_minus``, ``dt``), its monodromy
        ``jacobian``, ``eigenvalues`` and stability, ``admissible`` and ``clearance``.

    Examples
    --------
    >>> import vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params(d=0.14, gbar=0.0949, r=0.5), "BBT", 5.855, 0.4185)
    >>> o.word, o.v_minus.round(5).tolist(), o.stable, o.admissible
    ('BBT', [0.40313, 0.18744, -0.46404], True, True)

    A simulation started on the orbit's first impact repeats its impacts:

    >>> run = vi.simulate(o.params, o.phi, o.v_minus[0], n_impacts=30)     # 10 periods of 3 impacts
    >>> bool(abs(run.v_minus.values[-3:] - o.v_minus).max() < 1e-9)
    True

    Raises
    ------
    ValueError
        Bad word or k.
    OrbitError
        The guess does not follow the word, or Newton's method fails.
    """

    walls = parse_word(word)
    if int(k) != k or k < 1:
        raise ValueError(f"k = {k!r}; allowed: an integer >= 1 (forcing periods of the orbit)")
    n = len(word)
    run = simulate(params, phi, v0, n_impacts=n + 1)
    seen = "".join("B" if w == 1 else "T" for w in run["wall"].values[:n])
    if run.sizes["impact"] < n + 1 or not np.all(K.hits(run["kind"].values[: n + 1])):
        raise OrbitError(f"the guess (phi={phi!r}, v0={v0!r}) sticks or ends before {n} impacts")
    rot = next((i for i in range(n) if word[i:] + word[:i] == seen), None)
    if rot is None:
        raise OrbitError(f"the guess (phi={phi!r}, v0={v0!r}) follows {seen!r}, not a rotation of {word!r}")
    t = run["t"].values
    tau = np.diff(t)
    v = run["v_minus"].values[:n]
    # scale flight times so that they close the period exactly
    tau = tau * (2.0 * k / tau.sum())
    z = np.concatenate([[phi % TWO_PI], tau, v])
    z = solve_orbit(z, np.roll(walls, -rot), params.d, params.gbar, params.r, k)
    # rotate back so that impact 0 is the word's first letter
    if rot:
        m = (n - rot) % n
        theta = (z[0] + PI * np.sum(z[1:1 + m])) % TWO_PI
        z = np.concatenate([[theta], np.roll(z[1:n + 1], -m), np.roll(z[n + 1:], -m)])
    return _assemble(params, word, int(k), z)
