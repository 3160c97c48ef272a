"""Located transitions: where the motion a sweep follows changes, to a tolerance in d, and what kind of change
it is (:func:`vibroimpact.analysis.motions.transition_kind`); among the periods lost, the period doublings, placed
at their flips (:func:`period_doublings`)."""

from __future__ import annotations

import math
import threading
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np
import xarray as xr

from .._progress import Progress
from .motions import (
    APERIODIC,
    CHAOTIC,
    NO_PERIOD_LABELS,
    Motion,
    motion_without_period,
    orbit_motion,
    transition_kind,
)
from .settled import split_no_period
from .windows import EVENT_VARS, last_bottom_impact, run_window, window_motion, window_motions

__all__ = ["locate_transitions", "period_doublings", "PERIOD_DOUBLING"]


def locate_transitions(sw: xr.Dataset, *, xtol: float = 1e-7, max_periods: float = 20_000,
                       max_events: int = 2_000_000, max_trials: int = 200,
                       progress: bool | None = None, workers: int | None = None) -> xr.Dataset:
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
        Longest transient per run (forcing periods) and cap on its events (by default 20 000 periods and
        2 000 000 events, a hundred events a period).
    max_trials : int
        Runs allowed per transition.
    progress : bool, optional
        A progress bar over the changes looked for (default: only when run interactively).
    workers : int, optional
        Threads locating the changes side by side (default: numba's thread count); the result is the same
        for any number.

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
    chains = _candidates(sw, motions)
    bar = Progress(sum(map(len, chains)), "locate transitions", progress, unit="change")

    def locate(task):
        k_dir, name, i, j = task
        sign = 1.0 if name == "up" else -1.0
        before = motions[k_dir, i]
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
        if after.kind == APERIODIC and after_start is not None:  # what the motion beyond is: its long run says
            after = motion_without_period(split_no_period(y, g0[i] + slope * (y - dvals[i]), r, *after_start,
                                                          tol=tol).label)
        status = "refined" if refined else f"not refined: {max_trials} runs (max_trials) left a bracket of {abs(y - x):.1e}"
        bar.update()
        return y, (name, 0.5 * (x + y), abs(y - x), before.label, after.label, transition_kind(before, after), status)

    def passed(task, last_end):  # this change was already passed by the previous located transition
        sign = 1.0 if task[1] == "up" else -1.0
        return last_end is not None and sign * (dvals[task[2]] - last_end) < 0

    rows = _run_chains(chains, locate, passed, numba.get_num_threads() if workers is None else int(workers))
    bar.close()
    return _transitions_dataset(rows, beta, xtol, max_periods)


def _candidates(sw, motions):
    """Per direction, in the sweep's order, the neighbouring points ``(k_dir, name, i, j)`` whose motions differ
    where the first has a period: where :func:`locate_transitions` looks for a change."""
    m = sw.sizes["point"]
    chains = []
    for k_dir, name in enumerate(sw.direction.values):
        order = range(m - 1) if name == "up" else range(m - 1, 0, -1)
        step = 1 if name == "up" else -1
        chains.append([(k_dir, str(name), i, i + step) for i in order
                       if motions[k_dir, i] != motions[k_dir, i + step] and motions[k_dir, i].periodic])
    return chains


def _run_chains(chains, run, passed, workers):
    """The rows of ``run(task)`` (``(end, row)``) over each chain of tasks in order, a task left out where
    ``passed(task, end)`` with the ``end`` of the last task kept before it: the same rows as running the
    chains one task after the other, computed on up to ``workers`` threads (the kernels release the GIL).

    A thread takes the next task whose predecessors are all settled (deciding on the way which are passed
    over); where none is, it computes one ahead (its result is used only if the task turns out to be kept)."""
    state = _ChainState(chains, passed)
    if workers > 1 and sum(map(len, chains)) > 1:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            for f in [pool.submit(state.work, run) for _ in range(workers)]:
                f.result()
    else:
        state.work(run)
    return state.rows()


class _ChainState:
    """Which tasks of :func:`_run_chains` are started, done, kept or passed over (under one lock)."""

    def __init__(self, chains, passed):
        self.chains, self.passed = chains, passed
        self.results = [dict() for _ in chains]
        self.started = [set() for _ in chains]
        self.settled = [0] * len(chains)  # tasks before this index are decided (kept and done, or passed)
        self.kept = [[] for _ in chains]
        self.last = [None] * len(chains)
        self.lock = threading.Lock()

    def _settle(self, c):
        """Decide chain ``c``'s tasks in order as far as their predecessors' ends are known."""
        tasks = self.chains[c]
        while self.settled[c] < len(tasks):
            k = self.settled[c]
            if self.passed(tasks[k], self.last[c]):
                self.settled[c] += 1
            elif k in self.results[c]:
                self.last[c] = self.results[c][k][0]
                self.kept[c].append(k)
                self.settled[c] += 1
            else:
                return

    def _next(self):
        """The next task to compute: ``(chain, index)`` or None when every needed one is started."""
        for c in range(len(self.chains)):
            self._settle(c)
        ahead = None
        for c, tasks in enumerate(self.chains):
            todo = [k for k in range(self.settled[c], len(tasks)) if k not in self.started[c]]
            if todo and todo[0] == self.settled[c]:
                return c, todo[0]  # its predecessors are decided: it is needed
            if todo and (ahead is None or len(todo) > ahead[2]):
                ahead = (c, todo[0], len(todo))
        return ahead and ahead[:2]

    def work(self, run):
        while True:
            with self.lock:
                nxt = self._next()
                if nxt is None:
                    return
                self.started[nxt[0]].add(nxt[1])
            res = run(self.chains[nxt[0]][nxt[1]])
            with self.lock:
                self.results[nxt[0]][nxt[1]] = res

    def rows(self):
        for c in range(len(self.chains)):
            self._settle(c)
        return [self.results[c][k][1] for c in range(len(self.chains)) for k in self.kept[c]]


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


#: the kind of a located transition at a flip of the orbit it leaves or reaches (an eigenvalue -1), whichever
#: way the sweep crosses it (:func:`period_doublings`)
PERIOD_DOUBLING = "period doubling"


def period_doublings(transitions: xr.Dataset, sw: xr.Dataset, branches=()) -> xr.Dataset:
    """Name the located transitions that are period doublings, and place each at its flip.

    Near a period doubling (a flip: an eigenvalue of the orbit's monodromy matrix at -1) the attractor
    converges ever more slowly (critical slowing), from either side.  :func:`locate_transitions` follows it
    with runs of at most ``max_periods`` forcing periods, so its detector gives up short of the flip, where
    the transient outlasts the cap, and records a period lost (``"no period found"``, named by its long run:
    its lambda_1 is near 0 there, so mostly quasi-periodic or unsettled).  That label change is where the
    detector gave up, not the bifurcation.  A located transition from a motion with a period to one without
    is a **period doubling** when

    * **at a branch's B**: a continued branch on the sweep's line of parameters (the same gbar at the same d,
      the same r) whose orbit is that motion, or that motion over half its period, has a flip (``critical_kind
      == "B"``, admissible) ahead of the transition in the sweep's direction, within the half-width of
      critical slowing ``delta = k ln(1/tol) / (|dlambda/dd| max_periods)`` of it: with the multiplier
      ``lambda(d) = -1 + (dlambda/dd) (d - B)`` (the branch's, between its two points around B) a transient
      of size 1 shrinks by ``|lambda|`` per ``k`` forcing periods, and within ``delta`` of B it does not reach
      the sweep's ``tol`` in ``max_periods`` (beyond B the doubled orbit converges faster, at about twice the
      rate, so the same ``delta`` bounds both sides).  The flip is located at B (Newton's method and the
      eigenvalue -1, to the branch's xtol); its uncertainty is the measured distance from B to where the
      detector gave up (the far end of the transition's bracket), so that it covers the slowing;
    * **between two identifications** (where no branch applies): the nearest motion either sweep identifies
      beyond the transition (a grid point's or the other direction's located transition's last d) is the
      same motion over twice or half the period (the same impacts per forcing period), and the transition's
      sweep found no chaos between: the flip lies in that bracket, located at its middle, uncertain by half its
      width.

    A period lost into chaos (its long run's lambda_1 above 0) is not the slowing near a flip, where lambda_1
    tends to 0, and stays a period lost.

    The motion past the flip, ``beyond``, is the doubled (or halved) motion where a sweep identifies it next
    beyond the flip, and empty where it does not (a flip past which the sweeps find another motion).  Applied
    again (to transitions it named, with other branches), it names them afresh.

    Parameters
    ----------
    transitions : xarray.Dataset
        The sweep's located transitions (:func:`locate_transitions`).
    sw : xarray.Dataset
        The sweep (:func:`sweep`).
    branches : sequence of xarray.Dataset
        Continued branches (:func:`continue_orbit`); those on another line of parameters, failed or without
        critical points are not used.

    Returns
    -------
    xarray.Dataset
        ``transitions`` with ``kind`` set to ``"period doubling"`` where one is found, and along
        ``transition``: ``bifurcation_d`` (the flip's d; NaN where the transition is no period doubling),
        ``bifurcation_d_width`` (twice its uncertainty), ``bifurcation_source`` (the branch's motion whose B it
        is, ``"sweeps"``, or empty), ``beyond`` (the motion past the flip) and ``slowing_width`` (twice
        ``delta``, where a branch gives it).  ``d``, ``d_width``, ``before`` and ``after`` keep where the
        detector's label changed and what it found there.

    Examples
    --------
    A length sweep at beta = pi/3 over the 2:1 period doubling, with short transients (2000 forcing periods): the
    up sweep's detector gives up below the flip, the down sweep's above it; with the 2:1 branch both are placed
    at its B, and past it each sweep finds the other side's motion:

    >>> import math, numpy as np, vibroimpact as vi
    >>> sw = vi.sweep("s", np.array([0.156, 0.158, 0.160]) / 0.6225, beta=math.pi / 3, phi=1.0, v0=0.2,
    ...               max_periods=2000, long_impacts=0)
    >>> tr = vi.locate_transitions(sw, max_periods=2000)
    >>> tr.direction.values.tolist(), tr.before.values.tolist(), tr.d.values.round(5).tolist()
    (['up', 'down'], ['2:1 period-4', '2:1 period-2'], [0.158, 0.15827])
    >>> o = vi.find_orbit(vi.Params.from_physical(s=0.17 / 0.6225, beta=math.pi / 3), "BBT", 1.0, 0.2)
    >>> pd = vi.period_doublings(tr, sw, [vi.continue_orbit(o, vary="s", d_range=(0.155, 0.171))])
    >>> pd.kind.values.tolist(), pd.bifurcation_d.values.round(7).tolist(), pd.beyond.values.tolist()
    (['period doubling', 'period doubling'], [0.1580747, 0.1580747], ['2:1 period-2', '2:1 period-4'])
    """
    n = transitions.sizes.get("transition", 0)
    kinds = transitions["kind"].values.astype(str).copy() if n else np.array([], str)
    found = [None] * n
    if n:
        seen = _identified(transitions, sw)
        flips = _flips(sw, branches, float(sw.attrs["tol"]), float(transitions.attrs["max_periods"]))
        for k in range(n):
            before, after = seen["motions"].get(str(transitions.before.values[k])), str(transitions.after.values[k])
            if before is None or not before.periodic or after not in NO_PERIOD_LABELS:
                continue
            # the detector's kind (a period lost), whether or not a call before named it
            kinds[k] = transition_kind(before, motion_without_period(after))
            if after == CHAOTIC:
                continue  # lambda_1 > 0: chaos, not the slowing near a flip (lambda_1 -> 0 there)
            direction = str(transitions.direction.values[k])
            sign = 1.0 if direction == "up" else -1.0
            d, w = float(transitions.d.values[k]), float(transitions.d_width.values[k])
            x, far = d - sign * w / 2, d + sign * w / 2  # the last d with the motion, the first without it
            found[k] = (_at_flip(before, x, far, sign, flips, seen)
                        or _between(before, x, sign, seen, direction))
            if found[k] is not None:
                kinds[k] = PERIOD_DOUBLING
    return _with_doublings(transitions, kinds, found)


def _with_doublings(transitions, kinds, found):
    """The transitions with their kinds and the variables of :func:`period_doublings` (``found``: per transition,
    ``(bifurcation_d, its width, source, beyond, slowing width)`` or None)."""
    tr = transitions.copy()
    nan = (np.nan, np.nan, "", "", np.nan)
    cols = list(zip(*[f or nan for f in found], strict=True)) if found else [()] * 5
    tr["kind"] = ("transition", np.asarray(kinds).astype(str), tr["kind"].attrs)
    tr["bifurcation_d"] = ("transition", np.array(cols[0], float), {
        "units": "1", "long_name": "d of the period doubling (flip) the transition is: a branch's B, or the middle "
        "of the sweeps' bracket"})
    tr["bifurcation_d_width"] = ("transition", np.array(cols[1], float), {
        "units": "1", "long_name": "twice the uncertainty of bifurcation_d: it covers where the detector gave up "
        "(critical slowing)"})
    tr["bifurcation_source"] = ("transition", np.array(cols[2], dtype=object).astype(str), {
        "long_name": "where bifurcation_d comes from: the branch (its motion) whose B it is, or the sweeps"})
    tr["beyond"] = ("transition", np.array(cols[3], dtype=object).astype(str), {
        "long_name": "the motion past the period doubling, as a sweep identifies it next (empty: not identified)"})
    tr["slowing_width"] = ("transition", np.array(cols[4], float), {
        "units": "1", "long_name": "twice the half-width of critical slowing around the branch's B, within which "
        "the detector cannot identify the motion"})
    return tr


def _twice(m: Motion) -> Motion:
    return Motion(period=2 * m.period, bottom=2 * m.bottom, top=2 * m.top, sticking=m.sticking)


def _partners(m: Motion) -> list[Motion]:
    """The motion over twice and (where whole) half its period: the two sides of a flip."""
    out = [_twice(m)]
    if m.period % 2 == 0 and m.bottom % 2 == 0 and m.top % 2 == 0:
        out.append(Motion(period=m.period // 2, bottom=m.bottom // 2, top=m.top // 2, sticking=m.sticking))
    return out


def _identified(tr: xr.Dataset, sw: xr.Dataset) -> dict:
    """Where each sweep identified which motion: every grid point's motion, and every located transition's last
    d with its motion before and, where it has a period, its first d with the motion after; the d of each
    direction's chaotic points; each motion by its label."""
    motions = window_motions(sw)
    dv = sw["d"].values
    at, chaotic, by_label = [], {str(n): [] for n in sw.direction.values}, {}
    for idx in np.ndindex(motions.shape):
        m = motions[idx]
        by_label.setdefault(m.label, m)
        if m.periodic:
            at.append((float(dv[idx[-1]]), m.label))
        elif m.kind == CHAOTIC:
            chaotic[str(sw.direction.values[idx[0]])].append(float(dv[idx[-1]]))
    for k in range(tr.sizes["transition"]):
        sign = 1.0 if str(tr.direction.values[k]) == "up" else -1.0
        d, half = float(tr.d.values[k]), float(tr.d_width.values[k]) / 2
        at.append((d - sign * half, str(tr.before.values[k])))
        if str(tr.after.values[k]) not in NO_PERIOD_LABELS:
            at.append((d + sign * half, str(tr.after.values[k])))
    return {"at": at, CHAOTIC: {k: np.array(v) for k, v in chaotic.items()}, "motions": by_label}


def _next_identified(x, sign, seen):
    """The nearest identification beyond ``x`` in the direction ``sign``: ``(d, label)`` or None."""
    ahead = [(sign * (d - x), d, lab) for d, lab in seen["at"] if sign * (d - x) > 0]
    return min(ahead)[1:] if ahead else None


def _chaotic_between(a, b, seen, direction):
    """Whether the sweep's ``direction`` found chaos strictly between ``a`` and ``b``."""
    lo, hi = min(a, b), max(a, b)
    c = seen[CHAOTIC][direction]
    return bool(np.any((c > lo) & (c < hi)))


def _flips(sw, branches, tol, max_periods):
    """Every admissible B point of the branches on the sweep's line of parameters: ``(B, motion, delta)``, delta
    the half-width of critical slowing (:func:`period_doublings`)."""
    d, g = sw["d"].values, sw["gbar"].values
    line = np.polyfit(d, g, 1) if d.size > 1 else (0.0, float(g[0]))
    out = []
    for br in branches:
        if br.attrs.get("status") == "failed" or "critical_kind" not in br or not br.sizes.get("point"):
            continue
        if not math.isclose(float(br.attrs["r"]), float(sw.attrs["r"]), rel_tol=1e-12):
            continue
        k = int(br.attrs.get("k", 1))
        for kind, b, ok in zip(br.critical_kind.values.astype(str), br.critical_d.values,
                               br.critical_admissible.values, strict=True):
            if kind != "B" or not ok:
                continue
            g_branch = float(br.attrs["gbar_intercept"]) + float(br.attrs["gbar_slope"]) * b
            if not math.isclose(g_branch, float(np.polyval(line, b)), rel_tol=1e-9, abs_tol=1e-12):
                continue  # another line of parameters (another force, another incline)
            slope = _multiplier_slope(br, float(b))
            if not math.isfinite(slope) or slope == 0:
                continue
            delta = k * math.log(1 / tol) / (abs(slope) * max_periods)
            out.append((float(b), orbit_motion(str(br.attrs["word"]), k), delta))
    return out


def _multiplier_slope(br, b) -> float:
    """d lambda / d d of the real eigenvalue that crosses -1 at ``b``, between the two neighbouring points of
    the branch around it (NaN where none is found)."""
    d = br.d.values
    lam = np.where(np.abs(br.eig_imag.values) < 1e-12, br.eig_real.values, np.nan)
    best = (math.inf, math.nan)
    for i in range(d.size - 1):
        if not (min(d[i], d[i + 1]) <= b <= max(d[i], d[i + 1])) or d[i] == d[i + 1]:
            continue
        for e in range(lam.shape[1]):
            a, c = lam[i, e], lam[i + 1, e]
            if np.isfinite(a) and np.isfinite(c) and (a + 1) * (c + 1) <= 0:
                gap = abs(d[i + 1] - d[i])
                if gap < best[0]:
                    best = (gap, float((c - a) / (d[i + 1] - d[i])))
    return best[1]


def _at_flip(before, x, far, sign, flips, seen):
    """The flip of a branch the transition from ``before`` (last seen at ``x``, gone at ``far``) runs into."""
    best = None
    for b, motion, delta in flips:
        if before.label not in (motion.label, _twice(motion).label):
            continue
        if sign * (b - x) < 0 or abs(b - x) > delta:
            continue  # behind the transition, or beyond the slowing
        nxt = _next_identified(x, sign, seen)
        if nxt is not None and sign * (nxt[0] - b) < 0:
            continue  # a motion identified between the transition and the flip
        if best is None or abs(b - x) < abs(best[0] - x):
            other = _twice(motion).label if before.label == motion.label else motion.label
            best = (b, motion, delta, other if nxt is not None and nxt[1] == other else "")
    if best is None:
        return None
    b, motion, delta, past = best
    return b, 2 * max(abs(x - b), abs(far - b)), motion.label, past, 2 * delta


def _between(before, x, sign, seen, direction):
    """The flip between the transition's last sight of ``before`` at ``x`` and the next identification
    beyond, where that is ``before`` over twice or half its period and the transition's sweep found no chaos
    between (the other direction's may follow another, coexisting motion there)."""
    nxt = _next_identified(x, sign, seen)
    if (nxt is None or nxt[1] not in {m.label for m in _partners(before)}
            or _chaotic_between(x, nxt[0], seen, direction)):
        return None
    return 0.5 * (x + nxt[0]), abs(nxt[0] - x), "sweeps", nxt[1], math.nan


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
