"""What is well-posed about a simulated attractor: the exact cycle of a periodic motion, and long-run
statistics of an aperiodic one.

A run is declared periodic once two consecutive cycles agree to the periodicity tolerance, so the
impacts it records are the orbit's only to within that tolerance divided by the distance of the
orbit's largest eigenvalue from the unit circle: near a period doubling or a fold (1e-6 and worse
measured along the paper's sweeps) they depend on where the transient happened to stop, and a
last-bit change of one ``sin`` moves them.  :func:`polish_cycle` solves the periodic orbit through
the recorded cycle by Newton's method (:func:`vibroimpact.analysis.orbits.solve_orbit`) and returns it from a
canonical first impact, so the values are the orbit's to rounding, wherever the run stopped.  A cycle
that sticks is the orbit already (every state that sticks leaves the wall at the release phase), to the
accuracy of its summed chatter.

Where no period is found (chaos, a quasi-periodic motion, a period longer than the cap, or a transient
longer than the allowed time), single impacts and short-window averages are samples of the motion and
part company between two machines after a few impacts; what is reproducible is their long-run
statistics.  :func:`long_run` continues the motion for a fixed number of impacts and returns the
batch means of what the figures draw, with their standard errors.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..dynamics import kernels as K
from ..dynamics.flight import PI, TWO_PI
from ..dynamics.params import Params
from ..dynamics.runs import simulate
from .lyapunov import exponents_of_events, exponents_of_run, multiplier_sensitivity
from .motions import no_period_label
from .orbits import OrbitError, orbit_from_vector, parse_word, solve_orbit, step_jacobians
from .windows import EVENT_VARS, last_bottom_impact

__all__ = ["polish_cycle", "long_run", "long_runs", "long_statistics", "batch_means", "canonical_start", "split_no_period",
           "NoPeriodSplit",
           "settle_attractors",
           "SETTLE_MATCH", "STICK_REL", "LONG_IMPACTS", "LONG_BATCHES"]

#: a Newton orbit is the recorded cycle's own when every impact's velocity and phase lie within this of
#: the recorded ones (the recorded cycle converged to the periodicity tolerance divided by the orbit's
#: distance from a bifurcation: up to 2e-4 was measured; distinct orbits of one word lie further apart)
SETTLE_MATCH = 1e-3
#: relative accuracy of a sticking cycle's values: its chatter is summed where the acceleration changes
#: by less than 1e-9 of itself before the bounces accumulate (vibroimpact.dynamics.kernels), and two machines'
#: sticking cycles were measured 1.06e-9 apart (relative) in the design maps' outputs
STICK_REL = 1e-9
#: impacts of an aperiodic motion's long run, and the batches its means are taken over
LONG_IMPACTS = 4000
LONG_BATCHES = 20


def canonical_start(wall, kind, phase) -> int:
    """Index of the cycle's canonical first event: the bottom impact with the smallest phase (any
    event with the smallest phase where the cycle has no bottom impact).  Phases are well-conditioned,
    so two runs of the same orbit start its cycle at the same impact."""
    wall, kind, phase = (np.asarray(a) for a in (wall, kind, phase))
    ph = np.mod(phase, TWO_PI)
    cand = np.flatnonzero((wall == 1) & (kind == K.IMPACT))
    if not cand.size:
        cand = np.arange(ph.size)
    return int(cand[np.argmin(ph[cand])])


def polish_cycle(d, gbar, r, t, wall, v_minus, phase, kind, span) -> dict:
    """The exact periodic orbit through one recorded cycle of a run.

    Parameters
    ----------
    d, gbar, r : float
        Parameters.
    t, wall, v_minus, phase, kind : array_like
        The cycle's events in order (one period: from an event up to, not including, its return).
    span : float
        The cycle's duration (a whole number of forcing periods, 2 time units each), e.g. from an
        event to the same event one period earlier.

    Returns
    -------
    dict
        ``status``: ``"newton"`` (solved; the orbit matches the cycle to :data:`SETTLE_MATCH`),
        ``"sticking"`` (the recorded cycle: it sticks, so it is the orbit to :data:`STICK_REL`; not
        settled), or why it is not settled (a grazing
        contact, Newton failed, another orbit, not admissible); ``settled`` (bool); and the cycle from
        its canonical first event (:func:`canonical_start`): ``t`` (from 0), ``wall``, ``v_minus``,
        ``phase``, ``kind``; where settled, the orbit's ``jacobian`` (its map's over one period, eq.
        ``Lin2``), its factors ``step_jacobians`` (one per flight) and ``multipliers`` (its eigenvalues).

    Examples
    --------
    The 2:1 cycle of a run at the point of Figure 7 (a), solved exactly: its multipliers are a complex pair
    of modulus ``r^N = 0.125`` for ``N = 3`` impacts (the map's determinant is ``r^(2N)``):

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
    >>> a = vi.identify_attractor(vi.simulate(p, phi=1.015, v0=0.1924, n_impacts=200))
    >>> c = a.cycle
    >>> orbit = vi.polish_cycle(p.d, p.gbar, p.r, c.t.values, c.wall.values, c.v_minus.values, c.phase.values,
    ...                         c.kind.values, span=2.0 * a.period)
    >>> orbit["status"], orbit["settled"], orbit["wall"].tolist()
    ('newton', True, [1, -1, 1])
    >>> [round(float(abs(m)), 9) for m in orbit["multipliers"]]
    [0.125, 0.125]
    """
    t, v_minus, phase = (np.asarray(a, dtype=float) for a in (t, v_minus, phase))
    wall, kind = np.asarray(wall, dtype=np.int8), np.asarray(kind, dtype=np.int8)
    n = t.size
    j0 = canonical_start(wall, kind, phase)
    k = max(int(round(float(span) / 2.0)), 1)
    span = 2.0 * k
    order = np.roll(np.arange(n), -j0)
    tt = np.mod(t[order] - t[j0], span)
    out = dict(t=tt, wall=wall[order], v_minus=v_minus[order], phase=np.mod(phase[order], TWO_PI),
               kind=kind[order], status="", settled=False)
    if np.any((kind == K.STICK) | (kind == K.RELEASE)):  # its chatter's last bounces are grazing contacts
        # every state that sticks leaves the wall at the release phase, so the recorded cycle is the orbit,
        # to the accuracy of its summed chatter (STICK_REL), not to rounding
        return out | dict(status="sticking")
    if np.any(kind == K.GRAZING):
        return out | dict(status="not settled: a grazing contact in the cycle")
    tau = np.diff(np.append(tt, span))
    z0 = np.concatenate([[out["phase"][0]], tau, out["v_minus"]])
    word = "".join("B" if w == 1 else "T" for w in out["wall"])
    try:
        z = solve_orbit(z0, out["wall"].astype(np.int64), d, gbar, r, k)
        o = orbit_from_vector(Params(d=d, gbar=gbar, r=r), word, k, z)
    except (OrbitError, ValueError, np.linalg.LinAlgError) as err:
        return out | dict(status=f"not settled: Newton failed ({err})")
    dphase = (o.phase - out["phase"] + np.pi) % TWO_PI - np.pi
    dev = max(float(np.max(np.abs(o.v_minus - out["v_minus"]))), float(np.max(np.abs(dphase))))
    if not dev <= SETTLE_MATCH:
        return out | dict(status=f"not settled: the Newton orbit lies {dev:.1e} from the cycle")
    if not o.admissible:
        return out | dict(status=f"not settled: the Newton orbit is not admissible ({o.reason})")
    return out | dict(t=o.t, v_minus=np.array(o.v_minus), phase=np.array(o.phase), status="newton", settled=True,
                      multipliers=np.asarray(o.eigenvalues), jacobian=np.asarray(o.jacobian),
                      step_jacobians=step_jacobians(o.z, parse_word(o.word), float(gbar), float(r)))


def batch_means(values, batches: int = LONG_BATCHES):
    """Mean and its standard error from ``batches`` consecutive batches of equal length."""
    v = np.asarray(values, dtype=float)
    m = v.size // batches
    if m < 1:
        return np.nan, np.nan
    b = v[:m * batches].reshape(batches, m).mean(axis=1)
    return float(b.mean()), float(b.std(ddof=1) / np.sqrt(batches))


def long_run(d, gbar, r, phi, v0, *, impacts: int = LONG_IMPACTS, tol: float = 1e-9) -> dict:
    """An aperiodic motion continued for ``impacts`` events from a bottom impact ``(phi, v0)``.

    The start is typically the last bottom impact of a run that found no period.

    Parameters
    ----------
    d, gbar, r : float
        Parameters.
    phi, v0 : float
        Phase (rad) and pre-impact velocity of the bottom impact it starts from.
    impacts : int
        Events of the continuation.
    tol : float
        Periodicity tolerance: the continuation stops if it becomes periodic.

    Returns
    -------
    dict
        ``status``: ``"aperiodic"``, or ``"settles"`` when the continuation becomes periodic after all (a
        transient longer than the run that found no period: its statistics depend on where it settles, so
        none are given), or ``"stuck"``; the events ``t``, ``v_minus``, ``kind`` of the continuation
        (impacts and grazing contacts are ``kind`` 0 and 1); and ``exponents``, its Lyapunov exponents
        (:class:`~vibroimpact.analysis.lyapunov.Lyapunov`, the first tenth of it discarded) where it is
        aperiodic; where it settles, those of the same run continued to ``impacts`` impacts (the orbit it
        settles on); else None.

    Examples
    --------
    At d = 0.235 on the incline pi/3 the motion is chaotic: the largest exponent is positive, and the two add
    up to ``2 ln r = -1.386`` per impact (each impact contracts areas by ``r^2``), up to a boundary term of
    order ``1 / impacts``:

    >>> import math, vibroimpact as vi
    >>> gbar = vi.Device().gbar(math.pi / 3)
    >>> run = vi.long_run(0.235, gbar, 0.5, 0.42, 0.87, impacts=2000)
    >>> lam = run["exponents"]
    >>> run["status"], lam.per_impact[0] > 0.1, abs(sum(lam.per_impact) - 2 * math.log(0.5)) < 0.01
    ('aperiodic', True, True)
    """
    run = simulate(Params(d=float(d), gbar=float(gbar), r=float(r)), float(phi), float(v0),
                   n_impacts=int(impacts), stop_when_periodic=True, tol=tol)

    status = {"periodic": "settles", "stuck_forever": "stuck"}.get(run.attrs["status"], "aperiodic")
    lam = None
    if status == "aperiodic":
        lam = exponents_of_run(run, transient=int(impacts) // 10, batches=LONG_BATCHES)
    elif status == "settles":  # its exponents are those of the orbit it settles on: run on, all the impacts
        on = simulate(Params(d=float(d), gbar=float(gbar), r=float(r)), float(phi), float(v0), n_impacts=int(impacts))
        lam = exponents_of_run(on, transient=int(impacts) // 10, batches=LONG_BATCHES)
    return dict(status=status, t=run.t.values, v_minus=run.v_minus.values, kind=run.kind.values, exponents=lam)


def long_statistics(events: dict, batches: int = LONG_BATCHES):
    """Batch means of ``|Zdot-|`` over the impacts of a :func:`long_run`: ``(mean, se)``, NaN unless
    its status is ``"aperiodic"``."""
    if events["status"] != "aperiodic":
        return np.nan, np.nan
    hit = K.hits(events["kind"])
    return batch_means(np.abs(events["v_minus"][hit]), batches)


#: runs of a batch of long runs simulated at once (bounds its buffers: ``impacts`` events each)
LONG_CHUNK = 256


def _run_events(d, gbar, r, phi, v0, *, impacts: int, detect: bool, tol: float) -> list:
    """The events of runs from bottom impacts ``(phi, v0)`` as :func:`~vibroimpact.simulate` records them with
    ``n_impacts=impacts`` and ``stop_when_periodic=detect`` (the same kernel, the same start), side by side on
    numba's threads (:func:`~vibroimpact.dynamics.kernels.run_batch`): per run ``(t, wall, v_minus, phase, kind,
    status name)``."""
    d, gbar, r, phi, v0 = (np.asarray(a, dtype=float).ravel() for a in (d, gbar, r, phi, v0))
    theta0 = np.array([(PI * 0.0 + float(p)) % TWO_PI for p in phi])  # simulate's start phase, at t0 = 0
    settings = K.Settings(t_end=math.inf, v_chatter=K.V_CHATTER, detect=bool(detect), tol=float(tol))
    out = []
    for a in range(0, d.size, LONG_CHUNK):
        sl = slice(a, min(a + LONG_CHUNK, d.size))
        m, n = sl.stop - sl.start, int(impacts)
        bufs = K.EventBuffers(*(np.empty((m, n), np.int8 if v in ("wall", "kind") else float)
                                for v in K.EventBuffers._fields))
        ends = K.Ends(n=np.zeros(m, np.int64), status=np.zeros(m, np.int8), lag=np.zeros(m, np.int64))
        K.run_batch(K.Batch(*(np.ascontiguousarray(x[sl]) for x in (d, gbar, r, theta0, v0))), settings, 64, bufs,
                    ends)
        for k in range(m):
            n_k = int(ends.n[k])
            out.append((*(getattr(bufs, v)[k, :n_k].copy() for v in EVENT_VARS), K.STATUS_NAMES[int(ends.status[k])]))
    return out


def long_runs(d, gbar, r, phi, v0, *, impacts: int = LONG_IMPACTS, tol: float = 1e-9,
              exponents: bool = True) -> list:
    """:func:`long_run` of many starts at once, the runs side by side on numba's threads.

    Parameters
    ----------
    d, gbar, r, phi, v0 : array_like
        Each run's parameters and first bottom impact (1-D, of one length).
    impacts, tol : int, float
        As :func:`long_run`'s.
    exponents : bool
        Whether to estimate the Lyapunov exponents (else each dict's ``exponents`` is None).

    Returns
    -------
    list of dict
        :func:`long_run`'s dict of each run, the same to the last bit.

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> from vibroimpact.analysis.settled import long_runs
    >>> gbar = vi.Device().gbar(math.pi / 3)
    >>> one = vi.long_run(0.235, gbar, 0.5, 0.42, 0.87, impacts=2000)
    >>> many = long_runs([0.235, 0.16], gbar, 0.5, [0.42, 1.0], [0.87, 0.2], impacts=2000)
    >>> [m["status"] for m in many], bool((many[0]["v_minus"] == one["v_minus"]).all())
    (['aperiodic', 'settles'], True)
    >>> many[0]["exponents"].per_impact == one["exponents"].per_impact
    True
    """
    d, gbar, r, phi, v0 = np.broadcast_arrays(*(np.atleast_1d(np.asarray(a, dtype=float)) for a in (d, gbar, r, phi, v0)))
    first = _run_events(d, gbar, r, phi, v0, impacts=impacts, detect=True, tol=tol)
    status = [{"periodic": "settles", "stuck_forever": "stuck"}.get(ev[5], "aperiodic") for ev in first]
    again = [k for k, st in enumerate(status) if st == "settles"] if exponents else []
    # where it settles: its exponents are those of the orbit it settles on, the same run continued (long_run)
    on = dict(zip(again, _run_events(*(a[again] for a in (d, gbar, r, phi, v0)), impacts=impacts, detect=False,
                                     tol=tol), strict=True))
    out = []
    for k, ev in enumerate(first):
        src = ev if status[k] == "aperiodic" else on.get(k)
        lam = None if src is None or not exponents else _tangent_estimate(src, (d[k], gbar[k], r[k]), int(impacts))
        out.append(dict(status=status[k], t=ev[0], v_minus=ev[2], kind=ev[4], exponents=lam))
    return out


def _tangent_estimate(ev, dgr, impacts):
    """:func:`~vibroimpact.analysis.lyapunov.exponents_of_run` of a run of ``impacts`` events (a
    :func:`_run_events` entry), as :func:`long_run` takes it: its first tenth discarded."""
    return exponents_of_events(K.Window(*ev[:5]), K.Model(*(float(x) for x in dgr)), ev[5],
                                transient=impacts // 10, batches=LONG_BATCHES, slow_speed=1e-3, confidence=0.95)


# a record a call returns: its fields are Attributes, not Parameters
@dataclass(frozen=True)
class NoPeriodSplit:  # numpydoc ignore=PR01
    """What a motion with no period is, by its continuation (:func:`split_no_period`).

    Attributes
    ----------
    label : str
        Chaotic, quasi-periodic or unsettled (:func:`~vibroimpact.analysis.motions.no_period_label`).
    status : str
        Of the continuation (:func:`long_run`).
    lyap1, lyap1_low, lyap1_high : float
        Its largest Lyapunov exponent per impact and that exponent's confidence interval.
    lyap1_time : float
        The same exponent per unit time.
    run : dict
        The continuation itself (:func:`long_run`'s dict).
    """

    label: str
    status: str
    lyap1: float
    lyap1_low: float
    lyap1_high: float
    lyap1_time: float
    run: dict


def split_no_period(d, gbar, r, phi, v0, *, impacts: int | None = None, tol: float = 1e-9) -> NoPeriodSplit:
    """Continue a motion with no period from a bottom impact ``(phi, v0)`` (e.g. the last of its window)
    and say what it is (:class:`NoPeriodSplit`)."""
    return _split(long_run(d, gbar, r, phi, v0, impacts=LONG_IMPACTS if impacts is None else int(impacts), tol=tol))


def _split(run: dict) -> NoPeriodSplit:
    """:func:`split_no_period` of a continuation already run (:func:`long_run`'s dict)."""
    lam = run["exponents"]
    nan = float("nan")
    lyap = (lam.per_impact[0], *lam.interval[0], lam.per_time[0]) if lam is not None else (nan,) * 4
    label = no_period_label(run["status"], lyap[1], lyap[2], lam.sticks if lam is not None else 0)
    return NoPeriodSplit(label=label, status=run["status"], lyap1=lyap[0], lyap1_low=lyap[1], lyap1_high=lyap[2],
                         lyap1_time=lyap[3], run=run)


def settle_attractors(ds: xr.Dataset, d, gbar, r, *, long_impacts: int | None = None,
                      tol: float = 1e-9, batch: bool = True) -> xr.Dataset:
    """Add what is well-posed about each attractor of a window dataset (a sweep's or
    :func:`~vibroimpact.analysis.windows.attractor_batch`'s): the exact cycle of a periodic one, the long-run statistics of an
    aperiodic one (:func:`polish_cycle`, :func:`long_run`), and the largest Lyapunov exponent of each.

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
    or a ball at rest, else the long run's tangent estimate (:func:`vibroimpact.lyapunov`).  The long runs
    go side by side on numba's threads (:func:`long_runs`); ``batch=False`` runs them one at a time
    (:func:`long_run`), with the same result.
    """
    long_impacts = LONG_IMPACTS if long_impacts is None else int(long_impacts)
    shape = ds["status"].shape
    d, gbar, r = (np.broadcast_to(np.asarray(a, dtype=float), shape) for a in (d, gbar, r))
    lags = ds["period_events"].values
    status = ds["status"].values
    acc = _settled_arrays(shape, max(int(lags.max()) if lags.size else 1, 1), ds["label"].values)
    ev = {v: ds[v].values for v in EVENT_VARS}
    n_real = np.isfinite(ev["t"]).sum(axis=-1)
    starts = {idx: last_bottom_impact(*(ev[v][idx] for v in EVENT_VARS), int(n_real[idx])) for idx in np.ndindex(shape)}
    dgr = {idx: (d[idx], gbar[idx], r[idx]) for idx in np.ndindex(shape)}
    cyclic = {idx: bool(lags[idx]) and int(n_real[idx]) > int(lags[idx]) for idx in np.ndindex(shape)}
    splits = [(idx, dgr[idx], starts[idx]) for idx in np.ndindex(shape) if not cyclic[idx]
              and int(status[idx]) != K.STUCK_FOREVER and starts[idx] is not None and long_impacts]
    with ThreadPoolExecutor(max_workers=1) as pool:
        # the long runs of the motions with no period go on numba's threads while the cycles are solved here
        pending = pool.submit(_split_runs, splits, long_impacts, tol, batch) if batch else None
        estimates = []  # the periodic runs whose cycle is not solved: (idx, (d, gbar, r), start)
        for idx in np.ndindex(shape):
            n, lag = int(n_real[idx]), int(lags[idx])
            if cyclic[idx]:
                rows = {v: ev[v][idx][:n] for v in EVENT_VARS}
                if _settle_cycle(acc, idx, dgr[idx], rows, n, lag, starts[idx], long_impacts):
                    estimates.append((idx, dgr[idx], starts[idx]))
            elif int(status[idx]) == K.STUCK_FOREVER:  # at rest on the bottom for good: exact
                acc["settled"][idx], acc["status"][idx], acc["long_status"][idx] = True, "stuck", "stuck"
                acc["lyap"][idx] = -np.inf
                acc["source"][idx] = "at rest on the bottom for good"
            else:
                _settle_no_period(acc, idx, starts[idx], long_impacts)
        _estimate(acc, estimates, long_impacts, batch)
        _fill_splits(acc, splits, pending.result() if batch else _split_runs(splits, long_impacts, tol, batch),
                     long_impacts)
    return _with_settled(ds, acc, long_impacts)


def _settled_arrays(shape, width, labels):
    """What :func:`settle_attractors` fills in, run by run."""
    cyc = {v: np.full((*shape, width), np.nan) for v in ("t", "v_minus", "phase")}
    cyc |= {v: np.zeros((*shape, width), np.int8) for v in ("wall", "kind")}
    return dict(
        cycle=cyc, settled=np.zeros(shape, bool), status=np.empty(shape, dtype=object),
        long_status=np.full(shape, "", dtype=object), long_start=np.full((*shape, 2), np.nan),
        stats=np.full((*shape, 2), np.nan),
        lyap=np.full((*shape, 4), np.nan),  # lambda_1 per impact, its interval, per unit time
        sens=np.full(shape, np.nan),  # of an exact lambda_1: its sensitivity to the monodromy matrix's entries
        source=np.full(shape, "", dtype=object), labels=labels.astype(object))


def _settle_cycle(acc, idx, dgr, rows, n, lag, start, long_impacts) -> bool:
    """A run with a period: its Newton-solved cycle and exact lambda_1, or why not; True where lambda_1 is
    to be estimated from a long run instead (:func:`_estimate`)."""
    span = rows["t"][n - 1] - rows["t"][n - 1 - lag]
    res = polish_cycle(*dgr, *(rows[v][n - lag:n] for v in EVENT_VARS), span=span)
    for v, arr in acc["cycle"].items():
        arr[idx][:lag] = res[v]
    acc["settled"][idx], acc["status"][idx] = res["settled"], res["status"]
    if res["settled"]:  # exact: the multipliers of the Newton-solved cycle
        top = float(np.log(np.abs(res["multipliers"]).max()))
        acc["lyap"][idx] = (top / lag, top / lag, top / lag, top / (2.0 * round(span / 2.0)))
        acc["sens"][idx] = multiplier_sensitivity(res["step_jacobians"]) / lag
        acc["source"][idx] = "multipliers of the Newton-solved cycle"
    elif res["status"] == "sticking":
        acc["lyap"][idx] = -np.inf
        acc["source"][idx] = "sticking cycle: its map over a period is constant (multipliers 0)"
    elif start is not None and long_impacts:  # periodic, not solved: the tangent estimate of a run
        return True
    else:
        acc["source"][idx] = f"not estimated: the cycle is not solved ({res['status']}) and no long run " + (
            "(long_impacts = 0)" if not long_impacts else "(no bottom impact to restart from)")
    return False


def _estimate(acc, runs, long_impacts, batch):
    """lambda_1 of the periodic runs whose cycle is not solved, from the tangent estimate of a run of
    ``long_impacts`` impacts from each start (``runs``: ``(idx, (d, gbar, r), start)``)."""
    if batch and runs:
        cols = [np.array([(*dgr, *start)[c] for _, dgr, start in runs]) for c in range(5)]
        lams = [_tangent_estimate(ev, dgr, long_impacts) for ev, (_, dgr, _) in zip(
            _run_events(*cols, impacts=long_impacts, detect=False, tol=1e-9), runs, strict=True)]
    else:
        lams = [exponents_of_run(simulate(Params(d=float(dgr[0]), gbar=float(dgr[1]), r=float(dgr[2])), *start,
                                          n_impacts=long_impacts), transient=long_impacts // 10, batches=LONG_BATCHES)
                for _, dgr, start in runs]
    for (idx, _, _), lam in zip(runs, lams, strict=True):
        acc["lyap"][idx] = (lam.per_impact[0], *lam.interval[0], lam.per_time[0])
        acc["source"][idx] = f"long run of {long_impacts} impacts ({acc['status'][idx]})"


def _settle_no_period(acc, idx, start, long_impacts) -> None:
    """A run without a period: its restart, or why it has no long run (made by :func:`_split_runs`)."""
    acc["status"][idx] = "aperiodic"
    if start is None or not long_impacts:
        acc["long_status"][idx] = "no restart" if start is None else "not run"
        acc["source"][idx] = ("not estimated: no bottom impact in the window to restart a long run from"
                              if start is None else "not estimated: no long run (long_impacts = 0)")
        return
    acc["long_start"][idx] = start


def _split_runs(runs, long_impacts, tol, batch) -> list:
    """What each motion with no period is (:class:`NoPeriodSplit`), from its long run (``runs``:
    ``(idx, (d, gbar, r), start)``): side by side (:func:`long_runs`), or one at a time."""
    if batch and runs:
        cols = [np.array([(*dgr, *start)[c] for _, dgr, start in runs]) for c in range(5)]
        return [_split(run) for run in long_runs(*cols, impacts=long_impacts, tol=tol)]
    return [split_no_period(*dgr, *start, impacts=long_impacts, tol=tol) for _, dgr, start in runs]


def _fill_splits(acc, runs, splits, long_impacts):
    """The long runs' statistics, lambda_1 and what each motion is, into ``acc``."""
    for (idx, _, _), split in zip(runs, splits, strict=True):
        acc["long_status"][idx] = split.status
        acc["labels"][idx] = split.label
        acc["stats"][idx] = long_statistics(split.run, LONG_BATCHES)
        acc["lyap"][idx] = (split.lyap1, split.lyap1_low, split.lyap1_high, split.lyap1_time)
        acc["source"][idx] = f"long run of {long_impacts} impacts" + {
            "aperiodic": "", "settles": " (it settles: the estimate over the orbit it settles on)",
            "stuck": " (it comes to rest for good)"}.get(split.status, f" ({split.status})")
        if split.status == "stuck":  # at rest on the bottom for good: exact
            acc["lyap"][idx] = -np.inf


def _with_settled(ds, acc, long_impacts):
    """``ds`` with what :func:`settle_attractors` found, described."""
    edims = (*ds["status"].dims, "cycle")
    pdims = ds["status"].dims
    ds["label"] = (pdims, acc["labels"].astype(str), ds["label"].attrs | {
        "long_name": "motion: n:m impacts per period and period, or (no period within the cap) chaotic, "
                     "quasi-periodic or unsettled by the largest Lyapunov exponent of its long run"})
    ds["settled"] = (pdims, acc["settled"], {"units": "1", "long_name": "the attractor's values are well-posed: a Newton-solved or sticking (exact) cycle"})
    ds["settle_status"] = (pdims, acc["status"].astype(str), {"units": "1", "long_name": "how the cycle was settled, or why not"})
    names = {"t": ("time from the cycle's canonical first event", "1"), "wall": ("wall (1 bottom, -1 top)", "1"),
             "v_minus": ("pre-impact velocity Zdot-", "1"), "phase": ("forcing phase", "rad"), "kind": ("event kind", "1")}
    for v, (text, unit) in names.items():
        ds[f"cycle_{v}"] = (edims, acc["cycle"][v], {"units": unit, "long_name": f"attractor cycle (exact where settled): {text}"})
    ds["long_status"] = (pdims, acc["long_status"].astype(str), {"units": "1", "long_name": "long run of a motion with no period: aperiodic, settles (a longer transient), stuck"})
    ds["long_phi"] = (pdims, acc["long_start"][..., 0], {"units": "rad", "long_name": "long run: phase of its first bottom impact"})
    ds["long_v0"] = (pdims, acc["long_start"][..., 1], {"units": "1", "long_name": "long run: pre-impact velocity of its first bottom impact"})
    ds["abs_v_mean"] = (pdims, acc["stats"][..., 0], {"units": "1", "long_name": "long run: mean |Zdot-| over its impacts (batch means)"})
    ds["abs_v_se"] = (pdims, acc["stats"][..., 1], {"units": "1", "long_name": "long run: standard error of abs_v_mean (batch means)"})
    level = "95 % confidence interval (batch means over the long run; the exact value twice for a solved cycle)"
    ds["lyap1"] = (pdims, acc["lyap"][..., 0], {"units": "1", "long_name": "largest Lyapunov exponent lambda_1, per impact"})
    ds["lyap1_low"] = (pdims, acc["lyap"][..., 1], {"units": "1", "long_name": f"lambda_1 per impact: lower end of its {level}"})
    ds["lyap1_high"] = (pdims, acc["lyap"][..., 2], {"units": "1", "long_name": f"lambda_1 per impact: upper end of its {level}"})
    ds["lyap1_time"] = (pdims, acc["lyap"][..., 3], {"units": "1", "long_name": "largest Lyapunov exponent lambda_1, per unit of non-dimensional time"})
    ds["lyap1_sensitivity"] = (pdims, acc["sens"], {"units": "1", "long_name": "exact lambda_1 (a solved cycle): its change per unit of relative perturbation of the monodromy matrix's entries (componentwise condition of the largest multiplier, over the period's impacts)"})
    ds["lyap1_source"] = (pdims, acc["source"].astype(str), {"units": "1", "long_name": "how lambda_1 was obtained"})
    ds.attrs.update(long_impacts=long_impacts, long_batches=LONG_BATCHES)
    return ds
