"""Sweeps: the attractor followed along one parameter, up and down (paper Figs 0, 2, BiS, 5: the numerical
points).

Each point starts from the last bottom impact of the previous point's attractor, so the up and down sweeps
show hysteresis; each point runs until its motion repeats or for ``max_periods`` forcing periods
(:mod:`~vibroimpact.analysis.windows`), and what is well-posed about its attractor is added
(:func:`~vibroimpact.analysis.settled.settle_attractors`).  Where the motion changes:
:mod:`~vibroimpact.analysis.transitions`; where two coexist: :mod:`~vibroimpact.analysis.bistability`.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._progress import Progress
from ..datasets import annotate
from ..dynamics.device import Device
from .grids import held_values, parameter_grid
from .settled import settle_attractors
from ..dynamics import kernels as K
from .windows import check_window, empty_windows, last_bottom_impact, run_window, window_dataset, window_limits

__all__ = ["sweep"]


def sweep(vary: str, values, *, beta: float, phi: float = 0.0, v0: float = 0.5, max_periods: float = 200,
          max_events: int = 200_000, tol: float = 1e-9, window: int = 65, pmax: int = 64,
          progress: bool | None = None, long_impacts: int | None = None, device: Device | None = None,
          batch: bool = True, **held) -> xr.Dataset:
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
        Impacts of the long run of every point with no period (:func:`~vibroimpact.analysis.settled.settle_attractors`; default
        :data:`vibroimpact.analysis.settled.LONG_IMPACTS`, 0: none).
    device : Device, optional
        The harvester (default the paper's, ``Device()``): its mass, forcing, gravity and restitution.
    batch : bool
        Whether the points' runs go in one compiled call, the two directions side by side, and the long runs
        of :func:`~vibroimpact.analysis.settled.settle_attractors` side by side (the default); ``False`` makes
        every run from Python, one after the other: the reference the batched path is tested against (the
        same dataset, to the last bit).
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
        well-posed about each attractor (:func:`~vibroimpact.analysis.settled.settle_attractors`): ``settled`` and ``settle_status``, its exact
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
    check_window(window, pmax)
    device, held = held_values(device, held)
    held.pop("beta", None)
    d, gbar, s_arr, F_arr = parameter_grid(vary, values, beta=beta, device=device, **held)
    order = np.argsort(d)
    d, gbar, s_arr, F_arr = d[order], gbar[order], s_arr[order], F_arr[order]
    r = device.r
    m = d.shape[0]
    win = empty_windows((2, m), window)
    ends = K.WindowEnds(status=np.zeros((2, m), np.int8), lag=np.zeros((2, m), np.int64),
                        total=np.zeros((2, m), np.int64), n=np.zeros((2, m), np.int64))
    starts = np.zeros((2, m, 2))
    follow = _follow_chains if batch else _follow_points
    with Progress(2 * m, f"sweep of {vary} (up and down)", progress, unit="point") as bar:
        follow((d, gbar, r), (phi, v0), (max_periods, max_events, tol, window, pmax), (win, ends, starts), bar)
    st, lag, tot, nw = ends
    ds = window_dataset(win, st, lag, tot, nw, dims=("direction", "point"))
    ds = settle_attractors(ds, d[None, :], gbar[None, :], r, long_impacts=long_impacts, tol=tol, batch=batch)
    ds = ds.assign_coords(direction=["up", "down"], point=np.arange(m), d=("point", d), gbar=("point", gbar),
                          s=("point", s_arr), F=("point", F_arr))
    ds["start_phi"] = (("direction", "point"), starts[..., 0], {"units": "rad", "long_name": "phase of the start impact"})
    ds["start_v0"] = (("direction", "point"), starts[..., 1], {"units": "1", "long_name": "pre-impact velocity of the start impact"})
    ds["s"].attrs.update(units="m", long_name="cylinder length s")
    ds["F"].attrs.update(units="N", long_name="forcing amplitude ||F||")
    ds.attrs.update(vary=vary, beta=beta, r=r, max_periods=max_periods, tol=tol, window=int(window), pmax=int(pmax),
                    first_phi=phi, first_v0=v0, **held, **device.attrs())
    return annotate(ds)


def _follow_chains(dgr, first, settings, out, bar):
    """Both directions' points in compiled calls (:func:`~vibroimpact.dynamics.kernels.chain_windows`), the two
    side by side, in tenths; ``settings``: ``(max_periods, max_events, tol, window, pmax)``; ``out``: the windows,
    their ends and the starts used, filled in."""
    d, gbar, r = dgr
    max_periods, max_events, tol, _, pmax = settings
    limits = window_limits(max_periods, max_events, tol, pmax)
    win, ends, starts = out
    m = d.shape[0]
    order = np.stack([np.arange(m), np.arange(m - 1, -1, -1)])
    chain = K.Chain(d=np.ascontiguousarray(d, dtype=float), gbar=np.ascontiguousarray(gbar, dtype=float), r=float(r),
                    order=order, start=np.array([first, first], dtype=float), used=starts)
    cuts = np.linspace(0, m, 11 if m >= 20 else 2).astype(int)  # in tenths, for the bar and the log
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        K.chain_windows(chain, (int(a), int(b)), limits, win, ends)
        bar.update(2 * int(b - a))


def _follow_points(dgr, first, settings, out, bar):
    """:func:`_follow_chains` one point at a time from Python (:func:`~vibroimpact.analysis.windows.run_window`),
    up then down: the reference of the compiled chains."""
    d, gbar, r = dgr
    win, ends, starts = out
    m = d.shape[0]
    for k_dir, idx in enumerate((range(m), range(m - 1, -1, -1))):
        start = first
        for i in idx:
            bar.update()
            w1, *res = run_window(d[i], gbar[i], r, start[0], start[1], *settings)
            for arr, x in zip(ends, res, strict=True):
                arr[k_dir, i] = x
            starts[k_dir, i] = start
            for arr, w in zip(win, w1, strict=True):
                arr[k_dir, i] = w
            start = last_bottom_impact(*w1, int(res[3])) or start
