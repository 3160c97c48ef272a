"""Codimension-one points followed in two parameters: curves of period doubling, folds and grazing.

A point where an orbit's test function vanishes (:data:`~vibroimpact.analysis.continuation.TESTS`: ``B`` an
eigenvalue -1, ``fold`` an eigenvalue +1, ``A`` node <-> focus, ``grazing`` zero clearance) is a
solution of the orbit equations ``F(z; p1, p2) = 0`` augmented with ``T(z; p1, p2) = 0``: 2N+2 equations
in 2N+3 unknowns ``(z, p1, p2)``, a curve, followed by pseudo-arclength continuation as the branches
are.  ``F``'s Jacobian in ``z`` is exact; its parameter columns follow from the chain rule through
``(d, gbar, r)``; ``T``'s gradient, a function of the orbit's eigenvalues or clearance, is a central
difference.  Along the curve the other test functions are watched: where one changes sign the curve
meets another codimension-one set (e.g. a period-doubling curve crossing the grazing curve), which is
recorded with its location.  Why a curve stops is recorded too.

Parameters (two of :data:`~vibroimpact.analysis.continuation.PARAMETERS`): non-dimensional ``d``, ``gbar``,
``r``, or physical ``s``, ``F``, ``beta``, ``omega`` (paper section 2 scaling, the others from the
orbit's :meth:`~vibroimpact.dynamics.params.Params.from_physical`).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .._progress import Progress
from ..datasets import annotate
from ..dynamics.params import Params
from .continuation import PARAMETERS, TESTS, OutOfRange, bifurcation_functions, follow_curve, null_tangent
from .grazing import admissibility
from .motions import NO_PERIOD_LABELS
from .orbits import Orbit, OrbitError, map_jacobian, orbit_from_vector, parse_word, residual_and_jacobian

__all__ = ["bistable_band", "curve_crossings", "curve_set", "curve_values", "follow_point", "map_boundaries", "plane_cusps"]

#: test-function values beyond this are a singular impact map (an impact at zero speed), not a crossing
REGULAR = 1e6
#: a curve point is converged when its residual, the test function included, is below this
RESIDUAL = 1e-9
#: the kinds of point that can be followed (test functions of :mod:`vibroimpact.analysis.continuation`)
KINDS = ("B", "fold", "A", "grazing")
_PHYSICAL = ("s", "F", "beta", "omega")


class _TwoParameters:
    """``(d, gbar, r)`` as functions of two parameters, the rest fixed at the orbit's values."""

    def __init__(self, orbit: Orbit, names):
        for n in names:
            if n not in PARAMETERS:
                raise ValueError(f"parameter {n!r}; allowed: {', '.join(PARAMETERS)}")
        if len(set(names)) != 2:
            raise ValueError(f"params = {tuple(names)!r}: two different parameters")
        phys = [n for n in names if n in _PHYSICAL]
        nondim = [n for n in names if n in ("d", "gbar")]
        if phys and nondim:
            raise ValueError(f"params = {tuple(names)!r}: mix {phys[0]!r} with physical parameters or 'r', "
                             f"not with {nondim[0]!r}")
        p = orbit.params
        if phys and not p.physical:
            raise ValueError(f"params = {tuple(names)!r} need physical parameters: build the orbit's Params "
                             "with Params.from_physical")
        self.names, self.base, self.physical = tuple(names), dict(p.physical), bool(phys)
        self.base.update(d=p.d, gbar=p.gbar, r=p.r)

    def start(self):
        return np.array([self.base[n] for n in self.names], dtype=float)

    def at(self, lam):
        v = dict(self.base)
        v.update(zip(self.names, (float(x) for x in lam), strict=True))
        if self.physical:
            return (v["s"] * v["M"] * v["omega"] ** 2 / (v["F"] * math.pi**2), v["M"] * v["g"] * math.sin(v["beta"]) / v["F"],
                    v["r"])
        return v["d"], v["gbar"], v["r"]

    def valid(self, lam) -> bool:
        d, gbar, r = self.at(lam)
        v = dict(zip(self.names, lam, strict=True))
        return bool(d > 0 and gbar >= 0 and 0 <= r < 1 and 0 <= v.get("beta", 0.5) <= math.pi / 2
                    and v.get("F", 1.0) > 0 and v.get("omega", 1.0) > 0 and v.get("s", 1.0) > 0)

    def jac(self, lam):
        """d(d, gbar, r)/d(lam1, lam2), by central differences of the closed forms."""
        out = np.empty((3, 2))
        for i in range(2):
            h = 1e-6 * max(1.0, abs(lam[i]))
            lp, lm = np.array(lam, float), np.array(lam, float)
            lp[i] += h
            lm[i] -= h
            out[:, i] = (np.array(self.at(lp)) - np.array(self.at(lm))) / (2 * h)
        return out


def _orbit(X, template: Orbit, pm: _TwoParameters) -> Orbit:
    d, gbar, r = pm.at(X[-2:])
    return orbit_from_vector(Params(d=float(d), gbar=float(gbar), r=float(r)), template.word, template.k,
                             X[:-2].copy())


def _test(X, walls, pm, kind):
    """The test function ``kind`` at X = (z, lam1, lam2), from only what it needs (as
    :func:`~vibroimpact.analysis.continuation.bifurcation_functions` of the orbit there): the monodromy's trace and determinant
    for B, fold and A, the clearance for grazing."""
    z = X[:-2]
    d, gbar, r = pm.at(X[-2:])
    if kind == "grazing":
        return admissibility(z, walls, d, gbar, r)[2]
    J = map_jacobian(z, walls, gbar, r)
    tr, det = J[0, 0] + J[1, 1], J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
    return {"B": 1 + tr + det, "fold": 1 - tr + det, "A": tr * tr - 4 * det}[kind]


def _residual(X, walls, template, pm, kind):
    """Residual [F; T] (2N+2) at X = (z, lam1, lam2)."""
    d, gbar, r = pm.at(X[-2:])
    F, _ = residual_and_jacobian(X[:-2], walls, d, gbar, r, template.k)
    return np.append(F, _test(X, walls, pm, kind))


def _system(X, walls, template, pm, kind):
    """Residual [F; T] (2N+2) and its Jacobian (2N+2 x 2N+3) at X = (z, lam1, lam2)."""
    n = walls.shape[0]
    z, lam = X[:-2], X[-2:]
    d, gbar, r = pm.at(lam)
    F, Jz = residual_and_jacobian(z, walls, d, gbar, r, template.k)
    # parameter columns: dF/d(d, gbar, r) times d(d, gbar, r)/dlam
    tau, v = z[1:n + 1], z[n + 1:]
    dF = np.zeros((2 * n + 1, 3))
    for j in range(n):
        jn = (j + 1) % n
        dF[2 * j] = (-(walls[jn] - walls[j]) * 0.5, 0.5 * tau[j] ** 2, -v[j] * tau[j])
        dF[2 * j + 1] = (0.0, tau[j], -v[j])
    J = np.zeros((2 * n + 2, 2 * n + 3))
    J[:2 * n + 1, :2 * n + 1] = Jz
    J[:2 * n + 1, 2 * n + 1:] = dF @ pm.jac(lam)
    t0 = _test(X, walls, pm, kind)
    for i in range(X.size):
        h = 1e-7 * max(1.0, abs(X[i]))
        xp, xm = X.copy(), X.copy()
        xp[i] += h
        xm[i] -= h
        J[-1, i] = (_test(xp, walls, pm, kind) - _test(xm, walls, pm, kind)) / (2 * h)
    return np.append(F, t0), J


def _newton(X, walls, template, pm, kind, row=None, target=0.0, tol=1e-12, max_iter=20, J=None):
    """Newton on [F; T] = 0 plus ``row . X = target`` (the pseudo-arclength or a fixed parameter).

    With ``J`` (the Jacobian at a nearby point, e.g. the curve's last point) the corrector is the chord
    method: residuals only, the Jacobian kept while each step at least halves the one before, and
    recomputed where it does not.  Converged: a step below ``tol`` (relative) and a residual below 1e-9."""
    last = math.inf
    for _ in range(max_iter):
        if J is None:
            G, J = _system(X, walls, template, pm, kind)
        else:
            G = _residual(X, walls, template, pm, kind)
        A = np.vstack([J, row])
        step = np.linalg.solve(A, -np.append(G, row @ X - target))
        X = X + step
        size = np.max(np.abs(step))
        if size < tol * max(1.0, np.max(np.abs(X))) and np.max(np.abs(_residual(X, walls, template, pm, kind))) < RESIDUAL:
            return X
        if size > 0.5 * last:
            J = None  # the chord's Jacobian is too far off: a true Newton step next
        last = size
    raise OrbitError(f"the {kind} point's corrector did not converge")


def follow_point(orbit: Orbit, kind: str, *, params, ranges, step: float = 2e-3, max_points: int = 2000) -> xr.Dataset:
    """Follow the ``kind`` point of ``orbit``'s branch as a curve in the parameter pair ``params``.

    Parameters
    ----------
    orbit : Orbit
        An orbit near the point (e.g. from :func:`~vibroimpact.analysis.orbits.find_orbit`): the point is
        first located in ``params[0]`` at the orbit's value of ``params[1]``, by Newton's method on the
        augmented system from the orbit.
    kind : {"B", "fold", "A", "grazing"}
        The defining condition: an eigenvalue -1, +1, a double eigenvalue, zero clearance.
    params : (str, str)
        The two parameters (:data:`~vibroimpact.analysis.continuation.PARAMETERS`).
    ranges : ((float, float), (float, float))
        Box of the two parameters; the curve stops where it leaves it.
    step : float
        Arclength step in ``(z, p1, p2)`` (halved on a failed corrector, down to 1e-9).
    max_points : int
        Most points per direction.

    Returns
    -------
    xarray.Dataset
        Along ``point`` (by arclength): the two parameters (named by ``params``), ``d``, ``gbar``,
        ``r``, ``admissible``, ``clearance``, ``trace``, ``det``, ``phase`` and ``v_minus`` of the
        first impact, and ``z``, the orbit's unknowns.  Along ``event``: ``event_kind`` (another test
        function changing sign: the curve meets that set) and the two parameters there (linear between
        points).  Attributes: ``kind``, ``word``, ``k``, ``params``, ``stop_increasing``,
        ``stop_decreasing`` (why each end stopped).

    Examples
    --------
    The 2:1 orbit's grazing point followed in ``(d, gbar)`` from ``gbar = 0.0949``: the clearance stays
    zero along the curve, which passes through the grazing point G1 at the paper's incline pi/6
    (``gbar = 0.12201``), d = 0.1376:

    >>> import numpy as np, vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params(d=0.14, gbar=0.0949, r=0.5), "BBT", 5.855, 0.4185)
    >>> c = vi.follow_point(o, "grazing", params=("d", "gbar"), ranges=((0.13, 0.15), (0.09, 0.125)),
    ...                     step=4e-3)
    >>> bool(abs(c.clearance).max() < 1e-9), round(float(np.interp(0.12201, c.gbar, c.d)), 4)
    (True, 0.1376)
    """
    if kind not in KINDS:
        raise ValueError(f"kind = {kind!r}; allowed: {', '.join(KINDS)}")
    pm = _TwoParameters(orbit, params)
    box = np.array([sorted(float(x) for x in r) for r in ranges])
    if box.shape != (2, 2):
        raise ValueError(f"ranges = {ranges!r}: two (low, high) pairs")
    walls = parse_word(orbit.word)
    X = np.append(orbit.z, pm.start())
    # locate the point in params[0] with params[1] fixed
    row = np.zeros(X.size)
    row[-1] = 1.0
    try:
        X0 = _newton(X, walls, orbit, pm, kind, row=row, target=X[-1])
    except (ValueError, np.linalg.LinAlgError) as err:
        raise OrbitError(f"no {kind} point found in {params[0]} from this orbit ({err})") from err
    if abs(X0[-2] - X[-2]) > 0.05 * max(1.0, abs(X[-2])):
        raise OrbitError(f"Newton went from {params[0]} = {X[-2]:.6g} to a {kind} point at {X0[-2]:.6g}: "
                         "start from an orbit nearer the point")
    if not (np.all(box[:, 0] <= X0[-2:]) and np.all(X0[-2:] <= box[:, 1])):
        raise ValueError(f"the {kind} point found, {dict(zip(params, X0[-2:], strict=True))}, is outside ranges = {ranges!r}")
    _, J0 = _system(X0, walls, orbit, pm, kind)
    t0 = null_tangent(J0)
    halves, stops = [], []
    for sign in (+1.0, -1.0):
        Xs, stop = _half_curve(X0, J0, sign * t0, walls, orbit, pm, kind, params, box, step, max_points)
        halves.append(Xs)
        stops.append(stop)
    Xs = halves[1][::-1] + halves[0][1:]
    return _curve_dataset(Xs, orbit, pm, kind, params, stops, box[:, 1] - box[:, 0])

def _half_curve(X0, J0, t, walls, orbit, pm, kind, params, box, step, max_points):
    """One direction of :func:`follow_point` from ``X0`` along the tangent ``t`` (:func:`follow_curve`): its points
    and why it stopped."""
    J = [J0]  # the last accepted point's Jacobian, the corrector's first

    def correct(X, h, t):
        Xp = X + h * t
        if not pm.valid(Xp[-2:]):
            raise OutOfRange
        Xn = _newton(Xp, walls, orbit, pm, kind, row=t, target=t @ Xp, J=J[0])
        if not pm.valid(Xn[-2:]):
            raise OutOfRange
        return Xn

    def tangent(X, t):
        _, J[0] = _system(X, walls, orbit, pm, kind)
        return null_tangent(J[0], t)

    return follow_curve(
        X0, t, step=step, max_points=max_points, correct=correct, tangent=tangent,
        degenerate=lambda X: (f"a flight time reached zero at {_where(params, X)}: the word {orbit.word} degenerates"
                              if np.any(X[1:1 + len(walls)] <= 0) else ""),
        outside=lambda X: ("" if np.all(box[:, 0] <= X[-2:]) and np.all(X[-2:] <= box[:, 1])
                           else f"left the box at {_where(params, X)}"),
        where=lambda X: _where(params, X),
        edge=lambda X: f"reached the edge of the model's range (d > 0, 0 <= beta <= pi/2, ...) at {_where(params, X)}")


def plane_cusps(lam, scale=(1.0, 1.0)) -> np.ndarray:
    """Indices of the points where a curve's projection on the parameter plane turns back: the chords
    to the neighbours on either side point the same way (a negative dot product of successive chords,
    in units of ``scale`` per axis).  On a fold curve this is the cusp where two folds meet and end;
    the curve itself, smooth in (z, p1, p2), goes on."""
    lam = np.asarray(lam, dtype=float) / np.asarray(scale, dtype=float)
    if len(lam) < 3:
        return np.zeros(0, dtype=int)
    d = np.diff(lam, axis=0)
    return np.flatnonzero(np.sum(d[:-1] * d[1:], axis=1) < 0) + 1


#: two curves that "cross" COINCIDE_RUN times or more in a row, each crossing within COINCIDE_GAP of the
#: plane's extent (or three of the first curve's segments, if longer) of the next, are one set sampled
#: twice (their polylines' chords differ by ~1e-5)
COINCIDE_RUN = 3
COINCIDE_GAP = 0.02


def curve_crossings(curves: xr.Dataset) -> xr.Dataset:
    """Where two curves of a :func:`curve_set` cross in the plane (segment intersections): e.g. where the
    2:1 grazing curve G1 crosses the 3:1 fold curve G2, the bistable interval between them closes.
    Returns along ``crossing``: the two curves' indices and names, and the two parameters there
    (``crossing_<name>``); attribute ``coincide``: the pairs of curves that run together (one set sampled
    twice, :data:`COINCIDE_RUN`), from where to where, whose meetings are not crossings."""
    names = curves.attrs["params"].split()
    idx = curves.curve_index.values
    xs, ys = curves[names[0]].values, curves[names[1]].values
    segs = {}
    for c in np.unique(idx):
        sel = np.flatnonzero(idx == c)
        if sel.size >= 2:
            segs[int(c)] = (xs[sel], ys[sel])
    rows, coincide = [], []
    keys = sorted(segs)
    scale = (max(np.ptp(xs), 1e-300), max(np.ptp(ys), 1e-300)) if xs.size else (1.0, 1.0)
    for a_i, a in enumerate(keys):
        ax, ay = segs[a]
        for b in keys[a_i + 1:]:
            bx, by = segs[b]
            # all segment pairs: p + t r = q + u w, 0 <= t, u <= 1
            px, py, rx, ry = ax[:-1, None], ay[:-1, None], np.diff(ax)[:, None], np.diff(ay)[:, None]
            qx, qy, wx, wy = bx[None, :-1], by[None, :-1], np.diff(bx)[None, :], np.diff(by)[None, :]
            den = rx * wy - ry * wx
            with np.errstate(divide="ignore", invalid="ignore"):
                t = ((qx - px) * wy - (qy - py) * wx) / den
                u = ((qx - px) * ry - (qy - py) * rx) / den
            hit = (den != 0) & (t >= 0) & (t < 1) & (u >= 0) & (u < 1)
            found = sorted((i, float(px[i, 0] + t[i, j] * rx[i, 0]), float(py[i, 0] + t[i, j] * ry[i, 0]))
                           for i, j in zip(*np.nonzero(hit), strict=True))
            # where two curves are one set (e.g. the 2:1 grazing curve and the 3:1 grazing curve: the 3:1
            # orbit born at G1 is the 2:1 orbit grazing), their polylines, sampled apart, "cross" at every
            # other point: a run of COINCIDE_RUN or more crossings, each near the next (COINCIDE_GAP), is
            # recorded as the two curves running together, not as crossings
            gap = max(COINCIDE_GAP, 3 * float(np.median(np.hypot(np.diff(ax) / scale[0], np.diff(ay) / scale[1]))))
            groups = []
            for f in found:
                if groups and math.hypot((f[1] - groups[-1][-1][1]) / scale[0],
                                         (f[2] - groups[-1][-1][2]) / scale[1]) < gap:
                    groups[-1].append(f)
                else:
                    groups.append([f])
            for g in groups:
                if len(g) >= COINCIDE_RUN:
                    coincide.append((a, b, g[0][1:], g[-1][1:]))
                else:
                    rows += [(a, b, x, y) for _, x, y in g]
    name = lambda c: f"{curves.curve_word.values[c]} {curves.curve_kind.values[c]}"
    ds = xr.Dataset(
        {
            "curve_a": ("crossing", np.array([r[0] for r in rows], dtype=int)),
            "curve_b": ("crossing", np.array([r[1] for r in rows], dtype=int)),
            "name_a": ("crossing", np.array([name(r[0]) for r in rows], dtype=object).astype(str)),
            "name_b": ("crossing", np.array([name(r[1]) for r in rows], dtype=object).astype(str)),
            f"crossing_{names[0]}": ("crossing", np.array([r[2] for r in rows], dtype=float)),
            f"crossing_{names[1]}": ("crossing", np.array([r[3] for r in rows], dtype=float)),
        },
        coords={"crossing": np.arange(len(rows))},
    )
    ds.attrs["coincide"] = "; ".join(f"{name(a)} = {name(b)} from ({p[0]:.6g}, {p[1]:.6g}) to ({q[0]:.6g}, {q[1]:.6g})"
                                     for a, b, p, q in coincide)
    return annotate(ds)


def _where(params, X):
    return ", ".join(f"{n} = {v:.10g}" for n, v in zip(params, X[-2:], strict=True))


def _curve_dataset(Xs, template, pm, kind, params, stops, scale) -> xr.Dataset:
    orbits = [_orbit(X, template, pm) for X in Xs]
    lam = np.array([X[-2:] for X in Xs])
    tests = [bifurcation_functions(o) for o in orbits]
    events = []
    for other in TESTS:
        if other == kind or other == "NS":
            continue
        vals = np.array([tt[other] for tt in tests])
        # a sign change between finite, moderate values; where an impact speed is zero on the curve the
        # map's Jacobian is singular and its test functions flip between +-1e16 (no crossing)
        ok = np.isfinite(vals) & (np.abs(vals) < REGULAR)
        for i in np.flatnonzero(ok[:-1] & ok[1:] & (vals[:-1] * vals[1:] < 0)):
            w = vals[i] / (vals[i] - vals[i + 1])
            events.append((other, *(lam[i] + w * (lam[i + 1] - lam[i]))))
    for i in plane_cusps(lam, scale):
        events.append(("cusp", *lam[i]))
    admissible = np.array([o.admissible for o in orbits])
    clearance = np.array([o.clearance for o in orbits])
    if kind == "grazing":
        # on a grazing curve the orbit touches a wall (or hits it at zero speed) by construction: a
        # clearance within the corrector's residual, on either side of zero, is that contact and not a
        # violation (its sign is rounding, and would make the drawn admissibility flicker along the curve)
        admissible |= np.abs(clearance) < RESIDUAL
    data = {
        params[0]: ("point", lam[:, 0]),
        params[1]: ("point", lam[:, 1]),
        "d": ("point", np.array([o.params.d for o in orbits])),
        "gbar": ("point", np.array([o.params.gbar for o in orbits])),
        "r": ("point", np.array([o.params.r for o in orbits])),
        "admissible": ("point", admissible),
        "clearance": ("point", clearance),
        "trace": ("point", np.array([o.trace for o in orbits])),
        "det": ("point", np.array([o.det for o in orbits])),
        "phase": ("point", np.array([o.phase[0] for o in orbits])),
        "v_minus": ("point", np.array([o.v_minus[0] for o in orbits])),
        "z": (("point", "unknown"), np.array([X[:-2] for X in Xs]),
              {"long_name": "the orbit's unknowns (phase, flight times, pre-impact velocities): "
                            "orbits.orbit_from_vector rebuilds it"}),
        "event_kind": ("event", np.array([e[0] for e in events], dtype=object).astype(str)),
        f"event_{params[0]}": ("event", np.array([e[1] for e in events], dtype=float)),
        f"event_{params[1]}": ("event", np.array([e[2] for e in events], dtype=float)),
    }
    ds = xr.Dataset(data, coords={"point": np.arange(len(Xs)), "event": np.arange(len(events))})
    ds.attrs.update(kind=kind, word=template.word, k=template.k, params=" ".join(params),
                    stop_increasing=stops[0], stop_decreasing=stops[1])
    return annotate(ds)


def curve_set(branches, params, ranges, *, kinds=("B", "fold", "grazing"), step=1e-2, physics=None,
              max_points=2000, progress: bool | None = None) -> xr.Dataset:
    """Every critical point of ``kinds`` on continued branches, followed as a curve in two parameters.

    A point that cannot be followed is kept as a curve without points, with its reason.

    Parameters
    ----------
    branches : list of xarray.Dataset
        Branches of :func:`~vibroimpact.continue_orbit` in s, whose admissible, refined critical points start
        the curves.
    params : (str, str)
        The two parameters of the plane (:data:`~vibroimpact.analysis.continuation.PARAMETERS`).
    ranges : ((float, float), (float, float))
        Their box; a curve stops where it leaves it.
    kinds : sequence of str
        The kinds of point followed: ``"B"`` (period doubling), ``"fold"``, ``"grazing"``, ``"A"``.
    step : float
        Arclength step of :func:`~vibroimpact.follow_point`.
    physics : dict, optional
        The device's values for :meth:`~vibroimpact.Params.from_physical` (beta, M, F, omega, r, g) at the
        branches.
    max_points : int
        Most points per curve and direction.
    progress : bool, optional
        A bar over the points followed (default: only when run interactively).

    Returns
    -------
    xarray.Dataset
        The curves end to end: along ``point`` the two parameters, ``admissible`` and ``curve_index``
        (index into the ``curve`` dimension: ``curve_kind``, ``curve_word``, ``curve_start_s``,
        ``curve_start_stable``, ``curve_status``, ``curve_reason``, ``curve_stop``); along ``event``
        (``event_curve``, ``event_kind`` and the two parameters) where a curve meets another set of its
        orbit or its projection turns back (``cusp``); along ``crossing`` (``curve_a``, ``curve_b``,
        ``name_a``, ``name_b`` and the two parameters) where two curves cross in the plane.  Attributes:
        ``params``, ``ranges``, ``kinds``, ``step`` and ``coincide`` (pairs of curves that run together).

    Examples
    --------
    The 2:1 branch at the paper's incline pi/6 grazes at G1, s = 0.22104 m (d = 0.1376); followed in
    ``(s, beta)`` the grazing point moves to longer cylinders on steeper inclines:

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.2249, beta=math.pi / 6)
    >>> br = vi.continue_orbit(vi.find_orbit(p, "BBT", 5.855, 0.4185), vary="s", d_range=(0.136, 0.141),
    ...                        step=2e-3)
    >>> br.attrs["status"] = "ok"          # as vi.branch_from_simulation marks a branch it found
    >>> cs = vi.curve_set([br], ("s", "beta"), ((0.2, 0.25), (0.5, 0.55)), kinds=("grazing",), step=1e-2,
    ...                   physics={"beta": math.pi / 6})
    >>> cs.curve_kind.values.tolist(), cs.curve_status.values.tolist(), round(float(cs.curve_start_s[0]), 5)
    (['grazing'], ['ok'], 0.22104)
    >>> bool((cs.s.diff("point") * cs.beta.diff("point") > 0).all())
    True
    """
    physics = dict(physics or {})
    pts, events, rows = [], [], []
    usable = [br for br in branches if br.attrs.get("status", "ok") == "ok" and "critical_kind" in br]
    todo = sum(1 for br in usable for i, kind in enumerate(br.critical_kind.values)
               if kind in kinds and bool(br.critical_admissible[i]) and bool(br.critical_refined[i]))
    bar = Progress(todo, f"bifurcation curves in ({params[0]}, {params[1]})", progress, unit="curve")
    for br in usable:
        word, k = br.attrs["word"], int(br.attrs["k"])
        for i, kind in enumerate(br.critical_kind.values):
            if kind not in kinds or not bool(br.critical_admissible[i]) or not bool(br.critical_refined[i]):
                continue
            bar.update()
            s0 = float(br.critical_s[i])
            row = dict(kind=str(kind), word=word, start_s=s0, start_stable=False, status="ok", reason="", stop="")
            try:
                # the branch's own orbit at its admissible point nearest the located one (its z from the
                # dataset: no Newton, which is singular at a fold); the test function is smooth there
                adm = np.flatnonzero(br.admissible.values)
                j = int(adm[np.argmin(np.abs(br.d.values[adm] - float(br.critical_d[i])))])
                row["start_stable"] = bool(br.stable.values[j])
                z = np.concatenate([[float(br.phase[j, 0])], np.roll(br.dt.values[j], -1), br.v_minus.values[j]])
                o = orbit_from_vector(Params.from_physical(s=float(br.s[j]), **physics), word, k, z)
                c = follow_point(o, str(kind), params=params, ranges=ranges, step=step, max_points=max_points)
            except (OrbitError, ValueError, np.linalg.LinAlgError) as err:
                row.update(status="failed", reason=f"{type(err).__name__}: {err}")
                rows.append(row)
                continue
            n = len(rows)
            row["stop"] = f"{c.attrs['stop_increasing']}; {c.attrs['stop_decreasing']}"
            pts.append((np.full(c.sizes["point"], n), c[params[0]].values, c[params[1]].values,
                        c.admissible.values))
            for e in range(c.sizes["event"]):
                events.append((n, str(c.event_kind.values[e]), float(c[f"event_{params[0]}"][e]),
                               float(c[f"event_{params[1]}"][e])))
            rows.append(row)
    bar.close()
    ds = _curves_dataset(pts, events, rows, params)
    ds.attrs.update(params=" ".join(params), ranges=str(ranges), kinds=" ".join(kinds), step=step)
    cross = curve_crossings(ds)
    ds = xr.merge([ds, cross], combine_attrs="override")
    ds.attrs["coincide"] = cross.attrs["coincide"]
    return annotate(ds)


def _curves_dataset(pts, events, rows, params):
    """:func:`curve_set`'s curves: their points ``pts``, the events along them and one row per curve."""
    cat = (lambda i: np.concatenate([p[i] for p in pts]) if pts else np.array([]))
    return xr.Dataset(
        {
            "curve_index": ("point", cat(0).astype(int), {"long_name": "the curve a point belongs to"}),
            params[0]: ("point", cat(1).astype(float)),
            params[1]: ("point", cat(2).astype(float)),
            "admissible": ("point", cat(3).astype(bool), {"long_name": "the orbit on the curve is admissible"}),
            "curve_kind": ("curve", np.array([r["kind"] for r in rows], dtype=object).astype(str)),
            "curve_word": ("curve", np.array([r["word"] for r in rows], dtype=object).astype(str)),
            "curve_start_s": ("curve", np.array([r["start_s"] for r in rows], dtype=float),
                              {"units": "m", "long_name": "length s where the point was located on its branch"}),
            "curve_start_stable": ("curve", np.array([r["start_stable"] for r in rows], dtype=bool),
                                   {"long_name": "the orbit is stable where the point was located on its branch"}),
            "curve_status": ("curve", np.array([r["status"] for r in rows], dtype=object).astype(str)),
            "curve_reason": ("curve", np.array([r["reason"] for r in rows], dtype=object).astype(str)),
            "curve_stop": ("curve", np.array([r["stop"] for r in rows], dtype=object).astype(str),
                           {"long_name": "why the curve ends, each way"}),
            "event_curve": ("event", np.array([e[0] for e in events], dtype=int)),
            "event_kind": ("event", np.array([e[1] for e in events], dtype=object).astype(str)),
            f"event_{params[0]}": ("event", np.array([e[2] for e in events], dtype=float)),
            f"event_{params[1]}": ("event", np.array([e[3] for e in events], dtype=float)),
        },
        coords={"point": np.arange(len(cat(0))), "curve": np.arange(len(rows)), "event": np.arange(len(events))},
    )


def curve_values(curves: xr.Dataset, index: int, at, along: str) -> np.ndarray:
    """The other parameter where curve ``index`` of a :func:`curve_set` passes ``along = at``: linear
    between the curve's points, the first crossing by arclength (NaN where it does not pass)."""
    other = [n for n in curves.attrs["params"].split() if n != along][0]
    sel = curves.curve_index.values == index
    xs, ys = curves[along].values[sel], curves[other].values[sel]
    out = np.full(np.size(at), np.nan)
    for j, a in enumerate(np.atleast_1d(at)):
        for i in range(len(xs) - 1):
            if (xs[i] - a) * (xs[i + 1] - a) <= 0 and xs[i] != xs[i + 1]:
                out[j] = ys[i] + (a - xs[i]) / (xs[i + 1] - xs[i]) * (ys[i + 1] - ys[i])
                break
    return out


def bistable_band(curves: xr.Dataset, at, *, along: str = "beta") -> xr.Dataset:
    """Where the 2:1 and 3:1 motions coexist, from the curves: G1 (the 2:1 orbit grazes, the 3:1 is born)
    and G2 (the 3:1 orbit's fold), as the length s at each value of ``along`` (the paper's
    [G1, G2] at beta = pi/6, 0.1376 < d < 0.1419, for any incline).  Needs a :func:`curve_set` in
    ``(s, along)`` holding the 2:1 grazing curve through the smallest s and the 3:1 fold curve; where it holds
    none (another device without G1 or G2, a curve not followed), that end is NaN and the attribute ``status``
    says why (``"ok"`` where both curves are there)."""
    ok = curves.curve_status.values == "ok"
    at = np.atleast_1d(np.asarray(at, float))
    missing = []

    def end(word, kind):
        sel = (curves.curve_word.values == word) & (curves.curve_kind.values == kind)
        idx = np.flatnonzero(ok & sel)
        if not idx.size:
            why = "; ".join(sorted(set(curves.curve_reason.values[sel].astype(str)))) or "none was followed"
            missing.append(f"no {word} {kind} curve ({why})")
            return np.full(at.size, np.nan)
        return curve_values(curves, int(idx[np.argmin(curves.curve_start_s.values[idx])]), at, along)

    g1, g2 = end("BBT", "grazing"), end("BBBT", "fold")
    width = np.where(g2 > g1, g2 - g1, 0.0)
    ds = xr.Dataset(
        {
            "s_G1": (along, g1, {"units": "m", "long_name": "G1: the 2:1 orbit grazes, the 3:1 is born"}),
            "s_G2": (along, g2, {"units": "m", "long_name": "G2: the 3:1 orbit's fold"}),
            "width": (along, width, {"units": "m", "long_name": "length of the bistable interval [G1, G2] (0: none)"}),
        },
        coords={along: at},
        attrs={"status": "; ".join(missing) or "ok"},
    )
    return annotate(ds)


#: a simulated boundary within this many grid cells of a curve counts as on the curve (a cell boundary
#: lies half a cell from the cells' centres, and a curve crossing a cell may pass half a cell beyond)
ON_CURVE_CELLS = 1.5


def _segment_distance(px, py, xs, ys):
    """Distance from each point (px, py) to the polyline (xs, ys), NaN-separated pieces allowed."""
    ax, ay, bx, by = xs[:-1], ys[:-1], xs[1:], ys[1:]
    ok = np.isfinite(ax + ay + bx + by)
    ax, ay, bx, by = ax[ok], ay[ok], bx[ok], by[ok]
    if ax.size == 0:
        return np.full(px.shape, np.inf)
    dx, dy = bx - ax, by - ay
    L2 = np.where(dx * dx + dy * dy > 0, dx * dx + dy * dy, 1.0)
    t = np.clip(((px[:, None] - ax) * dx + (py[:, None] - ay) * dy) / L2, 0.0, 1.0)
    return np.min(np.hypot(ax + t * dx - px[:, None], ay + t * dy - py[:, None]), axis=1)


def map_boundaries(regime_map: xr.Dataset, curves: xr.Dataset, *, cells: float = ON_CURVE_CELLS) -> xr.Dataset:
    """The simulated boundaries of a brute-force regime map and whether a bifurcation curve explains each.

    A boundary is the edge between two neighbouring grid points (along either axis) whose attractors
    have different labels; its position is the edge's midpoint.  It is ``on_curve`` where a curve of
    ``curves`` (:func:`curve_set` in the map's plane) passes within ``cells`` grid cells of it (distances
    in units of the grid spacing along each axis).  A boundary on no curve gets a ``cause``:
    ``"aperiodic"`` where one side had no period within the run's cap (chaotic, quasi-periodic or
    unsettled: no curve of periodic orbits bounds it), ``"jump"`` where both sides are periodic motions (the single
    start fell into another basin where two motions coexist, or an orbit not in the set bifurcates).
    """
    ydim, xdim = regime_map.label.dims
    names = curves.attrs["params"].split()
    if set(names) != {xdim, ydim}:
        raise ValueError(f"curves in {tuple(names)} do not lie in the map's plane ({xdim}, {ydim})")
    lab = regime_map.label.values.astype(str)
    x, y = regime_map[xdim].values.astype(float), regime_map[ydim].values.astype(float)
    hx = np.diff(x).mean() if x.size > 1 else 1.0
    hy = np.diff(y).mean() if y.size > 1 else 1.0
    pts = []
    for i, j in zip(*np.nonzero(lab[:, :-1] != lab[:, 1:]), strict=True):
        pts.append((0.5 * (x[j] + x[j + 1]), y[i], lab[i, j], lab[i, j + 1]))
    for i, j in zip(*np.nonzero(lab[:-1, :] != lab[1:, :]), strict=True):
        pts.append((x[j], 0.5 * (y[i] + y[i + 1]), lab[i, j], lab[i + 1, j]))
    px = np.array([p[0] for p in pts], dtype=float)
    py = np.array([p[1] for p in pts], dtype=float)
    dist = np.full(px.size, np.inf)
    for c in range(curves.sizes["curve"]):
        sel = curves.curve_index.values == c
        if sel.sum() >= 2:
            dist = np.minimum(dist, _segment_distance(px / hx, py / hy, curves[xdim].values[sel] / hx,
                                                      curves[ydim].values[sel] / hy))
    on = dist <= cells
    aperiodic = np.array([p[2] in NO_PERIOD_LABELS or p[3] in NO_PERIOD_LABELS for p in pts], dtype=bool)
    cause = np.where(on, "on a curve", np.where(aperiodic, "aperiodic", "jump"))
    ds = xr.Dataset(
        {
            xdim: ("boundary", px, {"units": regime_map[xdim].attrs.get("units", "1"), "long_name": f"{xdim} of the boundary"}),
            ydim: ("boundary", py, {"units": regime_map[ydim].attrs.get("units", "1"), "long_name": f"{ydim} of the boundary"}),
            "label_a": ("boundary", np.array([p[2] for p in pts], dtype=object).astype(str),
                        {"long_name": "attractor on the lower side"}),
            "label_b": ("boundary", np.array([p[3] for p in pts], dtype=object).astype(str),
                        {"long_name": "attractor on the upper side"}),
            "distance": ("boundary", dist, {"units": "1", "long_name": "to the nearest curve, in grid cells"}),
            "on_curve": ("boundary", on, {"long_name": f"a curve passes within {cells:g} grid cells"}),
            "cause": ("boundary", cause.astype(str), {"long_name": "on a curve; else aperiodic (one side has no "
                                                                   "period) or jump (two periodic motions)"}),
        },
        coords={"boundary": np.arange(px.size)},
    )
    ds.attrs.update(cells=cells, xdim=xdim, ydim=ydim)
    return annotate(ds)
