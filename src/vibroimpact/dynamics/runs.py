"""Public simulation API: exact event-driven runs returned as xarray datasets."""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr
from numba import njit

from ..datasets import annotate
from . import kernels as K
from .flight import INV_PI2, PI, TWO_PI, displacement, velocity
from .params import Params

__all__ = ["simulate", "simulate_batch", "trajectory"]

_KIND_ATTRS = {
    "flag_values": np.arange(len(K.KIND_NAMES), dtype=np.int8),
    "flag_meanings": " ".join(K.KIND_NAMES),
}
_STATUS_ATTRS = {
    "flag_values": np.arange(len(K.STATUS_NAMES), dtype=np.int8),
    "flag_meanings": " ".join(K.STATUS_NAMES),
}


def _finite(name, x):
    try:
        x = float(x)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {x!r} is not a number; allowed: a finite real") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} = {x!r} is not finite; allowed: a finite real")
    return x


def _start(params, phi, v0, t0, Z0):
    """The checked start of a run: ``phi, v0, t0, Z0`` and the kernels' first event ``(kind, z, wall)``, a
    bottom impact (``Z0`` None) or a flight from ``Z0``."""
    if not isinstance(params, Params):
        raise TypeError(f"params must be a vibroimpact.Params, got {type(params).__name__}")
    phi, v0, t0 = _finite("phi", phi), _finite("v0", v0), _finite("t0", t0)
    half = 0.5 * params.d
    if Z0 is None:
        if v0 < 0:
            raise ValueError(
                f"v0 = {v0!r}: the pre-impact velocity of a bottom impact points into the wall; allowed: v0 >= 0"
            )
        return phi, v0, t0, Z0, (K.IMPACT, half, 1)
    Z0 = _finite("Z0", Z0)
    if abs(Z0) > half:
        raise ValueError(f"Z0 = {Z0!r} is outside the cylinder; allowed: |Z0| <= d/2 = {half!r}")
    return phi, v0, t0, Z0, (K.START, Z0, 0)


def _limits(n_impacts, t_end, stop_when_periodic, max_events):
    if n_impacts is None and t_end is None and not stop_when_periodic:
        raise ValueError("give n_impacts, t_end or stop_when_periodic=True: the run needs an end")
    if n_impacts is not None:
        if int(n_impacts) != n_impacts or n_impacts < 1:
            raise ValueError(f"n_impacts = {n_impacts!r}; allowed: an integer >= 1")
        n_impacts = int(n_impacts)
    t_end = math.inf if t_end is None else float(t_end)
    cap = n_impacts if n_impacts is not None else int(max_events)
    return cap, t_end


def simulate(
    params: Params,
    phi: float,
    v0: float,
    *,
    Z0: float | None = None,
    t0: float = 0.0,
    n_impacts: int | None = None,
    t_end: float | None = None,
    stop_when_periodic: bool = False,
    tol: float = 1e-9,
    max_period_events: int = 64,
    v_chatter: float = 1e-9,
    max_events: int = 10_000_000,
) -> xr.Dataset:
    """Follow the ball exactly from impact to impact.

    Parameters
    ----------
    params : Params
        Model parameters.
    phi : float
        Forcing phase at ``t0`` (the forcing is ``cos(pi t + phi)`` with t measured from 0).
    v0 : float
        With ``Z0=None``: pre-impact velocity (``>= 0``) of a bottom impact at ``t0``, the paper's
        convention (docs/guide/model.md).  Otherwise the velocity ``Zdot(t0)`` in flight.
    Z0 : float, optional
        Start in flight at ``Z(t0) = Z0`` (``|Z0| <= d/2``) instead of at a bottom impact.
    t0 : float
        Start time.
    n_impacts : int, optional
        Number of events to record (impacts, grazing contacts, stick and release events; the
        initial impact or start counts as one).
    t_end : float, optional
        Stop at this time.
    stop_when_periodic : bool
        Stop as soon as the motion is identified as periodic (two full cycles repeat to ``tol``).
    tol : float
        Tolerance of the periodicity test (velocity, phase and time lag).
    max_period_events : int
        Longest period, in events, that the periodicity test looks for.
    v_chatter : float
        Rebound speed below which a chattering sequence is summed to its accumulation point
        (see :mod:`vibroimpact.dynamics.kernels`).
    max_events : int
        Hard cap on events when only ``t_end`` or ``stop_when_periodic`` bounds the run.

    Returns
    -------
    xarray.Dataset
        Dimension ``impact``; variables ``t``, ``wall``, ``v_minus``, ``v_plus``, ``phase``, ``z``,
        ``dt``, ``kind``; attributes with the parameters, the run ``status`` (why it stopped) and
        ``period_events`` when the motion was identified as periodic.

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)   # Figure 7 (a)
    >>> round(p.d, 4), round(p.gbar, 4)
    (0.16, 0.122)
    >>> run = vi.simulate(p, phi=1.015, v0=0.1924, n_impacts=200)
    >>> run.sizes["impact"], run.attrs["status"]
    (200, 'n_events')
    """
    phi, v0, t0, Z0, (kind0, z0, wall0) = _start(params, phi, v0, t0, Z0)
    cap_total, t_end = _limits(n_impacts, t_end, stop_when_periodic, max_events)
    if t_end <= t0:
        raise ValueError(f"t_end = {t_end!r} must be later than t0 = {t0!r}")
    bufs, n, status, lag = _event_loop(params, K.Start(t0, (PI * t0 + phi) % TWO_PI, z0, v0, kind0, wall0),
                                       (cap_total, n_impacts is None),
                                       K.Settings(t_end=float(t_end), v_chatter=float(v_chatter),
                                                  detect=bool(stop_when_periodic), tol=float(tol)),
                                       int(max_period_events))
    ds = events_dataset(bufs, n)
    ds.attrs.update(_param_attrs(params))
    ds.attrs.update(phi=phi, v0=v0, t0=t0, start="bottom impact" if Z0 is None else f"flight at Z0={Z0!r}",
                    status=K.STATUS_NAMES[status], period_events=int(lag), tol=tol, v_chatter=v_chatter,
                    t_valid=float(t_end) if status == K.T_END else float(bufs.t[n - 1]))
    if status == K.STUCK_FOREVER:
        ds.attrs["note"] = "gbar >= 1: the ball never leaves the bottom wall after it sticks"
    return ds


def _event_loop(params, start, caps, settings, max_period_events):
    """:func:`simulate`'s event loop from its first event ``start`` (:data:`~vibroimpact.dynamics.kernels.Start`):
    ``caps`` is ``(events at most, whether the count is open)`` (buffers that grow where it is); returns the
    buffers, the events recorded, the status and the period found (in events), and warns where the ball comes to
    rest for good."""
    cap_total, open_count = caps
    counts = np.zeros(int(max_period_events) + 1, dtype=np.int64)
    cap = min(cap_total, 4096) if open_count else cap_total
    bufs = _alloc(cap)
    model = K.Model(d=float(params.d), gbar=float(params.gbar), r=float(params.r))
    n, status, lag = K.advance(model, start, 0, settings, counts, bufs)
    while status == K.FULL and n < cap_total:
        # grow the buffers and resume from the last recorded event
        new_cap = min(2 * cap, cap_total)
        bufs = K.EventBuffers(*(np.concatenate([b, np.zeros(new_cap - cap, b.dtype)]) for b in bufs))
        cap = new_cap
        j = n - 1
        start = K.Start(bufs.t[j], bufs.phase[j], bufs.z[j], bufs.v_plus[j], K.resume_code(int(bufs.kind[j])),
                        int(bufs.wall[j]))
        n, status, lag = K.advance(model, start, n, settings, counts, bufs)
    if status == K.STUCK_FOREVER:
        warnings.warn(
            f"gbar = {params.gbar:.6g} >= 1: the ball rests on the bottom wall and the forcing can never "
            "lift it off again; the run ends there (status 'stuck_forever')",
            stacklevel=3,
        )
    return bufs, n, status, lag


def simulated_events(params: Params, phi: float, v0: float, n_impacts: int):
    """The events of ``simulate(params, phi, v0, n_impacts=n_impacts)`` without its dataset (the same loop):
    ``(bufs, n, status)``, the first ``n`` entries of each buffer (:data:`~vibroimpact.dynamics.kernels.EventBuffers`)
    the run's events.  For the callers that run many short runs and keep few of them."""
    phi, v0, t0, _, (kind0, z0, wall0) = _start(params, phi, v0, 0.0, None)
    cap_total, t_end = _limits(n_impacts, None, False, 10_000_000)
    bufs, n, status, _ = _event_loop(params, K.Start(t0, (PI * t0 + phi) % TWO_PI, z0, v0, kind0, wall0),
                                     (cap_total, False), K.Settings(t_end=t_end, v_chatter=1e-9, detect=False, tol=1e-9),
                                     64)
    return bufs, n, status


def _alloc(n, runs=None):
    """Event buffers ``(t, wall, v_minus, v_plus, phase, kind, z)`` of length ``n`` (with a leading axis of
    ``runs`` if given), as rows of one float block (with a sixth row, for ``dt``, reached as the
    buffers' common base) and one int8 block.  One allocation each rather than seven: a block of several
    MB gets transparent huge pages, so the kernel's first writes fault a few times instead of once per
    4 kB page, which on this project's virtual machines costs more than computing the impact.  Not
    zeroed: the kernel writes every entry it reports."""
    lead = () if runs is None else (runs,)
    f = np.empty((6, *lead, n))
    i = np.empty((2, *lead, n), dtype=np.int8)
    return K.EventBuffers(t=f[0], wall=i[0], v_minus=f[1], v_plus=f[2], phase=f[3], kind=i[1], z=f[4])


def _param_attrs(params: Params) -> dict:
    out = dict(d=params.d, gbar=params.gbar, r=params.r)
    for key, val in params.physical.items():
        out[key] = val
    return out


def events_dataset(bufs, n, dim="impact") -> xr.Dataset:
    """The first ``n`` events of a run's buffers (t, wall, v_minus, v_plus, phase, kind, Z) as a dataset along
    ``dim``, with ``dt``, the time since the previous event (NaN for the first)."""
    t, wall, vm, vp, phase, kind, z = (b[..., :n] for b in bufs)
    base = bufs.t.base
    # the block's spare row when the buffers are still the block's rows, else a new array
    dt = base[5][..., :n] if base is not None and base.shape[0] == 6 and bufs.phase.base is base else np.empty_like(t)
    dt[..., 0] = np.nan
    np.subtract(t[..., 1:], t[..., :-1], out=dt[..., 1:])
    dims = bufs.t.shape[:-1] and ("run", dim) or (dim,)
    ds = xr.Dataset(
        {
            "t": (dims, t), "wall": (dims, wall), "v_minus": (dims, vm), "v_plus": (dims, vp),
            "phase": (dims, phase), "z": (dims, z), "dt": (dims, dt), "kind": (dims, kind),
        }
    )
    annotate(ds)
    ds["kind"].attrs.update(_KIND_ATTRS)
    return ds


def simulate_batch(d, gbar, r, phi, v0, *, n_impacts, t_end=None, stop_when_periodic=False, tol=1e-9,
                   max_period_events=64, v_chatter=1e-9) -> xr.Dataset:
    """Many runs in parallel (on numba's threads), each from a bottom impact at t = 0 (paper convention).

    Parameters
    ----------
    d, gbar, r : array_like
        Parameters of each run (:class:`~vibroimpact.Params`); broadcast with ``phi`` and ``v0`` to a common
        1-D shape, one run each.
    phi, v0 : array_like
        Phase (rad) and pre-impact velocity of each run's first bottom impact.
    n_impacts : int
        Events recorded per run at most.
    t_end : float, optional
        Time at which a run stops.
    stop_when_periodic : bool
        Stop a run as soon as its motion repeats to ``tol``.
    tol : float
        Periodicity tolerance.
    max_period_events : int
        Longest period looked for, in events.
    v_chatter : float
        Rebound speed below which a chattering sequence is summed (see :func:`~vibroimpact.simulate`).

    Returns
    -------
    xarray.Dataset
        Events on ``(run, impact)`` (``t``, ``wall``, ``v_minus``, ``v_plus``, ``phase``, ``z``, ``dt``,
        ``kind``); a run that stops early is NaN-padded (``n_events`` says how many events are real); per run
        ``status`` (flags: 0 ``n_events``, 1 ``t_end``, 2 ``periodic``, 3 ``stuck_forever``, 4 ``no_impact``),
        ``period_events``, and the inputs ``d``, ``gbar``, ``r``, ``phi``, ``v0``.

    Examples
    --------
    Two starts at the point of Figure 7 (a) both settle on the 2:1 motion (3 events a period), and a run of
    the batch is the run :func:`~vibroimpact.simulate` makes from the same start:

    >>> import vibroimpact as vi
    >>> ds = vi.simulate_batch(0.16, 0.122, 0.5, phi=[1.015, 3.0], v0=[0.1924, 0.3], n_impacts=200,
    ...                        stop_when_periodic=True)
    >>> ds.status.values.tolist(), ds.period_events.values.tolist()     # 2: periodic
    ([2, 2], [3, 3])
    >>> p = vi.Params(d=0.16, gbar=0.122)
    >>> one = vi.simulate(p, 1.015, 0.1924, n_impacts=200, stop_when_periodic=True)
    >>> n = int(ds.n_events[0])
    >>> n == one.sizes["impact"] and bool(abs(ds.t[0, :n].values - one.t.values).max() < 1e-12)
    True
    """
    arrs = np.broadcast_arrays(*(np.atleast_1d(np.asarray(a, dtype=np.float64)) for a in (d, gbar, r, phi, v0)))
    d, gbar, r, phi, v0 = (np.ascontiguousarray(a.ravel()) for a in arrs)
    for name, a, ok, allowed in (("d", d, d > 0, "d > 0"), ("gbar", gbar, gbar >= 0, "gbar >= 0"),
                                 ("r", r, (r >= 0) & (r < 1), "0 <= r < 1"), ("v0", v0, v0 >= 0, "v0 >= 0")):
        bad = ~(ok & np.isfinite(a))
        if bad.any():
            raise ValueError(f"{name} = {a[bad][0]!r} (run {int(np.argmax(bad))}) is out of range; allowed: {allowed}")
    cap, t_end = _limits(n_impacts, t_end, stop_when_periodic, 0)
    m = d.shape[0]
    bufs = _alloc(cap, runs=m)
    ends = K.Ends(n=np.zeros(m, np.int64), status=np.zeros(m, np.int8), lag=np.zeros(m, np.int64))
    settings = K.Settings(t_end=float(t_end), v_chatter=float(v_chatter), detect=bool(stop_when_periodic),
                          tol=float(tol))
    K.run_batch(K.Batch(d=d, gbar=gbar, r=r, theta0=phi % TWO_PI, v0=v0), settings, int(max_period_events), bufs,
                ends)
    out_n, out_status, out_lag = ends
    mask = np.arange(cap)[None, :] >= out_n[:, None]
    for b in bufs:  # the padding: NaN, and 0 for wall and kind
        b[mask] = np.nan if b.dtype.kind == "f" else 0
    ds = events_dataset(bufs, cap)
    for name, a in (("d", d), ("gbar", gbar), ("r", r), ("phi", phi), ("v0", v0)):
        ds[name] = ("run", a)
    ds["n_events"] = ("run", out_n)
    ds["status"] = ("run", out_status, dict(_STATUS_ATTRS))
    ds["period_events"] = ("run", out_lag)
    return annotate(ds)


# ---------------------------------------------------------------------------------------------
# Dense output
# ---------------------------------------------------------------------------------------------


#: a sample this close to an event (absolute, or relative beyond t = 1) is read just after it: rounding
#: decides on which side of an impact a sample at the impact's instant falls, so without this rule the
#: same figure could show the pre-impact velocity on one machine and the post-impact one on another.
#: Rounding moves an impact time by ~1e-15 (1e-13 for a slow impact, polished in double-double); the
#: shortest recorded flight (a chattering bounce at the 1e-9 cut-off speed) lasts ~1e-9, so a sample
#: inside a flight is never snapped out of it
SNAP = 1e-12


@njit(cache=True)
def _dense(times, events, gbar, out_z, out_v):
    """The state ``(Z, Zdot)`` at the sorted ``times`` into ``out_z``, ``out_v``, from a run's ``events``
    (:data:`~vibroimpact.dynamics.kernels.EventBuffers`) and its ``gbar``."""
    t, phase, z, vp, kind = events.t, events.phase, events.z, events.v_plus, events.kind
    j = 0
    n = t.shape[0]
    for i in range(times.shape[0]):
        ti = times[i]
        while j + 1 < n and t[j + 1] <= ti + SNAP * max(1.0, abs(ti)):
            j += 1
        tau = ti - t[j]
        if kind[j] == K.STICK:
            out_z[i] = z[j]
            out_v[i] = 0.0
        else:
            c = np.cos(phase[j])
            s = np.sin(phase[j])
            out_z[i] = z[j] + displacement(tau, c, s, vp[j], gbar)
            out_v[i] = velocity(tau, c, s, vp[j], gbar)


def trajectory(ds: xr.Dataset, times) -> xr.Dataset:
    """Exact state at any ``times`` within a run: ``Z``, ``Zdot``, cylinder ``X`` (X*) and ball ``x`` (x*).

    ``X*(t) = -cos(pi t + phi) / pi^2`` is the zero-mean periodic cylinder motion (``X*'' = cos``);
    ``x* = X* - Z``.  Times must lie within the run: from its first event to its last, or to
    ``t_end`` when the run stopped there (no impact happened in between).  The state is right-continuous
    at events, and a time within :data:`SNAP` (1e-12, relative beyond t = 1) before an event is read after it,
    so a sample at an impact's instant is the post-impact state whichever side rounding puts it.

    Parameters
    ----------
    ds : xarray.Dataset
        A run from :func:`simulate`.
    times : array_like
        Non-dimensional times within the run, in any order.

    Returns
    -------
    xarray.Dataset
        Along ``time``: ``Z``, ``Zdot``, ``X`` and ``x``.

    Examples
    --------
    At its impact times the closed-form flight is at the walls (``Z = +d/2`` bottom, ``-d/2`` top) with the
    rebound velocity; the cylinder's position is ``X* = -cos(pi t + phi) / pi^2``:

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.2, beta=math.pi / 6)
    >>> run = vi.simulate(p, phi=1.015, v0=0.1924, n_impacts=5)
    >>> tr = vi.trajectory(run, run.t.values[:4])
    >>> (tr.Z / (p.d / 2)).round(9).values.tolist(), run.wall.values[:4].tolist()
    ([1.0, -1.0, 1.0, 1.0], [1, -1, 1, 1])
    >>> bool(abs(tr.Zdot - run.v_plus[:4].values).max() < 1e-12)
    True
    >>> round(float(vi.trajectory(run, [0.0]).X[0]), 6), round(-math.cos(1.015) / math.pi**2, 6)
    (-0.053459, -0.053459)
    """
    times = np.asarray(times, dtype=np.float64)
    t = ds["t"].values
    t_last = max(float(ds.attrs.get("t_valid", t[-1])), float(t[-1]))
    if times.size and (times.min() < t[0] - SNAP * max(1.0, abs(t[0]))
                       or times.max() > t_last + SNAP * max(1.0, abs(t_last))):
        raise ValueError(
            f"times span [{times.min()!r}, {times.max()!r}]; allowed: within the run [{t[0]!r}, {t_last!r}]"
        )
    order = np.argsort(times, kind="stable")
    Z = np.empty_like(times)
    V = np.empty_like(times)
    zs, vs = np.empty(times.size), np.empty(times.size)
    events = K.EventBuffers(t=t, wall=ds["wall"].values, v_minus=ds["v_minus"].values, v_plus=ds["v_plus"].values,
                            phase=ds["phase"].values, kind=ds["kind"].values.astype(np.int64), z=ds["z"].values)
    _dense(times[order], events, float(ds.attrs["gbar"]), zs, vs)
    Z[order] = zs
    V[order] = vs
    phi = float(ds.attrs["phi"])
    X = -np.cos(PI * times + phi) * INV_PI2
    out = xr.Dataset({"Z": ("time", Z), "Zdot": ("time", V), "X": ("time", X), "x": ("time", X - Z)},
                     coords={"time": times})
    out.attrs.update({k: ds.attrs[k] for k in ("d", "gbar", "r", "phi") if k in ds.attrs})
    return annotate(out)
