"""Numerical bifurcation sweeps: attractors along a parameter, located transitions, bistability,
basins of attraction and regime maps (paper Figs 0, 2, BiS, 5: the numerical points).

Every run starts with a bottom impact (paper convention) and stops as soon as its motion repeats
(:func:`vibroimpact.dynamics.kernels.run_window`), or after ``max_periods`` forcing periods, in which case the
motion is classed ``"no period found"`` (not periodic within the allowed time).  A sweep follows the
attractor: each point starts from the last bottom impact of the previous point's attractor, so
the up and down sweeps show hysteresis.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .._progress import Progress, interactive
from ..datasets import annotate
from ..dynamics import kernels as K
from ..dynamics.device import PAPER, Device
from ..dynamics.params import Params
from ..dynamics.simulate import cycle_class

__all__ = ["parameter_grid", "attractor_batch", "sweep", "settle", "locate_transitions", "bistable_intervals",
           "basins", "regime_map", "plane_params", "split_no_period", "no_period", "no_period_label", "APERIODIC",
           "CHAOTIC", "QUASI_PERIODIC", "UNSETTLED", "NO_PERIOD_LABELS"]

#: Label of a run whose motion did not repeat within the allowed transient: chaotic, quasi-periodic,
#: of a period longer than ``pmax`` events, or converging too slowly (near a period doubling or fold).
APERIODIC = "no period found"
#: What such a motion is, by the largest Lyapunov exponent lambda_1 of its continuation over
#: ``LONG_IMPACTS`` impacts (:func:`split_no_period`); defined here once, for the sweeps, the maps, the
#: tables and the figures.  Chaotic: the interval of lambda_1 lies above 0.
CHAOTIC = "chaotic"
#: The interval of lambda_1 contains 0: neighbouring motions neither separate nor approach at a rate the
#: continuation can tell from 0 (a torus, or a period beyond the cap's reach, or the edge of chaos).
QUASI_PERIODIC = "quasi-periodic"
#: Neither: the interval lies below 0 (the motion converges, more slowly than the cap allows), or the
#: continuation finds a period, sticks (a motion that sticks again and again is eventually periodic: each
#: release starts from the same state) or comes to rest: a transient longer than the cap.
UNSETTLED = "unsettled"
#: every label of a motion without a period within the cap ("no period found" where it was not split)
NO_PERIOD_LABELS = (APERIODIC, CHAOTIC, QUASI_PERIODIC, UNSETTLED)


def no_period(labels):
    """Where a label (or array of labels) is one of a motion with no period within the cap."""
    return np.isin(np.asarray(labels).astype(str), NO_PERIOD_LABELS)


def no_period_label(long_status: str, low: float, high: float, sticks: int = 0) -> str:
    """The label of a motion with no period from its continuation (:func:`vibroimpact.long_run`): its status
    and the confidence interval ``[low, high]`` of its largest Lyapunov exponent.  Without a
    continuation (``"not run"``, ``"no restart"``) it stays :data:`APERIODIC`."""
    if long_status in ("settles", "stuck"):
        return UNSETTLED
    if long_status != "aperiodic" or not (np.isfinite(low) and np.isfinite(high)):
        return APERIODIC
    if sticks:
        return UNSETTLED
    if low > 0:
        return CHAOTIC
    if high < 0:
        return UNSETTLED
    return QUASI_PERIODIC


def split_no_period(d, gbar, r, phi, v0, *, impacts: int | None = None, tol: float = 1e-9) -> dict:
    """Continue a motion with no period from a bottom impact ``(phi, v0)`` (e.g. the last of its window)
    and say what it is: ``label`` (:func:`no_period_label`), ``status`` of the continuation, its largest
    Lyapunov exponent ``lyap1`` per impact with the interval ``lyap1_low``, ``lyap1_high``, and per unit
    time ``lyap1_time``, and the continuation itself (``run``, :func:`vibroimpact.long_run`'s dict)."""
    from .settled import LONG_IMPACTS, long_run

    run = long_run(d, gbar, r, phi, v0, impacts=LONG_IMPACTS if impacts is None else int(impacts), tol=tol)
    lam = run["exponents"]
    nan = float("nan")
    lyap = (lam.per_impact[0], *lam.interval[0], lam.per_time[0]) if lam is not None else (nan,) * 4
    label = no_period_label(run["status"], lyap[1], lyap[2], lam.sticks if lam is not None else 0)
    return dict(label=label, status=run["status"], lyap1=lyap[0], lyap1_low=lyap[1], lyap1_high=lyap[2],
                lyap1_time=lyap[3], run=run)
_EVENT_VARS = ("t", "wall", "v_minus", "phase", "kind")


#: the values a plane, sweep or map holds where they are not its axis (a length for a force sweep, ...)
HELD = ("s", "F", "beta")


def held_values(device: Device | None, physical: dict) -> tuple[Device, dict]:
    """The device and the held values (``s``, ``F``, ``beta``; ``r`` changes the device's restitution) of a
    sweep, map or plane.  The cylinder's mass, the forcing frequency and gravity belong to the device: passing
    them alone is refused, naming the way to another device."""
    device = PAPER if device is None else device
    extra = sorted(set(physical) - {*HELD, "r"})
    if extra:
        raise ValueError(f"{', '.join(extra)} = {[physical[k] for k in extra]!r}: a property of the device; allowed: "
                         f"device=vi.Device().replace({extra[0]}=...) (held values: {', '.join(HELD)}, and r)")
    if "r" in physical:
        device = device.replace(r=float(physical["r"]))
    return device, {k: physical[k] for k in HELD if k in physical}


def parameter_grid(vary: str, values, *, beta: float, device: Device | None = None, s: float = 0.85,
                   F: float | None = None):
    """``(d, gbar, s, F)`` arrays for a sweep of the length ``s`` (``vary="s"``, at the forcing ``F``,
    default the device's) or of the force ``F`` (``vary="F"``, at the length ``s``) of a ``device``
    (default the paper's, ``Device()``); every value is validated through :class:`Params`."""
    if vary not in ("s", "F"):
        raise ValueError(f"vary = {vary!r}; allowed: 's' (length at fixed force) or 'F' (force at fixed length)")
    device = PAPER if device is None else device
    F = device.F if F is None else F
    values = np.atleast_1d(np.asarray(values, dtype=float))
    ps = [device.params(s=v if vary == "s" else s, beta=beta, F=v if vary == "F" else F) for v in values]
    d = np.array([p.d for p in ps])
    gbar = np.array([p.gbar for p in ps])
    s_arr = values if vary == "s" else np.full(values.shape, float(s))
    F_arr = values if vary == "F" else np.full(values.shape, float(F))
    return d, gbar, s_arr, F_arr


def _classify(win, n, status, lag):
    """Label of one run from its window of the last ``n`` events (a period is identified only after
    three periods of events, so a periodic window holds more than one period)."""
    if status != K.PERIODIC or lag == 0 or lag >= n:
        return 0, 0, 0, APERIODIC
    t, wall, kind = win[0], win[1], win[4]
    k, nb, nt, _, label = cycle_class(wall[n - lag:n], kind[n - lag:n], float(t[n - 1] - t[n - 1 - lag]))
    return k, nb, nt, label


def _check_window(window, pmax):
    """A period of ``p`` events is identified from the window only if it holds more than ``p``."""
    if int(pmax) < 1:
        raise ValueError(f"pmax = {pmax!r}; allowed: an integer >= 1")
    if int(window) < int(pmax) + 1:
        raise ValueError(f"window = {window!r}; allowed: >= pmax + 1 = {int(pmax) + 1} (pmax = {pmax!r})")


def attractor_batch(d, gbar, r, phi, v0, *, max_periods: float = 200, max_events: int = 200_000,
                    tol: float = 1e-9, window: int = 65, pmax: int = 64, progress: bool | None = None,
                    desc: str = "attractors") -> xr.Dataset:
    """Attractors of many runs in parallel: the last ``window`` events and the motion's class.

    Parameters
    ----------
    d, gbar, r, phi, v0 : array_like
        Each run's parameters and first bottom impact (phase, pre-impact velocity); broadcast to one
        dimension ``run``.
    max_periods : float
        Longest transient, in forcing periods, before a run is called aperiodic.
    max_events : int
        Cap on events per run.
    tol : float
        Periodicity tolerance.
    window : int
        Events kept per run (``>= pmax + 1``).
    pmax : int
        Longest period looked for, in events.
    progress : bool, optional
        A bar (the runs then go in tenths, each in parallel, with the same results).
    desc : str
        The bar's name.

    Returns
    -------
    xarray.Dataset
        ``t, wall, v_minus, phase, kind`` on ``(run, event)`` (NaN-padded), and per run ``label``,
        ``period`` (forcing periods, 0 when aperiodic), ``period_events``, ``n_bottom``, ``n_top``,
        ``n_events`` (simulated) and ``status``.

    Examples
    --------
    At d = 0.13975 on the paper's incline pi/6 (between G1 and G2) two starts reach the two coexisting
    motions, the 2:1 (two bottom impacts, one top) and the 3:1 (three bottom, one top):

    >>> import vibroimpact as vi
    >>> ab = vi.attractor_batch(0.13975, 0.12201, 0.5, phi=[5.855, 1.645], v0=[0.4185, 0.05067])
    >>> ab.label.values.tolist(), ab.n_bottom.values.tolist(), ab.n_top.values.tolist()
    (['2:1 period-2', '3:1 period-2'], [2, 3], [1, 1])
    >>> ab.period.values.tolist(), ab.period_events.values.tolist()    # one forcing period each
    ([1, 1], [3, 4])
    """
    _check_window(window, pmax)
    arrs = np.broadcast_arrays(*(np.atleast_1d(np.asarray(a, dtype=float)) for a in (d, gbar, r, phi, v0)))
    d, gbar, r, phi, v0 = (np.ascontiguousarray(a.ravel()) for a in arrs)
    m = d.shape[0]
    win = [np.full((m, window), np.nan), np.zeros((m, window), np.int8), np.full((m, window), np.nan),
           np.full((m, window), np.nan), np.zeros((m, window), np.int8)]
    st = np.zeros(m, np.int8)
    lag = np.zeros(m, np.int64)
    tot = np.zeros(m, np.int64)
    nw = np.zeros(m, np.int64)
    phi = phi % (2 * np.pi)
    shown = interactive() if progress is None else bool(progress)
    # in one parallel call unless a bar is shown: then in tenths (each run is independent of the others)
    cuts = np.linspace(0, m, 11 if shown and m >= 20 else 2).astype(int)
    with Progress(m, desc, shown, unit="run") as bar:
        for a, b in zip(cuts[:-1], cuts[1:], strict=True):
            K.window_batch(d[a:b], gbar[a:b], r[a:b], phi[a:b], v0[a:b], int(max_events), 2.0 * float(max_periods),
                           1e-9, float(tol), int(pmax), max(4096, 4 * (3 * pmax + 1)), *(w[a:b] for w in win),
                           st[a:b], lag[a:b], tot[a:b], nw[a:b])
            bar.update(int(b - a))
    return _window_dataset(win, st, lag, tot, nw, dims=("run",))


def _window_dataset(win, st, lag, tot, nw, dims):
    shape = st.shape
    labels = np.empty(shape, dtype=object)
    per = np.zeros(shape, np.int64)
    nb = np.zeros(shape, np.int64)
    nt = np.zeros(shape, np.int64)
    flat = [w.reshape(-1, w.shape[-1]) for w in win]
    for idx in range(int(np.prod(shape))):
        n = int(nw.flat[idx])
        rows = [f[idx, :n] for f in flat]  # the real events lead the window, NaN-padded after
        k, b, t_, lab = _classify(rows, n, int(st.flat[idx]), int(lag.flat[idx]))
        per.flat[idx], nb.flat[idx], nt.flat[idx], labels.flat[idx] = k, b, t_, lab
    edims = (*dims, "event")
    ds = xr.Dataset(
        {name: (edims, w) for name, w in zip(_EVENT_VARS, win, strict=True)}
        | {
            "label": (dims, labels.astype(str)),
            "period": (dims, per, {"units": "1", "long_name": "period of the attractor in forcing periods (0: no period found)"}),
            "period_events": (dims, np.where(st == K.PERIODIC, lag, 0),
                              {"units": "1", "long_name": "events per period of the attractor"}),
            "n_bottom": (dims, nb, {"units": "1", "long_name": "impacts on the bottom wall per period"}),
            "n_top": (dims, nt, {"units": "1", "long_name": "impacts on the top wall per period"}),
            "n_events": (dims, tot, {"units": "1", "long_name": "events simulated until identified or stopped"}),
            "status": (dims, st, {"units": "1", "long_name": "run status",
                                  "flag_values": np.arange(len(K.STATUS_NAMES), dtype=np.int8),
                                  "flag_meanings": " ".join(K.STATUS_NAMES)}),
        }
    )
    ds["label"].attrs.update(units="1", long_name="attractor: n:m impacts per period and period, or aperiodic")
    ds["kind"].attrs.update(flag_values=np.arange(len(K.KIND_NAMES), dtype=np.int8),
                            flag_meanings=" ".join(K.KIND_NAMES))
    return annotate(ds)


def settle(ds: xr.Dataset, d, gbar, r, *, long_impacts: int | None = None, tol: float = 1e-9) -> xr.Dataset:
    """Add what is well-posed about each attractor of a window dataset (a sweep's or
    :func:`attractor_batch`'s): the exact cycle of a periodic one, the long-run statistics of an
    aperiodic one (:mod:`vibroimpact.analysis.settled`), and the largest Lyapunov exponent of each.

    ``d``, ``gbar``, ``r`` broadcast to the dataset's per-run shape.  Added, per run: ``settled`` and
    ``settle_status``; ``cycle_t``, ``cycle_wall``, ``cycle_v_minus``, ``cycle_phase``, ``cycle_kind``
    on a ``cycle`` dimension (the Newton-solved orbit from its canonical first impact, or the recorded
    cycle where it is not settled; NaN-padded); for runs with no period, ``long_status``, the restart
    ``long_phi``, ``long_v0`` (the window's last bottom impact) and ``abs_v_mean``, ``abs_v_se`` (batch
    means of ``|Zdot-|`` over ``long_impacts`` impacts; ``long_impacts = 0`` skips the long runs), and
    their ``label`` split into :data:`CHAOTIC`, :data:`QUASI_PERIODIC` and :data:`UNSETTLED`
    (:func:`no_period_label`); for every run ``lyap1`` (per impact) with its interval ``lyap1_low``,
    ``lyap1_high``, ``lyap1_time`` (per unit time) and ``lyap1_source``: the multipliers of the
    Newton-solved cycle (exact, ``ln max|mu| / N``), ``-inf`` for a sticking cycle (its map is constant)
    or a ball at rest, else the long run's tangent estimate (:func:`vibroimpact.lyapunov`).
    """
    from .lyapunov import exponents_of_run, multiplier_sensitivity
    from .settled import LONG_BATCHES, LONG_IMPACTS, long_statistics, polish_cycle

    long_impacts = LONG_IMPACTS if long_impacts is None else int(long_impacts)
    shape = ds["status"].shape
    d, gbar, r = (np.broadcast_to(np.asarray(a, dtype=float), shape) for a in (d, gbar, r))
    lags = ds["period_events"].values
    width = max(int(lags.max()) if lags.size else 1, 1)
    cyc = {v: np.full((*shape, width), np.nan) for v in ("t", "v_minus", "phase")}
    cyc |= {v: np.zeros((*shape, width), np.int8) for v in ("wall", "kind")}
    settled = np.zeros(shape, bool)
    status = np.empty(shape, dtype=object)
    long_status = np.full(shape, "", dtype=object)
    long_start = np.full((*shape, 2), np.nan)
    stats = np.full((*shape, 2), np.nan)
    lyap = np.full((*shape, 4), np.nan)  # lambda_1 per impact, its interval, per unit time
    sens = np.full(shape, np.nan)  # of an exact lambda_1: its sensitivity to the monodromy matrix's entries
    source = np.full(shape, "", dtype=object)
    labels = ds["label"].values.astype(object)
    ev = {v: ds[v].values for v in _EVENT_VARS}
    n_real = np.isfinite(ev["t"]).sum(axis=-1)
    for idx in np.ndindex(shape):
        n, lag = int(n_real[idx]), int(lags[idx])
        rows = {v: ev[v][idx][:n] for v in _EVENT_VARS}
        start = last_bottom_impact(*(rows[v] for v in _EVENT_VARS), n)
        if lag and n > lag:
            span = rows["t"][n - 1] - rows["t"][n - 1 - lag]
            res = polish_cycle(d[idx], gbar[idx], r[idx], *(rows[v][n - lag:n] for v in _EVENT_VARS), span=span)
            for v in cyc:
                cyc[v][idx][:lag] = res[v]
            settled[idx], status[idx] = res["settled"], res["status"]
            if res["settled"]:  # exact: the multipliers of the Newton-solved cycle
                top = float(np.log(np.abs(res["multipliers"]).max()))
                lyap[idx] = (top / lag, top / lag, top / lag, top / (2.0 * round(span / 2.0)))
                sens[idx] = multiplier_sensitivity(res["step_jacobians"]) / lag
                source[idx] = "multipliers of the Newton-solved cycle"
            elif res["status"] == "sticking":
                lyap[idx] = -np.inf
                source[idx] = "sticking cycle: its map over a period is constant (multipliers 0)"
            elif start is not None and long_impacts:  # periodic, not solved: the tangent estimate of a run
                from ..dynamics.simulate import simulate

                run = simulate(Params(d=float(d[idx]), gbar=float(gbar[idx]), r=float(r[idx])), *start,
                               n_impacts=long_impacts)
                lam = exponents_of_run(run, transient=long_impacts // 10, batches=LONG_BATCHES)
                lyap[idx] = (lam.per_impact[0], *lam.interval[0], lam.per_time[0])
                source[idx] = f"long run of {long_impacts} impacts ({res['status']})"
            else:
                source[idx] = f"not estimated: the cycle is not solved ({res['status']}) and no long run " + (
                    "(long_impacts = 0)" if not long_impacts else "(no bottom impact to restart from)")
            continue
        if int(ds["status"].values[idx]) == K.STUCK_FOREVER:  # at rest on the bottom for good: exact
            settled[idx], status[idx], long_status[idx] = True, "stuck", "stuck"
            lyap[idx] = -np.inf
            source[idx] = "at rest on the bottom for good"
            continue
        status[idx] = "aperiodic"
        if start is None or not long_impacts:
            long_status[idx] = "no restart" if start is None else "not run"
            source[idx] = ("not estimated: no bottom impact in the window to restart a long run from" if start is None
                           else "not estimated: no long run (long_impacts = 0)")
            continue
        long_start[idx] = start
        split = split_no_period(d[idx], gbar[idx], r[idx], *start, impacts=long_impacts, tol=tol)
        long_status[idx] = split["status"]
        labels[idx] = split["label"]
        stats[idx] = long_statistics(split["run"], LONG_BATCHES)
        lyap[idx] = (split["lyap1"], split["lyap1_low"], split["lyap1_high"], split["lyap1_time"])
        source[idx] = f"long run of {long_impacts} impacts" + {
            "aperiodic": "", "settles": " (it settles: the estimate over the orbit it settles on)",
            "stuck": " (it comes to rest for good)"}.get(split["status"], f" ({split['status']})")
        if split["status"] == "stuck":  # at rest on the bottom for good: exact
            lyap[idx] = -np.inf
    edims = (*ds["status"].dims, "cycle")
    pdims = ds["status"].dims
    ds["label"] = (pdims, labels.astype(str), ds["label"].attrs | {
        "long_name": "motion: n:m impacts per period and period, or (no period within the cap) chaotic, "
                     "quasi-periodic or unsettled by the largest Lyapunov exponent of its long run"})
    ds["settled"] = (pdims, settled, {"units": "1", "long_name": "the attractor's values are well-posed: a Newton-solved or sticking (exact) cycle"})
    ds["settle_status"] = (pdims, status.astype(str), {"units": "1", "long_name": "how the cycle was settled, or why not"})
    names = {"t": ("time from the cycle's canonical first event", "1"), "wall": ("wall (1 bottom, -1 top)", "1"),
             "v_minus": ("pre-impact velocity Zdot-", "1"), "phase": ("forcing phase", "rad"), "kind": ("event kind", "1")}
    for v, (text, unit) in names.items():
        ds[f"cycle_{v}"] = (edims, cyc[v], {"units": unit, "long_name": f"attractor cycle (exact where settled): {text}"})
    ds["long_status"] = (pdims, long_status.astype(str), {"units": "1", "long_name": "long run of a motion with no period: aperiodic, settles (a longer transient), stuck"})
    ds["long_phi"] = (pdims, long_start[..., 0], {"units": "rad", "long_name": "long run: phase of its first bottom impact"})
    ds["long_v0"] = (pdims, long_start[..., 1], {"units": "1", "long_name": "long run: pre-impact velocity of its first bottom impact"})
    ds["abs_v_mean"] = (pdims, stats[..., 0], {"units": "1", "long_name": "long run: mean |Zdot-| over its impacts (batch means)"})
    ds["abs_v_se"] = (pdims, stats[..., 1], {"units": "1", "long_name": "long run: standard error of abs_v_mean (batch means)"})
    level = "95 % confidence interval (batch means over the long run; the exact value twice for a solved cycle)"
    ds["lyap1"] = (pdims, lyap[..., 0], {"units": "1", "long_name": "largest Lyapunov exponent lambda_1, per impact"})
    ds["lyap1_low"] = (pdims, lyap[..., 1], {"units": "1", "long_name": f"lambda_1 per impact: lower end of its {level}"})
    ds["lyap1_high"] = (pdims, lyap[..., 2], {"units": "1", "long_name": f"lambda_1 per impact: upper end of its {level}"})
    ds["lyap1_time"] = (pdims, lyap[..., 3], {"units": "1", "long_name": "largest Lyapunov exponent lambda_1, per unit of non-dimensional time"})
    ds["lyap1_sensitivity"] = (pdims, sens, {"units": "1", "long_name": "exact lambda_1 (a solved cycle): its change per unit of relative perturbation of the monodromy matrix's entries (componentwise condition of the largest multiplier, over the period's impacts)"})
    ds["lyap1_source"] = (pdims, source.astype(str), {"units": "1", "long_name": "how lambda_1 was obtained"})
    ds.attrs.update(long_impacts=long_impacts, long_batches=LONG_BATCHES)
    return ds


def last_bottom_impact(win_t, win_wall, win_vm, win_phase, win_kind, n):
    """Phase and pre-impact speed of the last bottom impact among a window's first ``n`` events (a start on
    the same motion), or None where the window holds none."""
    for j in range(n - 1, -1, -1):
        if win_wall[j] == 1 and win_kind[j] == K.IMPACT and win_vm[j] > 0:
            return float(win_phase[j]), float(win_vm[j])
    return None


def _run_one(d, gbar, r, phi, v0, max_periods, max_events, tol, window, pmax):
    win = [np.full(window, np.nan), np.zeros(window, np.int8), np.full(window, np.nan),
           np.full(window, np.nan), np.zeros(window, np.int8)]
    st, lag, tot, n = K.run_window(d, gbar, r, phi % (2 * np.pi), v0, int(max_events), 2.0 * float(max_periods),
                                   1e-9, float(tol), int(pmax), max(4096, 4 * (3 * pmax + 1)), *win)
    return win, st, lag, tot, n


def sweep(vary: str, values, *, beta: float, phi: float = 0.0, v0: float = 0.5, max_periods: float = 200,
          max_events: int = 200_000, tol: float = 1e-9, window: int = 65, pmax: int = 64,
          progress: bool | None = None, long_impacts: int | None = None, device: Device | None = None,
          **held) -> xr.Dataset:
    """Sweep ``s`` (fixed force) or ``F`` (fixed length) up and down, following the attractor.

    Parameters
    ----------
    vary : {"s", "F"}
        Swept physical parameter.
    values : array_like
        Its values (m or N; any order: the points are sorted by ``d``).
    beta : float
        Incline (rad).
    phi, v0 : float
        First point's start: a bottom impact at phase ``phi`` with pre-impact velocity ``v0``.
    max_periods : float
        Longest transient, in forcing periods, before a point is called aperiodic.
    max_events, tol, window, pmax : int, float, int, int
        Cap on events per point, periodicity tolerance, events kept per point, longest period
        (in events) looked for; ``window >= pmax + 1``.
    progress : bool, optional
        A progress bar (default: only when run interactively, :mod:`vibroimpact._progress`).
    long_impacts : int, optional
        Impacts of the long run of every point with no period (:func:`settle`; default
        :data:`vibroimpact.analysis.settled.LONG_IMPACTS`, 0: none).
    device : Device, optional
        The harvester (default the paper's, ``Device()``): its mass, forcing, gravity and restitution.
    **held
        The fixed ``s`` (m, of a force sweep; 0.85 by default) or ``F`` (N, of a length sweep; the device's
        by default), and ``r`` to change the device's restitution.

    Returns
    -------
    xarray.Dataset
        Dimensions ``direction`` (``"up"``: d increasing, ``"down"``), ``point`` (coordinate ``d``,
        increasing, with ``s``, ``F``, ``gbar``) and ``event`` (the last ``window`` events of each
        attractor); per point ``label``, ``period``, ``period_events``, ``n_bottom``, ``n_top``,
        ``n_events``, ``status`` and the start used (``start_phi``, ``start_v0``); and what is
        well-posed about each attractor (:func:`settle`): ``settled`` and ``settle_status``, its exact
        cycle on dimension ``cycle`` (``cycle_t``, ``cycle_wall``, ``cycle_v_minus``, ``cycle_phase``,
        ``cycle_kind``), or the long-run statistics of a motion with no period (``long_status``,
        ``long_phi``, ``long_v0``, ``abs_v_mean``, ``abs_v_se``); the largest Lyapunov exponent
        ``lyap1`` with ``lyap1_low``, ``lyap1_high``, ``lyap1_time``, ``lyap1_sensitivity`` and
        ``lyap1_source``.  Attributes: the settings and the device.

    Examples
    --------
    At the paper's incline pi/6 the 3:1 and 2:1 motions coexist between G1 (d = 0.1376, the 2:1 orbit
    grazes) and G2 (d = 0.1420, the 3:1 orbit folds) (Fig BiS).  Below G1 both sweeps end on the 3:1 motion
    and above G2 on the 2:1; at d = 0.13975, between them, the up sweep keeps the 3:1 motion and the down
    sweep the 2:1:

    >>> import math, vibroimpact as vi
    >>> sw = vi.sweep("s", [0.219, 0.2245, 0.23], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=0)
    >>> sw.d.values.round(5).tolist()
    [0.13633, 0.13975, 0.14318]
    >>> sw.label.values.tolist()     # up, then down
    [['3:1 period-2', '3:1 period-2', '2:1 period-2'], ['3:1 period-2', '2:1 period-2', '2:1 period-2']]
    """
    _check_window(window, pmax)
    device, held = held_values(device, held)
    held.pop("beta", None)
    d, gbar, s_arr, F_arr = parameter_grid(vary, values, beta=beta, device=device, **held)
    order = np.argsort(d)
    d, gbar, s_arr, F_arr = d[order], gbar[order], s_arr[order], F_arr[order]
    r = device.r
    m = d.shape[0]
    win = [np.full((2, m, window), np.nan), np.zeros((2, m, window), np.int8), np.full((2, m, window), np.nan),
           np.full((2, m, window), np.nan), np.zeros((2, m, window), np.int8)]
    st = np.zeros((2, m), np.int8)
    lag = np.zeros((2, m), np.int64)
    tot = np.zeros((2, m), np.int64)
    nw = np.zeros((2, m), np.int64)
    starts = np.zeros((2, m, 2))
    bar = Progress(2 * m, f"sweep of {vary} (up and down)", progress, unit="point")
    for k_dir, idx in enumerate((range(m), range(m - 1, -1, -1))):
        start = (phi, v0)
        for i in idx:
            bar.update()
            w1, st[k_dir, i], lag[k_dir, i], tot[k_dir, i], nw[k_dir, i] = _run_one(
                d[i], gbar[i], r, start[0], start[1], max_periods, max_events, tol, window, pmax)
            starts[k_dir, i] = start
            for arr, w in zip(win, w1, strict=True):
                arr[k_dir, i] = w
            nxt = last_bottom_impact(*w1, int(nw[k_dir, i]))
            if nxt is not None:
                start = nxt
    bar.close()
    ds = _window_dataset(win, st, lag, tot, nw, dims=("direction", "point"))
    ds = settle(ds, d[None, :], gbar[None, :], r, long_impacts=long_impacts, tol=tol)
    ds = ds.assign_coords(direction=["up", "down"], point=np.arange(m), d=("point", d), gbar=("point", gbar),
                          s=("point", s_arr), F=("point", F_arr))
    ds["start_phi"] = (("direction", "point"), starts[..., 0], {"units": "rad", "long_name": "phase of the start impact"})
    ds["start_v0"] = (("direction", "point"), starts[..., 1], {"units": "1", "long_name": "pre-impact velocity of the start impact"})
    ds["s"].attrs.update(units="m", long_name="cylinder length s")
    ds["F"].attrs.update(units="N", long_name="forcing amplitude ||F||")
    ds.attrs.update(vary=vary, beta=beta, r=r, max_periods=max_periods, tol=tol, window=int(window), pmax=int(pmax),
                    first_phi=phi, first_v0=v0, **held, **device.attrs())
    return annotate(ds)


# ---------------------------------------------------------------------------------------------
# Transitions and bistability
# ---------------------------------------------------------------------------------------------


def _ratio(label):
    """(n, m, period) of a periodic label like '2:1 period-2', else None."""
    if label in NO_PERIOD_LABELS or "over" in label or "sticking" in label:
        return None
    nm, per = label.split(" period-")
    n, m = nm.split(":")
    return int(n), int(m), int(per)


def transition_kind(before: str, after: str) -> str:
    """Name the change of motion from ``before`` to ``after`` (in the sweep's direction)."""
    if before in NO_PERIOD_LABELS and after in NO_PERIOD_LABELS:
        return "none"
    if after in NO_PERIOD_LABELS:
        return f"period lost ({after})"
    if before in NO_PERIOD_LABELS:
        return "period found"
    a, b = _ratio(before), _ratio(after)
    if a is None or b is None:
        return "other"
    if a[:2] == b[:2]:
        if b[2] == 2 * a[2]:
            return "period doubling"
        if a[2] == 2 * b[2]:
            return "period halving"
        return "period change"
    if a[2] == b[2]:
        if b[0] > a[0] and b[1] == a[1]:
            return "grazing: extra bottom impact"
        if b[0] < a[0] and b[1] == a[1]:
            return "bottom impact lost"
        if b[1] > a[1] and b[0] == a[0]:
            return "grazing: extra top impact"
        if b[1] < a[1] and b[0] == a[0]:
            return "top impact lost"
    return "other"


def locate_transitions(sw: xr.Dataset, *, xtol: float = 1e-7, max_periods: float = 20_000,
                       max_events: int = 2_000_000, max_trials: int = 200,
                       progress: bool | None = None) -> xr.Dataset:
    """Locate where each direction's followed attractor changes, to ``xtol`` in d.

    The changes are looked for between neighbouring points of the sweep whose motions differ.

    From the point before the change the attractor is followed in the sweep's direction, each run
    starting from the previous attractor, with a step that doubles (up to the grid step) after a
    run keeping the motion and halves after one losing it, until the step is below ``xtol`` or
    ``max_trials`` runs were made.  Unlike bisection inside the grid interval, this can pass the next
    grid point: near a grazing point the basin of the followed motion is thin, and a whole grid step
    can throw the run onto the other motion before the motion itself ends.  The longer transient
    (``max_periods``) is for the slow convergence near folds and period doublings.

    Parameters
    ----------
    sw : xarray.Dataset
        A sweep from :func:`sweep`.
    xtol : float
        Target width of the bracket in d.
    max_periods, max_events : float, int
        Longest transient per run (forcing periods) and cap on its events.
    max_trials : int
        Runs allowed per transition.
    progress : bool, optional
        A progress bar over the sweep's points (default: only when run interactively).

    Returns
    -------
    xarray.Dataset
        Along ``transition``: ``direction``, ``d`` (middle of the final bracket), ``d_width`` (its
        width), ``before``/``after`` labels, ``kind`` and ``status`` (``"refined"``, or why the
        bracket could not be narrowed to ``xtol``: such a point is kept, with its width).  Attributes:
        ``beta``, ``xtol`` and ``max_periods``.

    Examples
    --------
    The sweep of :func:`sweep`'s example loses the 3:1 motion going up at G2 (d = 0.14195, its fold) and
    the 2:1 motion going down at G1 (d = 0.1376, where it grazes the bottom wall):

    >>> import math, vibroimpact as vi
    >>> sw = vi.sweep("s", [0.219, 0.2245, 0.23], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=0)
    >>> tr = vi.locate_transitions(sw, xtol=1e-6)
    >>> [(str(a), round(float(d), 5)) for a, d in zip(tr.direction.values, tr.d.values)]
    [('up', 0.14195), ('down', 0.1376)]
    >>> tr.before.values.tolist(), tr.status.values.tolist(), bool((tr.d_width < 1e-5).all())
    (['3:1 period-2', '2:1 period-2'], ['refined', 'refined'], True)
    """
    beta = float(sw.attrs["beta"])
    g0 = sw["gbar"].values
    dvals = sw["d"].values
    r = float(sw.attrs["r"])
    tol = float(sw.attrs["tol"])
    # the sweep's own window and longest period (a sweep written without them used the defaults)
    window, pmax = int(sw.attrs.get("window", 65)), int(sw.attrs.get("pmax", 64))
    d_min, d_max = float(dvals.min()), float(dvals.max())
    rows = []
    bar = Progress(len(sw.direction) * (len(dvals) - 1), "locate transitions", progress, unit="point")
    for k_dir, name in enumerate(sw.direction.values):
        labels = sw["label"].values[k_dir]
        sign = 1.0 if name == "up" else -1.0
        order = range(len(dvals) - 1) if name == "up" else range(len(dvals) - 1, 0, -1)
        last_end = None
        for i in order:
            bar.update()
            j = i + 1 if name == "up" else i - 1
            if labels[i] == labels[j] or labels[i] in NO_PERIOD_LABELS:
                continue
            if last_end is not None and sign * (dvals[i] - last_end) < 0:
                continue  # this change was already passed by the previous located transition
            before = labels[i]
            n = int(np.sum(np.isfinite(sw["t"].values[k_dir, i])))
            w = [sw[v].values[k_dir, i] for v in _EVENT_VARS]
            start = last_bottom_impact(*w, n) or (float(sw["start_phi"][k_dir, i]), float(sw["start_v0"][k_dir, i]))
            slope = (g0[j] - g0[i]) / (dvals[j] - dvals[i])  # gbar is affine in d for both sweeps
            def follow(trial, start, gi=g0[i], slope=slope, di=dvals[i]):
                win, st, lag, _, nw = _run_one(trial, gi + slope * (trial - di), r, start[0], start[1],
                                               max_periods, max_events, tol, window, pmax)
                return _classify(win, nw, st, lag)[3], last_bottom_impact(*win, nw) or start

            # adaptive continuation of the followed motion: the step doubles (up to the grid step)
            # after a run that keeps the motion and halves after one that loses it
            h_grid = abs(dvals[j] - dvals[i])
            h = h_grid
            x, y = dvals[i], dvals[j]  # x: last d with the old motion; y: nearest d beyond it without
            after = labels[j]
            after_start = None  # where the motion beyond was last seen (its window's last bottom impact)
            y_checked = False  # y re-run from an attractor within 1e-3 grid steps of it
            refined = False
            for _ in range(max_trials):
                if (abs(y - x) < max(1e-3 * h_grid, 4 * xtol) or h <= xtol) and not y_checked:
                    # a failure far from the attractor it started on may be a jump out of a thin basin
                    lab, nxt = follow(y, start)
                    y_checked = True
                    if lab == before:
                        x, start, y, h, y_checked = y, nxt, y + sign * h_grid, h_grid, False
                        continue
                if h <= xtol:
                    refined = True
                    break
                trial = x + sign * h
                if not d_min <= trial <= d_max:
                    h *= 0.5
                    continue
                lab, nxt = follow(trial, start)
                if lab == before:
                    x, start = trial, nxt
                    h = min(2 * h, h_grid, 0.5 * abs(y - x))
                else:
                    y, after, after_start, y_checked = trial, lab, nxt, False
                    h = min(0.5 * h, 0.5 * abs(y - x))
            last_end = y
            if after == APERIODIC and after_start is not None:  # what the motion beyond is: its long run says
                after = split_no_period(y, g0[i] + slope * (y - dvals[i]), r, *after_start, tol=tol)["label"]
            status = "refined" if refined else f"not refined: {max_trials} runs (max_trials) left a bracket of {abs(y - x):.1e}"
            rows.append((name, 0.5 * (x + y), abs(y - x), before, after, transition_kind(before, after), status))
    bar.close()
    ds = xr.Dataset(
        {
            "direction": ("transition", np.array([r_[0] for r_ in rows], dtype=object).astype(str)),
            "d": ("transition", np.array([r_[1] for r_ in rows], dtype=float), {"units": "1", "long_name": "located transition d"}),
            "d_width": ("transition", np.array([r_[2] for r_ in rows], dtype=float), {"units": "1", "long_name": "final step: the transition lies within d +- d_width/2"}),
            "before": ("transition", np.array([r_[3] for r_ in rows], dtype=object).astype(str)),
            "after": ("transition", np.array([r_[4] for r_ in rows], dtype=object).astype(str)),
            "kind": ("transition", np.array([r_[5] for r_ in rows], dtype=object).astype(str)),
            "status": ("transition", np.array([r_[6] for r_ in rows], dtype=object).astype(str),
                       {"long_name": "refined to xtol, or why not"}),
        },
        coords={"transition": np.arange(len(rows))},
    )
    ds.attrs.update(beta=beta, xtol=xtol, max_periods=max_periods)
    return ds


def bistable_intervals(sw: xr.Dataset, transitions: xr.Dataset) -> xr.Dataset:
    """Intervals of d where two motions coexist, bounded by the located transitions.

    An interval is bistable where the up sweep (d increasing) follows one motion ``A`` and the down
    sweep another, ``B``: ``A`` exists up to where the up sweep loses it, and ``B`` down to where
    the down sweep loses it.  So the **lower end** is the located transition of the *down* sweep
    that ends ``B`` (the nearest one below the interval with ``before == B``) and the **upper end**
    the located transition of the *up* sweep that ends ``A``.  Two sources of intervals:

    * ``"sweeps differ"``: a run of grid points where the two sweeps end on different motions;
      ``B`` is the down sweep's motion at the run's lowest point and ``A`` the up sweep's at its
      highest.  An end whose motion is aperiodic has no located transition: it is then the middle
      of the grid step outside the run, with the grid step as its width (``*_source = "grid"``).
      A run that reaches the end of the swept range ends there (``*_source = "range end"``, width
      NaN): the interval may extend beyond it.
    * ``"transitions only"``: a located up transition where the up sweep goes from ``A`` to ``B``
      above a located down transition where the down sweep goes from ``B`` to ``A``, bounding no
      such run (both sweeps jump between the same two grid points).

    Parameters
    ----------
    sw : xarray.Dataset
        A sweep from :func:`sweep`.
    transitions : xarray.Dataset
        Its located transitions, from :func:`locate_transitions`.

    Returns
    -------
    xarray.Dataset
        Along ``interval``: ``d_lo``, ``d_hi``, their bracket widths ``d_lo_width``,
        ``d_hi_width``, ``lo_source``/``hi_source`` (``"located"``, ``"grid"`` or ``"range end"``), ``label_up``
        (``A``), ``label_down`` (``B``) and ``found_by``.

        An interval that would have zero or negative width (located ends in the wrong order) is left out and
        named in the attribute ``inconsistent_intervals``.

    Examples
    --------
    The bistable interval [G1, G2] of the paper's incline pi/6, bounded by the located transitions:

    >>> import math, vibroimpact as vi
    >>> sw = vi.sweep("s", [0.219, 0.2245, 0.23], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=0)
    >>> iv = vi.bistable_intervals(sw, vi.locate_transitions(sw, xtol=1e-6))
    >>> iv.d_lo.values.round(5).tolist(), iv.d_hi.values.round(5).tolist(), iv.lo_source.values.tolist()
    ([0.1376], [0.14195], ['located'])
    >>> iv.label_up.values.tolist(), iv.label_down.values.tolist(), iv.found_by.values.tolist()
    (['3:1 period-2'], ['2:1 period-2'], ['sweeps differ'])
    """
    up, down = sw["label"].values
    d = sw["d"].values
    step = float(np.median(np.diff(d))) if len(d) > 1 else 0.0
    t_dir = transitions["direction"].values.astype(str)
    t_d = transitions["d"].values
    t_w = transitions["d_width"].values
    t_before = transitions["before"].values.astype(str)

    def located(direction, label, side, bound):
        """The located transition of ``direction`` ending ``label`` nearest beyond ``bound``."""
        sel = (t_dir == direction) & (t_before == label)
        sel &= (t_d <= bound) if side < 0 else (t_d >= bound)
        if not sel.any():
            return None
        k = np.flatnonzero(sel)
        k = k[np.argmax(t_d[k])] if side < 0 else k[np.argmin(t_d[k])]
        return float(t_d[k]), float(t_w[k])

    rows = []
    differ = up != down
    i = 0
    while i < len(d):
        if not differ[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(d) and differ[j + 1]:
            j += 1
        lab_a, lab_b = str(up[j]), str(down[i])
        lo = located("down", lab_b, -1, d[i])
        hi = located("up", lab_a, +1, d[j])
        lo_src, hi_src = "located", "located"
        if lo is None and i == 0:  # the motions still differ at the range's end: it bounds the
            lo, lo_src = (float(d[0]), math.nan), "range end"  # interval, which may go on beyond
        elif lo is None:  # the down motion ends aperiodic: not located
            lo, lo_src = (0.5 * (d[i - 1] + d[i]), step), "grid"
        if hi is None and j == len(d) - 1:
            hi, hi_src = (float(d[-1]), math.nan), "range end"
        elif hi is None:
            hi, hi_src = (0.5 * (d[j] + d[j + 1]), step), "grid"
        rows.append((lo[0], hi[0], lo[1], hi[1], lo_src, hi_src, lab_a, lab_b, "sweeps differ"))
        i = j + 1
    # hysteresis loops the grid did not see: the up sweep goes from A to B across a located up
    # transition above a located down transition where the down sweep goes from B to A (the
    # transitions' own "after" may be aperiodic: a slow transient just past a fold)
    def sweep_label(k_dir, x, side):
        beyond = np.flatnonzero(d > x) if side > 0 else np.flatnonzero(d < x)
        return str(sw["label"].values[k_dir][beyond[0] if side > 0 else beyond[-1]]) if beyond.size else None

    for k in np.flatnonzero(t_dir == "up"):
        lab_b = sweep_label(0, t_d[k], +1)
        for m in np.flatnonzero((t_dir == "down") & (t_before == lab_b)):
            lo_d, hi_d = float(t_d[m]), float(t_d[k])
            if sweep_label(1, lo_d, -1) != t_before[k] or lab_b == t_before[k]:
                continue
            if lo_d < hi_d and not any(r_[0] <= hi_d and lo_d <= r_[1] for r_ in rows):
                rows.append((lo_d, hi_d, float(t_w[m]), float(t_w[k]), "located", "located",
                             str(t_before[k]), str(t_before[m]), "transitions only"))
    rows.sort(key=lambda r_: r_[0])
    bad = [f"d_lo = {r_[0]!r} >= d_hi = {r_[1]!r} (up sweep {r_[6]!r}, down sweep {r_[7]!r})"
           for r_ in rows if not r_[1] > r_[0]]
    rows = [r_ for r_ in rows if r_[1] > r_[0]]
    col = list(zip(*rows, strict=True)) if rows else [()] * 9
    ds = xr.Dataset(
        {
            "d_lo": ("interval", np.array(col[0], dtype=float),
                     {"units": "1", "long_name": "lower end: the down sweep loses label_down"}),
            "d_hi": ("interval", np.array(col[1], dtype=float),
                     {"units": "1", "long_name": "upper end: the up sweep loses label_up"}),
            "d_lo_width": ("interval", np.array(col[2], dtype=float),
                           {"units": "1", "long_name": "the lower end lies within d_lo +- d_lo_width/2"}),
            "d_hi_width": ("interval", np.array(col[3], dtype=float),
                           {"units": "1", "long_name": "the upper end lies within d_hi +- d_hi_width/2"}),
            "lo_source": ("interval", np.array(col[4], dtype=object).astype(str),
                          {"long_name": "located transition, grid step (aperiodic motion, not located) or range end"}),
            "hi_source": ("interval", np.array(col[5], dtype=object).astype(str),
                          {"long_name": "located transition, grid step (aperiodic motion, not located) or range end"}),
            "label_up": ("interval", np.array(col[6], dtype=object).astype(str),
                         {"long_name": "motion followed by the up sweep (d increasing)"}),
            "label_down": ("interval", np.array(col[7], dtype=object).astype(str),
                           {"long_name": "motion followed by the down sweep (d decreasing)"}),
            "found_by": ("interval", np.array(col[8], dtype=object).astype(str),
                         {"long_name": "sweeps differ on the grid, or transitions only"}),
        },
        coords={"interval": np.arange(len(rows))},
    )
    if bad:
        ds.attrs["inconsistent_intervals"] = ("intervals of non-positive width, left out (the located transitions "
                                              "are inconsistent): " + "; ".join(bad))
    return ds


# ---------------------------------------------------------------------------------------------
# Basins and regime maps
# ---------------------------------------------------------------------------------------------


def _codes(labels: np.ndarray):
    """Integer codes for labels, most frequent first; returns (codes, legend)."""
    uniq, counts = np.unique(labels, return_counts=True)
    legend = list(uniq[np.argsort(-counts, kind="stable")])
    lookup = {lab: i for i, lab in enumerate(legend)}
    return np.vectorize(lookup.__getitem__, otypes=[np.int16])(labels), legend


def _attractor_codes(ds: xr.Dataset, dims) -> xr.Dataset:
    codes, legend = _codes(ds["label"].values)
    ds["attractor"] = (dims, codes, {"units": "1", "long_name": "attractor class (index into the legend)",
                                      "legend": "; ".join(f"{i}: {lab}" for i, lab in enumerate(legend))})
    ds.attrs["legend"] = json_list(legend)
    return ds


def json_list(items):
    import json

    return json.dumps([str(x) for x in items])


def basins(params: Params, phis, v0s, *, max_periods: float = 400, tol: float = 1e-9, window: int = 65,
           progress: bool | None = None) -> xr.Dataset:
    """Attractor reached from each bottom impact ``(phase, v0)`` of a grid, at one parameter point.

    Parameters
    ----------
    params : Params
        The parameter point.
    phis, v0s : array_like
        Grid axes: phase (rad) and pre-impact velocity of the first bottom impact.
    max_periods : float
        Longest transient, in forcing periods, before a start is called aperiodic.
    tol : float
        Tolerance of the periodicity test.
    window : int
        Events kept per run.
    progress : bool, optional
        A progress bar (default: only when run interactively).

    Returns
    -------
    xarray.Dataset
        On ``(phi, v0)``: ``label`` (e.g. ``"2:1 period-2"``), ``period``, ``n_events`` and the integer
        ``attractor``, an index into the labels listed (as JSON) in the ``legend`` attribute.

    Examples
    --------
    Between G1 and G2 (d = 0.13975, pi/6) the starts of a small grid split between the two coexisting motions:

    >>> import json, numpy as np, vibroimpact as vi
    >>> b = vi.basins(vi.Params(d=0.13975, gbar=0.12201), np.linspace(0, 2 * np.pi, 4, endpoint=False),
    ...               [0.1, 0.4])
    >>> legend = json.loads(b.attrs["legend"])
    >>> sorted(legend)
    ['2:1 period-2', '3:1 period-2']
    >>> bool((np.array(legend)[b.attractor.values] == b.label.values).all())
    True
    """
    P, V = np.meshgrid(np.asarray(phis, float), np.asarray(v0s, float), indexing="ij")
    ds = attractor_batch(params.d, params.gbar, params.r, P.ravel(), V.ravel(), max_periods=max_periods,
                         tol=tol, window=window, progress=progress, desc="basins")
    shape = P.shape
    out = xr.Dataset(
        {
            "label": (("phi", "v0"), ds["label"].values.reshape(shape)),
            "period": (("phi", "v0"), ds["period"].values.reshape(shape), ds["period"].attrs),
            "n_events": (("phi", "v0"), ds["n_events"].values.reshape(shape), ds["n_events"].attrs),
        },
        coords={"phi": np.asarray(phis, float), "v0": np.asarray(v0s, float)},
    )
    out.attrs.update(d=params.d, gbar=params.gbar, r=params.r, max_periods=max_periods, tol=tol,
                     **{k: v for k, v in params.physical.items()})
    return annotate(_attractor_codes(out, ("phi", "v0")))


def plane_params(x_name: str, xs, y_name: str, ys, *, device: Device | None = None, **held):
    """The model parameters over a grid of two parameters (the plane of a regime or design map).

    ``x_name, y_name``: two different names, both physical (``s``, ``F``, ``beta``, with ``r``) or both
    non-dimensional (``d``, ``gbar``, with ``r``); ``device``: the harvester (default
    the paper's, ``Device()``); ``**held``: the values held where they are not an axis (``s`` 0.85 m, ``F`` the
    device's, ``beta`` pi/6 by default; ``r`` changes the device's).  Returns ``X, Y, d, gbar, r`` on
    ``(len(ys), len(xs))`` and the values held fixed (a dict).
    """
    allowed = ("s", "F", "beta", "d", "gbar", "r")
    for name in (x_name, y_name):
        if name not in allowed:
            raise ValueError(f"map axis {name!r}; allowed: {allowed}")
    if x_name == y_name:
        raise ValueError(f"map axes x_name = y_name = {x_name!r}; allowed: two different names of {allowed}")
    axes = {x_name, y_name}
    nondim = sorted(axes & {"d", "gbar"})
    if nondim and axes & {"s", "F", "beta"}:
        raise ValueError(f"map axes ({x_name!r}, {y_name!r}): {nondim[0]!r} is non-dimensional; allowed: "
                         "two of s, F, beta, r or two of d, gbar, r")
    device, held = held_values(device, held)
    X, Y = np.meshgrid(np.asarray(xs, float), np.asarray(ys, float), indexing="xy")
    base = dict(s=0.85, F=device.F, beta=math.pi / 6) | held
    p0 = device.params(**base)
    d, gbar, r = np.empty(X.shape), np.empty(X.shape), np.empty(X.shape)
    for k, (x, y) in enumerate(zip(X.ravel(), Y.ravel(), strict=True)):
        if nondim:
            v = dict(d=p0.d, gbar=p0.gbar, r=p0.r)
            v[x_name], v[y_name] = x, y
            p = Params(d=v["d"], gbar=v["gbar"], r=v["r"])
        else:
            kw = dict(base, r=device.r)
            kw[x_name], kw[y_name] = x, y
            p = device.replace(r=kw.pop("r")).params(**kw)
        d.flat[k], gbar.flat[k], r.flat[k] = p.d, p.gbar, p.r
    fixed = ({k: float(getattr(p0, k)) for k in ("d", "gbar", "r") if k not in axes} if nondim
             else {k: v for k, v in (base | {"r": device.r}).items() if k not in axes}
             | {k: getattr(device, k) for k in ("M", "omega", "g")})
    return X, Y, d, gbar, r, fixed


def _split_cells(ds, d, gbar, r, tol):
    """Labels of an :func:`attractor_batch` with every run that found no period split by its long run
    (:func:`split_no_period`, from its window's last bottom impact), and ``(lambda_1, low, high)`` of those."""
    labels = ds["label"].values.astype(object)
    lyap = np.full((labels.size, 3), np.nan)
    ev = [ds[v].values for v in _EVENT_VARS]
    for i in np.flatnonzero(labels == APERIODIC):
        start = last_bottom_impact(*(e[i] for e in ev), int(np.isfinite(ev[0][i]).sum()))
        if start is None:
            continue
        split = split_no_period(d[i], gbar[i], r[i], *start, tol=tol)
        labels[i] = split["label"]
        lyap[i] = split["lyap1"], split["lyap1_low"], split["lyap1_high"]
    return labels.astype(str), lyap


def regime_map(x_name: str, xs, y_name: str, ys, *, phi: float = 0.0, v0: float = 0.5, max_periods: float = 200,
               tol: float = 1e-9, window: int = 65, progress: bool | None = None, device: Device | None = None,
               **held) -> xr.Dataset:
    """Attractor class over a grid of two parameters, each run from the same bottom impact.

    Parameters
    ----------
    x_name, y_name : {"s", "F", "beta", "d", "gbar", "r"}
        The two axes (different): physical (``s``, ``F``, ``beta``, with ``r``) or non-dimensional
        (``d``, ``gbar``, with ``r``), not a mix.
    xs, ys : array_like
        Their values (m, N, rad or 1).
    phi, v0 : float
        Start of every run: a bottom impact at phase ``phi`` with pre-impact velocity ``v0``.
    max_periods, tol, window, progress
        As in :func:`basins`.
    device : Device, optional
        The harvester (default the paper's, ``Device()``).
    **held
        The values held where they are not an axis (``s``, ``F``, ``beta``; ``r`` changes the device's):
        :func:`plane_params`.  On non-dimensional axes they fix the parameter that is not an axis
        (``gbar`` on a (d, r) map, ``r`` on a (d, gbar) map) through the device's scaling.

    Returns
    -------
    xarray.Dataset
        On ``(y_name, x_name)``: ``label`` (a cell with no period split into chaotic, quasi-periodic or
        unsettled by its long run, :func:`no_period_label`), ``lyap1`` with ``lyap1_low``, ``lyap1_high``
        for those cells, ``period``, ``d``, ``gbar`` and ``attractor`` (an index into the labels of the
        ``legend`` attribute, JSON); attributes: the start, the settings and the values held.

    Examples
    --------
    From the same start, the shorter cylinder settles on the 3:1 motion on both inclines, the longer one on
    the 2:1 at pi/6 only; ``gbar = M g sin(beta) / F`` along beta:

    >>> import math, vibroimpact as vi
    >>> rm = vi.regime_map("s", [0.219, 0.23], "beta", [math.pi / 6, math.pi / 3], phi=5.855, v0=0.4185)
    >>> rm.label.values.tolist()
    [['3:1 period-2', '2:1 period-2'], ['3:1 period-2', '3:1 period-2']]
    >>> rm.d.values[0].round(5).tolist(), rm.gbar.values[:, 0].round(5).tolist()
    ([0.13633, 0.14318], [0.12201, 0.21133])
    """
    X, Y, d, gbar, r, fixed = plane_params(x_name, xs, y_name, ys, device=device, **held)
    axes = {x_name, y_name}
    d, gbar, r = d.ravel(), gbar.ravel(), r.ravel()
    ds = attractor_batch(d, gbar, r, phi, v0, max_periods=max_periods, tol=tol, window=window, progress=progress,
                         desc=f"regime map over ({x_name}, {y_name})")
    shape = X.shape
    labels, lyap = _split_cells(ds, d, gbar, r, tol)
    level = "its 95 % confidence interval (batch means over the long run)"
    data = {
        "label": ((y_name, x_name), labels.reshape(shape)),
        "lyap1": ((y_name, x_name), lyap[:, 0].reshape(shape), {"units": "1", "long_name": "largest Lyapunov exponent per impact of a cell with no period (its long run; NaN elsewhere)"}),
        "lyap1_low": ((y_name, x_name), lyap[:, 1].reshape(shape), {"units": "1", "long_name": f"lambda_1: lower end of {level}"}),
        "lyap1_high": ((y_name, x_name), lyap[:, 2].reshape(shape), {"units": "1", "long_name": f"lambda_1: upper end of {level}"}),
        "period": ((y_name, x_name), ds["period"].values.reshape(shape), ds["period"].attrs),
        "d": ((y_name, x_name), d.reshape(shape)),
        "gbar": ((y_name, x_name), gbar.reshape(shape)),
    }
    out = xr.Dataset({k: v for k, v in data.items() if k not in axes},  # an axis is its own coordinate
                     coords={x_name: np.asarray(xs, float), y_name: np.asarray(ys, float)})
    units = {"s": ("m", "cylinder length s"), "F": ("N", "forcing amplitude ||F||"), "beta": ("rad", "incline beta"),
             "d": ("1", "non-dimensional gap d"), "gbar": ("1", "non-dimensional gravity gbar"),
             "r": ("1", "coefficient of restitution r")}
    for name in (x_name, y_name):
        out[name].attrs.update(units=units[name][0], long_name=units[name][1])
    out.attrs.update(phi=phi, v0=v0, max_periods=max_periods, tol=tol, **fixed)
    return annotate(_attractor_codes(out, (y_name, x_name)))
