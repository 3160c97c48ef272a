"""Located transitions: where the motion a sweep follows changes, to a tolerance in d, and what kind of change
it is (:func:`vibroimpact.analysis.motions.transition_kind`)."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .._progress import Progress
from .motions import APERIODIC, motion_without_period, transition_kind
from .settled import split_no_period
from .windows import EVENT_VARS, last_bottom_impact, run_window, window_motion, window_motions

__all__ = ["locate_transitions"]


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
    beta, r, tol = float(sw.attrs["beta"]), float(sw.attrs["r"]), float(sw.attrs["tol"])
    # the sweep's own window and longest period (a sweep written without them used the defaults)
    window, pmax = int(sw.attrs.get("window", 65)), int(sw.attrs.get("pmax", 64))
    g0, dvals = sw["gbar"].values, sw["d"].values
    motions = window_motions(sw)
    ev = [sw[v].values for v in EVENT_VARS]
    rows = []
    bar = Progress(len(sw.direction) * (len(dvals) - 1), "locate transitions", progress, unit="point")
    for k_dir, name in enumerate(sw.direction.values):
        sign = 1.0 if name == "up" else -1.0
        order = range(len(dvals) - 1) if name == "up" else range(len(dvals) - 1, 0, -1)
        last_end = None
        for i in order:
            bar.update()
            j = i + 1 if name == "up" else i - 1
            before = motions[k_dir, i]
            if before == motions[k_dir, j] or not before.periodic:
                continue
            if last_end is not None and sign * (dvals[i] - last_end) < 0:
                continue  # this change was already passed by the previous located transition
            n = int(np.sum(np.isfinite(ev[0][k_dir, i])))
            start = last_bottom_impact(*(e[k_dir, i] for e in ev), n) or (
                float(sw["start_phi"][k_dir, i]), float(sw["start_v0"][k_dir, i]))
            slope = (g0[j] - g0[i]) / (dvals[j] - dvals[i])  # gbar is affine in d for both sweeps

            def follow(trial, start, gi=g0[i], slope=slope, di=dvals[i]):
                win, st, lag, _, nw = run_window(trial, gi + slope * (trial - di), r, start[0], start[1],
                                                 max_periods, max_events, tol, window, pmax)
                return window_motion(win, nw, st, lag)[0], last_bottom_impact(*win, nw) or start

            x, y, after, after_start, refined = _follow_to_change(
                follow, before, start, (dvals[i], dvals[j]), motions[k_dir, j], sign,
                (float(dvals.min()), float(dvals.max())), xtol, max_trials)
            last_end = y
            if after.kind == APERIODIC and after_start is not None:  # what the motion beyond is: its long run says
                after = motion_without_period(split_no_period(y, g0[i] + slope * (y - dvals[i]), r, *after_start,
                                                              tol=tol).label)
            status = "refined" if refined else f"not refined: {max_trials} runs (max_trials) left a bracket of {abs(y - x):.1e}"
            rows.append((name, 0.5 * (x + y), abs(y - x), before.label, after.label, transition_kind(before, after),
                         status))
    bar.close()
    return _transitions_dataset(rows, beta, xtol, max_periods)


def _follow_to_change(follow, before, start, grid, after, sign, d_range, xtol, max_trials):
    """Follow ``before`` from the grid point ``grid[0]`` towards ``grid[1]`` (where ``after`` was found) by the
    adaptive continuation of :func:`locate_transitions`: ``(x, y, after, after_start, refined)``, ``x`` the
    last d with the old motion, ``y`` the nearest d beyond it without, ``after`` the motion there and
    ``after_start`` where it was last seen (its window's last bottom impact)."""
    # the step doubles (up to the grid step) after a run that keeps the motion and halves after one that
    # loses it
    x, y = grid
    h_grid = abs(y - x)
    h = h_grid
    after_start = None
    y_checked = False  # y re-run from an attractor within 1e-3 grid steps of it
    for _ in range(max_trials):
        if (abs(y - x) < max(1e-3 * h_grid, 4 * xtol) or h <= xtol) and not y_checked:
            # a failure far from the attractor it started on may be a jump out of a thin basin
            motion, nxt = follow(y, start)
            y_checked = True
            if motion == before:
                x, start, y, h, y_checked = y, nxt, y + sign * h_grid, h_grid, False
                continue
        if h <= xtol:
            return x, y, after, after_start, True
        trial = x + sign * h
        if not d_range[0] <= trial <= d_range[1]:
            h *= 0.5
            continue
        motion, nxt = follow(trial, start)
        if motion == before:
            x, start = trial, nxt
            h = min(2 * h, h_grid, 0.5 * abs(y - x))
        else:
            y, after, after_start, y_checked = trial, motion, nxt, False
            h = min(0.5 * h, 0.5 * abs(y - x))
    return x, y, after, after_start, False


def _transitions_dataset(rows, beta, xtol, max_periods):
    """The located transitions' dataset (:func:`locate_transitions`'s Returns)."""
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
