"""Batch windows: runs that stop as soon as their motion repeats (or after a cap), each keeping the window of
its last events, and the dataset of those windows with each run's motion
(:func:`vibroimpact.analysis.motions.cycle_class`).

Every run starts with a bottom impact (paper convention) and stops as soon as its motion repeats
(:func:`vibroimpact.dynamics.kernels.run_window`), or after ``max_periods`` forcing periods, in which case the
motion is classed ``"no period found"`` (:data:`~vibroimpact.analysis.motions.APERIODIC`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._progress import Progress, interactive
from ..datasets import annotate
from ..dynamics import kernels as K
from .motions import APERIODIC, NO_PERIOD_LABELS, Motion, cycle_class, motion_without_period, resolved_impacts

__all__ = ["EVENT_VARS", "check_window", "empty_windows", "run_window", "window_motion", "window_motions",
           "window_dataset", "last_bottom_impact", "attractor_batch"]

#: the events a window keeps, in the order of the kernels' buffers
EVENT_VARS = ("t", "wall", "v_minus", "phase", "kind")


def check_window(window, pmax):
    """A period of ``p`` events is identified from the window only if it holds more than ``p``."""
    if int(pmax) < 1:
        raise ValueError(f"pmax = {pmax!r}; allowed: an integer >= 1")
    if int(window) < int(pmax) + 1:
        raise ValueError(f"window = {window!r}; allowed: >= pmax + 1 = {int(pmax) + 1} (pmax = {pmax!r})")


def empty_windows(shape, window):
    """The five window buffers (:data:`EVENT_VARS`, a :data:`~vibroimpact.dynamics.kernels.Window`) of ``window``
    events for runs of ``shape``: NaN times, velocities and phases, zero walls and kinds."""
    shape = (*np.broadcast_shapes(shape), int(window))
    return K.Window(np.full(shape, np.nan), np.zeros(shape, np.int8), np.full(shape, np.nan), np.full(shape, np.nan),
                    np.zeros(shape, np.int8))


def window_limits(max_periods, max_events, tol, pmax):
    """The kernels' :data:`~vibroimpact.dynamics.kernels.WindowSettings` of a run of at most ``max_events``
    events and ``max_periods`` forcing periods, its period test's tolerance ``tol`` and longest period
    ``pmax`` (events), with the simulator's default chattering speed :data:`~vibroimpact.dynamics.kernels.V_CHATTER`."""
    return K.WindowSettings(max_events=int(max_events), t_end=2.0 * float(max_periods), v_chatter=K.V_CHATTER,
                            tol=float(tol), pmax=int(pmax), cap=history(pmax))


def history(pmax):
    """Events the kernels keep to find a period of up to ``pmax`` events (three periods and more)."""
    return max(4096, 4 * (3 * int(pmax) + 1))


def run_window(d, gbar, r, phi, v0, max_periods, max_events, tol, window, pmax):
    """One run from a bottom impact ``(phi, v0)``: its window, status, period in events, events simulated and
    events in the window."""
    win = empty_windows((), window)
    st, lag, tot, n = K.run_window(K.Model(d=float(d), gbar=float(gbar), r=float(r)), phi % (2 * np.pi), v0,
                                   window_limits(max_periods, max_events, tol, pmax), win)
    return win, st, lag, tot, n


def window_motion(win, n, status, lag) -> tuple[Motion, int, int]:
    """The motion of one run from its window of the last ``n`` events (a period is identified only after
    three periods of events, so a periodic window holds more than one period), and the impacts the simulator
    resolved on each wall over one period."""
    if status != K.PERIODIC or lag == 0 or lag >= n:
        return motion_without_period(APERIODIC), 0, 0
    t, wall, kind = win[0], win[1], win[4]
    motion = cycle_class(wall[n - lag:n], kind[n - lag:n], float(t[n - 1] - t[n - 1 - lag]))
    return motion, *resolved_impacts(wall[n - lag:n], kind[n - lag:n])


def window_motions(ds: xr.Dataset) -> np.ndarray:
    """The :class:`~vibroimpact.analysis.motions.Motion` of each run of a window dataset (a sweep's or
    :func:`attractor_batch`'s), from its events; a run without a period is the one its label names (after
    :func:`vibroimpact.analysis.settled.settle_attractors`, chaotic, quasi-periodic or unsettled)."""
    shape = ds["status"].shape
    out = np.empty(shape, dtype=object)
    ev = [ds[v].values for v in EVENT_VARS]
    labels = ds["label"].values
    n_real = np.isfinite(ev[0]).sum(axis=-1)
    lags = ds["period_events"].values
    for idx in np.ndindex(shape):
        if str(labels[idx]) in NO_PERIOD_LABELS:
            out[idx] = motion_without_period(str(labels[idx]))
            continue
        n = int(n_real[idx])
        out[idx] = window_motion([e[idx][:n] for e in ev], n, K.PERIODIC, int(lags[idx]))[0]
    return out


def last_bottom_impact(win_t, win_wall, win_vm, win_phase, win_kind, n):
    """Phase and pre-impact speed of the last bottom impact among a window's first ``n`` events (a start on
    the same motion), or None where the window holds none."""
    for j in range(n - 1, -1, -1):
        if win_wall[j] == 1 and win_kind[j] == K.IMPACT and win_vm[j] > 0:
            return float(win_phase[j]), float(win_vm[j])
    return None


def attractor_batch(d, gbar, r, phi, v0, *, t0=None, Z0=None, max_periods: float = 200, max_events: int = 200_000,
                    tol: float = 1e-9, window: int = 65, pmax: int = 64, progress: bool | None = None,
                    desc: str = "attractors") -> xr.Dataset:
    """Attractors of many runs in parallel: the last ``window`` events and the motion's class.

    Parameters
    ----------
    d, gbar, r, phi, v0 : array_like
        Each run's parameters and first bottom impact (phase, pre-impact velocity); broadcast to one
        dimension ``run``.
    t0, Z0 : array_like, optional
        Starts in flight instead (as :func:`vibroimpact.simulate`'s): at time ``t0`` (forcing phase
        ``pi t0 + phi``) with ``Z = Z0`` (``|Z0| <= d/2``) and ``Zdot = v0``; each run then lasts
        ``max_periods`` after its start.
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
        ``sticking`` (whether its cycle sticks to a wall), ``period`` (forcing periods, 0 when aperiodic), ``period_events``, ``n_bottom``, ``n_top``,
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
    check_window(window, pmax)
    in_flight = Z0 is not None
    if in_flight != (t0 is not None):
        raise ValueError(f"t0 = {t0!r}, Z0 = {Z0!r}; allowed: both (starts in flight) or neither (bottom impacts)")
    arrs = np.broadcast_arrays(*(np.atleast_1d(np.asarray(a, dtype=float))
                                 for a in (d, gbar, r, phi, v0, *((t0, Z0) if in_flight else ()))))
    d, gbar, r, phi, v0, *rest = (np.ascontiguousarray(a.ravel()) for a in arrs)
    m = d.shape[0]
    win = empty_windows(m, window)
    ends = K.WindowEnds(status=np.zeros(m, np.int8), lag=np.zeros(m, np.int64), total=np.zeros(m, np.int64),
                        n=np.zeros(m, np.int64))
    if in_flight:
        t0, Z0 = rest
        if not (np.isfinite(t0).all() and (np.abs(Z0) <= 0.5 * d).all()):
            raise ValueError("t0 and Z0: allowed finite start times and |Z0| <= d/2 (inside the cylinder)")
        batch = K.FlightBatch(d=d, gbar=gbar, r=r, t0=t0, theta0=(np.pi * t0 + phi) % (2 * np.pi), z0=Z0, v0=v0)
        kernel = K.flight_window_batch
    else:
        batch, kernel = K.Batch(d=d, gbar=gbar, r=r, theta0=phi % (2 * np.pi), v0=v0), K.window_batch
    limits = window_limits(max_periods, max_events, tol, pmax)
    shown = interactive() if progress is None else bool(progress)
    # in one parallel call unless a bar is shown: then in tenths (each run is independent of the others)
    cuts = np.linspace(0, m, 11 if shown and m >= 20 else 2).astype(int)
    with Progress(m, desc, shown, unit="run") as bar:
        for a, b in zip(cuts[:-1], cuts[1:], strict=True):
            kernel(type(batch)(*(x[a:b] for x in batch)), limits, K.Window(*(w[a:b] for w in win)),
                   K.WindowEnds(*(e[a:b] for e in ends)))
            bar.update(int(b - a))
    return window_dataset(win, *ends, dims=("run",))


def window_dataset(win, st, lag, tot, nw, dims):
    """The dataset of runs' windows (``win``, :func:`empty_windows`) on ``dims`` with each run's motion, status
    (``st``), period in events (``lag``), events simulated (``tot``) and events in its window (``nw``)."""
    shape = st.shape
    labels = np.empty(shape, dtype=object)
    per = np.zeros(shape, np.int64)
    nb = np.zeros(shape, np.int64)
    nt = np.zeros(shape, np.int64)
    sticks = np.zeros(shape, bool)
    flat = [w.reshape(-1, w.shape[-1]) for w in win]
    for idx in range(int(np.prod(shape))):
        n = int(nw.flat[idx])
        rows = [f[idx, :n] for f in flat]  # the real events lead the window, NaN-padded after
        motion, b, t_ = window_motion(rows, n, int(st.flat[idx]), int(lag.flat[idx]))
        per.flat[idx], nb.flat[idx], nt.flat[idx], labels.flat[idx] = motion.period, b, t_, motion.label
        sticks.flat[idx] = motion.sticking
    edims = (*dims, "event")
    ds = xr.Dataset(
        {name: (edims, w) for name, w in zip(EVENT_VARS, win, strict=True)}
        | {
            "label": (dims, labels.astype(str)),
            "sticking": (dims, sticks),
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
