"""A harvest that survives knocks: the critical shock of every attractor of a design map, the design that keeps
its output under the knocks it will meet, and the basins a knock crosses.

:func:`knock_map` gives, at every point of a design map (:func:`vibroimpact.design_map`), the critical shock
(:func:`vibroimpact.critical_shock`) of each of its attractors, and of its highest-output one;
:func:`robust_choice` the design of highest output among those whose highest-output motion survives every
knock up to a given size, beside the best design regardless of knocks, and the Pareto front of output against
critical shock; :func:`knock_section` the basins in a ``(Z, Zdot)`` section at the forcing phase of a
motion's critical shock, the picture of what the knock crosses.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np
import xarray as xr

from ..datasets import annotate, attractor_codes
from ..dynamics.device import PAPER, Device
from ..dynamics.params import Params
from .._progress import Progress, interactive
from .design import AT_REST
from .motions import NO_PERIOD_LABELS
from .shocks import FINE_SPAN, KINDS, Shock, critical_shock
from .windows import attractor_batch

__all__ = ["knock_map", "robust_choice", "pareto_front", "mark_choices", "table_choices", "knock_section", "point_params"]

_UNIT = {"velocity": "m/s", "position": "m"}


def point_params(dm: xr.Dataset, iy: int, ix: int, device: Device) -> Params:
    """The :class:`Params` of the point ``(iy, ix)`` of a design map: its axes' values and those held."""
    x, y = dm.attrs["x"], dm.attrs["y"]
    values = {k: float(dm.attrs[k]) for k in ("s", "F", "beta") if k in dm.attrs}
    values |= {x: float(dm[x].values[ix]), y: float(dm[y].values[iy])}
    return device.params(**values)


def _why_not(label: str, phase: float, v_minus: float) -> str:
    """Why an attractor's critical shock is not computed ('' where it is)."""
    if label == AT_REST:
        return "at rest on the bottom membrane: the forcing never lifts the ball"
    if label in NO_PERIOD_LABELS:
        return f"{label}: the critical shock is defined for periodic motions only"
    if not (math.isfinite(phase) and math.isfinite(v_minus)):
        return "no bottom impact of the motion recorded to start it from"
    return ""


def knock_map(dm: xr.Dataset, *, kind: str = "velocity", device: Device | None = None, workers: int = 1,
              progress: bool | None = None, **shock_kw) -> xr.Dataset:
    """The critical shock of every attractor at every point of a design map.

    Parameters
    ----------
    dm : xarray.Dataset
        A design map (:func:`vibroimpact.design_map`): each attractor's label, output ``U_T``, share and a bottom
        impact on it (``impact_phase``, ``impact_v_minus``) at every point.
    kind : {"velocity", "position"}
        The knock (:func:`vibroimpact.critical_shock`).
    device : Device, optional
        The harvester the map was made for (the paper's by default).
    workers : int
        Threads the points are shared among (one numba thread each; 1: this thread, its kernels in parallel).  The
        result does not depend on it.
    progress : bool, optional
        A progress bar over the points (default: only when run interactively).
    **shock_kw
        Passed to :func:`vibroimpact.critical_shock` (``phases``, ``rtol``, ``refine``, ``max_periods``, ...).

    Returns
    -------
    xarray.Dataset
        The design map's attractors with, on ``(y, x, attractor)``: ``shock`` (SI), ``shock_size``
        (non-dimensional), ``shock_phase``, ``shock_direction``, ``shock_reached`` and ``shock_reached_U_T``,
        ``shock_runs`` and ``shock_reason`` (why there is none: '' where found, or where no admissible knock
        leaves, ``shock = inf``); per point the highest-output attractor (``top``, its ``top_label``,
        ``top_U_T`` and ``top_shock``, ``top_reason``).  Attributes: the knock's kind and unit.

    Examples
    --------
    Two lengths at the paper's incline pi/6: in the bistable band (s = 0.2245 m) the 2:1 and the 3:1 coexist, the
    2:1 delivers a little more and a small knock drops it to the 3:1; beyond G2 (s = 0.23 m) the 2:1 is alone
    and no admissible knock drops it:

    >>> import math, vibroimpact as vi
    >>> phi, v0 = vi.start_states(8, distribution="box", seed=0)
    >>> dm = vi.design_map("s", [0.2245, 0.23], "beta", [math.pi / 6], phi=phi, v0=v0)
    >>> km = vi.knock_map(dm, phases=8, refine=2)
    >>> km.top_label.values.tolist()
    [['2:1 period-2', '2:1 period-2']]
    >>> [round(float(v), 3) for v in km.top_shock.values[0]]    # m/s
    [0.022, inf]
    >>> km.shock_reached.values[0, 0].tolist(), str(km.shock_reason.values[0, 1, 0])
    (['2:1 period-2', '3:1 period-2'], 'no velocity knock within the admissible range leaves the basin')
    """
    if kind not in KINDS:
        raise ValueError(f"kind = {kind!r}; allowed: one of {KINDS}")
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers = {workers!r}; allowed: an integer >= 1")
    device = PAPER if device is None else device
    shape = dm["label"].shape
    fields = {k: np.full(shape, np.nan) for k in ("shock", "shock_size", "shock_phase", "shock_reached_U_T")}
    ints = {k: np.zeros(shape, np.int64) for k in ("shock_direction", "shock_runs")}
    reached = np.full(shape, "", dtype=object)
    reason = np.full(shape, "", dtype=object)
    labels = dm["label"].values.astype(str)
    ny, nx, na = shape
    tasks = [(point_params(dm, iy, ix, device), [(a, labels[iy, ix, a], float(dm["impact_phase"].values[iy, ix, a]),
                                                 float(dm["impact_v_minus"].values[iy, ix, a])) for a in range(na)
                                                if labels[iy, ix, a]], kind, device, shock_kw)
             for iy in range(ny) for ix in range(nx)]
    shown = interactive() if progress is None else bool(progress)
    with Progress(ny * nx, f"critical shocks over ({dm.attrs['x']}, {dm.attrs['y']})", shown, unit="point") as bar:
        for flat, found in enumerate(_each_point(tasks, workers)):
            iy, ix = divmod(flat, nx)
            for a, sh, why in found:
                if sh is not None:
                    _fill(fields, ints, reached, (iy, ix, a), sh)
                reason[iy, ix, a] = why
            bar.update(1)
    return _assemble(dm, kind, fields, ints, reached, reason, shock_kw)


def _point_shocks(task):
    """The critical shocks of one point's attractors: ``[(attractor, Shock or None, reason)]``."""
    params, attractors, kind, device, shock_kw = task
    out = []
    for a, label, phase, vm in attractors:
        why, sh = _why_not(label, phase, vm), None
        if not why:
            try:
                sh = critical_shock(params, phase, vm, kind=kind, device=device, **shock_kw)
                why = sh.reason
            except ValueError as err:  # the start's run finds no period within the cap
                why = f"no critical shock: {err}"
        out.append((a, sh, why))
    return out


def _one_thread():
    numba.set_num_threads(1)


def _each_point(tasks, workers):
    """:func:`_point_shocks` of every task, in order: in this process, or on ``workers`` threads of one numba
    thread each (each shock is the same either way: the runs of a batch are independent; on one numba thread
    the knocked runs go through the serial kernel, which releases the GIL)."""
    if workers == 1:
        yield from map(_point_shocks, tasks)
        return
    with ThreadPoolExecutor(workers, initializer=_one_thread) as pool:
        yield from pool.map(_point_shocks, tasks)


def _fill(fields, ints, reached, at, sh: Shock):
    fields["shock"][at], fields["shock_size"][at] = sh.size_si, sh.size
    fields["shock_phase"][at], fields["shock_reached_U_T"][at] = sh.phase, sh.reached_U_T
    ints["shock_direction"][at], ints["shock_runs"][at] = sh.direction, sh.simulations
    reached[at] = sh.reached


def _assemble(dm, kind, fields, ints, reached, reason, shock_kw):
    dims3 = dm["label"].dims
    unit = _UNIT[kind]
    what = "velocity Zdot" if kind == "velocity" else "position Z"
    ds = dm.copy()
    ds["shock"] = (dims3, fields["shock"], {"units": unit, "long_name": f"critical shock: the smallest knock of the "
                   f"ball's {what} that drops the attractor to another (inf: no admissible knock does; NaN: none "
                   "computed, see shock_reason)"})
    ds["shock_size"] = (dims3, fields["shock_size"], {"units": "1", "long_name": "critical shock, non-dimensional"})
    ds["shock_phase"] = (dims3, fields["shock_phase"], {"units": "rad", "long_name": "forcing phase of the knock"})
    ds["shock_direction"] = (dims3, ints["shock_direction"], {"units": "1", "long_name": "sign of the knock "
                             "(+1 towards the bottom membrane; 0: none)"})
    ds["shock_reached"] = (dims3, reached.astype(str), {"units": "1", "long_name": "the motion the knock drops "
                           "the harvester to"})
    ds["shock_reached_U_T"] = (dims3, fields["shock_reached_U_T"], {"units": "V", "long_name": "U_T of the motion "
                               "reached"})
    ds["shock_runs"] = (dims3, ints["shock_runs"], {"units": "1", "long_name": "knocked runs simulated"})
    ds["shock_reason"] = (dims3, reason.astype(str), {"units": "1", "long_name": "why no critical shock was "
                          "computed ('' where it was)"})
    _top(ds, dm.attrs.get("min_share", 0.0))
    ds.attrs.update(knock_kind=kind, knock_unit=unit, shock_fine_span=FINE_SPAN,
                    **{f"shock_{k}": v for k, v in shock_kw.items()})
    return annotate(ds)


def _top(ds, min_share):
    """The highest-output attractor of each point (among those reached by at least ``min_share`` of the starts):
    ``top`` (its index, -1 where none has an output), ``top_label``, ``top_U_T``, ``top_shock``, ``top_reason``."""
    u = np.where((ds["share"].values >= min_share) & np.isfinite(ds["U_T"].values), ds["U_T"].values, -np.inf)
    top = np.argmax(u, axis=-1)
    none = ~np.isfinite(np.take_along_axis(u, top[..., None], -1)[..., 0])
    pick = lambda v: np.take_along_axis(ds[v].values, top[..., None], -1)[..., 0]
    dims2 = ds["d"].dims
    ds["top"] = (dims2, np.where(none, -1, top), {"units": "1", "long_name": "index of the point's highest-output "
                 f"attractor (reached by at least {min_share:g} of the starts; -1: none)"})
    ds["top_label"] = (dims2, np.where(none, "", pick("label")).astype(str), {"units": "1", "long_name":
                       "the highest-output attractor"})
    ds["top_U_T"] = (dims2, np.where(none, np.nan, pick("U_T")), {"units": "V", "long_name": "its output U_T"})
    ds["top_shock"] = (dims2, np.where(none, np.nan, pick("shock")), {"units": ds["shock"].attrs["units"],
                       "long_name": "its critical shock (inf: no admissible knock drops it)"})
    ds["top_reason"] = (dims2, np.where(none, "no attractor with an output", pick("shock_reason")).astype(str),
                        {"units": "1", "long_name": "why its critical shock is missing ('' where known)"})


def pareto_front(U_T, shock) -> np.ndarray:
    """Indices (into the flattened arrays) of the designs no other beats on both output ``U_T`` and critical
    ``shock`` (higher is better for both; NaN is left out), by decreasing shock.

    Parameters
    ----------
    U_T, shock : array_like
        Each design's output and critical shock (``inf``: no admissible knock drops it).

    Returns
    -------
    numpy.ndarray
        The indices of the front.

    Examples
    --------
    >>> from vibroimpact.analysis.robust import pareto_front
    >>> pareto_front([3.0, 2.0, 1.0, 2.5], [1.0, 2.0, 3.0, 0.5]).tolist()
    [2, 1, 0]
    """
    u, s = np.ravel(np.asarray(U_T, float)), np.ravel(np.asarray(shock, float))
    ok = np.flatnonzero(np.isfinite(u) & ~np.isnan(s))
    order = ok[np.lexsort((-u[ok], -s[ok]))]  # by shock descending, then output descending
    front, best = [], -np.inf
    for i in order:
        if u[i] > best:
            front.append(int(i))
            best = u[i]
    return np.array(front, dtype=int)


def robust_choice(km: xr.Dataset, knock: float, *, row: int | None = None) -> dict:
    """The design of highest output whose highest-output motion survives every knock up to ``knock`` (in the
    map's unit: its critical shock is at least ``knock``), beside the best design regardless of knocks; among
    the designs of one ``row`` of the map (one value of its y axis, e.g. one incline) if given.

    Parameters
    ----------
    km : xarray.Dataset
        A knock map (:func:`knock_map`).
    knock : float
        The knock the design must survive, in the map's unit (``km.attrs["knock_unit"]``).
    row : int, optional
        Only the designs of this row of the map (an index along its y axis).

    Returns
    -------
    dict
        ``robust`` and ``best``: each a dict of the design's axes' values, ``U_T`` (V), ``shock``, ``motion``
        (None where no design qualifies), and ``knock``, ``unit``, ``designs`` (points with a known output and
        shock) and ``survive`` (how many of them survive the knock).

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> from vibroimpact.analysis.robust import robust_choice
    >>> phi, v0 = vi.start_states(8, distribution="box", seed=0)
    >>> dm = vi.design_map("s", [0.2245, 0.23], "beta", [math.pi / 6], phi=phi, v0=v0)
    >>> ch = robust_choice(vi.knock_map(dm, phases=8, refine=2), knock=0.1)
    >>> ch["robust"]["s"], ch["robust"]["shock"], ch["survive"], ch["designs"]
    (0.23, inf, 1, 2)
    """
    if not (isinstance(knock, (int, float)) and knock >= 0 and math.isfinite(knock)):
        raise ValueError(f"knock = {knock!r}; allowed: a finite size >= 0 (in {km.attrs['knock_unit']})")
    u, s = km["top_U_T"].values, km["top_shock"].values
    known = np.isfinite(u) & ~np.isnan(s)
    if row is not None:
        known &= np.arange(u.shape[0])[:, None] == row
    survive = known & (s >= knock)

    def design(mask):
        if not mask.any():
            return None
        iy, ix = np.unravel_index(int(np.argmax(np.where(mask, u, -np.inf))), u.shape)
        x, y = km.attrs["x"], km.attrs["y"]
        return {x: float(km[x].values[ix]), y: float(km[y].values[iy]), "U_T": float(u[iy, ix]),
                "shock": float(s[iy, ix]), "motion": str(km["top_label"].values[iy, ix])}

    return {"robust": design(survive), "best": design(known), "knock": float(knock), "unit": km.attrs["knock_unit"],
            "designs": int(known.sum()), "survive": int(survive.sum())}


def table_choices(km: xr.Dataset, knock: float, rows_at=()) -> dict:
    """:func:`robust_choice` over the whole map (key ``"whole map"``) and within each row of the map at a value of
    ``rows_at`` on its y axis (e.g. the design table's inclines; key: the value), for the knocks table
    (:func:`vibroimpact.outputs.tables.knocks_table`).

    Parameters
    ----------
    km : xarray.Dataset
        A knock map (:func:`knock_map`).
    knock : float
        The knock the robust design survives, in the map's unit.
    rows_at : sequence of float
        Values of the map's y axis; those not on it are passed over.

    Returns
    -------
    dict
        The choices, by where they are made.
    """
    ys = km[km.attrs["y"]].values
    rows = {float(v): int(np.argmin(np.abs(ys - v))) for v in rows_at if np.min(np.abs(ys - v)) < 1e-12}
    return {"whole map": robust_choice(km, knock)} | {v: robust_choice(km, knock, row=r) for v, r in rows.items()}


def mark_choices(km: xr.Dataset, knock: float) -> xr.Dataset:
    """``km`` with the designs a figure marks, per point: ``pareto`` (on the Pareto front of output against
    critical shock, :func:`pareto_front`), ``best`` and ``robust`` (the designs :func:`robust_choice` picks over
    the whole map for ``knock``); the knock in the attributes ``knock``, ``knock_unit``.

    Parameters
    ----------
    km : xarray.Dataset
        A knock map (:func:`knock_map`).
    knock : float
        The knock the robust design survives, in the map's unit.

    Returns
    -------
    xarray.Dataset
        The knock map with the three flags.
    """
    ch = robust_choice(km, knock)
    dims, shape = km["top_U_T"].dims, km["top_U_T"].shape
    front = np.zeros(shape, bool)
    front.flat[pareto_front(km["top_U_T"].values, km["top_shock"].values)] = True
    x, y = km.attrs["x"], km.attrs["y"]

    def flag(d):
        out = np.zeros(shape, bool)
        if d is not None:
            out[int(np.argmin(np.abs(km[y].values - d[y]))), int(np.argmin(np.abs(km[x].values - d[x])))] = True
        return out

    km = km.assign(pareto=(dims, front, {"units": "1", "long_name": "on the Pareto front of output against "
                                         "critical shock (no design has more of both)"}),
                   best=(dims, flag(ch["best"]), {"units": "1", "long_name": "the design of highest output"}),
                   robust=(dims, flag(ch["robust"]), {"units": "1", "long_name": "the design of highest output "
                                                      f"whose highest-output motion survives a knock of {knock:g} "
                                                      f"{ch['unit']}"}))
    km.attrs["knock"] = float(knock)
    return km


def knock_section(params: Params, shock: Shock | None, phi: float, zs, vs, *, max_periods: float = 200,
                  progress: bool | None = None) -> xr.Dataset:
    """The basins in the ``(Z, Zdot)`` section at the forcing phase of a critical shock: the motion reached from
    each state of a grid at that phase, with the knocked state and the knock.

    Parameters
    ----------
    params : Params
        The harvester's parameters.
    shock : Shock or None
        A critical shock at these parameters (:func:`vibroimpact.critical_shock`).  Where it is None or infinite
        (no knock leaves) the section is at the phase ``phi`` and says why in its ``reason`` attribute.
    phi : float
        The forcing phase at t = 0 the shock was computed with (its start's ``phi``).
    zs, vs : array_like
        The grid's ``Z`` (within ``|Z| <= d/2``) and ``Zdot`` values (non-dimensional).
    max_periods : float
        Longest transient, in forcing periods.
    progress : bool, optional
        A progress bar (default: only when run interactively).

    Returns
    -------
    xarray.Dataset
        On ``(Zdot, Z)``: ``label`` and the integer ``attractor`` (index into the ``legend`` attribute); attributes
        the section's phase, the knocked state ``Z_knock``, ``Zdot_knock``, the knock's ``size``, ``direction``,
        ``kind``, the motion knocked and the one reached.

    Examples
    --------
    >>> import math, numpy as np, vibroimpact as vi
    >>> p = vi.Params(d=0.13975, gbar=0.12201)
    >>> sh = vi.critical_shock(p, 1.645, 0.05067, phases=4, refine=0, rtol=1e-2)
    >>> sec = vi.knock_section(p, sh, 1.645, np.linspace(-0.06, 0.06, 5), np.linspace(-0.5, 0.5, 4))
    >>> sorted(set(sec.label.values.ravel().tolist())) == ['2:1 period-2', '3:1 period-2']
    True
    """
    zs, vs = np.asarray(zs, float), np.asarray(vs, float)
    if np.any(np.abs(zs) > 0.5 * params.d):
        raise ValueError(f"zs = [{zs.min()!r} .. {zs.max()!r}]; allowed: |Z| <= d/2 = {0.5 * params.d!r}")
    found = shock is not None and math.isfinite(shock.size)
    # a time with the knock's forcing phase (without one: the start's, t = 0)
    t0 = ((shock.phase - phi) % (2 * math.pi)) / math.pi if found else 0.0
    Z, V = np.meshgrid(zs, vs, indexing="xy")
    ds = attractor_batch(params.d, params.gbar, params.r, phi, V.ravel(), t0=t0, Z0=Z.ravel(),
                         max_periods=max_periods, progress=progress, desc="basins in a section")
    out = xr.Dataset({"label": (("Zdot", "Z"), ds["label"].values.reshape(Z.shape)),
                      "sticking": (("Zdot", "Z"), ds["sticking"].values.reshape(Z.shape))},
                     coords={"Z": ("Z", zs, {"units": "1", "long_name": "position Z (towards the bottom membrane)"}),
                             "Zdot": ("Zdot", vs, {"units": "1", "long_name": "velocity Zdot"})})
    out.attrs.update(phase=(math.pi * t0 + phi) % (2 * math.pi), t0=t0, phi=phi, d=params.d, gbar=params.gbar,
                     r=params.r, max_periods=max_periods, reason="" if found else
                     (shock.reason if shock is not None else "no periodic motion to knock"))
    if shock is not None:
        z, v = shock.state
        kz, kv = ((z + shock.direction * shock.size, v) if shock.kind == "position" else
                  (z, v + shock.direction * shock.size)) if found else (math.nan, math.nan)
        out.attrs.update(Z_state=z, Zdot_state=v, Z_knocked=kz, Zdot_knocked=kv, size=shock.size,
                         size_si=shock.size_si, direction=shock.direction, kind=shock.kind, motion=shock.motion,
                         reached=shock.reached)
    return annotate(attractor_codes(out, ("Zdot", "Z")))
