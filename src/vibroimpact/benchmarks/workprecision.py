"""Work-precision of the simulation methods and where each fails.

Errors are measured against the 40-digit reference of :mod:`vibroimpact.dynamics.reference` (never against
the package's own simulator); costs are wall-clock seconds measured in one process, one method
after another.
"""

from __future__ import annotations

import math
import subprocess
import time

import numpy as np
import xarray as xr

from .._progress import Progress
from ..analysis.continuation import continue_orbit
from ..analysis.lyapunov import lyapunov
from ..analysis.motions import identify_attractor, no_period_label
from ..analysis.orbits import find_orbit
from ..analysis.sweeps import sweep
from ..analysis.transitions import locate_transitions
from ..datasets import annotate
from ..dynamics import kernels as K
from ..dynamics.device import PAPER
from ..dynamics.events import next_impact
from ..dynamics.params import Params
from ..dynamics.reference import bounce_by_bounce, first_impact, grazing_state, trajectory
from ..dynamics.runs import simulate
from . import methods as M
from .outcomes import OUTCOMES  # noqa: F401  (defined on the standard library alone; this module's name too)
from . import peer_heyoka, peer_siconos

#: Scenes from the paper's captions and its chaotic window: (beta, d, phi, v0)
SCENES = {
    "1:1": (math.pi / 3, 0.38, 0.4217, 0.8673),
    "2:1": (math.pi / 6, 0.16, 1.015, 0.1924),
    "3:1": (math.pi / 6, 0.138, 0.7342, 0.1845),
    "chaotic": (math.pi / 3, 0.235, 0.4, 0.6),
}


def _params(beta, d, r=PAPER.r):
    """The paper's device at incline ``beta`` with the non-dimensional length ``d``."""
    return Params(d=d, gbar=PAPER.gbar(beta), r=r)


def peer_status() -> dict[str, str]:
    """For each peer library: its version, or why it is absent (recorded in the datasets)."""

    out = {"heyoka": peer_heyoka.heyoka_version() or "not installed (pip install heyoka: the 'peers' extra)"}
    out["siconos"] = (peer_siconos.version() if peer_siconos.available()
                      else peer_siconos.unavailable_reason() or peer_siconos.NOT_INSTALLED)
    return out


def method_ladder(ivp_methods, ivp_tols, rk4_steps, heyoka_tols=(), siconos_tols=(), siconos_steps=()):
    """(family, setting, label) of every method configuration; the peers' only where installed
    (:func:`peer_status`)."""

    out = [("exact", math.nan, "exact (numba)"), ("python", math.nan, "same algorithm, plain Python")]
    out += [(f"ivp-{m}", tol, f"solve_ivp {m} rtol={tol:g}") for m in ivp_methods for tol in ivp_tols]
    out += [("rk4", h, f"RK4 + bisection h={h:g}") for h in rk4_steps]
    if heyoka_tols and peer_heyoka.available():
        out += [("heyoka", tol, f"heyoka tol={tol:.0e}") for tol in heyoka_tols]
    if (siconos_tols or siconos_steps) and peer_siconos.available():
        out += [("siconos-ed", tol, f"Siconos event-driven tol={tol:.0e}") for tol in siconos_tols]
        out += [("siconos-mj", h, f"Siconos Moreau-Jean h={h:g}") for h in siconos_steps]
    return out


#: wall-clock safety net of a solve_ivp run stopped by its budget of right-hand-side evaluations
IVP_SAFETY_SECONDS = 120.0


def _run(family, setting, p, phi, v0, n, t_end=math.inf, max_seconds=30.0, max_evals=None):
    if family == "exact":
        return M.run_exact(p, phi, v0, n, t_end=t_end)
    if family == "python":
        return M.run_python(p, phi, v0, n, t_end=t_end)
    if family.startswith("ivp-"):
        # a budget of evaluations, where given, instead of seconds: the same run on any machine and load
        return M.run_ivp(p, phi, v0, n, method=family[4:], rtol=setting, atol=setting * 1e-2, t_end=t_end,
                         max_seconds=max_seconds if max_evals is None else IVP_SAFETY_SECONDS, max_evals=max_evals)
    if family == "heyoka":

        return peer_heyoka.run_heyoka(p, phi, v0, n, tol=setting, t_end=t_end, max_seconds=max_seconds)
    if family.startswith("siconos"):

        kw = {"tol": setting} if family == "siconos-ed" else {"h": setting}
        method = "event-driven" if family == "siconos-ed" else "moreau-jean"
        # a peer process that dies or outlives its time is recorded by run_siconos ("crashed", "stalled")
        return peer_siconos.run_siconos(p, phi, v0, n, method=method, t_end=t_end, max_seconds=max_seconds, **kw)
    return M.run_rk4(p, phi, v0, n, h=setting, t_end=t_end)


def _cost_key(family):
    return "ivp" if family.startswith("ivp") else family


def _errors(run, ref):
    """Largest impact-time and impact-velocity errors over the reference impacts, and the index of
    the first impact on the wrong wall (-1 if none)."""
    n = min(len(ref), len(run.t))
    rt = np.array([float(x[0]) for x in ref[:n]])
    rw = np.array([x[1] for x in ref[:n]])
    rv = np.array([float(x[2]) for x in ref[:n]])
    wrong = np.flatnonzero(run.wall[:n] != rw)
    if wrong.size or n < len(ref):
        return math.inf, math.inf, int(wrong[0]) if wrong.size else n
    return float(np.max(np.abs(run.t[:n] - rt))), float(np.max(np.abs(run.v[:n] - rv))), -1


def work_precision(*, n_err=20, n_cost=None, ivp_methods=("RK45", "DOP853", "LSODA", "Radau"),
                   ivp_tols=(1e-3, 1e-5, 1e-7, 1e-9, 1e-11), rk4_steps=(1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4),
                   heyoka_tols=(), siconos_tols=(), siconos_steps=(), scenes=None,
                   progress: bool | None = None) -> xr.Dataset:
    """Errors against the reference over the first ``n_err`` impacts, and cost per impact over
    ``n_cost[family]`` impacts, for every method configuration and scene.  Compilation (numba, heyoka's
    LLVM) happens before each timed run and is reported apart (``compile_seconds``, heyoka).
    ``progress``: a bar over the runs (default: only when run interactively)."""
    scenes = scenes or SCENES
    n_cost = ({"exact": 20_000, "python": 400, "ivp": 60, "rk4": 2_000, "heyoka": 2_000, "siconos-ed": 60,
               "siconos-mj": 20} | (n_cost or {}))
    ladder = method_ladder(ivp_methods, ivp_tols, rk4_steps, heyoka_tols, siconos_tols, siconos_steps)
    shape = (len(ladder), len(scenes))
    err_t, err_v, cost, total = (np.full(shape, np.nan) for _ in range(4))
    wrong = np.full(shape, -1, dtype=np.int64)
    # the plain-Python runs of every scene in one interpreter (its start-up is not part of the cost)
    python = (M.run_python_many([(_params(b, d), phi, v0, max(n_err, n_cost["python"]), math.inf)
                                 for b, d, phi, v0 in scenes.values()])
              if any(f == "python" for f, _, _ in ladder) else None)
    bar = Progress(len(scenes) * len(ladder), "work-precision", progress, unit="run")
    t_window = np.full(len(scenes), np.nan)
    motion = [scene_motion(_params(b, d), phi, v0) for b, d, phi, v0 in scenes.values()]
    for j, (_, (beta, d, phi, v0)) in enumerate(scenes.items()):
        p = _params(beta, d)
        ref = trajectory(p.d, p.gbar, p.r, phi, v0, n_err)
        t_window[j] = float(ref[-1][0]) if ref else np.nan
        for i, (family, setting, _) in enumerate(ladder):
            bar.update()
            n = max(n_err, n_cost[_cost_key(family)])
            run = python[j] if family == "python" else _run(family, setting, p, phi, v0, n)
            err_t[i, j], err_v[i, j], wrong[i, j] = _errors(run, ref)
            cost[i, j] = run.seconds / max(len(run.t), 1) * 1e6
            total[i, j] = run.seconds
    bar.close()
    ds = xr.Dataset(
        {
            "err_t": (("solver", "scene"), err_t, {"units": "1", "long_name": "largest impact-time error over the first impacts (inf: wrong walls)"}),
            "err_v": (("solver", "scene"), err_v, {"units": "1", "long_name": "largest pre-impact velocity error (inf: wrong walls)"}),
            "us_per_impact": (("solver", "scene"), cost, {"units": "us", "long_name": "wall-clock cost per impact"}),
            "seconds": (("solver", "scene"), total, {"units": "s", "long_name": "wall-clock time of the timed run"}),
            "first_wrong_wall": (("solver", "scene"), wrong, {"units": "1", "long_name": "first impact on the wrong wall (-1: none)"}),
            "family": ("solver", [m[0] for m in ladder]),
            "setting": ("solver", [m[1] for m in ladder],
                        {"long_name": "tolerance (solve_ivp rtol, heyoka, Siconos event-driven) or step h (RK4, Moreau-Jean)"}),
            "t_window": ("scene", t_window, {"units": "1", "long_name": "time of the last reference impact in the error "
                                                                         "window (its ulp is the errors' rounding level)"}),
            "scene_motion": ("scene", motion, {"long_name": "the motion each scene's start settles on (exact "
                                                            "simulator; no period: split by lambda_1)"}),
            "compile_seconds": ("solver", [_compile_seconds(f, s) for f, s, _ in ladder],
                                {"units": "s", "long_name": "compilation before the timed runs (excluded from the cost)"}),
        },
        coords={"solver": [m[2] for m in ladder], "scene": list(scenes)},
    )
    ds.attrs.update(n_err=n_err, n_cost=str(n_cost), reference="40-digit mpmath chain of flights (vibroimpact.dynamics.reference)",
                    peers=str(peer_status()), matched_accuracy=MATCHED_ACCURACY)
    return annotate(ds)


def scene_motion(p: Params, phi: float, v0: float, n_impacts: int = 4000) -> str:
    """The motion a scene's start settles on, by the exact simulator: a periodic motion's label, or, where no
    period is found, what the largest Lyapunov exponent of a long run says (``"chaotic"`` where its interval
    lies above 0: :func:`vibroimpact.analysis.motions.no_period_label`)."""
    att = identify_attractor(simulate(p, phi=phi, v0=v0, n_impacts=n_impacts))
    if att.periodic:
        return att.label
    ly = lyapunov(p, phi, v0, n_impacts=5 * n_impacts)
    (low, high), _ = ly.interval
    return no_period_label("aperiodic", low, high, ly.sticks)


def _compile_seconds(family, setting):
    if family == "heyoka":

        return peer_heyoka.compile_seconds(setting)
    return math.nan


#: the accuracy at which methods are compared for cost: the cheapest setting reaching it
MATCHED_ACCURACY = 1e-12


def matched_accuracy(wp: xr.Dataset, target: float = MATCHED_ACCURACY) -> xr.Dataset:
    """Per method family and scene: the cheapest setting whose impact-time error is at most ``target``
    (all walls right), its cost per impact and its ratio to the exact simulator's cost in the same run;
    ``reached`` is False ("cannot reach") where no setting gets there."""
    fams = list(dict.fromkeys(wp.family.values.astype(str)))
    scenes = list(wp.scene.values)
    cost = np.full((len(fams), len(scenes)), np.nan)
    setting = np.full_like(cost, np.nan)
    err = np.full_like(cost, np.nan)
    for i, f in enumerate(fams):
        rows = np.flatnonzero(wp.family.values == f)
        for j in range(len(scenes)):
            e = wp.err_t.values[rows, j]
            ok = np.isfinite(e) & (e <= target)
            if ok.any():
                k = rows[ok][np.argmin(wp.us_per_impact.values[rows[ok], j])]
                cost[i, j], setting[i, j], err[i, j] = wp.us_per_impact.values[k, j], wp.setting.values[k], wp.err_t.values[k, j]
    exact = cost[fams.index("exact")] if "exact" in fams else np.full(len(scenes), np.nan)
    # which setting is the cheapest is the run's timings' to decide (two settings of nearly equal cost trade
    # places from run to run): the setting, its error and the ratio are what a timing produces
    timed = {"provenance": "timing"}
    ds = xr.Dataset(
        {"us_per_impact": (("family", "scene"), cost, {"units": "us", "long_name": f"cheapest cost per impact at error <= {target:g}"}),
         "setting": (("family", "scene"), setting, {"long_name": "that setting (tolerance or step; NaN: none or not applicable)"} | timed),
         "err_t": (("family", "scene"), err, {"units": "1", "long_name": "its impact-time error"} | timed),
         "ratio_to_exact": (("family", "scene"), cost / exact, {"units": "1", "long_name": "cost / exact simulator's cost, same run"} | timed),
         "reached": (("family", "scene"), np.isfinite(cost), {"long_name": f"some setting reaches error <= {target:g}"})},
        coords={"family": fams, "scene": scenes},
    )
    ds.attrs.update(target=target)
    return annotate(ds)


# ---------------------------------------------------------------------------------------------
# Failure map
# ---------------------------------------------------------------------------------------------


def _flight(family, setting, theta, z0, u, d, gbar):
    if family in ("exact", "python"):
        return next_impact(theta, z0, u, d, gbar, math.inf)
    if family.startswith("ivp-"):
        tau, w, _ = M.ivp_flight(theta, z0, u, d, gbar, setting, setting * 1e-2, family[4:])
        return tau, w
    if family == "heyoka":

        tau, w, _ = peer_heyoka.heyoka_flight(theta, z0, u, d, gbar, setting)
        return tau, w
    tau, w, _, _ = M.rk4_flight(theta, z0, u, K.Model(float(d), float(gbar), 0.0),
                                M.FlightBudget(float(setting), 50.0, 10_000_000))
    return tau, w


def _flights(family, setting, states, d, gbar):
    """(tau, wall) of each flight; Siconos in one call of its peer process (a crash: no impacts)."""
    if family.startswith("siconos"):

        method = "event-driven" if family == "siconos-ed" else "moreau-jean"
        kw = {"tol": setting} if family == "siconos-ed" else {"h": setting}
        try:
            res = peer_siconos.siconos_flights([(*s, d, gbar) for s in states], method, **kw)
        except (peer_siconos.SiconosPeerError, subprocess.TimeoutExpired):  # the peer process died or hung: no impacts
            return [(math.inf, 0)] * len(states)
        return [(r.tau, r.wall) for r in res]
    return [_flight(family, setting, *s, d, gbar) for s in states]


#: impacts slower than this are inside a chattering sequence (the exact simulator sums those below
#: v_chatter = 1e-9); faster ones are compared one to one with the reference
CHATTER_V = 1e-6
#: an impact time is right when within this relative distance of the reference (and on its wall)
TIME_RTOL = 1e-8
#: a near-grazing hit reported more than this much later than the reference (or on the other wall) is missed
LATE = 1e-3
#: the long chaotic run follows the reference while every impact is on its wall and within this in t
CHAOS_ATOL = 1e-3


def failure_thresholds() -> dict:
    """The thresholds that decide each outcome of :func:`failure_map`, as recorded in its dataset."""
    return {"time_rtol": TIME_RTOL, "late": LATE, "chatter_v": CHATTER_V, "chaos_atol": CHAOS_ATOL}


def failure_map(*, epsilons=(1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12), ivp_methods=("RK45", "DOP853", "LSODA", "Radau"),
                ivp_tols=(1e-6, 1e-10), rk4_steps=(1e-2, 1e-3), heyoka_tols=(), siconos_tols=(), siconos_steps=(),
                chaos_impacts=100, chatter_t_end=20.0, max_seconds=2.0, chatter_max_evals=20_000,
                chaos_max_evals=50_000, progress: bool | None = None) -> xr.Dataset:
    """Outcome of every method on hard cases: near-grazing flights whose extremum passes eps inside
    a wall (no impact) or crosses it by eps (an impact) at both walls; chattering into sticking;
    a long chaotic run followed against the reference.

    A run that cannot finish is cut by a budget: ``solve_ivp`` by its right-hand-side evaluations
    (``chatter_max_evals``, ``chaos_max_evals``), so that where it stops, and so its outcome, is the
    same on every machine; the peers by ``max_seconds`` (Siconos runs in its own process).
    ``progress``: a bar over the methods (default: only when run interactively)."""
    ladder = [m for m in method_ladder(ivp_methods, ivp_tols, rk4_steps, heyoka_tols, siconos_tols, siconos_steps)
              if m[0] != "python"]
    d, gbar = 0.3, 0.2
    grazing = _grazing_cases(epsilons, d, gbar)
    cases = [g[0] for g in grazing] + ["chattering into sticking", f"chaotic run ({chaos_impacts} impacts)"]
    outcome = np.empty((len(ladder), len(cases)), dtype=object)
    detail = np.empty((len(ladder), len(cases)), dtype=object)
    seconds = np.full((len(ladder), len(cases)), np.nan)
    chat = [e for e in bounce_by_bounce(0.3, 0.15, -0.25, 0.3, 0.9, 0.5, t_end=chatter_t_end)
            if e[0] == "impact" and abs(float(e[3])) > CHATTER_V and float(e[1]) <= chatter_t_end]
    chat_t = np.array([float(e[1]) for e in chat])
    chat_w = np.array([e[2] for e in chat], dtype=int)
    bar = Progress(2 * len(ladder), "failure map", progress, unit="method x case family")
    order = compiled_last(ladder)
    for i in order:
        family, setting, _ = ladder[i]
        bar.update()
        found = _flights(family, setting, [g[1] for g in grazing], d, gbar)
        for j, (_, _state, ref_tau, ref_wall, side, wall) in enumerate(grazing):
            tau, w = found[j]
            if w == ref_wall and abs(tau - ref_tau) <= TIME_RTOL * max(1.0, ref_tau):
                out = "correct"
            elif side == "hit" and (w != wall or tau > ref_tau + LATE):
                out = "missed impact"
            elif side == "miss" and w == wall and abs(tau - 0.6) < 0.05:
                out = "spurious impact"
            else:
                out = "wrong time"
            outcome[i, j], detail[i, j] = out, f"tau={tau:.12g} wall={w} (reference {ref_tau:.12g}, {ref_wall})"
        # chattering into sticking: the impacts faster than CHATTER_V (those after each release,
        # which follow from the stick and release times) against the bounce-by-bounce reference
        p = Params(d=0.3, gbar=0.9, r=0.5)
        run = _run(family, setting, p, 0.3, 0.5, 200_000, t_end=chatter_t_end, max_seconds=max_seconds,
                   max_evals=chatter_max_evals)
        outcome[i, len(grazing)], detail[i, len(grazing)] = _chatter_outcome(run, chat_t, chat_w)
        seconds[i, len(grazing)] = run.seconds
    # long chaotic run against the reference
    beta, dc, phi, v0 = SCENES["chaotic"]
    pc = _params(beta, dc)
    ref = trajectory(pc.d, pc.gbar, pc.r, phi, v0, chaos_impacts)
    rt = np.array([float(x[0]) for x in ref])
    rw = np.array([x[1] for x in ref])
    sensitive = np.zeros((len(ladder), len(cases)), bool)
    for i in order:
        family, setting, _ = ladder[i]
        bar.update()
        run = _run(family, setting, pc, phi, v0, chaos_impacts, max_seconds=max_seconds, max_evals=chaos_max_evals)
        outcome[i, len(grazing) + 1], detail[i, len(grazing) + 1] = _chaos_outcome(run, rt, rw)
        seconds[i, len(grazing) + 1] = run.seconds
        # when a chaotic run parts from the reference is the last bit's to decide where the method's own error is
        # rounding: the same run from a start one ulp away says whether its outcome is
        moved = _run(family, setting, pc, math.nextafter(phi, math.inf), v0, chaos_impacts, max_seconds=max_seconds,
                     max_evals=chaos_max_evals)
        sensitive[i, len(grazing) + 1] = _chaos_outcome(moved, rt, rw)[0] != outcome[i, len(grazing) + 1]
    bar.close()
    ds = xr.Dataset(
        {
            "outcome": (("solver", "case"), outcome.astype(str), {"long_name": "outcome", "flag_meanings": " / ".join(OUTCOMES)}),
            "detail": (("solver", "case"), detail.astype(str)),
            "seconds": (("solver", "case"), seconds, {"units": "s", "long_name": "wall-clock time of the run (the "
                                                      "chattering and chaotic cases; NaN: a single flight)"}),
            "sensitive": (("solver", "case"), sensitive, {"long_name": "outcome changes when the start moves by one ulp "
                                                                        "(a chaotic run's, decided by the last bit)"}),
            "family": ("solver", [m[0] for m in ladder]),
            "setting": ("solver", [m[1] for m in ladder]),
        },
        coords={"solver": [m[2] for m in ladder], "case": cases},
    )
    ds.attrs.update(d=d, gbar=gbar, **failure_thresholds(), peers=str(peer_status()), note="the plain-Python run of the exact algorithm takes the same decisions as the compiled one")
    return ds


#: the families whose runs numba compiles (the exact event loop, RK4 with bisection)
COMPILED = ("exact", "rk4")


def compiled_last(ladder) -> list[int]:
    """The indices of ``ladder`` with the numba-compiled families (:data:`COMPILED`) last, each group in its
    order.  The failure map runs them so: a first run's kernels are then compiled by the job beside it (the
    workflow starts this one first), not by both at once, and each row's outcome is its method's alone."""
    return sorted(range(len(ladder)), key=lambda i: ladder[i][0] in COMPILED)


def _grazing_cases(epsilons, d, gbar):
    """The failure map's near-grazing flights: ``(name, state, reference time, reference wall, side, wall)``,
    an extremum passing ``eps`` inside each wall (``"miss"``) or crossing it by ``eps`` (``"hit"``)."""
    rng = np.random.default_rng(7)
    grazing = []
    for wall in (1, -1):
        for eps in epsilons:
            for side in ("miss", "hit"):
                # an extremum at tau = 0.6 with |Z''| > 0.2: the whole excursion past the wall lies
                # inside the flight, and the flight starts strictly inside the cylinder
                while True:
                    theta_e = rng.uniform(0, 2 * np.pi)
                    if wall * (math.cos(theta_e) + gbar) >= -0.2:
                        continue
                    state = grazing_state(theta_e, 0.6, d, gbar, wall, eps if side == "miss" else -eps)
                    ref_tau, ref_wall, clearance = first_impact(*state, d, gbar)
                    if abs(state[1]) < 0.45 * d and (side == "miss" or abs(float(ref_tau) - 0.6) < 0.5):
                        break
                grazing.append((f"{'B' if wall == 1 else 'T'} {side} by {eps:.0e}", state, float(ref_tau), ref_wall, side, wall))
    return grazing


def _chatter_outcome(run, chat_t, chat_w):
    """Outcome and detail of a run chattering into sticking: its impacts faster than CHATTER_V (those after each
    release, which follow from the stick and release times) against the bounce-by-bounce reference's."""
    fast = np.abs(run.v) > CHATTER_V
    st, sw = run.t[fast], run.wall[fast]
    n = min(len(st), len(chat_t))
    bad = np.flatnonzero((sw[:n] != chat_w[:n]) | (np.abs(st[:n] - chat_t[:n]) > TIME_RTOL * np.maximum(1.0, chat_t[:n])))
    followed = int(bad[0]) if bad.size else n
    if run.status.startswith(M.CRASHED):
        out = "crashed"
    elif followed == len(chat_t):
        out = "correct"
    elif followed == n and run.status == M.NO_IMPACT:
        out = "missed impact"  # the ball left through the wall: no further impact found
    elif followed == n and run.status != M.OK:
        out = "stalled"
    else:
        out = "wrong sequence"
    return out, (f"follows the reference's {len(chat_t)} impacts faster than {CHATTER_V:.0e} for {followed}, "
                 f"to t={run.t[-1] if len(run.t) else 0:.6g} ({run.status})")


def _chaos_outcome(run, rt, rw):
    """Outcome and detail of a long chaotic run against the reference's impact times ``rt`` and walls ``rw``."""
    n = min(len(run.t), len(rt))
    bad = np.flatnonzero((run.wall[:n] != rw[:n]) | (np.abs(run.t[:n] - rt[:n]) > CHAOS_ATOL))
    followed = int(bad[0]) if bad.size else n
    if followed == len(rt):
        out = "correct"
    elif run.status.startswith(M.CRASHED):
        out = "crashed"
    elif followed == n and run.status != M.OK:
        out = "stalled"  # right so far, but out of time (max_seconds) before the last impact
    else:
        out = "wrong sequence"
    return out, f"follows the reference for {followed} of {len(rt)} impacts ({run.status})"


# ---------------------------------------------------------------------------------------------
# Accuracy of the analytics against resolution and cost
# ---------------------------------------------------------------------------------------------


#: the located points' tolerances in d: the branch's critical points (the continuation's ``xtol``) and the sweeps'
#: transitions (:func:`vibroimpact.locate_transitions`'s); an error below one is the location's noise
BRANCH_XTOL, SWEEP_XTOL = 1e-13, 1e-9


def analytics_accuracy(*, steps=(2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4), points=(25, 50, 100, 200, 400, 800),
                       g1: float, g2: float) -> xr.Dataset:
    """How critical points converge with the continuation step, and how the sweep-located grazing
    points converge with the sweep resolution, against cost.

    (a) The beta = pi/3 2:1 branch: the period doubling B and the fold located by refinement, and
    the grid-only estimate (middle of the branch interval where the test function changes sign),
    against the finest step's located values.  (b) beta = pi/6 sweeps over 0.136 < d < 0.144: G1
    and G2 from the grid alone (middle of the interval where the motion changes) and located
    (followed attractor, ``SWEEP_XTOL``), against the analytic points ``g1``, ``g2``.
    """


    p = Params.from_physical(s=0.184 / 0.6225, beta=math.pi / 3)
    orbit = find_orbit(p, "BBT", 1.21, 0.2164)
    continue_orbit(orbit, vary="s", d_range=(0.15, 0.23), step=2e-2, xtol=BRANCH_XTOL)  # compile outside the timing
    located, grid, cost_a = [], [], []
    for h in steps:
        t0 = time.perf_counter()
        br = continue_orbit(orbit, vary="s", d_range=(0.15, 0.23), step=h, xtol=BRANCH_XTOL)
        cost_a.append(time.perf_counter() - t0)
        kinds, crit = br.critical_kind.values, br.critical_d.values
        located.append([float(crit[kinds == k][0]) for k in ("B", "fold")])
        tr, det = br.trace.values, br.det.values
        est = []
        for f in (1 + tr + det, 1 - tr + det):
            i = np.flatnonzero(np.diff(np.sign(f)) != 0)
            ok = i[np.abs(f[i]) + np.abs(f[i + 1]) < 10]  # sign changes through zero, not through a pole
            est.append(float(0.5 * (br.d.values[ok[0]] + br.d.values[ok[0] + 1])))
        grid.append(est)
    located, grid = np.array(located), np.array(grid)
    ref = located[-1]
    k_s = PAPER.d(1.0)  # d per metre of s at the paper's force
    sw_grid, sw_loc, cost_b = [], [], []
    sweep("s", np.linspace(0.136, 0.144, 5) / k_s, beta=math.pi / 6)  # compile
    for n in points:
        t0 = time.perf_counter()
        sw = sweep("s", np.linspace(0.136, 0.144, n) / k_s, beta=math.pi / 6, phi=5.855, v0=0.4185)
        t1 = time.perf_counter()
        tr = locate_transitions(sw, xtol=SWEEP_XTOL)
        t2 = time.perf_counter()
        est = []
        for k_dir, target in ((1, g1), (0, g2)):
            lab = sw.label.values[k_dir]
            i = np.flatnonzero(lab[:-1] != lab[1:])
            j = i[np.argmin(np.abs(sw.d.values[i] - target))]
            est.append(0.5 * (sw.d.values[j] + sw.d.values[j + 1]))
        down = tr.d.values[tr.direction.values == "down"]
        up = tr.d.values[tr.direction.values == "up"]
        sw_grid.append(est)
        sw_loc.append([down[np.argmin(np.abs(down - g1))], up[np.argmin(np.abs(up - g2))]])
        cost_b.append([t1 - t0, t2 - t1])
    sw_grid, sw_loc, cost_b = np.array(sw_grid), np.array(sw_loc), np.array(cost_b)
    exact = np.array([g1, g2])
    ds = xr.Dataset(
        {
            "branch_located_err": (("step", "point_kind"), np.abs(located - ref), {"units": "1", "long_name": "located critical point: |d - d(finest step)|"}),
            "branch_grid_err": (("step", "point_kind"), np.abs(grid - ref), {"units": "1", "long_name": "grid-only estimate: |d - d(finest step)|"}),
            "branch_seconds": ("step", np.array(cost_a), {"units": "s", "long_name": "continuation with stability and located points"}),
            "sweep_grid_err": (("points", "grazing"), np.abs(sw_grid - exact), {"units": "1", "long_name": "grid-only estimate: |d - analytic|"}),
            "sweep_located_err": (("points", "grazing"), np.abs(sw_loc - exact), {"units": "1", "long_name": "located transition: |d - analytic|"}),
            "sweep_seconds": (("points", "stage"), cost_b, {"units": "s", "long_name": "sweep (up and down) and transition location"}),
        },
        coords={"step": list(steps), "point_kind": ["B", "fold"], "points": list(points), "grazing": ["G1", "G2"],
                "stage": ["sweep", "locate"]},
    )
    ds.attrs.update(B_reference=float(ref[0]), fold_reference=float(ref[1]), G1=g1, G2=g2, branch_xtol=BRANCH_XTOL,
                    sweep_xtol=SWEEP_XTOL)
    return annotate(ds)
