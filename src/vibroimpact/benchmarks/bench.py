"""Speed and accuracy of the exact simulator against scipy's solve_ivp with terminal events.

Both are timed in the same process, one after the other, on the same scene; accuracy is the error
of single-flight impact times against the 40-digit reference of :mod:`vibroimpact.dynamics.reference`,
from the same post-impact states.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import threading
import time
import types
from contextlib import contextmanager
from functools import partial

import numba
import numpy as np
import xarray as xr

from ..analysis.bifurcation import follow_point
from ..analysis.bistability import bistable_intervals
from ..analysis.continuation import continue_orbit
from ..analysis.energy import sweep_energy
from ..analysis.family_exit import sweep_family_exit
from ..analysis.lyapunov import lyapunov
from ..analysis.motions import no_period
from ..analysis.orbits import find_orbit
from ..analysis.sweeps import sweep
from ..analysis.transitions import locate_transitions
from ..analysis.windows import empty_windows, window_limits
from ..datasets import annotate
from ..dynamics import events, flight, runs
from ..dynamics import kernels as K
from ..dynamics.device import PAPER
from ..dynamics.events import next_impact
from ..dynamics.params import Params
from ..dynamics.reference import first_impact
from ..dynamics.runs import simulate, simulate_batch
from . import peer_heyoka
from .methods import ivp_flight, run_ivp

#: Benchmark scene: beta = pi/3, d = 0.235 lies in the chaotic window (paper Figure 2): every kind of flight.
SCENE = dict(d=0.235, beta=math.pi / 3, phi=0.4, v0=0.6)


def simulator_benchmark(n_impacts: int, n_impacts_ivp: int, n_flights_accuracy: int,
                        rtol: float = 1e-12, atol: float = 1e-12) -> xr.Dataset:
    """Time both methods and measure their impact-time errors; returns a one-row dataset."""
    g = PAPER.gbar(SCENE["beta"])
    p = Params(d=SCENE["d"], gbar=g, r=PAPER.r)
    simulate(p, SCENE["phi"], SCENE["v0"], n_impacts=100)  # compile outside the timing
    simulate_batch([p.d] * 2, g, PAPER.r, SCENE["phi"], SCENE["v0"], n_impacts=100)
    lyapunov(p, SCENE["phi"], SCENE["v0"], 1000)

    ds = simulate(p, SCENE["phi"], SCENE["v0"], n_impacts=n_impacts)
    m = 2 * 64
    phis = np.linspace(0, 2 * np.pi, m, endpoint=False)
    # solve_ivp, a thousand times slower, is timed once
    best = _fastest_in_rounds({
        "exact": partial(_seconds, partial(simulate, p, SCENE["phi"], SCENE["v0"], n_impacts=n_impacts)),
        "batch": partial(_seconds, partial(simulate_batch, [p.d] * m, g, 0.5, phis, SCENE["v0"], n_impacts=n_impacts // m)),
        # the same run with both Lyapunov exponents (the tangent pass after the event loop)
        "lyapunov": partial(_seconds, partial(lyapunov, p, SCENE["phi"], SCENE["v0"], n_impacts)),
    }, REPEATS)
    exact_s = best["exact"] / n_impacts
    lyap_s = best["lyapunov"] / n_impacts
    batch_s = best["batch"] / (m * (n_impacts // m))

    ivp = run_ivp(p, SCENE["phi"], SCENE["v0"], n_impacts_ivp, rtol=rtol, atol=atol, max_seconds=math.inf)
    ivp_s = ivp.seconds / n_impacts_ivp

    # single-flight errors from the same exact post-impact states
    idx = np.linspace(1, min(n_impacts, 100_000) - 2, n_flights_accuracy).astype(int)
    err_exact, err_ivp = [], []
    for j in idx:
        th, z0, u = (float(ds[k].values[j]) for k in ("phase", "z", "v_plus"))
        ref, wall, clearance = first_impact(th, z0, u, p.d, p.gbar)
        if wall == 0 or clearance < 1e-6:
            continue
        tau, w = next_impact(th, z0, u, p.d, p.gbar, math.inf)
        tau_ivp, w_ivp, _ = ivp_flight(th, z0, u, p.d, p.gbar, rtol, atol)
        err_exact.append(abs(tau - float(ref)) if w == wall else math.inf)
        err_ivp.append(abs(tau_ivp - float(ref)) if w_ivp == wall else math.inf)
    out = xr.Dataset(
        {
            "exact_us_per_impact": ((), exact_s * 1e6, dict(units="us", long_name="exact simulator, one thread")),
            "exact_batch_us_per_impact": ((), batch_s * 1e6, dict(units="us", long_name="exact simulator, parallel batch")),
            "ivp_us_per_impact": ((), ivp_s * 1e6, dict(units="us", long_name=f"solve_ivp DOP853 rtol={rtol:g} atol={atol:g}")),
            "lyapunov_us_per_impact": ((), lyap_s * 1e6, dict(units="us", long_name="the same run with both Lyapunov exponents (tangent pass, QR per impact)")),
            "lyapunov_ratio": ((), lyap_s / exact_s, dict(units="1", long_name="time with Lyapunov exponents / time of the plain run, same run")),
            "speedup": ((), ivp_s / exact_s, dict(units="1", long_name="solve_ivp time / exact time per impact")),
            "exact_max_err_t": ((), max(err_exact), dict(units="1", long_name="exact simulator: max impact-time error")),
            "ivp_max_err_t": ((), max(err_ivp), dict(units="1", long_name="solve_ivp: max impact-time error")),
            "exact_median_err_t": ((), float(np.median(err_exact)), dict(units="1", long_name="exact simulator: median impact-time error")),
            "ivp_median_err_t": ((), float(np.median(err_ivp)), dict(units="1", long_name="solve_ivp: median impact-time error")),
            "n_flights_checked": ((), len(err_exact), dict(units="1", long_name="flights compared with the 40-digit reference")),
        },
        attrs=dict(scene=str(SCENE), n_impacts=n_impacts, n_impacts_ivp=n_impacts_ivp),
    )
    return annotate(out)


def report(ds: xr.Dataset) -> str:
    v = {k: float(ds[k]) for k in ds.data_vars}
    return (
        "| method | time per impact | max impact-time error | median error |\n|---|---|---|---|\n"
        f"| exact simulator (numba, 1 thread) | {v['exact_us_per_impact']:.3g} µs | {v['exact_max_err_t']:.1e} | {v['exact_median_err_t']:.1e} |\n"
        f"| exact simulator (parallel batch, 2 cores) | {v['exact_batch_us_per_impact']:.3g} µs | | |\n"
        + (f"| exact simulator with both Lyapunov exponents | {v['lyapunov_us_per_impact']:.3g} µs "
           f"({v['lyapunov_ratio']:.2f}× the plain run) | | |\n" if "lyapunov_ratio" in v else "")
        + f"| solve_ivp DOP853, rtol 1e-12, terminal events | {v['ivp_us_per_impact']:.4g} µs | {v['ivp_max_err_t']:.1e} | {v['ivp_median_err_t']:.1e} |\n"
        f"\nSpeed-up per impact: **{v['speedup']:.0f}×** ({int(v['n_flights_checked'])} flights checked against a 40-digit reference).\n"
        + (f"\nContinuation of the β = π/3 2:1 branch: {int(v['branch_points'])} points with eigenvalues, stability class, "
           f"admissibility and {int(v['branch_critical_points'])} located critical points in {v['branch_seconds']:.2f} s.\n"
           if "branch_points" in v else "")
        + (f"\nTwo-parameter curve (G1, the 2:1 grazing point, followed in (s, β) at 5 N): {int(v['curve_points'])} points, "
           f"its start located and its end points and events recorded, in {v['curve_seconds']:.2f} s.\n"
           if "curve_points" in v else "")
        + (f"\nSweep of d through s at β = π/3 (Figure 2's range), {int(v['sweep_points'])} points up and {int(v['sweep_points'])} down "
           f"(≤ 200 forcing periods of transient each, {int(v['sweep_events'])} events, {int(v['sweep_no_period'])} points without a period): "
           f"{v['sweep_seconds']:.2f} s.\n" if "sweep_points" in v else "")
        + (f"\nThe same sweep with its energy, located transitions, bistable intervals and 1:1 exit: "
           f"{int(v['sweep_full_events'])} events in {v['sweep_full_seconds']:.2f} s, "
           f"{v['sweep_full_events_per_second'] / 1e6:.2g} million events per second; the bare batch kernel on the "
           f"sweep's points, same run: {v['sweep_kernel_events_per_second'] / 1e6:.2g} million "
           f"(ratio {v['sweep_full_kernel_ratio']:.2f}); without the period test (run_batch, 500 events a point): "
           f"{v['sweep_batch_events_per_second'] / 1e6:.2g} million (ratio {v['sweep_full_batch_ratio']:.2f}).\n"
           if "sweep_full_batch_ratio" in v else "")
    )


def branch_benchmark(n_points: int = 1000) -> xr.Dataset:
    """Time a continuation of the beta = pi/3 2:1 branch with about ``n_points`` points, stability
    classification, admissibility and located critical points included."""

    p = Params.from_physical(s=0.184 / 0.6225, beta=math.pi / 3)
    orbit = find_orbit(p, "BBT", 1.21, 0.2164)
    continue_orbit(orbit, vary="s", d_range=(0.15, 0.23), step=1e-2)  # warm up the compiled parts
    # the arclength of this branch over 0.15 < d < 0.23 is about 1.2 in (z, d): choose the step
    trial = continue_orbit(orbit, vary="s", d_range=(0.15, 0.23), step=1e-2, locate=False)
    step = 1e-2 * trial.sizes["point"] / n_points
    t = time.perf_counter()
    br = continue_orbit(orbit, vary="s", d_range=(0.15, 0.23), step=step)
    el = time.perf_counter() - t
    return xr.Dataset(
        {
            "branch_points": ((), br.sizes["point"], dict(units="1", long_name="points on the branch")),
            "branch_seconds": ((), el, dict(units="s", long_name="continuation with stability, admissibility and critical points")),
            "branch_critical_points": ((), br.sizes["critical"], dict(units="1", long_name="located critical and grazing points")),
        }
    )


def curve_benchmark(n_points: int = 200) -> xr.Dataset:
    """Time a two-parameter curve of about ``n_points`` points: G1, the 2:1 orbit's grazing point at
    beta = pi/6, located from an orbit near it and followed in (s, beta) over the paper's s range and
    0.35 < beta < 0.75, with the events along it and why each end stops
    (:func:`~vibroimpact.analysis.bifurcation.follow_point`)."""

    p = Params.from_physical(s=0.1385 / Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    orbit = find_orbit(p, "BBT", 5.855, 0.4185)
    box = ((0.19, 0.72), (0.35, 0.75))
    trial = follow_point(orbit, "grazing", params=("s", "beta"), ranges=box, step=2e-2)  # also warms up
    step = 2e-2 * trial.sizes["point"] / n_points
    t = time.perf_counter()
    c = follow_point(orbit, "grazing", params=("s", "beta"), ranges=box, step=step)
    el = time.perf_counter() - t
    return xr.Dataset(
        {
            "curve_points": ((), c.sizes["point"], dict(units="1", long_name="points on the two-parameter curve")),
            "curve_seconds": ((), el, dict(units="s", long_name="two-parameter curve with its start located, events and end reasons")),
        }
    )


def sweep_benchmark(n_points: int = 1000, max_periods: float = 200, *, xtol: float = 1e-7,
                    locate_periods: float = 20_000, max_trials: int = 200) -> xr.Dataset:
    """Time a sweep of d through s at beta = pi/3 over the range of the paper's Figure 2 (1:1, period
    doubling, chaos, 2:1, 3:1), up and down: ``2 n_points`` attractors, each with up to
    ``max_periods`` forcing periods of transient; then everything the workflow derives from it (rule
    ``sweep``): its energy (:func:`~vibroimpact.sweep_energy`), its located transitions (``xtol``,
    ``locate_periods``, ``max_trials``: :func:`~vibroimpact.locate_transitions`), bistable intervals and 1:1 exit.

    The events of every kernel call are counted (the points' windows, the long runs, the transitions' and
    the exit's runs), and the bare batch kernel is timed in the same run on the same events: the sweep's
    points from the starts the sweep used (:func:`_kernel_rate`, the same windows), twice after it (the mean
    of the two)."""
    values = np.linspace(0.19, 0.72, n_points)
    small = sweep("s", values[:5], beta=math.pi / 3, max_periods=max_periods)  # compile outside the timing
    _derived(small, xtol, locate_periods, max_trials)
    _kernel_rate(small, max_periods)
    with _event_counter() as count:
        t = time.perf_counter()
        sw = sweep("s", values, beta=math.pi / 3, phi=0.42, v0=0.87, max_periods=max_periods)
        el = time.perf_counter() - t
        ev_sweep = count[0]
        stages = _derived(sw, xtol, locate_periods, max_trials)
        total = time.perf_counter() - t
    rate = float(np.mean([_kernel_rate(sw, max_periods) for _ in range(2)]))
    plain = float(np.mean([_batch_rate(sw) for _ in range(2)]))
    full = count[0] / total
    v = {
        "sweep_points": (n_points, "1", "points per direction"),
        "sweep_seconds": (el, "s", "up and down sweep, attractors settled (long runs included)"),
        "sweep_events": (int(sw.n_events.sum()), "1", "events simulated in the sweep's windows"),
        "sweep_no_period": (int(no_period(sw.label.values).sum()), "1", "points with no period within max_periods"),
        "sweep_all_events": (ev_sweep, "1", "events simulated by the sweep: its windows and its long runs"),
        "sweep_events_per_second": (ev_sweep / el, "1/s", "events per second of the sweep (windows and long runs)"),
        "sweep_energy_seconds": (stages[0], "s", "its energy (sweep_energy)"),
        "sweep_transitions_seconds": (stages[1], "s", "its located transitions, bistable intervals and 1:1 exit"),
        "sweep_full_seconds": (total, "s", "the sweep, its energy, transitions, bistable intervals and 1:1 exit"),
        "sweep_full_events": (count[0], "1", "events simulated by the sweep, its energy, transitions and 1:1 exit"),
        "sweep_full_events_per_second": (full, "1/s", "events per second of the sweep with its energy, transitions "
                                         "and 1:1 exit"),
        "sweep_kernel_events_per_second": (rate, "1/s", "bare batch kernel (window_batch) on the sweep's points "
                                           "from the starts it used: events per second, same run"),
        "sweep_full_kernel_ratio": (full / rate, "1", "events per second of the full sweep / of the bare batch "
                                    "kernel, same run"),
        "sweep_batch_events_per_second": (plain, "1/s", "run_batch (simulate_batch's kernel, no period test) on the "
                                          "sweep's points from the starts it used, 500 events each: events per "
                                          "second, same run"),
        "sweep_full_batch_ratio": (full / plain, "1", "events per second of the full sweep / of run_batch, same run"),
    }
    return annotate(xr.Dataset({k: ((), x, dict(units=u, long_name=n)) for k, (x, u, n) in v.items()},
                               attrs=dict(sweep_cores=numba.get_num_threads())))


def _derived(sw, xtol, locate_periods, max_trials):
    """What the workflow's rule ``sweep`` derives from a sweep (its energy; its transitions, bistable intervals
    and 1:1 exit): the seconds of each."""
    t = time.perf_counter()
    sweep_energy(sw)
    t1 = time.perf_counter()
    tr = locate_transitions(sw, xtol=xtol, max_periods=locate_periods, max_trials=max_trials)
    bistable_intervals(sw, tr)
    sweep_family_exit(sw, xtol=xtol)
    return t1 - t, time.perf_counter() - t1


def _kernel_rate(sw, max_periods, pmax: int = 64) -> float:
    """Events per second of the bare batch kernel (:func:`~vibroimpact.dynamics.kernels.window_batch`, as
    :func:`~vibroimpact.attractor_batch` calls it, without building the dataset) on a sweep's points from the
    starts it used: the same runs as the sweep's windows."""
    d, g = (np.broadcast_to(sw[v].values, sw.start_phi.shape).ravel() for v in ("d", "gbar"))
    m = d.size
    batch = K.Batch(d=np.ascontiguousarray(d), gbar=np.ascontiguousarray(g), r=np.full(m, float(sw.attrs["r"])),
                    theta0=sw.start_phi.values.ravel() % (2 * np.pi), v0=sw.start_v0.values.ravel())
    win = empty_windows(m, sw.sizes["event"])
    ends = K.WindowEnds(status=np.zeros(m, np.int8), lag=np.zeros(m, np.int64), total=np.zeros(m, np.int64),
                        n=np.zeros(m, np.int64))
    limits = window_limits(max_periods, 200_000, float(sw.attrs["tol"]), int(sw.attrs.get("pmax", pmax)))
    t = time.perf_counter()
    K.window_batch(batch, limits, win, ends)
    el = time.perf_counter() - t
    if not np.array_equal(ends.total, sw.n_events.values.ravel()):
        raise RuntimeError("the bare kernel's runs are not the sweep's: the rates would not compare")
    return float(ends.total.sum()) / el


def _batch_rate(sw, n_events: int = 500) -> float:
    """Events per second of :func:`~vibroimpact.dynamics.kernels.run_batch` (:func:`~vibroimpact.simulate_batch`'s
    kernel, without the dataset) on a sweep's points from the starts it used, ``n_events`` events each."""
    d, g = (np.ascontiguousarray(np.broadcast_to(sw[v].values, sw.start_phi.shape).ravel()) for v in ("d", "gbar"))
    m = d.size
    batch = K.Batch(d=d, gbar=g, r=np.full(m, float(sw.attrs["r"])), theta0=sw.start_phi.values.ravel() % (2 * np.pi),
                    v0=sw.start_v0.values.ravel())
    out = K.EventBuffers(*(np.empty((m, n_events), np.int8 if v in ("wall", "kind") else float)
                           for v in K.EventBuffers._fields))
    ends = K.Ends(n=np.zeros(m, np.int64), status=np.zeros(m, np.int8), lag=np.zeros(m, np.int64))
    settings = K.Settings(t_end=math.inf, v_chatter=K.V_CHATTER, detect=False, tol=float(sw.attrs["tol"]))
    t = time.perf_counter()
    K.run_batch(batch, settings, 64, out, ends)
    return float(ends.n.sum()) / (time.perf_counter() - t)


@contextmanager
def _event_counter():
    """Count the events of every kernel call made from Python inside the block (the window runs and chains,
    the batches, :func:`~vibroimpact.simulate`'s event loop), on any thread: yields a one-element list.  The
    event loop is counted where Python calls it (``runs._event_loop``), not by replacing the compiled
    ``advance``, which the other kernels call: one of them compiled inside the block would find a Python
    function there and fail to compile."""
    count, lock = [0], threading.Lock()
    where = {"run_window": K, "chain_windows": K, "run_batch": K, "_event_loop": runs}  # what is counted, and where
    saved = {name: getattr(owner, name) for name, owner in where.items()}

    def add(n):
        with lock:
            count[0] += int(n)

    def run_window(*a):
        out = saved["run_window"](*a)
        add(out[2])
        return out

    def chain_windows(chain, span, limits, win, ends):
        saved["chain_windows"](chain, span, limits, win, ends)
        add(sum(ends.total[k, chain.order[k, span[0]:span[1]]].sum() for k in range(chain.order.shape[0])))

    def run_batch(batch, settings, pmax, out, ends):
        saved["run_batch"](batch, settings, pmax, out, ends)
        add(ends.n.sum())

    def event_loop(*a):
        res = saved["_event_loop"](*a)  # (buffers, events recorded from the first, status, period)
        add(res[1])
        return res

    counting = {"run_window": run_window, "chain_windows": chain_windows, "run_batch": run_batch,
                "_event_loop": event_loop}
    for name, owner in where.items():
        setattr(owner, name, counting[name])
    try:
        yield count
    finally:
        for name, owner in where.items():
            setattr(owner, name, saved[name])


#: the two scenes of the kernel's speed target: (beta, d, phi, v0)
KERNEL_SCENES = {"2:1": (math.pi / 6, 0.16, 1.015, 0.1924), "chaotic": (math.pi / 3, 0.235, 0.4, 0.6)}


def _count_worker(args: str) -> None:
    """Run in a fresh interpreter with numba's JIT disabled: count, per impact, the sine/cosine calls
    and the point evaluations of the event finder over a stretch of each scene's flights."""


    a = json.loads(args)
    counts = {"trig": 0, "points": 0, "roots": 0}

    def counted(name, key):
        f = getattr(events, name)

        def g(*x):
            counts[key] += 1
            return f(*x)

        setattr(events, name, g)

    for name, key in (("kinematics", "points"), ("state_step", "points"), ("state_from_sc", "points"), ("rtsafe", "roots")):
        counted(name, key)
    fm = types.SimpleNamespace(**{k: getattr(math, k) for k in dir(math) if not k.startswith("_")})

    sines = []  # every sine's argument: the cosine of each is taken of the same angle

    def trig(f, record=None):
        def g(x):
            counts["trig"] += 1
            if record is not None:
                record.append(x)
            return f(x)
        return g

    fm.sin, fm.cos = trig(math.sin, sines), trig(math.cos)
    flight.math = events.math = fm
    out = {}
    for name, (beta, d, phi, v0) in KERNEL_SCENES.items():
        p = Params(d=d, gbar=PAPER.gbar(beta), r=PAPER.r)
        ds = simulate(p, phi, v0, n_impacts=a["n"] + 50)
        th, z0, u = (ds[k].values[50:-1] for k in ("phase", "z", "v_plus"))
        for k in counts:
            counts[k] = 0
        sines.clear()
        for j in range(th.size):
            c, s = math.cos(th[j]), math.sin(th[j])  # as the event loop does, once per flight
            sines.append(float(th[j]))
            events.flight_impact(th[j], c, s, math.acos(-p.gbar), z0[j], u[j], p.d, p.gbar, math.inf)
        counts["trig"] += 2 * th.size
        out[name] = {k: v / th.size for k, v in counts.items()} | {"sines": list(sines), "flights": th.size}
    print(json.dumps(out))


@numba.njit(cache=True, error_model="numpy")
def _sincos_chain(x, reps):
    """The sine and cosine of every angle of ``x``, ``reps`` times over, each angle waiting for the last pair's
    result (as the event finder's next point waits for this one's): the latency of the trigonometric calls
    alone, a floor under the kernel's cost per impact."""
    acc = 0.0
    for _ in range(reps):
        for i in range(x.shape[0]):
            a = x[i] + acc * 0.0
            acc = math.sin(a) + math.cos(a)
    return acc


def _trig_floor_timer(sines, reps: int):
    """A call timing :func:`_sincos_chain` over ``sines`` ``reps`` times (seconds)."""
    x = np.asarray(sines, dtype=float)
    _sincos_chain(x, 1)
    return partial(_seconds, partial(_sincos_chain, x, reps))


@numba.njit(cache=True, error_model="numpy")
def _finder_replay(theta, c, s, z0, u, d, gbar, out_tau):
    """The event finder alone (:func:`~vibroimpact.dynamics.events.flight_impact`) over recorded flights: the
    start phase ``theta`` with its cosine ``c`` and sine ``s``, position ``z0`` and velocity ``u`` of each, one
    after the other, each flight time into ``out_tau``.  What the event loop adds (the impact law, the
    chattering test, the recording and its bookkeeping) is left out: the finder's own cost per impact."""
    alpha = math.acos(-gbar) if gbar < 1.0 else 0.0
    for j in range(theta.shape[0]):
        out_tau[j] = events.flight_impact(theta[j], c[j], s[j], alpha, z0[j], u[j], d, gbar, math.inf)[0]


@numba.njit(cache=True, error_model="numpy")
def _cos_sin(theta):
    """Each phase's cosine and sine, as the event loop takes them (once per flight)."""
    c, s = np.empty_like(theta), np.empty_like(theta)
    for j in range(theta.shape[0]):
        c[j], s[j] = math.cos(theta[j]), math.sin(theta[j])
    return c, s


def finder_flights(p: Params, phi: float, v0: float, n_impacts: int):
    """The flights of a run of impacts only, as :func:`_finder_replay` takes them: ``(theta, c, s, z0, u)`` of
    each flight from one impact to the next."""
    run = simulate(p, phi, v0, n_impacts=n_impacts + 1)
    if not (run.kind.values == K.IMPACT).all():
        raise ValueError("the finder's replay takes a run of impacts only (no chattering, sticking or grazing)")
    theta, z0, u = (np.ascontiguousarray(run[k].values[:-1]) for k in ("phase", "z", "v_plus"))
    return (theta, *_cos_sin(theta), z0, u)


def _finder_timer(flights, d: float, gbar: float):
    """A call timing :func:`_finder_replay` over ``flights`` (:func:`finder_flights`; seconds)."""
    out = np.empty(flights[0].shape[0])
    _finder_replay(*(f[:10] for f in flights), d, gbar, out[:10])
    return partial(_seconds, partial(_finder_replay, *flights, d, gbar, out))


#: timed runs per measurement of the kernel benchmark; the fastest counts (timeit's convention: on a
#: shared machine the noise only ever adds time), for our kernel and heyoka's alike
REPEATS = 9


def _seconds(run, threads=None) -> float:
    """Seconds of one call of ``run()`` (on ``threads`` numba threads if given)."""

    if threads is not None:
        numba.set_num_threads(threads)
    t = time.perf_counter()
    run()
    return time.perf_counter() - t


def _fastest_in_rounds(timers: dict, repeats: int) -> dict:
    """The fastest of ``repeats`` seconds of each of ``timers`` (calls returning their seconds), taken
    in rounds over all of them, so that a noisy stretch of a shared machine slows one round of each,
    not all the runs of one of them."""
    best = dict.fromkeys(timers, math.inf)
    for _ in range(max(int(repeats), 1)):
        for key, timed in timers.items():
            best[key] = min(best[key], timed())
    return best


def kernel_profile(n_impacts: int = 1_000_000, n_counted: int = 400, n_heyoka: int = 20_000,
                   repeats: int = REPEATS) -> xr.Dataset:
    """Cost of the exact kernel on the two target scenes: microseconds per impact on one thread
    (``simulate``), impacts per second of ``simulate_batch`` on 1 and on all cores, and per impact the
    sine/cosine calls, point evaluations and root searches of the event finder (counted over
    ``n_counted`` flights of the same algorithm run as plain Python); in the same run, heyoka's
    stepping cost per impact at tol = eps (:func:`~vibroimpact.benchmarks.peer_heyoka.stepping_cost`, over
    ``n_heyoka`` impacts), NaN where heyoka is not installed; the floor the trigonometric calls set, the
    same angles' sines and cosines replayed compiled as a dependent chain (:func:`_sincos_chain`).  Every
    timing is the fastest of
    ``repeats`` runs (:data:`REPEATS`), taken in rounds over both scenes and all methods."""


    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    res = subprocess.run([sys.executable, "-m", "vibroimpact.benchmarks.bench", json.dumps({"n": n_counted})], env=env,
                         capture_output=True, text=True, check=True)
    counts = json.loads(res.stdout)
    sines = {n: c.pop("sines") for n, c in counts.items()}

    names = list(KERNEL_SCENES)
    cores = numba.config.NUMBA_NUM_THREADS
    m = 64 * cores
    phis = np.linspace(0, 2 * np.pi, m, endpoint=False)
    timers = {}  # (scene, what) -> a call returning its seconds
    hy_result = {}
    for name in names:
        beta, d, phi, v0 = KERNEL_SCENES[name]
        p = Params(d=d, gbar=PAPER.gbar(beta), r=PAPER.r)
        if peer_heyoka.available():
            timers[name, "heyoka"], hy_result[name] = peer_heyoka.stepping_timer(p, phi, v0, n_heyoka,
                                                                                tol=np.finfo(float).eps)
        simulate(p, phi, v0, n_impacts=100)
        simulate_batch([p.d] * m, p.gbar, 0.5, phis, v0, n_impacts=10)
        timers[name, "simulate"] = partial(_seconds, partial(simulate, p, phi, v0, n_impacts=n_impacts))
        timers[name, "trig"] = _trig_floor_timer(sines[name], max(1, n_impacts // counts[name]["flights"]))
        timers[name, "finder"] = _finder_timer(finder_flights(p, phi, v0, n_impacts), p.d, p.gbar)
        for threads in (1, cores):
            timers[name, threads] = partial(_seconds, partial(simulate_batch, [p.d] * m, p.gbar, 0.5, phis, v0,
                                                              n_impacts=n_impacts // m), threads=threads)
    best = _fastest_in_rounds(timers, repeats)  # ours and heyoka's alike
    numba.set_num_threads(cores)
    us = [best[n, "simulate"] / n_impacts * 1e6 for n in names]
    trig_us = [best[n, "trig"] / (max(1, n_impacts // counts[n]["flights"]) * counts[n]["flights"]) * 1e6
               for n in names]
    finder_us = [best[n, "finder"] / n_impacts * 1e6 for n in names]
    rate1 = [m * (n_impacts // m) / best[n, 1] for n in names]
    rateall = [m * (n_impacts // m) / best[n, cores] for n in names]
    hy = {n: hy_result[n](best[n, "heyoka"]) for n in hy_result}
    hy_us = [hy[n]["us_per_impact"] if n in hy else math.nan for n in names]
    hy_steps = [hy[n]["steps_per_impact"] if n in hy else math.nan for n in names]
    per = lambda key: ("scene", [counts[n][key] for n in names])
    ds = xr.Dataset(
        {
            "us_per_impact": ("scene", us, dict(units="us", long_name="simulate, one thread")),
            "impacts_per_second_1": ("scene", rate1, dict(units="1/s", long_name="simulate_batch on one core")),
            "impacts_per_second_all": ("scene", rateall, dict(units="1/s", long_name=f"simulate_batch on {cores} cores")),
            "trig_per_impact": (*per("trig"), dict(units="1", long_name="sine and cosine calls per impact")),
            "trig_floor_us_per_impact": ("scene", trig_us, dict(
                units="us", long_name="the sines and cosines of an impact alone, each angle waiting for the last "
                "(the angles the event finder takes, replayed compiled): a floor under the kernel's cost")),
            "finder_us_per_impact": ("scene", finder_us, dict(
                units="us", long_name="the event finder alone, replayed compiled over the run's own flights (their "
                "starts, and the sines and cosines of their phases, given): the kernel's cost less the event loop's")),
            "points_per_impact": (*per("points"), dict(units="1", long_name="points evaluated per impact")),
            "roots_per_impact": (*per("roots"), dict(units="1", long_name="root searches per impact")),
            "heyoka_stepping_us_per_impact": ("scene", hy_us, dict(
                units="us", long_name="heyoka at tol = eps: seconds per Taylor step (one propagate_until, no "
                "events, no Python loop) times its event loop's steps per impact")),
            "heyoka_steps_per_impact": ("scene", hy_steps, dict(units="1", long_name="heyoka's Taylor steps per impact at tol = eps")),
        },
        coords={"scene": names},
        attrs=dict(cores=cores, n_impacts=n_impacts, n_counted=n_counted, n_heyoka=n_heyoka, repeats=repeats,
                   heyoka=peer_heyoka.heyoka_version() or "not installed"),
    )
    return annotate(ds)


if __name__ == "__main__":
    import sys

    _count_worker(sys.argv[1])
