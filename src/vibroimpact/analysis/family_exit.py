"""Where a followed attractor leaves its impact family: the 1:1 exit and G1.

The *1:1 exit* is where the 1:1 motion, followed with decreasing d through its period doublings and
chaotic windows, stops being a motion of the 1:1 family: by grazing the bottom wall (a flight touches it
with zero velocity; "1:1 exit: grazing") or by a jump while still clear of the walls ("1:1 exit: jump").
The paper puts its d_graz there ("at d = d_graz, Zdot_j = 0 and Z_j = d/2, and there is a transition to 2:1
motion for d < d_graz") and also calls d_graz "the maximum value for 2:1 period-2 solutions";
:mod:`vibroimpact.analysis.d_graz` compares the two readings.  The exit is a property of the
*attractor*, not of an orbit of the branches: the 1:1 period-2 orbit itself is unstable there.  So it is
located by following the attractor, as the paper does numerically.

A motion is in the n:1 *family* when its impacts come in groups of ``n`` bottom impacts between
single top impacts, whatever its period (1:1 period-4, a chaotic 1:1 motion, ...).  Along a line of
parameters the attractor is followed from its largest d down, each run starting from the last
bottom impact of the previous attractor; where it stops being in the family, the exit is bracketed
to ``xtol`` by the same adaptive continuation as :func:`vibroimpact.analysis.transitions.locate_transitions`.
What says whether the exit is a grazing is measured there: the smallest *clearance* of the last
attractor in the family (the distance to a wall of the flights' interior extrema,
:func:`vibroimpact.analysis.grazing.interior_clearance`), which tends to zero at a grazing, and the
slowest impact of the motion beyond (an impact born at a grazing is born with zero speed).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
import xarray as xr

from ..datasets import VARIABLES, annotate
from ..dynamics import impact as law
from ..dynamics import kernels as K
from ..dynamics.params import Params
from ..dynamics.runs import simulate, simulated_events
from .grazing import interior_clearance
from .grids import plane_params
from .motions import identify_attractor

#: the kinds of exit: the last attractor in the family grazes a wall, or it leaves the family by a jump while clear
#: of the walls
EXIT_KINDS = ("grazing", "jump")

#: An exit is a grazing when the last attractor in the family comes closer to a wall than this
#: fraction of d.  Measured on the paper's sweeps (4000 impacts per run, xtol 1e-7): the exits
#: that graze leave the family at clearances of 3e-7 to 3e-5 (1e-6 to 2e-4 of d), those that do not
#: (pi/2 and pi/3, length sweeps) at 0.017 and 0.033 (7 % and 12 % of d); 1 % of d, the figures'
#: "near grazing" (vibroimpact.outputs.plots.NEAR_GRAZING), lies between by two orders of magnitude.
GRAZING_CLEARANCE = 0.01


def in_family(walls, kinds, n: int) -> bool:
    """Whether a stretch of events is a motion of the n:1 family: impacts only (no grazing contact,
    stick or release), single top impacts, and exactly ``n`` bottom impacts between consecutive top
    impacts (the stretch's ends may cut a group short)."""
    walls = np.asarray(walls)
    if walls.size == 0 or np.any(np.asarray(kinds) != K.IMPACT):
        return False
    top = np.flatnonzero(walls == -1)
    if top.size == 0 or np.any(np.diff(top) != n + 1):
        return False
    return bool(top[0] <= n and walls.size - 1 - top[-1] <= n)


def _clearance(run: xr.Dataset, d: float, gbar: float, r: float) -> float:
    """Smallest interior clearance of the run's flights (:func:`~vibroimpact.analysis.grazing.interior_clearance`)."""
    t, w, v, ph = (run[k].values for k in ("t", "wall", "v_minus", "phase"))
    return min((interior_clearance(ph[j], w[j] * 0.5 * d, law.rebound(v[j], r), d, gbar, t[j + 1] - t[j])
                for j in range(t.size - 1)), default=math.inf)


def _last_bottom(run):
    """Phase and pre-impact velocity of a run's last bottom impact (a :class:`_Tail`), or None."""
    b = np.flatnonzero((run.wall == 1) & (run.kind == K.IMPACT) & (run.v_minus > 0))
    return (float(run.phase[b[-1]]), float(run.v_minus[b[-1]])) if b.size else None


#: the events a :class:`_Tail` keeps
_TAIL_VARS = ("t", "wall", "v_minus", "phase", "kind")


class _Tail(namedtuple("_Tail", ("run", *_TAIL_VARS))):
    """The judged events of a run of :func:`family_exit` (``run``: ``(d, gbar, r, start, transient, impacts)``)."""

    def dataset(self) -> xr.Dataset:
        """The same events as :func:`~vibroimpact.simulate`'s dataset (the run made again: the same events)."""
        d, gbar, r, start, transient, impacts = self.run
        ev = simulate(Params(d=d, gbar=gbar, r=r), phi=start[0], v0=start[1], n_impacts=transient + impacts)
        return ev.isel(impact=slice(transient, None))


def family_exit(d, gbar, r: float, phi: float, v0: float, *, n: int = 1, impacts: int = 4000,
                transient: int = 1000, xtol: float = 1e-7, max_trials: int = 200) -> dict:
    """Follow the attractor down a line of parameters and locate where it leaves the n:1 family.

    Parameters
    ----------
    d, gbar : array_like
        The line: non-dimensional lengths and gravity terms, ``gbar`` affine in ``d`` (as along a
        sweep of s at fixed force, or of the force at fixed s); followed from the largest ``d`` down.
    r : float
        Coefficient of restitution.
    phi, v0 : float
        The first run's start at the largest ``d``: a bottom impact at phase ``phi`` with pre-impact
        velocity ``v0``.
    n : int
        The family: ``n`` bottom impacts per top impact (1: the 1:1 exit; 2: the paper's G1).
    impacts, transient : int
        Events judged per run, after ``transient`` events discarded.
    xtol : float
        Width of the final bracket in d.
    max_trials : int
        Runs allowed for the refinement.

    Returns
    -------
    dict
        ``status`` (``"located"``, or why not), ``d`` (middle of the bracket), ``d_width``,
        ``clearance`` (smallest interior clearance of the last attractor in the family, at the bracket's
        upper end), ``slowest_after`` (slowest impact speed of the motion at the bracket's lower end),
        ``kind`` (``"grazing"`` where ``clearance < GRAZING_CLEARANCE * d``, else
        ``"jump"``: :data:`EXIT_KINDS`), ``after`` (the motion at the bracket's lower end: its label, or its bottom
        impacts per top impact where no period is found) and ``sampled`` (the last attractor in the family
        has no period: its clearance is the least over the judged events, a statistic of the motion, and the
        kind near :data:`GRAZING_CLEARANCE` may be decided otherwise by another run).

    Examples
    --------
    >>> import math, numpy as np, vibroimpact as vi
    >>> p = [vi.Params.from_physical(s=s, beta=math.pi / 6) for s in np.linspace(0.345, 0.33, 6)]
    >>> ex = vi.family_exit([q.d for q in p], [q.gbar for q in p], 0.5, phi=0.42, v0=0.87, xtol=1e-5)
    >>> ex["status"], ex["kind"], round(ex["d"], 3)     # Fig FN2 (f): the 1:1 motion grazes near d = 0.21
    ('located', 'grazing', 0.211)
    """
    d = np.asarray(d, float)
    gbar = np.broadcast_to(np.asarray(gbar, float), d.shape)
    order = np.argsort(-d)
    d, gbar = d[order], gbar[order]
    out = {"status": "", "d": math.nan, "d_width": math.nan, "clearance": math.nan, "slowest_after": math.nan,
           "kind": "", "after": "", "sampled": False}
    if d.size < 2:
        return out | {"status": "not located: the line needs at least two points"}

    def g_at(x):
        return float(np.interp(x, d[::-1], gbar[::-1]))

    def run(x, start):  # the events only (a dataset is made for the runs kept at the end: _Tail.dataset)
        bufs, m, _ = simulated_events(Params(d=x, gbar=g_at(x), r=r), start[0], start[1], transient + impacts)
        tail = _Tail((x, g_at(x), r, start, transient, impacts), *(getattr(bufs, v)[transient:m] for v in _TAIL_VARS))
        return in_family(tail.wall, tail.kind, n), tail

    start = (phi, v0)
    ok, tail = run(d[0], start)
    if not ok:
        return out | {"status": f"not located: the attractor at the line's largest d = {d[0]:.6g} is not {n}:1"}
    last = tail
    i = 0
    while i + 1 < d.size:  # coarse: along the line's own points
        start = _last_bottom(last) or start
        ok, tail = run(d[i + 1], start)
        if not ok:
            break
        last, i = tail, i + 1
    if i + 1 == d.size:
        return out | {"status": f"not located: the attractor stays {n}:1 down to the line's smallest d = {d[-1]:.6g}"}
    x, y, last, beyond = _refine_exit(run, d[i], d[i + 1], last, tail, start, d[-1], xtol, max_trials)
    last, beyond = last.dataset(), beyond.dataset()
    refined = x - y <= xtol
    clearance = _clearance(last, x, g_at(x), r)
    att = identify_attractor(beyond)
    nb, nt = int((beyond.wall.values == 1).sum()), int((beyond.wall.values == -1).sum())
    after = att.label if att.periodic else f"no period found ({nb / max(nt, 1):.4g} bottom impacts per top impact)"
    return out | {
        "status": "located" if refined else f"not refined: {max_trials} runs (max_trials) left a bracket of {x - y:.1e}",
        "d": float(0.5 * (x + y)), "d_width": float(x - y), "clearance": clearance,
        "slowest_after": float(np.min(np.abs(beyond.v_minus.values[K.hits(beyond.kind.values)]), initial=math.inf)),
        "kind": EXIT_KINDS[0] if clearance < GRAZING_CLEARANCE * x else EXIT_KINDS[1],
        "after": after,
        # the clearance of a motion with no period is the least over its judged events: a statistic
        "sampled": not identify_attractor(last).periodic,
    }

def _refine_exit(run, x, y, last, beyond, start, d_min, xtol, max_trials):
    """Narrow ``[y, x]`` (``x`` the smallest d seen in the family, its run ``last``; ``y`` the largest out of it, its
    run ``beyond``) by the adaptive continuation of the family's attractor, as in
    :func:`vibroimpact.analysis.transitions.locate_transitions`: ``(x, y, last, beyond)``."""
    h_grid = x - y
    h = 0.5 * h_grid
    y_checked = False  # y re-run from an attractor of the family close to it
    for _ in range(max_trials):
        if x - y <= max(1e-3 * h_grid, 4 * xtol) and not y_checked:
            # a run that left the family far from where its start was an attractor may have jumped out of
            # a thin basin (near a grazing point): y is judged again from close by
            ok, tail = run(y, _last_bottom(last) or start)
            y_checked = True
            if ok:
                x, last, y, y_checked = y, tail, max(y - h_grid, d_min), False
                h = 0.5 * (x - y)
                continue
            beyond = tail
        if x - y <= xtol:
            break
        trial = x - min(h, 0.5 * (x - y))
        ok, tail = run(trial, _last_bottom(last) or start)
        if ok:
            x, last = trial, tail
            h = min(2 * h, h_grid)
        else:
            y, beyond, y_checked = trial, tail, False
            h = 0.5 * h
    return x, y, last, beyond



def _exit_variables(ex: dict, dim=()) -> dict:
    """:func:`family_exit`'s fields as dataset variables named ``exit_<field>`` (``exit_d``: its d)."""
    return {f"exit_{key}": (dim, value) for key, value in ex.items()}


def sweep_family_exit(sw: xr.Dataset, **kw) -> xr.Dataset:
    """The 1:1 exit along a sweep (:func:`vibroimpact.analysis.sweeps.sweep`): where its 1:1 motion, followed
    with d decreasing, leaves the 1:1 family, by grazing or by a jump.

    It is :func:`family_exit` of the 1:1 family on the sweep's line, from the start its down direction
    used at its largest d.

    Parameters
    ----------
    sw : xarray.Dataset
        A sweep of :func:`vibroimpact.sweep` (its ``d``, ``gbar``, ``s``, ``F`` and its down direction's
        first start).
    **kw
        :func:`family_exit`'s ``impacts``, ``transient``, ``xtol``, ``max_trials``.

    Returns
    -------
    xarray.Dataset
        Scalars ``exit_d``, ``exit_d_width``, ``exit_clearance``, ``exit_slowest_after``, ``exit_kind``
        (``"grazing"`` or ``"jump"``), ``exit_after``, ``exit_sampled``, ``exit_status`` (:func:`family_exit`'s
        fields), and the swept device at the exit: ``exit_s`` (m) and ``exit_F`` (N); attributes
        ``exit_impacts``, ``exit_xtol`` and ``exit_grazing_clearance``.

    Examples
    --------
    >>> import math, numpy as np, vibroimpact as vi
    >>> sw = vi.sweep("s", np.linspace(0.33, 0.345, 4), beta=math.pi / 6, phi=0.42, v0=0.87, long_impacts=0)
    >>> g = vi.sweep_family_exit(sw, xtol=1e-5)
    >>> str(g.exit_kind.values), round(float(g.exit_d), 3), round(float(g.exit_s), 3)   # s in m
    ('grazing', 0.211, 0.339)
    """
    dn = sw.sel(direction="down")
    top = int(np.argmax(sw.d.values))
    ex = family_exit(sw.d.values, sw.gbar.values, float(sw.attrs["r"]), float(dn.start_phi[top]),
                     float(dn.start_v0[top]), n=1, **kw)
    # s is proportional to d at fixed force, and the force inversely proportional at fixed s
    k = float(np.median(sw.s.values / (sw.d.values * sw.F.values)))  # d = s / (k F)
    s_at, F_at = ((ex["d"] * k * float(sw.F.values[0]), float(sw.F.values[0])) if sw.attrs["vary"] == "s"
                  else (float(sw.s.values[0]), float(sw.s.values[0]) / (k * ex["d"])))
    ds = xr.Dataset(_exit_variables(ex))
    ds["exit_s"], ds["exit_F"] = ((), s_at), ((), F_at)
    ds.attrs.update(exit_impacts=kw.get("impacts", 4000), exit_xtol=kw.get("xtol", 1e-7),
                    exit_grazing_clearance=GRAZING_CLEARANCE)
    return annotate(ds)


#: the parameters a line of a plane can follow d along, and how each scales with d on that line (the
#: others held fixed): s is proportional to d, the force inversely
_ALONG_D = {"s": 1.0, "d": 1.0, "F": -1.0}


def family_exit_curve(x_name: str, xs, y_name: str, ys, *, phi: float, v0: float, device=None,
                      **kw) -> xr.Dataset:
    """The 1:1 exit as a curve in a plane of two parameters: where the 1:1 motion, followed with d decreasing
    along lines of the plane, leaves the 1:1 family.

    It is :func:`family_exit` of the 1:1 family along lines of the plane, each followed from its largest d
    down.

    Parameters
    ----------
    x_name, xs, y_name, ys : str, array_like, str, array_like
        The plane (as :func:`vibroimpact.regime_map`: two of s, F, beta, r or two of d, gbar, r) and its
        grid.  The lines run along the axis that changes d (s, F or d; x first): one line per value of
        the other axis.
    phi, v0 : float
        Start of each line's first run (a bottom impact at its largest d).
    device : Device, optional
        The harvester (default the paper's, ``Device()``).
    **kw
        The values held where they are not an axis (``s``, ``F``, ``beta``; ``r``), as
        :func:`vibroimpact.regime_map`, and :func:`family_exit`'s ``impacts``, ``transient``, ``xtol``.

    Returns
    -------
    xarray.Dataset
        Along ``line``: the fixed axis' value (named after it), the exit's value of the line's axis
        (``at``: named by ``along`` in the attributes), ``exit_d`` and the other fields of
        :func:`family_exit` (``exit_d_width``, ``exit_clearance``, ``exit_slowest_after``, ``exit_kind``,
        ``exit_after``, ``exit_sampled``, ``exit_status``); attributes ``along``, ``other``, ``grid_step``
        (the lines' grid spacing along ``along``), ``exit_grazing_clearance`` and ``status``.  Where neither
        axis changes d, no line: the attribute ``status`` says so.

    Examples
    --------
    >>> import math, numpy as np, vibroimpact as vi
    >>> c = vi.family_exit_curve("s", np.linspace(0.32, 0.36, 5), "beta", [math.pi / 6], phi=0.42, v0=0.87,
    ...                          F=5.0, xtol=1e-5)
    >>> str(c.exit_kind.values[0]), round(float(c.at[0]), 3)    # the cylinder length s at the exit (m)
    ('grazing', 0.339)
    """

    fam = {k: kw.pop(k) for k in ("impacts", "transient", "xtol", "max_trials") if k in kw}
    along, other, values = ((x_name, y_name, ys) if x_name in _ALONG_D else
                            (y_name, x_name, xs) if y_name in _ALONG_D else (None, None, ()))
    if along is None:
        empty = xr.Dataset(coords={"line": np.arange(0)})
        empty.attrs.update(status=f"no 1:1 exit curve: neither axis ({x_name}, {y_name}) changes d", along="",
                           other="")
        return empty
    grid = np.asarray(xs if along == x_name else ys, float)
    rows = []
    for v in np.asarray(values, float):
        X, Y, d, gbar, r, _ = (plane_params(along, grid, other, [v], device=device, **kw) if along == x_name
                               else plane_params(other, [v], along, grid, device=device, **kw))
        d, gbar, r, a = d.ravel(), gbar.ravel(), float(r.ravel()[0]), (X if along == x_name else Y).ravel()
        ex = family_exit(d, gbar, r, phi, v0, n=1, **fam)
        # the line's parameter at the exit: proportional to d (s, d) or inversely (F)
        k = int(np.argmax(d))
        at = a[k] * (ex["d"] / d[k]) ** _ALONG_D[along] if np.isfinite(ex["d"]) else math.nan
        rows.append((v, at, ex))
    fields = rows[0][2] if rows else {}
    ds = xr.Dataset({other: ("line", np.array([v for v, _, _ in rows], float)),
                     "at": ("line", np.array([a for _, a, _ in rows], float))} |
                    _exit_variables({key: np.array([ex[key] for *_, ex in rows]) for key in fields}, "line"),
                    coords={"line": np.arange(len(rows))})
    ds["at"].attrs.update(units=VARIABLES[along][0], long_name=f"{VARIABLES[along][1]} at the 1:1 exit")
    ds.attrs.update(status="ok", along=along, other=other, exit_grazing_clearance=GRAZING_CLEARANCE,
                    grid_step=float(np.max(np.abs(np.diff(grid)))) if grid.size > 1 else 0.0)
    return annotate(ds)


__all__ = ["EXIT_KINDS", "GRAZING_CLEARANCE", "family_exit", "family_exit_curve", "in_family", "sweep_family_exit"]
