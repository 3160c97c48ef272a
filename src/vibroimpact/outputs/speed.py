"""The speed-and-accuracy page's numbers, generated from the benchmark datasets: one table of rows
(name, quantity, value, source), so that the page's prose names a row instead of typing a timing."""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import xarray as xr

from ..benchmarks.lyapunov_precision import summarise

#: the impact-time error the work-precision table asks of the cheapest setting of each method
WORK_PRECISION_TARGET = 1e-9


def _g(x: float, digits: int = 2) -> str:
    """A number to ``digits`` significant figures: plain from 1e-3 up, in exponent form below."""
    if not np.isfinite(x):
        return "n/a"
    s = f"{x:.{digits}g}"
    if "e+" in s:
        return f"{round(float(s)):d}"
    if x and abs(x) < 1e-3:
        return f"{x:.{digits - 1}e}"
    return s


def _range(values, digits: int = 2, unit: str = "") -> str:
    """``lo–hi`` (or one value where they agree to the digits shown) of the finite values, with a unit."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if not v.size:
        return "n/a"
    lo, hi = _g(float(v.min()), digits), _g(float(v.max()), digits)
    return (lo if lo == hi else f"{lo}–{hi}") + unit


def _per_scene(ds: xr.Dataset, var: str, digits: int = 2, unit: str = "") -> str:
    """``value (scene); value (scene)`` over a dataset's scenes."""
    return "; ".join(f"{_g(float(ds[var].sel(scene=s)), digits)}{unit} ({s})" for s in ds.scene.values)


def _row(rows: list, name: str, quantity: str, value: str, source: str) -> None:
    rows.append({"row": name, "quantity": quantity, "value": value, "source": source})


def _rows_of(rows: list, src: str, specs) -> None:
    """One row per ``(row name, variable, quantity, value)`` of ``specs`` whose value is not None, its source the
    variable of the dataset ``src``."""
    for name, var, quantity, value in specs:
        if value is not None:
            _row(rows, name, quantity, value, f"{src}: `{var}`")


def _kernel_rows(rows: list, kp: xr.Dataset) -> None:
    hy = kp["heyoka_stepping_us_per_impact"].values
    cores = kp.attrs.get("cores", "all")
    _rows_of(rows, "results/bench/kernel.nc", [
        ("kernel_us_per_impact", "us_per_impact",
         "exact simulator (`simulate`, one thread, dataset included): µs per impact",
         _per_scene(kp, "us_per_impact", 2, " µs")),
        ("kernel_points_per_impact", "points_per_impact", "points of a flight evaluated per impact",
         _per_scene(kp, "points_per_impact", 2)),
        ("kernel_trig_per_impact", "trig_per_impact", "sine and cosine calls per impact",
         _per_scene(kp, "trig_per_impact", 2)),
        ("kernel_trig_floor_us_per_impact", "trig_floor_us_per_impact",
         "the same sines and cosines alone, each waiting for the last: µs per impact (a floor under the kernel)",
         _per_scene(kp, "trig_floor_us_per_impact", 2, " µs") if "trig_floor_us_per_impact" in kp else None),
        ("kernel_finder_us_per_impact", "finder_us_per_impact",
         "the event finder alone, over the run's own flights (identical operations, no event loop): µs per impact",
         _per_scene(kp, "finder_us_per_impact", 2, " µs") if "finder_us_per_impact" in kp else None),
        ("heyoka_stepping_us_per_impact", "heyoka_stepping_us_per_impact",
         "heyoka at tol = eps, stepping alone (no events, no Python loop): µs per impact",
         _per_scene(kp, "heyoka_stepping_us_per_impact", 2, " µs") if np.isfinite(hy).any() else None),
        ("heyoka_stepping_ratio", "heyoka_stepping_us_per_impact` / `us_per_impact",
         "heyoka's stepping cost / the exact simulator's, same run",
         _range(hy / kp["us_per_impact"].values, 2, "×") if np.isfinite(hy).any() else None),
        ("impacts_per_second_1", "impacts_per_second_1", "`simulate_batch` on one core: million impacts per second",
         _range(kp["impacts_per_second_1"].values / 1e6, 2)),
        ("impacts_per_second_all", "impacts_per_second_all",
         f"`simulate_batch` on {cores} cores: million impacts per second",
         _range(kp["impacts_per_second_all"].values / 1e6, 2)),
    ])


def _simulator_rows(rows: list, sim: xr.Dataset) -> None:
    v = {k: float(sim[k]) for k in sim.data_vars}
    has = lambda *names: all(n in v for n in names)
    _rows_of(rows, "results/bench/simulator.nc", [
        ("simulator_speedup", "speedup", "solve_ivp DOP853 (rtol 1e-12) time per impact / the exact simulator's",
         _g(v["speedup"], 3) + "×"),
        ("lyapunov_ratio", "lyapunov_ratio", "a run with both Lyapunov exponents / the plain run, time",
         _g(v["lyapunov_ratio"], 3) + "×" if has("lyapunov_ratio") else None),
        ("branch_seconds", "branch_seconds",
         f"continuation of the β = π/3 2:1 branch, {int(v.get('branch_points', 0))} points with "
         "stability, admissibility and critical points: seconds",
         _g(v["branch_seconds"], 2) + " s" if has("branch_seconds") else None),
        ("curve_seconds", "curve_seconds",
         f"two-parameter curve of G1 in (s, β), {int(v.get('curve_points', 0))} points: seconds",
         _g(v["curve_seconds"], 2) + " s" if has("curve_seconds") else None),
        ("sweep_seconds", "sweep_seconds",
         f"sweep of d at β = π/3, {int(v.get('sweep_points', 0))} points each way, attractors settled: seconds",
         _g(v["sweep_seconds"], 3) + " s" if has("sweep_seconds") else None),
        ("sweep_full_events_per_second", "sweep_full_events_per_second",
         "the same sweep with its energy, transitions, bistable intervals and 1:1 exit: million events per second",
         _g(v["sweep_full_events_per_second"] / 1e6, 2) if has("sweep_full_events_per_second") else None),
        ("sweep_kernel_events_per_second", "sweep_kernel_events_per_second",
         "the bare batch kernel on the sweep's points, same run: million events per second",
         _g(v["sweep_kernel_events_per_second"] / 1e6, 2) if has("sweep_kernel_events_per_second") else None),
        ("sweep_full_kernel_ratio", "sweep_full_kernel_ratio",
         "events per second of the full sweep / of the bare batch kernel, same run",
         _g(v["sweep_full_kernel_ratio"], 2) if has("sweep_full_kernel_ratio") else None),
        ("sweep_batch_events_per_second", "sweep_batch_events_per_second",
         "the batch kernel without the period test (`run_batch`) on the sweep's points, same run: million events "
         "per second", _g(v["sweep_batch_events_per_second"] / 1e6, 2) if has("sweep_batch_events_per_second") else None),
        ("sweep_full_batch_ratio", "sweep_full_batch_ratio",
         "events per second of the full sweep / of `run_batch`, same run",
         _g(v["sweep_full_batch_ratio"], 2) if has("sweep_full_batch_ratio") else None),
    ])


def _cheapest(wp: xr.Dataset, family: str, target: float):
    """Per scene, the cheapest solver of ``family`` whose impact-time error is at most ``target``:
    ``{scene: (setting, error, µs per impact)}``, scenes it does not reach left out."""
    out = {}
    for sc in wp.scene.values:
        sub = wp.sel(scene=sc)
        m = (sub.family.values == family) & (sub.err_t.values <= target)
        if m.any():
            i = np.flatnonzero(m)[np.argmin(sub.us_per_impact.values[m])]
            out[str(sc)] = (
                float(sub.setting.values[i]),
                float(sub.err_t.values[i]),
                float(sub.us_per_impact.values[i]),
            )
    return out


def _work_precision_rows(rows: list, wp: xr.Dataset) -> None:
    src = "results/bench/work_precision.nc"
    exact = wp.sel(solver=wp.solver.values[wp.family.values == "exact"][0])
    _row(
        rows,
        "exact_error",
        "exact simulator: largest impact-time error over the scenes",
        _g(float(exact.err_t.max()), 2),
        f"{src}: `err_t`, solver `{str(exact.solver.values)}`",
    )
    _row(
        rows,
        "exact_us_per_impact",
        "exact simulator in the work-precision run: µs per impact over the scenes",
        _range(exact.us_per_impact.values, 2, " µs"),
        f"{src}: `us_per_impact`, solver `{str(exact.solver.values)}`",
    )
    for fam in dict.fromkeys(wp.family.values):
        if fam in ("exact", "python"):
            continue
        best = _cheapest(wp, fam, WORK_PRECISION_TARGET)
        scenes = ", ".join(best) if len(best) < wp.sizes["scene"] else "every scene"
        value = (
            "not reached"
            if not best
            else f"{_range([b[2] for b in best.values()], 2, ' µs')} ({scenes}; settings "
            + ", ".join(dict.fromkeys(_g(b[0], 3) for b in best.values()))
            + ")"
        )
        _row(
            rows,
            f"work_precision_{fam}",
            f"{fam}: cheapest setting reaching {WORK_PRECISION_TARGET:g} in impact " "times, µs per impact",
            value,
            f"{src}: `us_per_impact`, `err_t`, family `{fam}`",
        )
        err = wp.err_t.values[wp.family.values == fam]
        _row(
            rows,
            f"work_precision_{fam}_error",
            f"{fam}: impact-time errors over its ladder and the scenes",
            _range(err, 1),
            f"{src}: `err_t`, family `{fam}`",
        )


def _matched_rows(rows: list, ma: xr.Dataset) -> None:
    src = "results/bench/matched_accuracy.nc"
    target = _g(float(ma.attrs.get("target", math.nan)), 2)
    for fam in ma.family.values:
        if fam == "exact":
            continue
        r = ma.sel(family=fam)
        reached = r.reached.values
        if not reached.any():
            value = "reaches it on no scene"
        else:
            scenes = "every scene" if reached.all() else ", ".join(str(s) for s in r.scene.values[reached])
            value = (
                f"{_range(r.us_per_impact.values[reached], 2, ' µs')}, "
                f"{_range(r.ratio_to_exact.values[reached], 2, '×')} the exact simulator's ({scenes})"
            )
        _row(
            rows,
            f"matched_{fam}",
            f"{fam}: cheapest setting reaching {target} on every impact, cost and ratio",
            value,
            f"{src}: `us_per_impact`, `ratio_to_exact`, family `{fam}`",
        )


def _followed(detail: str) -> float:
    """The number of reference impacts a failure-map run followed, from its detail text."""
    m = re.search(r"for (\d+)", detail)
    return float(m.group(1)) if m else math.nan


def _failure_rows(rows: list, fm: xr.Dataset) -> None:
    src = "results/bench/failure_map.nc"
    fam = fm.family.values
    sign_change = np.array([f.startswith("ivp-") or f == "rk4" for f in fam])
    hits = [c for c in fm.case.values if " hit by " in str(c)]
    unseen = [
        float(str(c).split(" by ")[1])
        for c in hits
        if (fm.outcome.sel(case=c).values[sign_change] != "correct").all()
    ]
    _row(
        rows,
        "failure_sign_change_unseen",
        "largest ε of an impact by ε past a wall that no solve_ivp or RK4 setting gets right",
        _g(max(unseen), 1) if unseen else "none",
        f"{src}: `outcome`, cases `… hit by ε`",
    )
    chat = fm.detail.sel(case="chattering into sticking").values
    total = re.search(r"reference's (\d+)", str(chat[0]))
    _row(
        rows,
        "failure_chatter_followed",
        "chattering into sticking: most fast impacts a solve_ivp or RK4 setting "
        "follows" + (f" (of the reference's {total.group(1)})" if total else ""),
        _g(max(_followed(str(d)) for d in chat[sign_change]), 3),
        f"{src}: `detail`, case `chattering into sticking`",
    )
    chaos_case = [c for c in fm.case.values if str(c).startswith("chaotic")][0]
    loose = sign_change & np.array([f.startswith("ivp-") for f in fam]) & (fm.setting.values >= 1e-6)
    if loose.any():
        _row(
            rows,
            "failure_chaos_loose",
            f"{chaos_case}: impacts solve_ivp at rtol 1e-6 follows",
            _range([_followed(str(d)) for d in fm.detail.sel(case=chaos_case).values[loose]], 3),
            f"{src}: `detail`, case `{chaos_case}`",
        )


def _analytics_rows(rows: list, aa: xr.Dataset) -> None:
    src = "results/bench/analytics_accuracy.nc"
    coarse = aa.step.values != aa.step.values.min()  # the finest step is the reference
    _row(
        rows,
        "analytics_branch_located",
        "2:1 period doubling and fold located by refinement: largest change " "over the continuation steps",
        _g(float(aa.branch_located_err.values[coarse].max()), 1),
        f"{src}: `branch_located_err`",
    )
    _row(
        rows,
        "analytics_branch_grid",
        "the same points read off the grid alone: error",
        _range(aa.branch_grid_err.values, 1),
        f"{src}: `branch_grid_err`",
    )
    for g in aa.grazing.values:
        _row(
            rows,
            f"analytics_sweep_{g}",
            f"{g} located from a sweep: error against the analytic point, over the " "sweep resolutions",
            _range(aa.sweep_located_err.sel(grazing=g).values, 1),
            f"{src}: `sweep_located_err`, grazing `{g}`",
        )
    _row(
        rows,
        "analytics_sweep_grid",
        "G1 and G2 read off the sweep grid alone: error",
        _range(aa.sweep_grid_err.values, 1),
        f"{src}: `sweep_grid_err`",
    )


def _per_motion(values: dict) -> str:
    """``value (motion); value (motion)``."""
    return "; ".join(f"{v} ({m})" for m, v in values.items())


def _lyapunov_rows(rows: list, lp: xr.Dataset) -> None:
    src = "results/bench/lyapunov_precision.nc"
    s = summarise(lp)
    fam, n = lp.family.values, lp.n_impacts.values
    motions = [str(m) for m in lp.motion.values]
    k = lp.sizes["repeat"]

    def longest(family):
        m = fam == family
        return lp.solver.values[m][np.argmax(n[m])] if m.any() else None

    _row(rows, "lyap_reference", f"λ₁ per unit t of the reference runs ({int(lp.attrs.get('n_ref', 0))} impacts of the "
         "tangent map) and its 95 % interval", _per_motion({
             m: f"{float(lp.lambda_ref.sel(motion=m)):.4f} ({float(lp.lambda_ref_low.sel(motion=m)):.4f} … "
                f"{float(lp.lambda_ref_high.sel(motion=m)):.4f})" for m in motions}),
         f"{src}: `lambda_ref`, `lambda_ref_low`, `lambda_ref_high`")
    floquet = {m: float(lp.lambda_floquet.sel(motion=m)) for m in motions}
    _row(rows, "lyap_floquet", "ln max|μ| / 2 of the periodic orbits (their Floquet multipliers)",
         _per_motion({m: f"{v:.4f}" for m, v in floquet.items() if np.isfinite(v)}), f"{src}: `lambda_floquet`")
    for family, name in (("tangent", "tangent map"), ("benettin-exact", "Benettin on exact flights")):
        so = longest(family)
        if so is None:
            continue
        _row(rows, f"lyap_{family.replace('-', '_')}_error",
             f"{name}, its longest runs (n = {int(lp.n_impacts.sel(solver=so))}): median error over {k} starts",
             _per_motion({m: _g(float(s.error_median.sel(motion=m, solver=so)), 1) for m in motions}),
             f"{src}: `error`, solver `{so}`")
    m_ivp, m_ex = fam == "benettin-DOP853", fam == "benettin-exact"
    if m_ivp.any() and m_ex.any():  # seconds per impact followed (two flights each), same run
        per = s.seconds / lp.n_impacts
        ratio = np.concatenate([(v[m_ivp][:, None] / v[m_ex][None, :]).ravel() for v in per.values])  # per motion
        _row(rows, "lyap_benettin_ivp_cost", "Benettin on DOP853 / on exact flights: seconds per impact, same run "
             "(over the motions and settings)", _range(ratio, 2, "×"),
             f"{src}: `seconds`, `n_impacts`, families `benettin-DOP853`, `benettin-exact`")
    if m_ivp.any():
        best = {m: float(np.nanmin(s.error_median.sel(motion=m).values[m_ivp])) for m in motions}
        _row(rows, "lyap_benettin_ivp_error", "Benettin on solve_ivp DOP853: smallest median error over its settings",
             _per_motion({m: _g(v, 1) for m, v in best.items()}), f"{src}: `error`, family `benettin-DOP853`")
    for family in ("nolds-lyap_r", "nolds-lyap_e"):
        so = longest(family)
        if so is None:
            continue
        short = family.split("-")[1]  # lyap_r, lyap_e
        r = s.sel(solver=so)
        chaotic = [m for m in motions if not np.isfinite(floquet[m])]
        periodic = [m for m in motions if np.isfinite(floquet[m])]
        _rows_of(rows, src, [
            (f"lyap_nolds_{short[-1]}_chaotic", "error` / `lambda_ref",
             f"nolds {short}, n = {int(lp.n_impacts.sel(solver=so))}, on the chaotic motion: median relative error, "
             f"and starts whose sign is right (of {k})",
             "; ".join(f"{_g(float(r.relative_error.sel(motion=m)), 2)}, sign right {int(r.sign_agrees.sel(motion=m))}"
                       for m in chaotic) or None),
            (f"lyap_nolds_{short[-1]}_periodic", "reason", f"nolds {short}, n = {int(lp.n_impacts.sel(solver=so))}, on the "
             f"periodic motions: starts with a finite estimate (of {k})",
             _per_motion({m: str(int(r.finite.sel(motion=m))) for m in periodic}) or None),
        ])


def _cost_rows(rows: list, jobs: pd.DataFrame) -> None:
    src = "results/tables/workflow_cost.csv"
    per_rule = jobs.groupby("rule").seconds.agg(["count", "sum"])
    for rule, what in (
        ("sweep", "the sweeps"),
        ("regime_map", "the regime maps"),
    ):  # rules of the default target, which the workflow-cost table waits for
        if rule in per_rule.index:
            n, s = per_rule.loc[rule]
            _row(
                rows,
                f"cost_{rule}",
                f"{what}: jobs, total seconds",
                f"{int(n)} jobs, {_g(s, 3)} s",
                f"{src}: rule `{rule}`",
            )
    timed = [r for r in ("work_precision", "analytics_accuracy", "lyapunov_precision") if r in per_rule.index]
    if timed:
        _row(
            rows,
            "cost_timed_benchmarks",
            "the timed benchmarks ("
            + ", ".join(f"`{r}`" for r in timed)
            + "), which run alone: total seconds",
            _g(float(per_rule.loc[timed, "sum"].sum()), 3) + " s",
            f"{src}: rules " + ", ".join(f"`{r}`" for r in timed),
        )


def speed_summary(
    *,
    kernel: xr.Dataset | None = None,
    simulator: xr.Dataset | None = None,
    work_precision: xr.Dataset | None = None,
    matched_accuracy: xr.Dataset | None = None,
    failure_map: xr.Dataset | None = None,
    analytics_accuracy: xr.Dataset | None = None,
    workflow_cost: pd.DataFrame | None = None,
    lyapunov_precision: xr.Dataset | None = None,
) -> pd.DataFrame:
    """The numbers the speed-and-accuracy page cites, from the benchmark datasets.

    Parameters
    ----------
    kernel, simulator, work_precision, matched_accuracy, failure_map, analytics_accuracy : xarray.Dataset
        The ``bench`` target's datasets (``results/bench/*.nc``), each optional: one left out gives no
        rows.
    workflow_cost : pandas.DataFrame, optional
        The benchmarked jobs (``results/tables/workflow_cost.csv``).
    lyapunov_precision : xarray.Dataset, optional
        The largest Lyapunov exponent's speed against accuracy (``results/bench/lyapunov_precision.nc``).

    Returns
    -------
    pandas.DataFrame
        One row per number: ``row`` (its name, which the page cites), ``quantity``, ``value`` (as text,
        with its unit) and ``source`` (dataset and variable).

    Examples
    --------
    >>> import xarray as xr
    >>> ds = xr.Dataset({"speedup": ((), 1500.0)})
    >>> speed_summary(simulator=ds).value.tolist()
    ['1500×']
    """
    rows: list = []
    for ds, add in (
        (kernel, _kernel_rows),
        (simulator, _simulator_rows),
        (work_precision, _work_precision_rows),
        (matched_accuracy, _matched_rows),
        (failure_map, _failure_rows),
        (analytics_accuracy, _analytics_rows),
        (lyapunov_precision, _lyapunov_rows),
        (workflow_cost, _cost_rows),
    ):
        if ds is not None:
            add(rows, ds)
    return pd.DataFrame(rows, columns=["row", "quantity", "value", "source"])


def speed_summary_markdown(df: pd.DataFrame) -> str:
    """The summary as a Markdown table, its row names in code font so that the page can cite them."""
    lines = ["| row | quantity | value | source |", "|---|---|---|---|"]
    for r in df.itertuples():
        lines.append(f"| `{r.row}` | {r.quantity} | {r.value} | {r.source} |")
    return "\n".join(lines) + "\n"
