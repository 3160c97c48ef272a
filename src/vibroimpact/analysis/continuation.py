"""Pseudo-arclength continuation of periodic orbits in d, with stability, critical and grazing points.

Both physical parameterisations of the paper keep ``gbar`` affine in ``d``:

* ``vary="s"`` (cylinder length at fixed force): ``d`` changes, ``gbar`` is fixed;
* ``vary="F"`` (force at fixed length): ``d = s M omega^2 / (F pi^2)`` and ``gbar = M g sin(beta) / F``
  both scale with ``1/F``, so ``gbar = (gbar_0 / d_0) d``;
* ``vary="d"``: non-dimensional ``d`` at fixed ``gbar`` (same as "s", without physical units).

So the branch is continued in ``(z, d)`` with ``gbar(d) = g0 + g1 d``.  Critical points are zeros of
test functions along the branch, refined by Brent's method on the arclength between two branch
points with a pseudo-arclength corrector (so folds in d are no obstacle):

* ``B``: period doubling, an eigenvalue -1: ``det(I + DP) = 1 + Tr + Det``;
* ``fold``: an eigenvalue +1: ``det(I - DP) = 1 - Tr + Det``;
* ``A``: node <-> focus: ``Delta = Tr^2 - 4 Det``;
* ``NS``: complex pair on the unit circle: ``Det - 1`` where ``Delta < 0``;
* ``grazing``: the orbit's clearance (interior tangency with a wall, or an impact speed reaching 0).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .._progress import Progress
from ..datasets import VARIABLES, annotate
from ..dynamics.params import Params, length_factor
from ..dynamics.runs import simulate
from .motions import identify_attractor
from .orbits import Orbit, OrbitError, find_orbit, orbit_from_vector, parse_word, residual_and_jacobian

__all__ = ["follow_curve", "OutOfRange", "PARAMETERS", "ParameterMap", "branch_from_simulation", "branch_parameters", "continue_orbit", "simulate_along"]

TESTS = ("B", "fold", "A", "NS", "grazing")


def branch_parameters(orbit: Orbit, vary: str):
    """``(g0, g1, to_physical)``: ``gbar = g0 + g1 d`` and a function d -> dict of physical values."""
    p = orbit.params
    phys = p.physical
    if vary in ("s", "F") and not phys:
        raise ValueError(f"vary = {vary!r} needs physical parameters: build the orbit's Params with Params.from_physical")
    if vary in ("d", "s"):
        g0, g1 = p.gbar, 0.0
    elif vary == "F":
        g0, g1 = 0.0, p.gbar / p.d
    else:
        raise ValueError(f"vary = {vary!r}; allowed: 's' (length at fixed force), 'F' (force at fixed length), 'd'")

    def to_physical(d):
        if not phys:
            return {}
        k = length_factor(phys["M"], phys["omega"])  # d = k s / F
        if vary == "F":
            F = k * phys["s"] / d
            return dict(s=phys["s"], F=F)
        return dict(s=d * phys["F"] / k, F=phys["F"])

    return g0, g1, to_physical


#: parameters a branch can be continued in: non-dimensional, then physical (paper §2 scaling)
PARAMETERS = ("d", "gbar", "r", "s", "F", "beta", "omega")


class ParameterMap:
    """How the model's ``(d, gbar, r)`` follow the continuation variable ``lam`` when ``vary`` changes.

    ``vary`` in ``("d", "s", "F")``: ``lam = d`` and ``gbar = g0 + g1 d`` (module docstring).  ``vary`` in
    ``("gbar", "r", "beta", "omega")``: ``lam`` is that parameter, the others fixed at the orbit's:
    ``gbar = M g sin(beta) / F`` and ``d = s M omega^2 / (F pi^2)`` for the physical ones.
    """

    def __init__(self, orbit: Orbit, vary: str):
        if vary not in PARAMETERS:
            raise ValueError(f"vary = {vary!r}; allowed: {', '.join(PARAMETERS)}")
        p = orbit.params
        self.vary, self.phys, self.d0, self.g0, self.r0 = vary, dict(p.physical), p.d, p.gbar, p.r
        if vary in ("s", "F", "beta", "omega") and not self.phys:
            raise ValueError(f"vary = {vary!r} needs physical parameters: build the orbit's Params with "
                             "Params.from_physical")
        self.line = vary in ("d", "s", "F")
        if self.line:
            self.g_int, self.g_slope, _ = branch_parameters(orbit, vary)
        self.lam0 = {"gbar": p.gbar, "r": p.r}.get(vary, self.phys.get(vary, p.d)) if not self.line else p.d

    @property
    def label(self) -> str:
        """Name of the continuation variable (``d`` for the d-family)."""
        return "d" if self.line else self.vary

    def valid(self, lam) -> bool:
        """Does ``lam`` keep the model's parameters in their range (d > 0, gbar >= 0, 0 <= r < 1,
        0 <= beta <= pi/2, omega > 0)?"""
        d, gbar, r = self.at(lam)
        ok = d > 0 and gbar >= 0 and 0 <= r < 1
        if self.vary == "beta":
            ok = ok and 0 <= lam <= math.pi / 2
        if self.vary in ("omega", "F"):
            ok = ok and lam > 0
        return bool(ok)

    def at(self, lam):
        """``(d, gbar, r)`` at ``lam``."""
        if self.line:
            return lam, self.g_int + self.g_slope * lam, self.r0
        ph = self.phys
        if self.vary == "gbar":
            return self.d0, lam, self.r0
        if self.vary == "r":
            return self.d0, self.g0, lam
        if self.vary == "beta":
            return self.d0, ph["M"] * ph["g"] * math.sin(lam) / ph["F"], self.r0
        return length_factor(ph["M"], lam) * ph["s"] / ph["F"], self.g0, self.r0  # omega

    def deriv(self, lam):
        """``(dd/dlam, dgbar/dlam, dr/dlam)``."""
        if self.line:
            return 1.0, self.g_slope, 0.0
        ph = self.phys
        if self.vary == "gbar":
            return 0.0, 1.0, 0.0
        if self.vary == "r":
            return 0.0, 0.0, 1.0
        if self.vary == "beta":
            return 0.0, ph["M"] * ph["g"] * math.cos(lam) / ph["F"], 0.0
        return 2.0 * ph["s"] * ph["M"] * lam / (ph["F"] * math.pi**2), 0.0, 0.0  # omega

    def physical(self, lam) -> dict:
        """The physical values at ``lam`` that the branch changes (``s``, ``F``, ``beta``, ``omega``; empty
        for a non-dimensional parameterisation)."""
        if not self.phys:
            return {}
        d, _, _ = self.at(lam)
        ph, k = self.phys, length_factor(self.phys["M"], self.phys["omega"])
        if self.vary == "F":
            return dict(s=ph["s"], F=k * ph["s"] / d)
        if self.vary in ("s", "d"):
            return dict(s=d * ph["F"] / k, F=ph["F"])
        if self.vary in ("beta", "omega"):
            return {self.vary: lam}
        return {}

    def value(self, lam) -> float:
        """The varied parameter's own value at ``lam`` (``s`` in metres, ``F`` in newtons, ...)."""
        if self.vary in ("d", "gbar", "r", "beta", "omega"):
            return lam
        return self.physical(lam)[self.vary]


def _augmented(Y, walls, k, pm):
    """Residual F(z, lam) and its Jacobian [F_z | F_lam] (2N+1 x 2N+2), ``lam`` the last entry of ``Y``:
    the model's ``(d, gbar, r)`` and their derivatives in ``lam`` as the parameter map ``pm`` says."""
    n = walls.shape[0]
    z, lam = Y[:-1], Y[-1]
    d, gbar, r = pm.at(lam)
    dd, dg, dr = pm.deriv(lam)
    F, Jz = residual_and_jacobian(z, walls, d, gbar, r, k)
    J = np.zeros((2 * n + 1, 2 * n + 2))
    J[:, :-1] = Jz
    Fd = J[:, -1]
    # on Python's floats, which round as numpy's do (tau ** 2 is libm's pow on both, not tau * tau)
    tau, v, w = z[1:n + 1].tolist(), z[n + 1:].tolist(), walls.tolist()
    for j in range(n):
        jn = (j + 1) % n
        # d enters through the walls, gbar through the flight, r through the rebound u = -r v_j
        Fd[2 * j] = -(w[jn] - w[j]) * 0.5 * dd + dg * 0.5 * tau[j] ** 2
        Fd[2 * j + 1] = dg * tau[j]
        if dr != 0.0:
            Fd[2 * j] -= dr * v[j] * tau[j]
            Fd[2 * j + 1] -= dr * v[j]
    return F, J


def null_tangent(J, prev=None):
    """Unit null vector of the (m x m+1) Jacobian, oriented along ``prev`` (``t . prev > 0``: the
    extra row of the system asks for ``t . prev = 1``)."""
    m = J.shape[0]
    A = np.vstack([J, prev if prev is not None else np.eye(m + 1)[-1]])
    b = np.zeros(m + 1)
    b[-1] = 1.0
    t = np.linalg.solve(A, b)
    return t / np.linalg.norm(t)


def _correct(Yp, tangent, walls, k, pm, tol=1e-13, max_iter=12):
    """Newton on F = 0 plus tangent . (Y - Yp) = 0."""
    Y = Yp.copy()
    for _ in range(max_iter):
        F, J = _augmented(Y, walls, k, pm)
        G = np.append(F, tangent @ (Y - Yp))
        A = np.vstack([J, tangent])
        step = np.linalg.solve(A, -G)
        Y += step
        if np.max(np.abs(step)) < tol * max(1.0, np.max(np.abs(Y))):
            return Y
    F, _ = _augmented(Y, walls, k, pm)
    if np.max(np.abs(F)) < 1e-10:
        return Y
    raise OrbitError("corrector did not converge")


def _orbit_at(Y, template: Orbit, pm: ParameterMap):
    d, gbar, r = pm.at(float(Y[-1]))
    p = Params(d=float(d), gbar=float(gbar), r=float(r))
    return orbit_from_vector(p, template.word, template.k, Y[:-1].copy())


def bifurcation_functions(o: Orbit):
    """The test functions whose zeros are the orbit's critical points: period doubling ``B = 1 + Tr + Det``,
    ``fold = 1 - Tr + Det``, node/focus ``A = Tr^2 - 4 Det``, Neimark-Sacker ``NS = Det - 1`` (where
    ``A < 0``) and ``grazing`` (the orbit's clearance from the walls)."""
    tr, det = o.trace, o.det
    disc = tr * tr - 4 * det
    return {"B": 1 + tr + det, "fold": 1 - tr + det, "A": disc, "NS": (det - 1) if disc < 0 else math.nan,
            "grazing": o.clearance}


def continue_orbit(
    orbit: Orbit,
    *,
    vary: str = "d",
    d_range: tuple[float, float] | None = None,
    value_range: tuple[float, float] | None = None,
    step: float = 1e-3,
    max_points: int = 100_000,
    locate: bool = True,
    xtol: float = 1e-13,
    progress: bool | None = None,
) -> xr.Dataset:
    """Follow ``orbit`` in both directions along its branch in one parameter.

    Parameters
    ----------
    orbit : Orbit
        Starting orbit (from :func:`~vibroimpact.analysis.orbits.find_orbit`; built with
        :meth:`~vibroimpact.dynamics.params.Params.from_physical` for a physical parameter).
    vary : {"d", "gbar", "r", "s", "F", "beta", "omega"}
        The parameter: non-dimensional ``d``, ``gbar`` or ``r``, or physical cylinder length ``s`` (m),
        force ``F`` (N), incline ``beta`` (rad) or angular frequency ``omega`` (rad/s), the others fixed
        (:class:`ParameterMap`).
    d_range : (float, float), optional
        Interval of d to cover (``vary`` in "d", "s", "F", whose continuation variable is d).
    value_range : (float, float), optional
        Interval of the varied parameter itself (any ``vary``; for "s" and "F" instead of ``d_range``).
    step : float
        Arclength step in the ``(z, lam)`` space (halved on a failed corrector, down to 1e-9).
    locate : bool
        Refine the zeros of the test functions (critical and grazing points) to ``xtol`` in the
        continuation variable.
    xtol : float
        Tolerance of that refinement.
    max_points : int
        Most branch points per direction.
    progress : bool, optional
        A progress bar over the share of the interval covered (default: only when run interactively,
        :mod:`vibroimpact._progress`).

    Returns
    -------
    xarray.Dataset
        Along ``point`` (ordered by arclength): ``d``, ``gbar``; ``r`` where ``vary="r"``; ``value`` (the
        varied parameter) where it is not ``d``, ``s`` or ``F``; the physical values (``s`` and ``F``,
        or ``beta`` or ``omega``, with the others held) where ``vary`` is physical; per impact (``impact``,
        whose walls are ``wall``) ``v_minus``, ``phase``, ``dt``, ``t``; per eigenvalue ``eig_real``,
        ``eig_imag``, ``eig_abs``; ``trace``, ``det``, ``discriminant``, ``stable``, ``stability``,
        ``admissible``, ``reason``, ``clearance``.  Along ``critical`` (the points where a test function
        changes sign: ``"B"`` for an eigenvalue -1, ``"fold"`` for +1, ``"A"`` for a double eigenvalue,
        ``"NS"`` for a pair on the unit circle, ``"grazing"`` for zero clearance): ``critical_kind``,
        ``critical_d``, ``critical_value``, the physical values ``critical_s``, ``critical_F``, ...,
        ``critical_admissible``, ``critical_refined`` (located to ``xtol``; else a linear estimate between
        two branch points) and ``critical_note`` (why a point could not be refined, empty where it was).
        Attributes: ``word``, ``k``, ``r``, ``vary``, ``step``, ``stop_increasing`` and
        ``stop_decreasing`` (why each direction stopped), and for ``d``, ``s`` or ``F`` the line
        ``gbar = gbar_intercept + gbar_slope * d`` the branch lies on.

    Examples
    --------
    >>> import vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params(d=0.14, gbar=0.0949, r=0.5), "BBT", 5.855, 0.4185)
    >>> br = vi.continue_orbit(o, vary="d", d_range=(0.13, 0.15), step=1e-3)
    >>> [(str(k), round(float(d), 6)) for k, d in zip(br.critical_kind.values, br.critical_d.values)]
    [('grazing', 0.13672), ('A', 0.138944), ('A', 0.148631)]
    >>> br.critical_refined.values.tolist(), br.attrs["stop_increasing"].startswith("left d_range")
    ([True, True, True], True)
    """
    pm = ParameterMap(orbit, vary)
    lo, hi = _lam_range(pm, orbit, d_range, value_range)
    if not step > 0:
        raise ValueError(f"step = {step!r}; allowed: > 0")
    walls = parse_word(orbit.word)
    r, k = orbit.params.r, orbit.k
    Y0 = np.append(orbit.z, pm.lam0)
    _, J0 = _augmented(Y0, walls, k, pm)
    t0 = null_tangent(J0)
    halves, stops = [], []
    bar = Progress(1000, f"continue {orbit.word} in {vary}", progress, unit="‰ of the interval")
    seen = [float(Y0[-1]), float(Y0[-1])]
    for sign in (+1.0, -1.0):
        Ys, stop, seen = _half_branch(Y0, sign * t0, walls, k, pm, (step, max_points, lo, hi), bar, seen, orbit.word)
        halves.append(Ys)
        stops.append(stop)
    bar.close()
    Ys = halves[1][::-1] + halves[0][1:]
    orbits = [_orbit_at(Y, orbit, pm) for Y in Ys]
    lams = np.array([float(Y[-1]) for Y in Ys])
    ds = _branch_dataset(orbits, lams, pm)
    crit = _locate(Ys, orbits, orbit, walls, r, k, xtol, pm) if locate else []
    # keep only the points inside the range (the last step may overshoot)
    inside = (lams >= lo) & (lams <= hi)
    ds = ds.isel(point=np.flatnonzero(inside))
    crit = [c for c in crit if lo <= c[1] <= hi]
    ds = _with_critical(ds, crit, pm, vary)
    ds.attrs.update(word=orbit.word, k=k, r=r, vary=vary, step=step, stop_increasing=stops[0],
                    stop_decreasing=stops[1])
    if pm.line:
        ds.attrs.update(gbar_intercept=pm.g_int, gbar_slope=pm.g_slope)
    return ds

class OutOfRange(Exception):
    """A step of :func:`follow_curve` would leave the model's parameter range."""


def follow_curve(X0, t, *, step, max_points, correct, tangent, degenerate, outside, where, edge):
    """One direction of a pseudo-arclength continuation (a branch in one parameter, a curve of critical points in
    two): from ``X0`` along the tangent ``t``, each step predicted along the tangent and corrected
    (``correct(X, h, t)``, which raises :class:`OutOfRange` or a numerical error, and the step halves), its
    length doubling back up to ``step`` after each accepted point.  Returns the points and why it stopped: a
    degenerate point (``degenerate(X)``: a message or ""), a point outside the interval or box
    (``outside(X)``, after it is kept), a step halved below 1e-9 (``edge(X)`` or the corrector's error, at
    ``where(X)``) or ``max_points``.  ``tangent(X, t)``: the new tangent at an accepted point."""
    Xs, h, X = [X0], step, X0
    while len(Xs) < max_points:
        try:
            Xn = correct(X, h, t)
        except OutOfRange:
            h *= 0.5
            if h < 1e-9:
                stop = edge(X)
                break
            continue
        except (OrbitError, np.linalg.LinAlgError, ValueError) as err:
            h *= 0.5
            if h < 1e-9:
                stop = f"corrector failed down to a step of 1e-9 at {where(X)} ({err})"
                break
            continue
        stop = degenerate(Xn)
        if stop:
            break
        t = tangent(Xn, t)
        X = Xn
        Xs.append(X)
        h = min(step, 2 * h)
        stop = outside(X)
        if stop:
            break
    else:
        stop = f"max_points ({max_points}) reached"
    return Xs, stop


def _half_branch(Y0, t, walls, k, pm, limits, bar, seen, word):
    """One direction of :func:`continue_orbit` from ``Y0`` along the tangent ``t`` (:func:`follow_curve`): its
    points, why it stopped, and the interval of the parameter ``seen`` so far (for the bar).  ``limits``:
    ``(step, max_points, lo, hi)``."""
    step, max_points, lo, hi = limits
    seen = list(seen)

    def correct(Y, h, t):
        Yn = _correct(Y + h * t, t, walls, k, pm)
        if not pm.valid(Yn[-1]):
            raise OrbitError(f"{pm.vary} = {pm.value(Yn[-1]):.10g} is outside the model's range")
        return Yn

    def outside(Y):
        seen[:] = [min(seen[0], max(float(Y[-1]), lo)), max(seen[1], min(float(Y[-1]), hi))]
        bar.update(max(0, int(1000 * (seen[1] - seen[0]) / (hi - lo)) - bar.n))
        return "" if lo <= Y[-1] <= hi else f"left {'d_range' if pm.line else 'value_range'} at {pm.label} = {Y[-1]:.10g}"

    Ys, stop = follow_curve(
        Y0, t, step=step, max_points=max_points, correct=correct,
        tangent=lambda Y, t: null_tangent(_augmented(Y, walls, k, pm)[1], t),
        degenerate=lambda Y: (f"a flight time reached zero near {pm.label} = {Y[-1]:.10g}: the word {word} degenerates"
                              if np.any(Y[1:1 + len(walls)] <= 0) else ""),
        outside=outside, where=lambda Y: f"{pm.label} = {Y[-1]:.10g}", edge=None)
    return Ys, stop, seen


def _with_critical(ds, crit, pm, vary):
    """A branch dataset with its critical points ``crit`` (``(kind, lambda, admissible, refined, note)``)."""
    ds = ds.assign_coords(critical=np.arange(len(crit)))
    ds["critical_kind"] = ("critical", np.array([c[0] for c in crit], dtype=object).astype(str))
    ds["critical_d"] = ("critical", np.array([pm.at(c[1])[0] for c in crit], dtype=float))
    ds["critical_value"] = ("critical", np.array([pm.value(c[1]) for c in crit], dtype=float),
                            {"long_name": f"{vary} at the critical point", "units": VARIABLES[vary][0]})
    ds["critical_admissible"] = ("critical", np.array([c[2] for c in crit], dtype=bool))
    ds["critical_refined"] = ("critical", np.array([c[3] for c in crit], dtype=bool),
                              {"long_name": "located to xtol (else: linear estimate between branch points)"})
    ds["critical_note"] = ("critical", np.array([c[4] for c in crit], dtype=object).astype(str),
                           {"long_name": "why a point could not be refined (empty when it was)"})
    for key in pm.physical(pm.lam0):
        ds[f"critical_{key}"] = ("critical", np.array([pm.physical(c[1])[key] for c in crit], dtype=float))
    return ds



def _lam_range(pm: ParameterMap, orbit: Orbit, d_range, value_range):
    """The continuation variable's interval from ``d_range`` or ``value_range``, checked."""
    if (d_range is None) == (value_range is None):
        raise ValueError(f"give one of d_range = {d_range!r} and value_range = {value_range!r}")
    if d_range is not None:
        if not pm.line:
            raise ValueError(f"d_range is for vary in 'd', 's', 'F'; vary = {pm.vary!r} needs value_range")
        lo, hi = sorted(float(x) for x in d_range)
        what, rng = "d_range", d_range
    else:
        vals = [float(x) for x in value_range]
        if pm.vary in ("s", "F"):  # to d: d = k s / F
            ph = pm.phys
            kk = length_factor(ph["M"], ph["omega"])
            vals = [kk * v / ph["F"] if pm.vary == "s" else kk * ph["s"] / v for v in vals]
        lo, hi = sorted(vals)
        what, rng = "value_range", value_range
    if not lo < pm.lam0 < hi:
        name, val = ("d", pm.lam0) if d_range is not None else (pm.vary, pm.value(pm.lam0))
        raise ValueError(f"{what} = {rng!r} must contain the orbit's {name} = {val!r}")
    return lo, hi


def _locate(Ys, orbits, template, walls, r, k, xtol, pm):
    """Zeros of the test functions between consecutive branch points, refined on the arclength."""
    from scipy.optimize import brentq  # here, not at the top: the jobs that only read branches do not import scipy

    vals = [bifurcation_functions(o) for o in orbits]
    found = []
    for i in range(len(Ys) - 1):
        Ya, Yb = Ys[i], Ys[i + 1]
        chord = Yb - Ya
        tan = chord / np.linalg.norm(chord)
        for name in TESTS:
            fa, fb = vals[i][name], vals[i + 1][name]
            if not (np.isfinite(fa) and np.isfinite(fb)) or fa * fb > 0 or fa == fb:
                continue

            def f(sig, name=name, Ya=Ya, chord=chord, tan=tan):
                Y = _correct(Ya + sig * chord, tan, walls, k, pm)
                return bifurcation_functions(_orbit_at(Y, template, pm))[name]

            adm = orbits[i].admissible or orbits[i + 1].admissible
            try:
                sig = brentq(f, 0.0, 1.0, xtol=xtol / max(abs(chord[-1]), 1e-300), rtol=1e-15)
                Y = _correct(Ya + sig * chord, tan, walls, k, pm)
            except (ValueError, OrbitError, np.linalg.LinAlgError) as err:
                # kept, with a linear estimate between the branch points and the reason
                est = float(Ya[-1] + fa / (fa - fb) * (Yb[-1] - Ya[-1]))
                found.append((name, est, bool(adm), False, f"not refined ({type(err).__name__}: {err}); "
                              f"between {pm.label} = {Ya[-1]:.10g} and {Yb[-1]:.10g}"))
                continue
            o = _orbit_at(Y, template, pm)
            val = bifurcation_functions(o)[name]
            if abs(val) > 1e-7 * max(1.0, min(abs(fa), abs(fb))):
                # a jump, not a zero: the clearance when an extremum appears, or a pole of the
                # Jacobian where an impact velocity passes through zero
                continue
            # admissible on at least one side: the critical point belongs to the physical branch
            found.append((name, float(Y[-1]), bool(adm), True, ""))
    return found


def _branch_dataset(orbits, lams, pm: ParameterMap) -> xr.Dataset:
    n = orbits[0].n
    d = np.array([o.params.d for o in orbits])
    ev = np.array([np.sort_complex(o.eigenvalues) for o in orbits])
    ds = xr.Dataset(
        {
            "gbar": ("point", np.array([o.params.gbar for o in orbits])),
            "v_minus": (("point", "impact"), np.array([o.v_minus for o in orbits])),
            "phase": (("point", "impact"), np.array([o.phase for o in orbits])),
            "dt": (("point", "impact"), np.array([o.dt for o in orbits])),
            "t": (("point", "impact"), np.array([o.t for o in orbits])),
            "wall": ("impact", orbits[0].walls),
            "eig_real": (("point", "eig"), ev.real),
            "eig_imag": (("point", "eig"), ev.imag),
            "eig_abs": (("point", "eig"), np.abs(ev)),
            "trace": ("point", np.array([o.trace for o in orbits])),
            "det": ("point", np.array([o.det for o in orbits])),
            "discriminant": ("point", np.array([o.discriminant for o in orbits])),
            "stable": ("point", np.array([o.stable for o in orbits])),
            "stability": ("point", np.array([o.stability for o in orbits]).astype(str)),
            "admissible": ("point", np.array([o.admissible for o in orbits])),
            "reason": ("point", np.array([o.reason for o in orbits]).astype(str)),
            "clearance": ("point", np.array([o.clearance for o in orbits])),
        },
        coords={"point": np.arange(len(orbits)), "impact": np.arange(n), "eig": [0, 1], "d": ("point", d)},
    )
    if pm.vary == "r":
        ds["r"] = ("point", np.array([o.params.r for o in orbits]))
    if not pm.line:
        ds["value"] = ("point", np.array([pm.value(x) for x in lams]), {"long_name": f"the varied parameter, {pm.vary}",
                                                                          "units": VARIABLES[pm.vary][0]})
    phys = [pm.physical(x) for x in lams]
    for key in phys[0] if phys else ():
        ds[key] = ("point", np.array([p[key] for p in phys]))
    return annotate(ds)


def branch_from_simulation(params: Params, word: str, *, k: int = 1, vary: str, d_range, step: float,
                           phi: float = 1.0, v0: float = 0.2, n_impacts: int = 100_000) -> xr.Dataset:
    """Find the orbit ``word`` as the simulated attractor at ``params`` and continue it over ``d_range``.

    A failure (the attractor there is another motion, Newton or the continuation fails, or the branch
    found does not reach ``d_range``) gives an empty branch whose ``status`` attribute is ``"failed"`` and
    ``reason`` says why: recorded, not dropped.  A start outside ``d_range`` (a force range that another
    device maps to other d) is continued from where it is found to the range, and the branch kept inside it.

    Parameters
    ----------
    params : Params
        Where to start (from :meth:`~vibroimpact.Params.from_physical` for a physical ``vary``).
    word : str
        The orbit's walls over one period, e.g. ``"BBT"``.
    k : int
        Forcing periods per orbit period.
    vary : {"d", "gbar", "r", "s", "F", "beta", "omega"}
        The parameter to continue in (:func:`~vibroimpact.continue_orbit`).
    d_range : (float, float)
        Interval of d to cover.
    step : float
        Continuation step.
    phi, v0 : float
        First bottom impact of the simulation that finds the attractor.
    n_impacts : int
        Events of that simulation at most.

    Returns
    -------
    xarray.Dataset
        The branch (:func:`~vibroimpact.continue_orbit`), with attributes ``status`` (``"ok"`` or
        ``"failed"``) and ``reason``.

    Examples
    --------
    At the point of Figure 7 (a) the attractor is the 2:1 orbit: its branch is found and continued over
    ``d_range``; the 1:1 orbit ``"BT"`` is not the attractor there, a failure recorded with its reason:

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
    >>> br = vi.branch_from_simulation(p, "BBT", vary="d", d_range=(0.155, 0.165), step=2e-3, phi=1.015,
    ...                                v0=0.1924, n_impacts=2000)
    >>> br.attrs["status"], round(float(br.d.min()), 3), round(float(br.d.max()), 3), bool(br.stable.all())
    ('ok', 0.155, 0.165, True)
    >>> bt = vi.branch_from_simulation(p, "BT", vary="d", d_range=(0.155, 0.165), step=2e-3, phi=1.015,
    ...                                v0=0.1924, n_impacts=2000)
    >>> bt.attrs["status"], bt.attrs["reason"], bt.sizes["point"]
    ('failed', "the attractor at d=0.16 is 2:1 period-2 (BTB), not 'BT'", 0)
    """

    try:
        att = identify_attractor(simulate(params, phi, v0, n_impacts=n_impacts, stop_when_periodic=True))
        if not att.periodic:
            raise OrbitError(f"the simulated motion at d={params.d:.6g} is not periodic: no start for {word!r}")
        seen = "".join("B" if w == 1 else "T" for w in att.cycle.wall.values)
        if len(seen) != len(word) or seen not in word + word:
            raise OrbitError(f"the attractor at d={params.d:.6g} is {att.label} ({seen}), not {word!r}")
        bottom = att.cycle.where(att.cycle.wall == 1, drop=True)
        orbit = find_orbit(params, word, float(bottom.phase[0]), float(bottom.v_minus[0]), k=k)
        lo, hi = sorted(float(x) for x in d_range)
        reach = (min(lo, params.d - step), max(hi, params.d + step))  # from the start to the range
        ds = continue_orbit(orbit, vary=vary, d_range=reach, step=step)
        if reach != (lo, hi):
            ds = _within(ds, lo, hi)
            if not ds.sizes["point"]:
                raise OrbitError(f"the branch found at d={params.d:.6g}, outside d_range = [{lo:.6g}, {hi:.6g}], "
                                 f"does not reach it ({ds.attrs['stop_increasing']}; {ds.attrs['stop_decreasing']})")
            ds.attrs["started_at_d"] = params.d
        ds.attrs.update(status="ok", reason="")
    except (OrbitError, np.linalg.LinAlgError) as err:
        ds = xr.Dataset(coords={"point": np.arange(0)})
        ds.attrs.update(status="failed", reason=str(err), word=word, k=k, vary=vary)
    return ds


def _within(ds: xr.Dataset, lo: float, hi: float) -> xr.Dataset:
    """The points and critical points of a branch with ``lo <= d <= hi``."""
    keep = lambda d: np.flatnonzero((d >= lo) & (d <= hi))
    ds = ds.isel(point=keep(ds.d.values), critical=keep(ds.critical_d.values))
    return ds.assign_coords(point=np.arange(ds.sizes["point"]), critical=np.arange(ds.sizes["critical"]))


def simulate_along(branch: xr.Dataset, n: int, *, tol: float = 1e-11, n_impacts: int = 200_000) -> xr.Dataset:
    """Simulated attractors at ``n`` values of d spread over the stable, admissible part of a branch.

    Each run starts on the analytic orbit at that d; the attractor's impacts, rotated to the word's order,
    are compared with the analytic ones (``max_dev``).  These are the figures' open circles and the evidence
    that branch and simulation agree where the orbit is stable.

    Parameters
    ----------
    branch : xarray.Dataset
        From :func:`~vibroimpact.continue_orbit`.
    n : int
        Values of d to simulate at.
    tol : float
        Periodicity tolerance of the runs.
    n_impacts : int
        Events per run at most.

    Returns
    -------
    xarray.Dataset
        Along ``sim``: ``d``, the attractor's ``motion`` (its label), ``v_minus``, ``phase`` and ``dt`` per
        impact, ``max_dev`` from the analytic orbit and ``status`` (``"compared"``, or why not: the run
        settled on another motion, or no analytic orbit was found to start from).

    Examples
    --------
    Along the stable part of the 2:1 branch the simulated attractor is the analytic orbit:

    >>> import vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params(d=0.14, gbar=0.0949, r=0.5), "BBT", 5.855, 0.4185)
    >>> sims = vi.simulate_along(vi.continue_orbit(o, vary="d", d_range=(0.13, 0.15), step=1e-3), 2)
    >>> sims.motion.values.tolist(), sims.status.values.tolist(), bool(sims.max_dev.max() < 1e-9)
    (['2:1 period-2', '2:1 period-2'], ['compared', 'compared'], True)
    """

    ok = np.flatnonzero((branch.stable & branch.admissible).values) if branch.sizes["point"] else np.array([], int)
    word, k = branch.attrs["word"], int(branch.attrs["k"])
    rows = []
    if ok.size:
        d_vals = np.linspace(branch.d.values[ok].min(), branch.d.values[ok].max(), n + 2)[1:-1]
        g0, g1 = branch.attrs["gbar_intercept"], branch.attrs["gbar_slope"]
        for d in d_vals:
            i = ok[np.argmin(np.abs(branch.d.values[ok] - d))]
            p = Params(d=float(d), gbar=g0 + g1 * float(d), r=float(branch.attrs["r"]))
            m = len(word)
            try:
                o = find_orbit(p, word, float(branch.phase[i, 0]), float(branch.v_minus[i, 0]), k=k)
            except OrbitError as err:
                rows.append((d, "none", np.full(m, np.nan), np.full(m, np.nan), np.full(m, np.nan), np.nan,
                             f"skipped: no analytic orbit to start from ({err})"))
                continue
            att = identify_attractor(simulate(p, o.phi, o.v_minus[0], n_impacts=n_impacts, stop_when_periodic=True, tol=tol), tol=tol)
            if not att.periodic or att.events != o.n:
                rows.append((d, att.label, np.full(o.n, np.nan), np.full(o.n, np.nan), np.full(o.n, np.nan), np.nan,
                             f"not compared: the attractor is {att.label}, not the analytic motion"))
                continue
            v = att.cycle.v_minus.values
            shift = int(np.argmin([np.max(np.abs(np.roll(v, -s) - o.v_minus)) for s in range(o.n)]))
            v, ph, dt = (np.roll(att.cycle[x].values, -shift) for x in ("v_minus", "phase", "dt"))
            dt = np.roll(np.diff(np.append(np.roll(att.cycle.t.values, -shift), np.roll(att.cycle.t.values, -shift)[0] + 2 * k)), 1)
            dev = max(np.max(np.abs(v - o.v_minus)), np.max(np.abs((ph - o.phase + np.pi) % (2 * np.pi) - np.pi)))
            rows.append((d, att.label, v, ph, dt, dev, "compared"))
    m = len(word)
    ds = xr.Dataset(
        {
            "v_minus": (("sim", "impact"), np.array([r[2] for r in rows]).reshape(-1, m)),
            "phase": (("sim", "impact"), np.array([r[3] for r in rows]).reshape(-1, m)),
            "dt": (("sim", "impact"), np.array([r[4] for r in rows]).reshape(-1, m)),
            "motion": ("sim", np.array([r[1] for r in rows], dtype=object).astype(str)),
            "max_dev": ("sim", np.array([r[5] for r in rows], dtype=float),
                        {"units": "1", "long_name": "largest difference |simulated - analytic| of Zdot- and phase"}),
            "status": ("sim", np.array([r[6] for r in rows], dtype=object).astype(str),
                       {"long_name": "compared, or why this point was not"}),
        },
        coords={"sim": np.arange(len(rows)), "d": ("sim", np.array([r[0] for r in rows], dtype=float))},
    )
    ds.attrs.update(word=word, k=k, tol=tol)
    return annotate(ds)
