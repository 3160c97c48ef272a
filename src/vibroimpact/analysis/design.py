"""Design under multistability: the output a device delivers from switch-on, and where it is robust.

At every point of a grid over two design parameters (``s`` and ``beta`` at fixed force, or ``s`` and
``F`` at fixed incline) the same set of start states is run to its attractor
(:func:`vibroimpact.analysis.windows.attractor_batch`, in parallel).  The runs that reach one attractor give its
share of the starts, with a binomial (Clopper-Pearson) confidence interval, and its averages ``U_I``
and ``U_T`` (:func:`vibroimpact.analysis.energy.window_averages`: one whole period where the motion is
periodic, the last ``window_time`` time units where no period was found).  Per point:

* ``E_U_T = sum(share * U_T)``, what a device switched on at a random start delivers on average;
* ``worst_U_T``, the least ``U_T`` among attractors with share at least ``min_share``;
* the same for ``U_I``; ``multistable`` where two or more attractors have that share.

:func:`tolerance_analysis` adds, for a manufacturing tolerance (a box around each point), the lowest
``E_U_T`` over the box and the distance to the nearest bifurcation curve
(:func:`vibroimpact.analysis.bifurcation.curve_set`) in units of the box: a design is robust when no curve
crosses its box (``margin > 1``).  :func:`best_designs` picks, per incline, the robust design whose
lowest ``E_U_T`` over its box is largest, within a budget.

Start states (:func:`start_states`), the same at every point so that neighbouring points are compared
on the same starts: ``"rest"`` (the physical default) is the device switched on with the ball at rest
on the bottom membrane and the forcing phase uniform in ``[0, 2 pi)``; ``"box"`` is a bottom impact
uniform over a box of (phase, pre-impact velocity).  Both are drawn from a seeded generator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import xarray as xr

from .._progress import Progress, interactive
from ..datasets import annotate
from ..dynamics import kernels as K
from ..dynamics.device import Device
from .energy import LONG_BATCHES, batch_averages, voltage_gain, window_averages
from .grids import held_values, plane_params
from .motions import APERIODIC, no_period
from .settled import LONG_IMPACTS, STICK_REL, polish_cycle, split_no_period
from .starts import DESIGN_AXES, DISTRIBUTIONS, MIN_STARTS, RELATIVE, start_states
from .starts import fail as _fail
from .windows import attractor_batch, last_bottom_impact

__all__ = ["DISTRIBUTIONS", "MIN_STARTS", "AT_REST", "start_states", "design_map",
           "merge_chunks", "share_interval", "point_attractors", "table_designs", "tolerance_analysis", "curve_margin", "box_minimum", "best_designs"]

#: label of a run that comes to rest on the bottom for good (gbar >= 1): no impact, no output
AT_REST = "rests on the bottom"
#: runs of one label whose U_T agree to this (relative) are one attractor.  Two runs of one periodic
#: orbit agree to the periodicity tolerance (1e-9); distinct orbits of one n:m class differ far more.
SAME_ORBIT = 1e-6
_UNITS = {"s": ("m", "cylinder length s"), "F": ("N", "forcing amplitude ||F||"), "beta": ("rad", "incline beta")}


def grid_axes(spec: dict, grid, table_betas=()):
    """The axes of a design map: ``grid = [nx, ny]`` points over the map's ranges, and on a beta axis
    also the inclines of the design table (so that each has a row of its own)."""
    xs = np.linspace(*spec["x_range"], int(grid[0]))
    ys = np.linspace(*spec["y_range"], int(grid[1]))
    if spec["y"] == "beta":
        lo, hi = spec["y_range"]
        extra = [b for b in table_betas if lo <= b <= hi]
        ys = np.unique(np.concatenate([ys, extra]))
    return xs, ys


def _group(labels, u_t):
    """Attractors among the runs of one point: a periodic label split where U_T differs by more than
    :data:`SAME_ORBIT`; all runs without a period as one.  Returns lists of run-index arrays."""
    groups = []
    for lab in np.unique(labels):
        idx = np.flatnonzero(labels == lab)
        if lab in (APERIODIC, AT_REST):
            groups.append(idx)
            continue
        idx = idx[np.argsort(u_t[idx], kind="stable")]
        v = u_t[idx]
        cut = np.flatnonzero(np.abs(np.diff(v)) > SAME_ORBIT * np.maximum(np.abs(v[1:]), 1.0)) + 1
        groups.extend(np.split(idx, cut))
    return groups


@lru_cache(maxsize=4096)
def share_interval(k: int, n: int, confidence: float) -> tuple[float, float]:
    """Clopper-Pearson (exact) interval of a share of ``k`` starts out of ``n`` at level ``confidence``
    (scipy's ``binomtest``; cached, as every point of a map has the same ``n``; ``scipy.stats`` is imported here,
    as it costs 0.6 s a process that only reads a map)."""
    from scipy.stats import binomtest

    ci = binomtest(int(k), int(n)).proportion_ci(confidence_level=float(confidence), method="exact")
    return float(ci.low), float(ci.high)


def _settle_attractor(att, events, lag, d, gbar, r, F, device):
    """Make an attractor's outputs well-posed (:mod:`vibroimpact.analysis.settled`): a periodic one's are its exact
    cycle's (solved through one of its runs' recorded cycle), settled; resting on the bottom gives 0,
    settled; a motion with no period gets the long run's averages with their batch-means standard errors
    (continued from one of its runs: the window of a run is one sample of the motion, and the runs of one
    attractor need not be independent samples: starts at rest all leave the wall at the release phase),
    or keeps its runs' mean with no standard error where the long run settles after all."""

    att.settled, att.U_T_se, att.U_I_se = False, math.nan, math.nan
    if att.label == AT_REST:
        att.settled = True
        return
    if att.label == APERIODIC:
        phi, v0 = att.impact
        if not (math.isfinite(phi) and math.isfinite(v0)):
            return
        split = split_no_period(d, gbar, r, phi, v0, impacts=LONG_IMPACTS)
        att.label = split.label  # chaotic, quasi-periodic or unsettled, by its largest exponent
        run = split.run
        if run["status"] != "aperiodic":
            return
        u_i, se_i, u_t, se_t = batch_averages(run, F, device, batches=LONG_BATCHES)
        att.U_I, att.U_I_se, att.U_T, att.U_T_se = float(u_i), float(se_i), float(u_t), float(se_t)
        return
    t, wall, vm, phase, kind = events
    n = t.size
    if not lag or n <= lag:
        return
    sl = slice(n - lag, n)
    res = polish_cycle(d, gbar, r, t[sl], wall[sl], vm[sl], phase[sl], kind[sl], span=t[n - 1] - t[n - 1 - lag])
    if not (res["settled"] or res["status"] == "sticking"):
        return
    hit = K.hits(res["kind"])
    gain = voltage_gain(device.speed_si(res["v_minus"][hit], F), device.membrane)
    att.U_T = float(gain.sum() / (2.0 * att.period)) if att.period else math.nan
    att.U_I = float(gain.mean()) if gain.size else math.nan
    att.settled = bool(res["settled"])
    if res["status"] == "sticking":  # known to the accuracy of its summed chatter
        att.U_T_se, att.U_I_se = STICK_REL * abs(att.U_T), STICK_REL * abs(att.U_I)


# a record of one point's attractor, filled in as it is settled: its fields are Attributes, not Parameters
@dataclass
class PointAttractor:  # numpydoc ignore=PR01
    """One attractor of a design map's point (:func:`design_map`), from the runs that reach it.

    Attributes
    ----------
    label : str
        Its motion (with no period: chaotic, quasi-periodic or unsettled once its long run has said so).
    runs : numpy.ndarray
        The point's runs that reach it.
    count, share, low, high : int, float, float, float
        How many starts reach it, their share and the share's confidence interval.
    U_T, U_I, U_T_se, U_I_se : float
        Its output per unit time and per impact and their standard errors (NaN where exact or unknown).
    u_t_runs, u_i_runs : numpy.ndarray
        Each run's window averages.
    impact : tuple of float
        Phase and pre-impact speed of a bottom impact on it (a start of its long run).
    period, n_bottom, n_top : int
        Its period in forcing periods and impacts per period on each wall.
    settled : bool
        Its outputs are exact (a Newton-solved or sticking cycle, or at rest).
    """

    label: str
    runs: np.ndarray
    count: int
    share: float
    low: float
    high: float
    U_T: float
    U_I: float
    u_t_runs: np.ndarray
    u_i_runs: np.ndarray
    U_T_se: float = math.nan
    U_I_se: float = math.nan
    impact: tuple = (math.nan, math.nan)
    period: int = 0
    n_bottom: int = 0
    n_top: int = 0
    settled: bool = False


def _point_attractors(labels, u_t, u_i, confidence):
    """Per attractor of one point (largest share first): label, runs, share and its interval, U_T, U_I."""
    n = labels.size
    out = []
    for idx in _group(labels, u_t):
        k = idx.size
        low, high = share_interval(k, n, confidence)
        out.append(PointAttractor(label=str(labels[idx[0]]), runs=idx, count=k, share=k / n, low=low, high=high,
                                  U_T=float(np.mean(u_t[idx])),
                                  U_I=float(np.mean(u_i[idx])) if np.isfinite(u_i[idx]).all() else math.nan,
                                  u_t_runs=u_t[idx], u_i_runs=u_i[idx]))
    out.sort(key=lambda a: (-a.count, a.label, a.U_T))
    return out


def design_map(x_name: str, xs, y_name: str, ys, *, phi, v0, device: Device | None = None, max_periods: float = 200,
               tol: float = 1e-9, window: int = 96, window_time: float = 30.0, min_share: float = 0.01,
               confidence: float = 0.95, block: int = 20_000, progress: bool | None = None,
               **held) -> xr.Dataset:
    """Attractors, their shares and outputs at every point of a grid over two design parameters.

    Parameters
    ----------
    x_name, y_name : {"s", "F", "beta"}
        The two axes.
    xs, ys : array_like
        Their values (m, N or rad).
    phi, v0 : array_like
        The start states (:func:`start_states`), the same at every point.
    device : Device, optional
        The harvester (default the paper's, ``Device()``): its physics and the membranes of the outputs.
    max_periods, tol, window
        As in :func:`vibroimpact.analysis.windows.attractor_batch` (``window``: events kept per run, enough to
        span ``window_time`` where no period is found).
    window_time : float
        Averaging span of runs without a period (non-dimensional time), as in the sweeps.
    min_share : float
        Attractors with a smaller share are reported but do not count for the worst case or for
        multistability.
    confidence : float
        Level of the shares' Clopper-Pearson intervals.
    block : int
        Runs simulated at once (bounds the memory of the event windows).
    progress : bool, optional
        A progress bar over the points (default: only when run interactively).
    **held
        The values held where they are not an axis (``s``, ``F``, ``beta``; ``r`` changes the device's):
        :func:`vibroimpact.analysis.grids.plane_params`.

    Returns
    -------
    xarray.Dataset
        On ``(y_name, x_name)``: ``E_U_T``, ``E_U_I``, ``worst_U_T``, ``worst_U_I``, ``n_attractors``,
        ``multistable``, ``aperiodic_share``, ``d``, ``gbar``, ``n_events``; on
        ``(y_name, x_name, attractor)``: ``label``, ``share``, ``share_low``, ``share_high``, ``U_T``,
        ``U_I``, ``period``, ``n_bottom``, ``n_top``, and the last bottom impact of one run on it
        (``impact_phase``, ``impact_v_minus``).

        Beside these: the starts reaching each attractor (``count``), whether its output is exact
        (``settled``) or a long-run estimate with standard errors (``U_T_se``, ``U_I_se``), and per point
        ``E_U_T_se``, ``worst_U_T_se`` and ``point_settled``; attributes: the settings, the axes ``x`` and
        ``y`` and the values held.

    Examples
    --------
    Eight starts on two lengths at the paper's incline: on the bistable interval (s = 0.2245 m, d = 0.13975)
    they reach both motions, beyond G2 (s = 0.23 m) only the 2:1; the expected output ``E_U_T`` is the
    attractors' outputs weighted by their shares, and the worst case the lowest of them:

    >>> import math, numpy as np, vibroimpact as vi
    >>> phi, v0 = vi.start_states(8, distribution="box", seed=0)
    >>> dm = vi.design_map("s", [0.2245, 0.23], "beta", [math.pi / 6], phi=phi, v0=v0)
    >>> dm.n_attractors.values.tolist(), dm.multistable.values.tolist()
    ([[2, 1]], [[True, False]])
    >>> sorted(dm.label.values[0, 0].tolist())
    ['2:1 period-2', '3:1 period-2']
    >>> bool(np.allclose((dm.share * dm.U_T).sum("attractor"), dm.E_U_T))
    True
    >>> dm.worst_U_T.values.round(-1).tolist()
    [[33690.0, 34070.0]]
    """
    for name in (x_name, y_name):
        if name not in DESIGN_AXES:
            _fail("design map axis", name, f"one of {', '.join(DESIGN_AXES)} (the output needs the force F)")
    phi, v0 = (np.atleast_1d(np.asarray(a, dtype=float)) for a in np.broadcast_arrays(phi, v0))
    if phi.size < MIN_STARTS:
        _fail("starts", int(phi.size), f"at least {MIN_STARTS} start states")
    device, held = held_values(device, held)
    X, Y, d, gbar, r, fixed = plane_params(x_name, xs, y_name, ys, device=device, **held)
    F = X if x_name == "F" else Y if y_name == "F" else np.full(X.shape, float(fixed["F"]))
    shape, n_pts, n_st = X.shape, X.size, phi.size
    per_pt = max(1, block // n_st)
    points = []
    total = 0
    shown = interactive() if progress is None else bool(progress)
    with Progress(n_pts, f"design map over ({x_name}, {y_name})", shown, unit="point") as bar:
        for a in range(0, n_pts, per_pt):
            b = min(n_pts, a + per_pt)
            sl = slice(a, b)
            rep = lambda v, sl=sl: np.repeat(v.ravel()[sl], n_st)
            runs = attractor_batch(rep(d), rep(gbar), rep(r), np.tile(phi, b - a), np.tile(v0, b - a),
                                   max_periods=max_periods, tol=tol, window=window, progress=False)
            total += int(runs["n_events"].values.sum())
            points += _block_points(runs, range(a, b), n_st, (d, gbar, r, F), rep(F), device, window_time, confidence)
            bar.update(b - a)
    return _assemble(points, shape, x_name, xs, y_name, ys, d, gbar, fixed, n_st, total,
                     dict(max_periods=max_periods, tol=tol, window=window, window_time=window_time,
                          min_share=min_share, confidence=confidence))

def _block_points(runs, pts, n_st, grid, forces, device, window_time, confidence):
    """The attractors of the points ``pts`` of a design map from their ``n_st`` runs each (one
    :func:`~vibroimpact.analysis.windows.attractor_batch`, ``forces`` per run): per point, its attractors (each
    settled, :func:`_settle_attractor`) and its events simulated.  ``grid``: the map's ``(d, gbar, r, F)``."""
    d, gbar, r, F = grid
    st = runs["status"].values
    _, _, u_i, u_t, _, _ = window_averages(
        runs["t"].values, runs["v_minus"].values, runs["kind"].values, st, runs["period_events"].values,
        forces, device, window_time=window_time)
    labels = np.where(st == K.STUCK_FOREVER, AT_REST, runs["label"].values)
    ev = [runs[v].values for v in ("t", "wall", "v_minus", "phase", "kind")]
    nw = np.isfinite(ev[0]).sum(axis=1)
    lags = runs["period_events"].values
    points = []
    for j, pt in enumerate(pts):
        rs = slice(j * n_st, (j + 1) * n_st)
        atts = _point_attractors(labels[rs], u_t[rs], u_i[rs], confidence)
        for att in atts:
            k = rs.start + int(att.runs[0])
            last = last_bottom_impact(*(e[k] for e in ev), int(nw[k]))
            att.impact = last if last is not None else (math.nan, math.nan)
            att.period, att.n_bottom, att.n_top = (int(runs[v].values[k]) for v in ("period", "n_bottom", "n_top"))
            _settle_attractor(att, [e[k][:int(nw[k])] for e in ev], int(lags[k]), d.flat[pt], gbar.flat[pt],
                              r.flat[pt], F.flat[pt], device)
        points.append((atts, int(runs["n_events"].values[rs].sum())))
    return points



def point_attractors(runs, d, gbar, r, F, device, window_time, confidence):
    """The attractors of one parameter point ``(d, gbar, r)`` at the force ``F`` from its runs (one
    :func:`~vibroimpact.analysis.windows.attractor_batch` over any starts), grouped and settled as a design map's
    point: its :class:`PointAttractor` list (most starts first) and the events simulated."""
    n = runs.sizes["run"]
    grid = tuple(np.array([float(v)]) for v in (d, gbar, r, F))
    ((atts, events),) = _block_points(runs, [0], n, grid, np.full(n, float(F)), device, window_time, confidence)
    return atts, events


def _assemble(points, shape, x_name, xs, y_name, ys, d, gbar, fixed, n_st, total, settings):
    n_att = max(len(a) for a, _ in points)
    A = (*shape, n_att)
    arr = {v: np.full(A, np.nan) for v in ("share", "share_low", "share_high", "U_T", "U_I", "U_T_se", "U_I_se",
                                             "impact_phase", "impact_v_minus")}
    settled = np.zeros(A, bool)
    ints = {v: np.zeros(A, np.int64) for v in ("count", "period", "n_bottom", "n_top")}
    label = np.full(A, "", dtype=object)
    n_events = np.zeros(shape, np.int64)
    for flat, (atts, nev) in enumerate(points):
        iy, ix = np.unravel_index(flat, shape)
        n_events[iy, ix] = nev
        for k, att in enumerate(atts):
            label[iy, ix, k] = att.label
            for v, key in (("share", "share"), ("share_low", "low"), ("share_high", "high"), ("U_T", "U_T"),
                           ("U_I", "U_I"), ("U_T_se", "U_T_se"), ("U_I_se", "U_I_se")):
                arr[v][iy, ix, k] = getattr(att, key)
            settled[iy, ix, k] = att.settled
            arr["impact_phase"][iy, ix, k], arr["impact_v_minus"][iy, ix, k] = att.impact
            for v in ints:
                ints[v][iy, ix, k] = getattr(att, v)
    dims2, dims3 = (y_name, x_name), (y_name, x_name, "attractor")
    ds = xr.Dataset(
        {"label": (dims3, label.astype(str), {"units": "1", "long_name": "attractor: n:m impacts per period and "
                                                "period, or with no period chaotic, quasi-periodic or unsettled by its long run's largest Lyapunov "
                                                "exponent (largest share first; '' pads)"}),
         "count": (dims3, ints["count"], {"units": "1", "long_name": "starts reaching the attractor"}),
         "share": (dims3, arr["share"], {"units": "1", "long_name": "share of the starts reaching the attractor"}),
         "share_low": (dims3, arr["share_low"], {"units": "1", "long_name": "lower end of the share's "
                                                 f"{settings['confidence']:g} Clopper-Pearson interval"}),
         "share_high": (dims3, arr["share_high"], {"units": "1", "long_name": "upper end of the share's "
                                                   f"{settings['confidence']:g} Clopper-Pearson interval"}),
         "U_T": (dims3, arr["U_T"], {"units": "V", "long_name": "average voltage gain per unit time U_T of the "
                                     "attractor (mean over its runs)"}),
         "U_I": (dims3, arr["U_I"], {"units": "V", "long_name": "average voltage gain per impact U_I of the attractor"}),
         "U_T_se": (dims3, arr["U_T_se"], {"units": "V", "long_name": "standard error of U_T over the attractor's runs "
                                           "(no period found: each run's window is one sample; NaN where settled)"}),
         "U_I_se": (dims3, arr["U_I_se"], {"units": "V", "long_name": "standard error of U_I over the attractor's runs"}),
         "settled": (dims3, settled, {"units": "1", "long_name": "the attractor's outputs are exact: its Newton-solved "
                                      "or sticking cycle, or resting"}),
         "period": (dims3, ints["period"], {"units": "1", "long_name": "period in forcing periods (0: none found)"}),
         "n_bottom": (dims3, ints["n_bottom"], {"units": "1", "long_name": "bottom impacts per period"}),
         "n_top": (dims3, ints["n_top"], {"units": "1", "long_name": "top impacts per period"}),
         "impact_phase": (dims3, arr["impact_phase"], {"units": "rad", "long_name": "forcing phase at the last "
                                                       "bottom impact of one run on the attractor"}),
         "impact_v_minus": (dims3, arr["impact_v_minus"], {"units": "1", "long_name": "pre-impact velocity at that "
                                                           "impact (non-dimensional)"}),
         "d": (dims2, d, {"units": "1", "long_name": "non-dimensional gap d"}),
         "gbar": (dims2, gbar, {"units": "1", "long_name": "non-dimensional gravity gbar"}),
         "n_events": (dims2, n_events, {"units": "1", "long_name": "events simulated at the point, all starts"})},
        coords={x_name: np.asarray(xs, float), y_name: np.asarray(ys, float)},
    )
    for name in (x_name, y_name):
        ds[name].attrs.update(units=_UNITS[name][0], long_name=_UNITS[name][1])
    ds.attrs.update(settings, starts=n_st, events=total, x=x_name, y=y_name,
                    **{k: float(v) for k, v in fixed.items()})
    return annotate(summarise(ds))


#: the per-point variables :func:`summarise` derives from the attractors (recomputed after a merge)
SUMMARY = ("E_U_T", "E_U_I", "worst_U_T", "worst_U_I", "n_attractors", "multistable", "aperiodic_share", "E_U_T_se",
           "point_settled", "worst_U_T_se")


def summarise(ds: xr.Dataset) -> xr.Dataset:
    """Per point from its attractors: expected and worst-case outputs, how many attractors count, and
    the share without a period."""
    share, u_t, u_i = ds["share"].fillna(0.0), ds["U_T"], ds["U_I"]
    counts = ds["share"] >= ds.attrs["min_share"]
    ds["E_U_T"] = (share * u_t.fillna(0.0)).sum("attractor").where(ds["share"].notnull().any("attractor"))
    ds["E_U_T"].attrs.update(units="V", long_name="expected U_T from a random start: sum of share x U_T")
    ds["E_U_I"] = (share * u_i).sum("attractor", skipna=False).where(ds["share"].notnull().any("attractor"))
    ds["E_U_I"].attrs.update(units="V", long_name="expected U_I from a random start: sum of share x U_I "
                             "(NaN where an attractor has no impact)")
    ds["worst_U_T"] = u_t.where(counts).min("attractor")
    ds["worst_U_T"].attrs.update(units="V", long_name="least U_T among the attractors with share >= min_share")
    ds["worst_U_I"] = u_i.where(counts).min("attractor")
    ds["worst_U_I"].attrs.update(units="V", long_name="least U_I among the attractors with share >= min_share")
    ds["n_attractors"] = counts.sum("attractor").astype(np.int64)
    ds["n_attractors"].attrs.update(units="1", long_name="attractors with share >= min_share")
    ds["multistable"] = ds["n_attractors"] >= 2
    ds["multistable"].attrs.update(units="1", long_name="two or more attractors with share >= min_share")
    ds["aperiodic_share"] = share.where(no_period(ds["label"].values), 0.0).sum("attractor")
    ds["aperiodic_share"].attrs.update(units="1", long_name="share of the starts with no period found (chaotic, quasi-periodic or unsettled)")
    # how well E_U_T is known: the starts are a sample of the start distribution (the sampling error of
    # the mean over them), and a motion with no period contributes its runs' own spread
    present = ds["share"].notnull()
    n = float(ds.attrs.get("starts", 1))
    spread = (share * (u_t.fillna(0.0) - ds["E_U_T"]) ** 2).where(present).sum("attractor") / n
    own = (share**2 * ds["U_T_se"].fillna(0.0) ** 2).where(present).sum("attractor") if "U_T_se" in ds else 0.0
    ds["E_U_T_se"] = np.sqrt(spread + own).where(present.any("attractor"))
    if "settled" in ds:  # an attractor neither settled nor with a long-run error leaves E_U_T without one
        unknown = (present & ~ds["settled"] & ds["U_T_se"].isnull()).any("attractor")
        ds["E_U_T_se"] = ds["E_U_T_se"].where(~unknown)
    ds["E_U_T_se"].attrs.update(units="V", long_name="standard error of E_U_T: the sampling error over the starts "
                                "and the spread of runs with no period")
    if "settled" in ds:
        ds["point_settled"] = (ds["settled"] | ~present).all("attractor")
        ds["point_settled"].attrs.update(units="1", long_name="every attractor at the point has exact outputs")
        worst = u_t.where(counts).fillna(np.inf).argmin("attractor")
        ds["worst_U_T_se"] = ds["U_T_se"].isel(attractor=worst).where(ds["worst_U_T"].notnull())
        ds["worst_U_T_se"] = ds["worst_U_T_se"].where(~ds["settled"].isel(attractor=worst), 0.0)
        ds["worst_U_T_se"].attrs.update(units="V", long_name="standard error of worst_U_T (0 where that attractor is settled)")
    return ds


def merge_chunks(chunks: list[xr.Dataset]) -> xr.Dataset:
    """One design map from chunks of its rows (the same starts and settings; :func:`design_map` on
    consecutive blocks of the y axis), padded to a common number of attractors."""
    if not chunks:
        _fail("chunks", [], "at least one chunk")
    y = chunks[0].attrs["y"]
    n_att = max(c.sizes["attractor"] for c in chunks)
    padded = []
    for c in chunks:
        extra = n_att - c.sizes["attractor"]
        if extra:
            c = c.pad(attractor=(0, extra))
            c["label"] = c["label"].fillna("").astype(str)
            for v in ("count", "period", "n_bottom", "n_top"):
                c[v] = c[v].fillna(0).astype(np.int64)
            if "settled" in c:
                c["settled"] = c["settled"].fillna(False).astype(bool)
        padded.append(c)
    out = xr.concat(padded, dim=y, data_vars="minimal", coords="minimal", compat="override",
                    combine_attrs="override")
    out.attrs["events"] = int(sum(int(c.attrs["events"]) for c in chunks))
    return annotate(summarise(out.drop_vars([v for v in SUMMARY if v in out])))


# ---------------------------------------------------------------------------------------------
# Tolerance: the box around each design, the lowest output over it and the nearest bifurcation curve
# ---------------------------------------------------------------------------------------------


def half_widths(axis: str, values, tolerance: dict) -> np.ndarray:
    """Half-widths of the tolerance box along ``axis`` at ``values``: relative for ``s`` and ``F``,
    absolute (radians) for ``beta``; 0 where the tolerance names no such axis."""
    tol = float(tolerance.get(axis, 0.0))
    values = np.asarray(values, dtype=float)
    return tol * np.abs(values) if axis in RELATIVE else np.full(values.shape, tol)


def box_minimum(field: np.ndarray, xs, ys, hx, hy):
    """Lowest value of ``field`` (on ``(ys, xs)``) over each point's box ``[x - hx, x + hx] x [y - hy, y + hy]``,
    from the grid points that bracket the box (the grid points inside it and the nearest outside on every
    side, so that a box narrower than a grid cell still sees its neighbours); NaN counts as the lowest.
    Also whether the box lies inside the grid (else the value covers only its part inside)."""
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    out = np.full(field.shape, np.nan)
    inside = np.zeros(field.shape, bool)
    for iy, y in enumerate(ys):
        for ix, x in enumerate(xs):
            wx, wy = hx[iy, ix], hy[iy, ix]
            x0 = max(int(np.searchsorted(xs, x - wx, side="right")) - 1, 0)
            x1 = min(int(np.searchsorted(xs, x + wx, side="left")), xs.size - 1)
            y0 = max(int(np.searchsorted(ys, y - wy, side="right")) - 1, 0)
            y1 = min(int(np.searchsorted(ys, y + wy, side="left")), ys.size - 1)
            block = field[y0:y1 + 1, x0:x1 + 1]
            out[iy, ix] = np.nan if np.isnan(block).any() else block.min()
            inside[iy, ix] = xs[0] <= x - wx and x + wx <= xs[-1] and ys[0] <= y - wy and y + wy <= ys[-1]
    return out, inside


def curve_margin(px, py, wx, wy, ax, ay, bx, by):
    """Distance from each point ``(px, py)`` to the nearest segment ``(ax, ay)-(bx, by)`` in units of the
    point's box: ``max(|dx| / wx, |dy| / wy)`` (the box scaled by the margin just touches the segment,
    so a segment crosses the box exactly when the margin is <= 1).  A zero half-width makes the box a
    segment: only where the curve crosses its line does it count.  Returns the margin and the index of
    the nearest segment (-1 where there is none)."""
    px, py, wx, wy = (np.asarray(a, float).ravel()[:, None] for a in (px, py, wx, wy))
    ax, ay, bx, by = (np.asarray(a, float).ravel()[None, :] for a in (ax, ay, bx, by))
    if ax.size == 0:
        return np.full(px.shape[0], np.inf), np.full(px.shape[0], -1)
    ex, ey = bx - ax, by - ay
    with np.errstate(divide="ignore", invalid="ignore"):
        ux0, uy0 = (ax - px) / wx, (ay - py) / wy
        uxs, uys = ex / wx, ey / wy
        cands = [np.zeros_like(ux0 + uy0), np.ones_like(ux0 + uy0), -(ax - px) / ex, -(ay - py) / ey,
                 (uy0 - ux0) / (uxs - uys), -(uy0 + ux0) / (uxs + uys)]
        best = np.full(np.broadcast_shapes(ux0.shape, uy0.shape), np.inf)
        for t in cands:
            t = np.clip(np.nan_to_num(t, nan=0.0, posinf=0.0, neginf=0.0), 0.0, 1.0)
            fx, fy = ax + t * ex - px, ay + t * ey - py
            # a zero half-width: the distance along it is 0 on the line and infinite off it
            dx = np.where(wx > 0, np.abs(fx) / np.where(wx > 0, wx, 1.0), np.where(fx == 0, 0.0, np.inf))
            dy = np.where(wy > 0, np.abs(fy) / np.where(wy > 0, wy, 1.0), np.where(fy == 0, 0.0, np.inf))
            best = np.minimum(best, np.maximum(dx, dy))
    idx = np.argmin(best, axis=1)
    return best[np.arange(best.shape[0]), idx], idx


def _segments(curves: xr.Dataset, xname: str, yname: str):
    """The admissible pieces of every curve as segments, with each segment's curve name."""
    seg, names = [], []
    x, y = curves[xname].values, curves[yname].values
    ci, adm = curves["curve_index"].values, curves["admissible"].values.astype(bool)
    for c in range(curves.sizes["curve"]):
        sel = np.flatnonzero(ci == c)
        if sel.size < 2:
            continue
        a, b = sel[:-1], sel[1:]
        ok = adm[a] & adm[b] & np.isfinite(x[a] + y[a] + x[b] + y[b])
        seg.append(np.stack([x[a][ok], y[a][ok], x[b][ok], y[b][ok]], axis=1))
        names += [f"{curves.curve_kind.values[c]} of {curves.curve_word.values[c]}"] * int(ok.sum())
    if not seg:
        return np.zeros((0, 4)), []
    return np.concatenate(seg), names


def _with_fixed(ds: xr.Dataset, axis: str, shape):
    """Values of ``axis`` at every grid point: the coordinate where it is one, else the fixed value."""
    if axis in ds.coords:
        return ds[axis].broadcast_like(ds["E_U_T"]).transpose(*ds["E_U_T"].dims).values
    return np.full(shape, float(ds.attrs[axis]))


def tolerance_analysis(ds: xr.Dataset, curves: xr.Dataset | None, tolerance: dict) -> xr.Dataset:
    """Add, per design point, how a manufacturing tolerance affects it.

    The box's half-widths: ``tolerance[axis]`` relative to the nominal value for ``s`` and ``F``, in
    radians for ``beta``; a quantity that is not an axis of the map is held fixed.

    Parameters
    ----------
    ds : xarray.Dataset
        A design map (:func:`~vibroimpact.design_map`).
    curves : xarray.Dataset or None
        The bifurcation curves of the same plane (:func:`~vibroimpact.curve_set`); ``None``: no margin.
    tolerance : dict
        Half-width of the box per axis (``s``, ``F``: relative; ``beta``: rad).

    Returns
    -------
    xarray.Dataset
        ``ds`` with the tolerance box's lowest ``E_U_T`` (``box_min_E_U_T``; ``box_in_grid`` where the box
        lies inside the grid), the ``margin`` to the nearest admissible bifurcation curve in units of the box
        (``nearest_curve`` names it) and ``robust`` (``margin > 1``).

    Examples
    --------
    A tolerance of 1 % on the length at the paper's incline, against the curves of the 2:1 grazing (G1,
    s = 0.22104 m) and the 3:1 fold (G2, s = 0.22804 m): at s = 0.23 m G2 lies within the box (margin
    below 1), at 0.2355 m three boxes away:

    >>> import math, vibroimpact as vi
    >>> dev = vi.Device()
    >>> b21 = vi.continue_orbit(vi.find_orbit(dev.params(0.2249, math.pi / 6), "BBT", 5.855, 0.4185),
    ...                         vary="s", d_range=(0.13, 0.16), step=2e-3)
    >>> b31 = vi.continue_orbit(vi.find_orbit(dev.params(0.2249, math.pi / 6), "BBBT", 5.88, 0.3967),
    ...                         vary="s", d_range=(0.13, 0.16), step=2e-3)
    >>> b21.attrs["status"] = b31.attrs["status"] = "ok"
    >>> curves = vi.curve_set([b21, b31], ("s", "beta"), ((0.2, 0.25), (0.5, 0.55)),
    ...                       kinds=("fold", "grazing"), step=1e-2, physics={"beta": math.pi / 6})
    >>> phi, v0 = vi.start_states(8, distribution="box", seed=0)
    >>> dm = vi.design_map("s", [0.2245, 0.23, 0.2355, 0.241], "beta", [math.pi / 6], phi=phi, v0=v0)
    >>> out = vi.tolerance_analysis(dm, curves, {"s": 0.01})
    >>> out.margin.values.round(2).tolist(), out.robust.values.tolist()
    ([[1.54, 0.85, 3.17, 5.38]], [[True, False, True, True]])
    >>> out.nearest_curve.values.tolist(), out.box_in_grid.values.tolist()
    ([['grazing of BBT', 'fold of BBBT', 'fold of BBBT', 'fold of BBBT']], [[False, True, True, False]])
    """
    ds = ds.copy()  # the caller's dataset is left as it was
    xname, yname = ds.attrs["x"], ds.attrs["y"]
    shape = ds["E_U_T"].shape
    X, Y = np.meshgrid(ds[xname].values, ds[yname].values, indexing="xy")
    hx, hy = half_widths(xname, X, tolerance), half_widths(yname, Y, tolerance)
    if not ((hx > 0) | (hy > 0)).all():
        _fail(f"tolerance on ({xname}, {yname})", {xname: tolerance.get(xname, 0), yname: tolerance.get(yname, 0)},
              "a tolerance > 0 on at least one axis (else the box is empty)")
    box_min, inside = box_minimum(ds["E_U_T"].values, ds[xname].values, ds[yname].values, hx, hy)
    if curves is not None and curves.attrs.get("params", "").split() == [xname, yname]:
        seg, names = _segments(curves, xname, yname)
        curve_attr = curves.attrs.get("kinds", "")
    elif curves is not None:
        _fail("bifurcation curves' plane", curves.attrs.get("params"), f"the design map's plane '{xname} {yname}'")
    else:
        seg, names, curve_attr = np.zeros((0, 4)), [], ""
    margin, idx = curve_margin(X, Y, hx, hy, *seg.T)
    nearest = np.array([names[i] if i >= 0 and np.isfinite(m) else "" for i, m in zip(idx, margin, strict=True)])
    dims = ds["E_U_T"].dims
    ds["box_min_E_U_T"] = (dims, box_min, {"units": "V", "long_name": "lowest E_U_T over the tolerance box "
                                           "(from the grid points bracketing it)"})
    ds["box_in_grid"] = (dims, inside, {"units": "1", "long_name": "the tolerance box lies inside the grid"})
    ds["margin"] = (dims, margin.reshape(shape), {"units": "1", "long_name": "distance to the nearest admissible "
                                                  "bifurcation curve in units of the tolerance box (> 1: robust)"})
    ds["nearest_curve"] = (dims, nearest.reshape(shape), {"units": "1", "long_name": "the nearest curve"})
    ds["robust"] = (dims, margin.reshape(shape) > 1.0, {"units": "1", "long_name": "no bifurcation curve "
                                                        "crosses the tolerance box"})
    ds.attrs.update({f"tolerance_{k}": float(v) for k, v in tolerance.items()}, curve_kinds=curve_attr)
    return annotate(ds)


def best_designs(ds: xr.Dataset, budget: dict, per: str | None = None) -> list[dict]:
    """The best robust design for each value of ``per``.

    The best: the largest lowest-``E_U_T`` over its box, robust, its box inside the grid, within
    ``budget``; beside it, the longest device within the budget at the same ``per`` (the sweeps' "longest
    is best") with its robustness.

    Parameters
    ----------
    ds : xarray.Dataset
        A design map after :func:`~vibroimpact.tolerance_analysis`.
    budget : dict
        Upper bounds per axis (e.g. ``{"s": 0.72, "F": 22.0}``).
    per : str, optional
        A coordinate of ``ds`` to choose per value of (e.g. ``"beta"``); ``None``: the whole map.

    Returns
    -------
    list of dict
        One per value of ``per`` (one for ``None``): the design's coordinates, ``d``, ``motion``, ``E_U_T``,
        ``worst_U_T``, ``box_min_E_U_T``, ``margin``, ``nearest_curve``, ``robust`` and ``found`` (False,
        with the coordinates held only, where no point qualifies); with ``per`` and ``s`` the map's x
        axis, ``longest``: the same description of the longest device within the budget.

    Examples
    --------
    On the map of :func:`~vibroimpact.tolerance_analysis`'s example, within a length budget of 0.24 m, the
    best robust design whose box lies inside the grid is s = 0.2355 m, on the 2:1 motion alone:

    >>> import math, vibroimpact as vi
    >>> p0, pi6 = vi.Device().params(0.2249, math.pi / 6), math.pi / 6    # the 2:1 and 3:1 branches, then
    >>> branches = [vi.continue_orbit(vi.find_orbit(p0, word, *start), vary="s", d_range=(0.13, 0.16), step=2e-3)
    ...             for word, start in (("BBT", (5.855, 0.4185)), ("BBBT", (5.88, 0.3967)))]
    >>> for br in branches:                                          # G1 and G2 in (s, beta)
    ...     br.attrs["status"] = "ok"
    >>> curves = vi.curve_set(branches, ("s", "beta"), ((0.2, 0.25), (0.5, 0.55)), kinds=("fold", "grazing"),
    ...                       step=1e-2, physics={"beta": pi6})
    >>> phi, v0 = vi.start_states(8, distribution="box", seed=0)
    >>> dm = vi.design_map("s", [0.2245, 0.23, 0.2355, 0.241], "beta", [pi6], phi=phi, v0=v0)
    >>> best = vi.best_designs(vi.tolerance_analysis(dm, curves, {"s": 0.01}), {"s": 0.24}, per="beta")
    >>> [(b["found"], b["s"], b["motion"], round(b["margin"], 2)) for b in best]
    [(True, 0.2355, '2:1 period-2 (100%)', 3.17)]
    >>> best[0]["longest"]["s"]
    0.2355
    """
    xname, yname = ds.attrs["x"], ds.attrs["y"]
    shape = ds["E_U_T"].shape
    vals = {a: _with_fixed(ds, a, shape) for a in DESIGN_AXES}
    ok_budget = np.ones(shape, bool)
    for a, hi in budget.items():
        ok_budget &= vals[a] <= hi * (1 + 1e-12)
    rows_of = [np.arange(shape[0])] if per is None else [[i] for i in range(shape[0])] if per == yname else None
    if rows_of is None:
        _fail("per", per, f"None or the map's y axis {yname!r}")
    out = []
    for rows in rows_of:
        mask = np.zeros(shape, bool)
        mask[rows, :] = True
        cand = mask & ok_budget & ds["robust"].values & ds["box_in_grid"].values & np.isfinite(ds["box_min_E_U_T"].values)
        row = {a: float(vals[a][rows[0], 0]) for a in DESIGN_AXES if a not in (xname,) and (per or a != yname)}
        if cand.any():
            score = np.where(cand, ds["box_min_E_U_T"].values, -np.inf)
            iy, ix = np.unravel_index(np.argmax(score), shape)
            row.update(_describe(ds, iy, ix, vals), found=True)
        else:
            row.update(found=False)
        # the longest device within the budget (in the same row, at the largest x within budget)
        within = np.flatnonzero((mask & ok_budget)[rows[0]]) if per else np.array([])
        if within.size and xname == "s":
            jx = int(within[-1])
            row["longest"] = _describe(ds, rows[0], jx, vals)
        out.append(row)
    return out


def _describe(ds, iy, ix, vals):
    at = ds.isel({ds.attrs["y"]: iy, ds.attrs["x"]: ix})
    shares = at["share"].values
    motions = [f"{lab} ({sh:.0%})" for lab, sh in zip(at["label"].values, shares, strict=True)
               if lab and sh >= ds.attrs["min_share"]]
    return {**{a: float(vals[a][iy, ix]) for a in DESIGN_AXES}, "d": float(at["d"]), "motion": ", ".join(motions),
            "E_U_T": float(at["E_U_T"]), "worst_U_T": float(at["worst_U_T"]), "box_min_E_U_T": float(at["box_min_E_U_T"]),
            "margin": float(at["margin"]), "nearest_curve": str(at["nearest_curve"].values), "robust": bool(at["robust"])}


def table_designs(ds: xr.Dataset, budget: dict, table_betas) -> list[dict]:
    """:func:`best_designs` for the design table and figure: per incline of ``table_betas`` on a beta
    axis (each has its own row, :func:`grid_axes`), over the whole map otherwise."""
    if ds.attrs["y"] != "beta":
        return best_designs(ds, budget)
    return [b for b in best_designs(ds, budget, per="beta")
            if any(math.isclose(b["beta"], t, rel_tol=0.0, abs_tol=1e-12) for t in table_betas)]
