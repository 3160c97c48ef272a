"""Tables built from branch datasets (paper Table 1)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from ..analysis.energy import delivered
from ..analysis.lyapunov import t_quantile
from ..analysis.motion_names import CHAOTIC, ONE_ONE, TWO_ONE
from ..analysis.settled import LONG_BATCHES
from ..analysis.transitions import PERIOD_DOUBLING
from ..benchmarks.lyapunov_precision import summarise
from ..benchmarks.outcomes import OUTCOMES
from .paper import paper_stable, pi_tex


def stable_interval(branch: xr.Dataset):
    """Longest run of stable, admissible points: (d_lo, d_hi, cause_lo, cause_hi), each end snapped
    to the located critical point (B, fold, grazing, NS) nearest to it."""
    if branch.attrs.get("status") == "failed" or not branch.sizes.get("point", 0):
        return math.nan, math.nan, "", ""
    ok = (branch.stable & branch.admissible).values
    if not ok.any():
        return math.nan, math.nan, "", ""
    # longest contiguous run along the branch
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(int), [0]])))
    runs = edges.reshape(-1, 2)
    a, b = runs[np.argmax(runs[:, 1] - runs[:, 0])]
    d = branch.d.values[a:b]
    lo, hi = float(d.min()), float(d.max())
    kinds = branch.critical_kind.values
    crit = branch.critical_d.values
    ends = []
    for x in (lo, hi):
        mask = np.isin(kinds, ["B", "fold", "grazing", "NS"])
        if mask.any():
            j = np.argmin(np.abs(crit[mask] - x))
            if abs(crit[mask][j] - x) < 5 * float(branch.attrs.get("step", 1e-3)):
                ends.append((float(crit[mask][j]), str(kinds[mask][j])))
                continue
        ends.append((x, "end of range"))
    return ends[0][0], ends[1][0], ends[0][1], ends[1][1]


#: what changes sign at a critical point that bounds an interval of paper Table 1: Delta at A (node <-> focus),
#: the smaller eigenvalue + 1 at B (period doubling)
_SIGN_CHANGE = {"A": lambda br: br.discriminant.values, "B": lambda br: br.eig_real.values.min(axis=1) + 1.0}


def stability_types(branch: xr.Dataset) -> pd.DataFrame:
    """Node or focus, stable or unstable, on each interval of a branch's stable sheet (paper Table 1).

    The sheet is the side of the branch's fold (its largest d) that holds more of its stable, admissible
    points.  It is cut at the located critical points B (lambda = -1) and A (Delta = 0) that lie on it (their
    quantity changes sign between the sheet's points around them), numbered A1, A2, ... by increasing d, and
    ends at the lowest continued d and at the fold.  Each interval's type is read from the data at its
    middle: a node where the discriminant Delta (interpolated along the sheet) is positive, a focus where it
    is negative; stable as the nearest point is.  As in the paper's table, admissibility is not asked (the
    stable physical interval is :func:`table1`'s).

    Returns
    -------
    pandas.DataFrame
        One row per interval: ``d_from``, ``d_to``, ``from_point``, ``to_point`` (``branch end``, ``B``,
        ``A1``, ..., ``fold``), ``discriminant`` and ``stable`` at the middle, and ``type``.
    """
    cols = ["d_from", "d_to", "from_point", "to_point", "discriminant", "stable", "type"]
    if branch.attrs.get("status") == "failed" or not branch.sizes.get("point", 0):
        return pd.DataFrame(columns=cols)
    d = branch.d.values
    k = int(np.argmax(d))
    ok = (branch.stable & branch.admissible).values
    sheet = np.arange(k + 1) if ok[: k + 1].sum() >= ok[k:].sum() else np.arange(k, d.size)[::-1]
    ds = d[sheet]  # increasing along the sheet
    cuts = []
    for kind, c in zip(branch.critical_kind.values.astype(str), branch.critical_d.values, strict=True):
        if kind in _SIGN_CHANGE and ds[0] < c < ds[-1]:
            q = _SIGN_CHANGE[kind](branch)[sheet]
            j = int(np.searchsorted(ds, c))
            if q[j - 1] * q[j] <= 0:
                cuts.append([float(c), kind])
    cuts.sort()
    for n, cut in enumerate(c for c in cuts if c[1] == "A"):
        cut[1] = f"A{n + 1}"
    folds = branch.critical_d.values[branch.critical_kind.values.astype(str) == "fold"]
    top = "fold" if folds.size and np.min(np.abs(folds - ds[-1])) < 5 * float(branch.attrs.get("step", 1e-3)) else "branch end"
    edges = [(float(ds[0]), "branch end"), *map(tuple, cuts), (float(ds[-1]), top)]
    rows = []
    for (lo, a), (hi, b) in zip(edges[:-1], edges[1:], strict=True):
        mid = 0.5 * (lo + hi)
        disc = float(np.interp(mid, ds, branch.discriminant.values[sheet]))
        stable = bool(branch.stable.values[sheet][np.argmin(np.abs(ds - mid))])
        kind = ("stable " if stable else "unstable ") + ("node" if disc > 0 else "focus")
        rows.append(dict(d_from=lo, d_to=hi, from_point=a, to_point=b, discriminant=disc, stable=stable, type=kind))
    return pd.DataFrame(rows, columns=cols)


def _interval_name(lo: str, hi: str) -> str:
    """``d_B < d < d_A1`` as the paper's Table 1 writes an interval; an end of the continued branch is left open."""
    def sub(p):
        return "d_" + p

    if lo == "branch end":
        return f"d < {sub(hi)}" if hi != "branch end" else "all d"
    return f"d > {sub(lo)}" if hi == "branch end" else f"{sub(lo)} < d < {sub(hi)}"


def table1(branches: list[xr.Dataset]) -> pd.DataFrame:
    """One row per incline: the stable interval with its causes, the period-doubling point B, the
    node/focus points A_i inside it and the fold (where admissible, the largest d of the 2:1 period-2 orbit: the
    paper's d_graz, :func:`vibroimpact.branch_d_graz`), next to the paper's stable interval, and the type (node or
    focus, stable or unstable) of each interval between them (:func:`stability_types`, column ``types``)."""
    rows = []
    for br in branches:
        beta = float(br.attrs["beta"])
        row = {"beta": beta, "beta_deg": round(math.degrees(beta), 6)}
        if br.attrs.get("status") == "failed":
            row["note"] = br.attrs["reason"]
            rows.append(row)
            continue
        lo, hi, clo, chi = stable_interval(br)
        kinds, crit = br.critical_kind.values, br.critical_d.values
        a_pts = np.sort(crit[(kinds == "A") & (crit > lo) & (crit < hi)])
        row.update(stable_from=lo, stable_to=hi, lower_cause=clo, upper_cause=chi,
                   d_B=float(np.max(crit[kinds == "B"])) if (kinds == "B").any() else np.nan,
                   d_A=", ".join(f"{x:.6f}" for x in a_pts),
                   d_fold=float(np.max(crit[kinds == "fold"])) if (kinds == "fold").any() else np.nan)
        paper = paper_stable(beta)
        row.update(paper_from=paper[0] if paper else np.nan, paper_to=paper[1] if paper else np.nan)
        row["types"] = "; ".join(f"{_interval_name(r.from_point, r.to_point)}: {r.type}"
                                 for r in stability_types(br).itertuples())
        # nothing dropped: why the continuation stopped each way, and any point not refined
        row.update(branch_stops=f"{br.attrs.get('stop_decreasing', '?')}; {br.attrs.get('stop_increasing', '?')}")
        if "critical_refined" in br and not bool(br.critical_refined.all()):
            bad = ~br.critical_refined.values
            row["unrefined"] = "; ".join(f"{k} near {d:.6f}: {n}" for k, d, n in zip(
                br.critical_kind.values[bad], br.critical_d.values[bad], br.critical_note.values[bad], strict=True))
        else:
            row["unrefined"] = "none"
        rows.append(row)
    df = pd.DataFrame(rows)
    for col in TABLE1_COLUMNS:  # an incline without a branch has NaN there, and a table of such inclines these columns
        if col not in df:
            df[col] = np.nan
    return df


#: the columns :func:`table1` always has (NaN in the row of an incline without a branch, its ``note`` saying why)
TABLE1_COLUMNS = ("beta", "beta_deg", "stable_from", "stable_to", "lower_cause", "upper_cause", "d_B", "d_A", "d_fold",
                  "paper_from", "paper_to", "types", "branch_stops", "unrefined")


def table1_markdown(df: pd.DataFrame) -> str:
    lines = ["| β | 2:1 stable for d in | ends by | paper | d_B (λ = −1) | A points (node ↔ focus) | fold |",
             "|---|---|---|---|---|---|---|"]
    names = {90.0: "π/2", 60.0: "π/3", 45.0: "π/4", 30.0: "π/6"}
    for _, r in df.iterrows():
        name = names.get(round(r.beta_deg, 6), f"{r.beta:.4f}")
        if _failed(r):  # no branch at this incline: why, in the row
            lines.append(f"| {name} | no 2:1 branch: {r.note} | | | | | |")
            continue
        lines.append(
            f"| {name} | ({r.stable_from:.6f}, {r.stable_to:.6f}) | {r.lower_cause} / {r.upper_cause} | "
            f"({r.paper_from:g}, {r.paper_to:g}) | {r.d_B:.6f} | {r.d_A} | {r.d_fold:.6f} |"
        )
    lines += ["", "Node or focus on each interval (paper Table 1), along the stable sheet of each branch from its "
              "lowest continued d to its fold, cut at B and A1, A2, ... (d_A1 the first A on the sheet): read from "
              "the data at each interval's middle (node where Δ > 0, focus where Δ < 0), admissible or not:", "",
              "| β | interval: type |", "|---|---|"]
    for _, r in df.iterrows():
        name = names.get(round(r.beta_deg, 6), f"{r.beta:.4f}")
        lines.append(f"| {name} | {'no 2:1 branch' if _failed(r) else r.get('types', '')} |")
    lines += ["", "Where each continuation stopped (decreasing; increasing arclength) and critical points that "
              "could not be refined:", ""]
    for _, r in df.iterrows():
        name = names.get(round(r.beta_deg, 6), f"{r.beta:.4f}")
        lines.append(f"- {name}: no 2:1 branch ({r.note})." if _failed(r) else
                     f"- {name}: {r.get('branch_stops', '?')}. Unrefined critical points: {r.get('unrefined', '?')}.")
    return "\n".join(lines) + "\n"


def _failed(row) -> bool:
    """Whether a row of :func:`table1` is an incline without a branch (its ``note`` says why)."""
    return isinstance(row.get("note"), str) and bool(row.get("note"))


def d_graz_table(readings: dict[str, dict]) -> pd.DataFrame:
    """The paper's d_graz along each sweep (:func:`vibroimpact.sweep_d_graz`, by sweep name): one row per sweep,
    column ``sweep`` first."""
    return pd.DataFrame([{"sweep": name, **r} for name, r in readings.items()])


def _fmt(x, spec):
    return "—" if not np.isfinite(x) else format(x, spec)


def d_graz_summary(df: pd.DataFrame) -> str:
    """One sentence on the paper's identity over the sweeps of :func:`d_graz_table`: along how many it holds,
    and where it does not, the band between the down sweep's entry into 2:1 and the 1:1 exit."""
    if df.empty:
        return "No sweep to read d_graz along."
    held, fails = df[df.identity.astype(bool)], df[~df.identity.astype(bool)]
    text = (f"The paper's identity (the 1:1 motion grazes where 2:1 begins, at d_graz) holds along {len(held)} of "
            f"{len(df)} sweeps")
    if fails.empty:
        return text + "."
    kinds = fails.exit_kind.astype(str).value_counts()
    band = fails[fails.band_points > 0]
    text += (f". Along the other {len(fails)} the 1:1 motion leaves its family by "
             + " and ".join(f"{k} ({n})" for k, n in kinds.items())
             + f", {_fmt(fails.exit_minus_d_graz.abs().min(), '.4f')} to {_fmt(fails.exit_minus_d_graz.abs().max(), '.4f')}"
             " off d_graz")
    if len(band):
        text += (f", and {len(band)} down sweeps find {int(band.band_points.sum())} points between their entry into 2:1 "
                 f"and the exit (bands {_fmt(band.band_width.min(), '.4f')} to {_fmt(band.band_width.max(), '.4f')} wide), "
                 f"{int(band.band_chaotic.sum())} of them chaotic (λ₁ per impact up to "
                 f"{_fmt(band.band_lyap1_max.max(), '.3f')})")
    return text + "."


def d_graz_markdown(df: pd.DataFrame) -> str:
    """:func:`d_graz_table` as Markdown: per sweep, d_graz read from the 2:1 branch and from the sweeps, the 1:1
    exit, the band between and whether the paper's identity holds; then :func:`d_graz_summary`."""
    lines = ["d_graz is \"the maximum value for 2:1 period-2 solutions\": the fold of the 2:1 branch (analytic), "
             f"which the up sweep's {TWO_ONE.label} reaches before it is lost (located). The down sweep enters the "
             f"{TWO_ONE.label} at a sweep point (the entry lies within one step above it). The 1:1 exit is where the "
             "1:1 motion, followed with d decreasing, leaves its family, by grazing a wall or by a jump while clear of "
             "them. The paper's identity, \"at d = d_graz the 1:1 motion grazes and 2:1 follows for d < d_graz\", "
             "holds along a sweep where the exit is a grazing within the sweep step of both the entry and d_graz; "
             "the band is what the down sweep finds between its entry into 2:1 and the exit.", "",
             "| sweep | β | swept | d_graz (2:1 fold) | up sweep's 2:1 ends | down sweep enters 2:1 | d_graz − entry "
             "| 1:1 exit | how (clearance) | exit − d_graz | band: width, points | band's motions | λ₁ max | "
             "identity |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for _, r in df.iterrows():
        how = f"{r.exit_kind} ({r.exit_clearance:.1e})" if r.exit_kind else f"— ({r.exit_status})"
        lines.append(
            f"| {r.sweep} | {_pi_name(r.beta)} | {'length' if r.vary == 's' else 'force'} | {_fmt(r.d_graz, '.6f')} | "
            f"{_fmt(r.up_end_d, '.6f')} | {_fmt(r.entry_d, '.4f')} (+{_fmt(r.entry_step, '.1e')}) | "
            f"{_fmt(r.d_graz_minus_entry, '+.4f')} | {_fmt(r.exit_d, '.6f')} | {how} | "
            f"{_fmt(r.exit_minus_d_graz, '+.4f')} | {_fmt(r.band_width, '.4f')}, {r.band_points} | "
            f"{r.band_motions or '—'} | {_fmt(r.band_lyap1_max, '.3f')} | {'holds' if r.identity else 'fails'} |")
    return "\n".join(lines + ["", d_graz_summary(df)]) + "\n"


def grazing_lines(branches: list[xr.Dataset], scene: dict) -> dict:
    """G1 (grazing of the scene's branch at the graze incline) and G2 (fold of the other word's
    branch, e.g. 3:1): the ends of the bistable interval (paper Figure 5 (j)-(l), Figure 8)."""
    n = len(scene["betas"])
    beta = scene["grazing"]["beta"]
    main = next(b for b in branches[:n] if abs(float(b.attrs["beta"]) - beta) < 1e-9)
    other = branches[n]
    lo, hi, *_ = stable_interval(other)
    g1 = stable_interval(main)[0]
    return {"beta": beta, "G1": g1, "G2": hi}


def transitions_markdown(named: dict[str, xr.Dataset]) -> str:
    """Located transitions and bistable intervals of several sweeps as Markdown."""
    lines = ["| sweep | direction | d | ± | from | to | kind | status |", "|---|---|---|---|---|---|---|---|"]
    for name, tr in named.items():
        for k in range(tr.sizes.get("transition", 0)):
            r = tr.isel(transition=k)
            status = str(r.status.values) if "status" in r else "refined"
            d, half, after = float(r.d), float(r.d_width) / 2, str(r.after.values)
            if str(r.kind.values) == PERIOD_DOUBLING:
                d, half = float(r.bifurcation_d), float(r.bifurcation_d_width) / 2
                src = str(r.bifurcation_source.values)
                at = "between the sweeps' identifications" if src == "sweeps" else f"B of the {src} branch"
                status += f"; {at}, the detector gave up at {float(r.d):.7f} ({after})"
                after = str(r.beyond.values) or "not identified"
            lines.append(f"| {name} | {str(r.direction.values)} | {d:.7f} | {half:.0e} | "
                         f"{str(r.before.values)} | {after} | {str(r.kind.values)} | {status} |")
    lines += ["", "Period doubling: near a flip the attractor converges ever more slowly and the detector gives up "
              "short of it (critical slowing), so its label change is not the bifurcation; d is the flip, the "
              "period-doubling point B of the continued branch the status names (Newton's method, eigenvalue −1) "
              "or the middle of the bracket between the motions the two sweeps identify on either side, "
              "± covers where the detector gave up, and 'to' is the motion a sweep identifies past the flip "
              "(vibroimpact.period_doublings).", "",
              "Bistable intervals: the lower end is where the down sweep loses its motion, the upper end where "
              "the up sweep loses its motion (located transitions; an aperiodic motion's end is only known to the "
              "grid step; at a range end the interval may go on beyond the swept range).", "",
              "| sweep | bistable for d in | ± (lower, upper) | ends from | up sweep | down sweep | found by |",
              "|---|---|---|---|---|---|---|"]
    for name, tr in named.items():
        for k in range(tr.sizes.get("interval", 0)):
            r = tr.isel(interval=k)
            lines.append(f"| {name} | ({float(r.d_lo):.7f}, {float(r.d_hi):.7f}) | "
                         f"{_half_width(r.d_lo_width)}, {_half_width(r.d_hi_width)} | "
                         f"{str(r.lo_source.values)}, {str(r.hi_source.values)} | {str(r.label_up.values)} | "
                         f"{str(r.label_down.values)} | {str(r.found_by.values)} |")
    return "\n".join(lines) + "\n"


def _half_width(width) -> str:
    w = float(width)
    return f"{w / 2:.0e}" if math.isfinite(w) else "beyond range"


def design_table(energies: list[xr.Dataset]) -> pd.DataFrame:
    """For each sweep energy (an incline and a swept s or F): where U_T and U_I are largest, and
    the motion there (both sweep directions considered).  The outputs compared are what the device
    delivers (:func:`vibroimpact.analysis.energy.delivered`): the exact cycle's where the motion is periodic, the
    long run's where it is not (``U_T_se``, ``U_I_se``: their standard errors)."""

    rows = []
    for e in energies:
        vary = e.attrs["vary"]
        out = {q: delivered(e, q) for q in ("U_T", "U_I")}
        for q in ("U_T", "U_I"):
            vals = out[q][0]
            if not np.isfinite(vals).any():
                continue
            a, i = np.unravel_index(np.nanargmax(vals), vals.shape)
            rows.append({
                "beta": float(e.attrs["beta"]), "beta_deg": round(math.degrees(float(e.attrs["beta"])), 6),
                "vary": vary, "maximise": q, "best": float(e[vary].values[i]), "d": float(e.d.values[i]),
                "U_T": float(out["U_T"][0][a, i]), "U_I": float(out["U_I"][0][a, i]),
                "U_T_se": float(out["U_T"][1][a, i]), "U_I_se": float(out["U_I"][1][a, i]),
                "motion": str(e.label.values[a, i]), "direction": str(e.direction.values[a]),
                "s": float(e.s.values[i]), "F": float(e.F.values[i]),
            })
    return pd.DataFrame(rows)


def design_markdown(df: pd.DataFrame) -> str:
    """The design table as Markdown; an average the long run gives (no period found) with its standard
    error."""
    names = {90.0: "π/2", 60.0: "π/3", 45.0: "π/4", 30.0: "π/6"}
    lines = ["| β | vary | maximises | at | d | Ū_T (V) | Ū_I (V) | motion |", "|---|---|---|---|---|---|---|---|"]

    def value(x, se):
        return f"{x:.4g} ± {se:.2g}" if np.isfinite(se) and se > 0 else f"{x:.4g}"

    for _, r in df.iterrows():
        at = f"s = {r.best:.3f} m (F = {r.F:g} N)" if r.vary == "s" else f"F = {r.best:.2f} N (s = {r.s:g} m)"
        lines.append(f"| {names.get(r.beta_deg, f'{r.beta:.4f}')} | {r.vary} | {r.maximise} | {at} | {r.d:.4f} | "
                     f"{value(r.U_T, r.get('U_T_se', np.nan))} | {value(r.U_I, r.get('U_I_se', np.nan))} | "
                     f"{r.motion} |")
    return "\n".join(lines) + "\n"


def design_trends(energies: list[xr.Dataset], direction: str = "down") -> pd.DataFrame:
    """Where each average of each sweep energy rises and where it falls as the swept parameter grows.

    Along one direction of each sweep (the design figure's, ``"down"``: d decreasing), what the device delivers
    (:func:`vibroimpact.analysis.energy.delivered`) is compared between neighbouring points of the swept
    parameter (``s`` or ``F``, increasing); a point where it is not known (a transient longer than the cap, whose
    length rides on a chaotic stretch and so on the machine's last bits) is passed over: the step across it compares
    the known points on either side.  A fall is a run of consecutive falling steps.

    Parameters
    ----------
    energies : list of xarray.Dataset
        Sweep energies (:func:`vibroimpact.sweep_energy`), each of one incline and one swept ``s`` or ``F``.
    direction : str
        The sweep direction compared.

    Returns
    -------
    pandas.DataFrame
        One row per energy and average (``U_T``, ``U_I``): ``beta``, ``beta_deg``, ``vary``, ``average``,
        ``direction``, ``steps`` (compared), ``rising`` and ``falling`` (how many of them), and the largest fall
        (the run of falling steps that loses the most): ``fall_from``, ``fall_to`` (the swept parameter at its
        ends), ``value_from``, ``value_to`` (V), ``motion_from``, ``motion_to`` (the motions there), ``fall``
        (its loss relative to ``value_from``; 0 and NaN ends where nothing falls).

    Examples
    --------
    >>> import xarray as xr
    >>> en = xr.Dataset({"U_T": (("direction", "point"), [[1.0, 2.0, 3.0, 1.5, 4.0]]),
    ...                  "U_I": (("direction", "point"), [[5.0, 4.0, 3.0, 2.0, 1.0]]),
    ...                  "label": (("direction", "point"), [["a", "a", "a", "b", "b"]])},
    ...                 coords={"direction": ["down"], "s": ("point", [0.1, 0.2, 0.3, 0.4, 0.5])},
    ...                 attrs={"beta": 0.5, "vary": "s"})
    >>> t = design_trends([en]).set_index("average")
    >>> u_t, u_i = t.loc["U_T"], t.loc["U_I"]
    >>> int(u_t.steps), int(u_t.rising), int(u_t.falling), float(u_t.fall_from), float(u_t.fall_to), u_t.motion_to
    (4, 3, 1, 0.3, 0.4, 'b')
    >>> int(u_i.rising), int(u_i.falling), float(u_i.value_from), float(u_i.value_to), float(u_i.fall)
    (0, 4, 5.0, 1.0, 0.8)
    """
    rows = []
    for e in energies:
        vary = e.attrs["vary"]
        k = list(e.direction.values).index(direction)
        x = e[vary].values
        order = np.argsort(x)
        labels = e["label"].values[k][order]
        for q in ("U_T", "U_I"):
            v = delivered(e, q)[0][k][order]
            at = np.flatnonzero(np.isfinite(v))  # the known points, in the swept parameter's order
            dv = np.diff(v[at])  # a step from each known point to the next
            falls = dv < 0
            best, i = (0.0, -1, -1), 0
            while i < falls.size:  # runs of consecutive falling steps
                if not falls[i]:
                    i += 1
                    continue
                j = i
                while j + 1 < falls.size and falls[j + 1]:
                    j += 1
                if v[at[i]] - v[at[j + 1]] > best[0]:
                    best = (v[at[i]] - v[at[j + 1]], at[i], at[j + 1])
                i = j + 1
            _, a, b = best
            rows.append({
                "beta": float(e.attrs["beta"]), "beta_deg": round(math.degrees(float(e.attrs["beta"])), 6),
                "vary": vary, "average": q, "direction": direction, "steps": int(dv.size),
                "rising": int((dv > 0).sum()), "falling": int(falls.sum()),
                "fall_from": float(x[order][a]) if a >= 0 else math.nan,
                "fall_to": float(x[order][b]) if a >= 0 else math.nan,
                "value_from": float(v[a]) if a >= 0 else math.nan, "value_to": float(v[b]) if a >= 0 else math.nan,
                "motion_from": str(labels[a]) if a >= 0 else "", "motion_to": str(labels[b]) if a >= 0 else "",
                "fall": float((v[a] - v[b]) / v[a]) if a >= 0 else 0.0,
            })
    return pd.DataFrame(rows)


def design_trends_markdown(df: pd.DataFrame) -> str:
    """:func:`design_trends` as Markdown: per sweep and average, how many steps rise and the largest fall."""
    names = {"U_T": "Ū_T", "U_I": "Ū_I"}
    units = {"s": "m", "F": "N"}
    lines = ["| β | swept | average | steps rising (of those compared) | largest fall | where | motions across it |",
             "|---|---|---|---|---|---|---|"]
    for _, r in df.iterrows():
        if r.falling:
            fall = f"{r.value_from / 1e3:.1f} → {r.value_to / 1e3:.1f} kV (−{100 * r.fall:.0f} %)"
            fmt = ".2f" if r.vary == "F" else ".3f"
            where = f"{'‖F̂‖' if r.vary == 'F' else 's'} = {r.fall_from:{fmt}}–{r.fall_to:{fmt}} {units[r.vary]}"
            motions = r.motion_from if r.motion_from == r.motion_to else f"{r.motion_from} → {r.motion_to}"
        else:
            fall, where, motions = "none", "", ""
        lines.append(f"| {_pi_name(r.beta)} | {r.vary} | {names[r.average]} | {r.rising} of {r.steps} | {fall} | "
                     f"{where} | {motions} |")
    return "\n".join(lines) + "\n"


def _took(run: xr.Dataset) -> str:
    """A failure-map run's wall-clock time, as its table cell ends it."""
    return f", {float(run.seconds):.3g} s"


def failure_markdown(fm: xr.Dataset) -> str:
    """Counts of outcomes per method, and what happened in the chattering and chaotic cases."""

    grazing = [c for c in fm.case.values if " by " in str(c)]
    head = "| method | " + " | ".join(OUTCOMES) + " | chattering into sticking | long chaotic run |"
    lines = [head, "|" + "---|" * (len(OUTCOMES) + 3)]
    for i, m in enumerate(fm.solver.values):
        row = fm.isel(solver=i)
        g = row.sel(case=grazing).outcome.values
        counts = " | ".join(str(int((g == o).sum())) for o in OUTCOMES)
        chat = row.sel(case="chattering into sticking")
        chaos = row.isel(case=-1)
        lines.append(f"| {m} | {counts} | {str(chat.outcome.values)}: {str(chat.detail.values)}{_took(chat)} | "
                     f"{str(chaos.detail.values)}{_took(chaos)} |")
    lines.append("")
    lines.append(f"Near-grazing counts are over {len(grazing)} flights: both walls, extremum eps inside (no "
                 "impact) or past the wall (an impact), eps = " + ", ".join(sorted({str(c).split(' by ')[1] for c in grazing},
                                                                                   key=float, reverse=True)) + ".")
    return "\n".join(lines) + "\n"


def work_precision_markdown(wp: xr.Dataset) -> str:
    """Cheapest configuration of each method family reaching 1e-9 in impact times, per scene."""
    lines = ["| scene | method | cheapest setting reaching 1e-9 | error | µs per impact |", "|---|---|---|---|---|"]
    for sc in wp.scene.values:
        sub = wp.sel(scene=sc)
        for fam in dict.fromkeys(sub.family.values):
            m = (sub.family.values == fam) & (sub.err_t.values <= 1e-9)
            if not m.any():
                best = np.nanmin(sub.err_t.values[sub.family.values == fam])
                lines.append(f"| {sc} | {fam} | none (best error {best:.1e}) | | |")
                continue
            i = np.flatnonzero(m)[np.argmin(sub.us_per_impact.values[m])]
            setting = sub.setting.values[i]
            lines.append(f"| {sc} | {fam} | {'' if np.isnan(setting) else f'{setting:g}'} | "
                         f"{sub.err_t.values[i]:.1e} | {sub.us_per_impact.values[i]:.3g} |")
    return "\n".join(lines) + "\n"


def _lyap_setting(sub) -> str:
    tol = float(sub.tolerance)
    return f"n = {int(sub.n_impacts)}" + ("" if math.isnan(tol) else f", rtol {tol:.0e}")


def lyapunov_precision_markdown(ds: xr.Dataset) -> str:
    """The largest Lyapunov exponent by each method against the long reference run, per motion: the estimate
    (mean over the repeats), its error (median, and range over the repeats), the median relative error, the
    repeats whose estimate is finite and of the reference's sign, and the median cost; where no repeat gives a
    finite estimate, the reason instead.

    Parameters
    ----------
    ds : xarray.Dataset
        A :func:`vibroimpact.benchmarks.lyapunov_precision.lyapunov_precision` dataset.

    Returns
    -------
    str
        The Markdown table.
    """
    s = summarise(ds)
    k = ds.sizes["repeat"]
    lines = ["| motion | method | setting | λ₁ (per unit t) | error: median (range) | relative error | "
             f"sign right (of {k}) | seconds (median) |", "|---|---|---|---|---|---|---|---|"]
    for m in ds.motion.values:
        ref = ds.sel(motion=m)
        floquet = float(ref.lambda_floquet)
        note = "" if math.isnan(floquet) else f"; Floquet: {floquet:.6f}"
        lines.append(f"| {m} | reference: tangent map | n = {int(ds.attrs.get('n_ref', 0))} | {float(ref.lambda_ref):.5f} "
                     f"(95 %: {float(ref.lambda_ref_low):.5f} … {float(ref.lambda_ref_high):.5f}{note}) | | | | "
                     f"{float(ref.ref_seconds):.2g} |")
        for so in ds.solver.values:
            row, sub = s.sel(motion=m, solver=so), ds.sel(motion=m, solver=so)
            head = f"| {m} | {str(sub.family.values)} | {_lyap_setting(sub)} |"
            if int(row.finite) == 0:
                reasons = "; ".join(sorted(set(sub.reason.values.astype(str))))
                lines.append(f"{head} none: {reasons} | | | 0 | {float(row.seconds):.2g} |")
                continue
            lines.append(f"{head} {float(row.lambda1):.5f} | {float(row.error_median):.1e} ({float(row.error_min):.1e}"
                         f" … {float(row.error_max):.1e}) | {float(row.relative_error):.2g} | {int(row.sign_agrees)} | "
                         f"{float(row.seconds):.2g} |")
    return "\n".join(lines) + "\n"


#: Benchmark files (globs under benchmarks/) behind each figure, for the workflow-cost summary.
FIGURE_SOURCES = {
    "fig0b, fig4, figFN2 (caption orbits)": ["orbits/*.tsv"],
    "fig2, fig3, table1 (2:1 branches)": ["branches/*/orbit-BBT_vary-s.tsv", "branches/*/batch.tsv"],
    "figBiS": ["sweeps/*/figBiS*.tsv", "branches/beta-0.5236*/orbit-BBBT_vary-s.tsv", "branches/beta-0.5236*/batch.tsv"],
    "fig0": ["sweeps/*/fig0_*.tsv", "branches/beta-1.0472*/orbit-B*T_vary-*.tsv", "branches/beta-1.0472*/batch.tsv"],
    "fig5": ["sweeps/*/fig5_*.tsv", "branches/*/orbit-BT_vary-*.tsv", "branches/*/batch.tsv"],
    "design": ["sweeps/*/design_*.tsv"],
    "basins": ["basins/*/*.tsv"],
    "regime_map": ["maps/*.tsv"],
    "bench (simulator speed)": ["bench/simulator.tsv"],
    "work_precision": ["bench/work_precision.tsv"],
    "failure_map": ["bench/failure_map.tsv"],
    "analytics_accuracy": ["bench/analytics_accuracy.tsv"],
    "lyapunov_precision": ["bench/lyapunov_precision.tsv"],
}


#: the rule that wrote a benchmark file, from its path under ``benchmarks/`` (first match; else the
#: path's first directory, which is the rule's name for the rules that draw and tabulate)
RULE_OF_BENCHMARK = (
    (r"^orbits/caption-orbits", "caption_orbits"), (r"^branches/.*/orbit-", "branch"),
    (r"^sweeps/", "sweep"), (r"^basins/", "basins"), (r"^maps/", "regime_map"),
    (r"^bench/simulator", "bench_simulator"), (r"^bench/(\w+)\.tsv$", None),
)


def rule_of_benchmark(path: str) -> str:
    """The rule whose ``benchmark:`` file is ``path`` (relative to the benchmarks directory)."""

    for pattern, rule in RULE_OF_BENCHMARK:
        m = re.match(pattern, path)
        if m:
            return rule or m.group(1)
    return path.split("/")[0]


def workflow_cost(bench_dir) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Wall-clock seconds of every benchmarked job (from Snakemake ``benchmark:`` files) with its rule,
    and per figure.  A job feeding several figures counts in each."""

    bench_dir = Path(bench_dir)
    jobs = []
    for f in sorted(bench_dir.rglob("*.tsv")):
        t = pd.read_csv(f, sep="\t")
        rel = str(f.relative_to(bench_dir))
        jobs.append({"file": rel, "rule": rule_of_benchmark(rel), "seconds": float(t["s"].iloc[-1]),
                     "max_rss_mb": float(t["max_rss"].iloc[-1]) if "max_rss" in t and t["max_rss"].iloc[-1] != "-" else np.nan})
    jobs = pd.DataFrame(jobs)
    per_fig = []
    for fig, globs in FIGURE_SOURCES.items():
        files = {str(p.relative_to(bench_dir)) for g in globs for p in bench_dir.glob(g)}
        sel = jobs[jobs.file.isin(files)] if len(jobs) else jobs
        per_fig.append({"figure": fig, "jobs": len(sel), "seconds": float(sel.seconds.sum()) if len(sel) else 0.0})
    return jobs, pd.DataFrame(per_fig)


def workflow_cost_markdown(jobs: pd.DataFrame, per_fig: pd.DataFrame) -> str:
    """Per figure, then per rule (jobs, total and largest job seconds, most expensive first)."""
    lines = ["| figure | benchmarked jobs | total seconds |", "|---|---|---|"]
    for _, r in per_fig.iterrows():
        lines.append(f"| {r.figure} | {r.jobs} | {r.seconds:.1f} |")
    lines.append(f"| **all benchmarked jobs** | {len(jobs)} | {jobs.seconds.sum():.1f} |")
    if len(jobs) and "rule" in jobs:
        per_rule = (jobs.groupby("rule").seconds.agg(["count", "sum", "max"]).sort_values("sum", ascending=False)
                    .rename(columns={"count": "jobs", "sum": "total seconds", "max": "largest job (s)"}))
        lines += ["", "Per rule:", "", per_rule.round(1).to_markdown()]
    return "\n".join(lines) + "\n"


def matched_accuracy_markdown(ma: xr.Dataset) -> str:
    """Cost at matched accuracy (``workprecision.matched_accuracy``): per scene and method family, the
    cheapest setting reaching the target error, its cost and its ratio to the exact simulator's cost
    measured in the same run, or "cannot reach"."""
    rows = []
    for sc in ma.scene.values:
        for fam in ma.family.values:
            r = ma.sel(scene=sc, family=fam)
            if not bool(r.reached):
                rows.append({"scene": sc, "method": fam, "setting": "cannot reach", "error": "", "µs per impact": "",
                             "× exact": ""})
                continue
            s = float(r.setting)
            rows.append({"scene": sc, "method": fam, "setting": "" if np.isnan(s) else f"{s:g}",
                         "error": f"{float(r.err_t):.1e}", "µs per impact": f"{float(r.us_per_impact):.3g}",
                         "× exact": f"{float(r.ratio_to_exact):.3g}"})
    head = (f"Cost at matched accuracy: the cheapest setting of each method whose impact-time error over the "
            f"first impacts is at most {ma.attrs['target']:g} (walls all right); cost per impact and ratio to "
            "the exact simulator, measured in one run (compilation excluded).\n\n")
    return head + pd.DataFrame(rows).to_markdown(index=False) + "\n"


def _pi_name(x: float) -> str:

    return pi_tex(float(x)).replace("\\pi", "π")


def design_robust_table(rows_by_map: dict[str, list[dict]]) -> pd.DataFrame:
    """One row per map and incline: the best robust design (:func:`vibroimpact.analysis.design.best_designs`)
    and, where the map varies ``s``, the longest device within the budget at the same incline and force."""
    out = []
    for name, rows in rows_by_map.items():
        for r in rows:
            row = {"map": name, "beta": r["beta"], "found": r["found"]}
            if r["found"]:
                row.update({k: r[k] for k in ("s", "F", "d", "motion", "E_U_T", "worst_U_T", "box_min_E_U_T",
                                              "margin", "nearest_curve")})
            lg = r.get("longest")
            if lg:
                row.update({f"longest_{k}": lg[k] for k in ("s", "F", "motion", "E_U_T", "worst_U_T", "box_min_E_U_T",
                                                             "margin", "robust")})
            out.append(row)
    return pd.DataFrame(out)


def design_robust_markdown(df: pd.DataFrame) -> str:
    """The best robust designs, per incline, beside the longest device within the budget."""
    rows = []
    for _, r in df.iterrows():
        if not r["found"]:
            design = "no robust design within the budget"
            cols = dict.fromkeys(("motion", "E[Ū_T] (kV)", "worst Ū_T (kV)", "lowest E[Ū_T] over the box (kV)",
                                  "margin (nearest curve)"), "")
        else:
            design = f"s = {r.s:.3f} m, F = {r.F:.2f} N"
            cols = {"motion": r.motion, "E[Ū_T] (kV)": f"{r.E_U_T / 1e3:.2f}", "worst Ū_T (kV)": f"{r.worst_U_T / 1e3:.2f}",
                    "lowest E[Ū_T] over the box (kV)": f"{r.box_min_E_U_T / 1e3:.2f}",
                    "margin (nearest curve)": (f"{r.margin:.1f} ({r.nearest_curve})" if np.isfinite(r.margin)
                                               else "∞ (no curve meets the box's line)")}
        longest = ""
        if "longest_s" in r and isinstance(r.get("longest_motion"), str):
            longest = (f"s = {r.longest_s:.3f} m: E[Ū_T] {r.longest_E_U_T / 1e3:.2f}, worst {r.longest_worst_U_T / 1e3:.2f};"
                       f" {r.longest_motion}")
        rows.append({"map": r["map"], "β": _pi_name(r.beta), "best robust design": design, **cols,
                     "longest device within the budget": longest})
    return pd.DataFrame(rows).to_markdown(index=False) + "\n"


def design_cost_markdown(maps: dict[str, tuple[int, int]], seconds: dict[str, float]) -> str:
    """Runs, events and job time per design map (its chunks summed), with events per second."""
    rows = [{"map": m, "runs (points x starts)": runs, "events simulated": ev, "job time (s)": round(seconds[m], 1),
             "events per second": f"{ev / seconds[m]:.3g}"} for m, (runs, ev) in maps.items()]
    return pd.DataFrame(rows).to_markdown(index=False) + "\n"


def chaotic_windows(named: dict[str, xr.Dataset]) -> pd.DataFrame:
    """The windows of d where a sweep's motion is chaotic (:data:`vibroimpact.analysis.motions.CHAOTIC`: the
    95 % interval of its largest Lyapunov exponent lies above 0), per sweep and direction: maximal runs of
    consecutive chaotic points, their ends (each known to one grid step), the swept parameter there, and
    lambda_1 over the window (median, range, the lowest lower interval end), per impact and per unit time."""

    rows = []
    for name, sw in named.items():
        vary = sw.attrs["vary"]
        for direction in sw.direction.values:
            s = sw.sel(direction=direction)
            order = np.argsort(s.d.values)
            d = s.d.values[order]
            chaotic = s.label.values.astype(str)[order] == CHAOTIC
            edges = np.flatnonzero(np.diff(chaotic.astype(int))) + 1
            for seg in np.split(np.arange(d.size), edges):
                if not seg.size or not chaotic[seg[0]]:
                    continue
                lam = s.lyap1.values[order][seg]
                per_t = s.lyap1_time.values[order][seg]
                par = s[vary].values[order][seg]
                step = float(np.max(np.diff(d))) if d.size > 1 else math.nan
                rows.append({
                    "sweep": name, "beta": float(sw.attrs["beta"]), "vary": vary, "direction": str(direction),
                    "d_lo": float(d[seg[0]]), "d_hi": float(d[seg[-1]]), "step": step, "points": int(seg.size),
                    f"{vary}_lo": float(par.min()), f"{vary}_hi": float(par.max()),
                    "lyap1_median": float(np.median(lam)), "lyap1_min": float(lam.min()),
                    "lyap1_max": float(lam.max()), "lyap1_low_min": float(s.lyap1_low.values[order][seg].min()),
                    "lyap1_time_median": float(np.median(per_t)),
                })
    return pd.DataFrame(rows)


def chaotic_outputs(named: dict[str, xr.Dataset]) -> pd.DataFrame:
    """At every chaotic point of the sweep energies (:func:`vibroimpact.sweep_energy`): the averages U_T
    and U_I of the paper's fixed window (``window_time`` units of time after the transient) beside the
    long run's, with its 95 % interval (batch means, Student's t), and their difference in volts and in
    the long run's standard errors."""

    crit = t_quantile(0.975, LONG_BATCHES - 1)
    rows = []
    for name, en in named.items():
        vary = en.attrs["vary"]
        for a, direction in enumerate(en.direction.values):
            lab = en.label.values[a].astype(str)
            for i in np.flatnonzero(lab == CHAOTIC):
                row = {"sweep": name, "beta": float(en.attrs["beta"]), "vary": vary, "direction": str(direction),
                       "d": float(en.d.values[i]), vary: float(en[vary].values[i]),
                       "window_time": float(en.window_time.values[a, i])}
                for q in ("U_T", "U_I"):
                    win, long, se = (float(en[v].values[a, i]) for v in (q, f"{q}_long", f"{q}_long_se"))
                    row |= {f"{q}_window": win, f"{q}_long": long, f"{q}_long_ci": crit * se,
                            f"{q}_diff": win - long, f"{q}_diff_se": (win - long) / se if se > 0 else math.nan}
                rows.append(row)
    return pd.DataFrame(rows)


def between_2to1_and_1to1(sw: xr.Dataset, transitions: xr.Dataset | None = None) -> pd.DataFrame:
    """The motions of a sweep's down direction (the attractor followed with d decreasing) between the 1:1
    period-2 and the 2:1 period-2 motions, where the paper sees period doubling and "apparently chaotic"
    motion: from the largest d of the 2:1 period-2 run below up to the smallest d of the 1:1 period-2 run
    above, as runs of one motion with the range of lambda_1 per impact over each run and where it is
    largest.  With the sweep's ``transitions``, the 1:1 exit (:func:`vibroimpact.sweep_family_exit`: where the
    1:1 motion followed down leaves its family, by grazing or by a jump) is one row, in its place.  Empty where the down sweep has no 2:1 period-2 point below a 1:1 period-2 one."""
    dn = sw.sel(direction="down")
    order = np.argsort(dn.d.values)
    d, lab, lam = dn.d.values[order], dn.label.values.astype(str)[order], dn.lyap1.values[order]
    two = np.flatnonzero(lab == TWO_ONE.label)
    one = np.flatnonzero(lab == ONE_ONE.label)
    if not two.size or not one.size or one.max() <= two.min():
        return pd.DataFrame(columns=["d_lo", "d_hi", "motion", "points", "lyap1_min", "lyap1_max", "d_at_max"])
    hi = int(one[one > two.min()].min())
    lo = int(two[two < hi].max())
    rows = []
    edges = np.flatnonzero(lab[lo:hi + 1][1:] != lab[lo:hi + 1][:-1]) + 1 + lo
    for a, b in zip(np.r_[lo, edges], np.r_[edges, hi + 1], strict=True):
        seg = lam[a:b]
        fin = np.isfinite(seg)
        k = a + int(np.argmax(np.where(fin, seg, -np.inf))) if fin.any() else a
        rows.append({"d_lo": float(d[a]), "d_hi": float(d[b - 1]), "motion": str(lab[a]), "points": int(b - a),
                     "lyap1_min": float(np.min(seg[fin])) if fin.any() else math.nan,
                     "lyap1_max": float(np.max(seg[fin])) if fin.any() else math.nan, "d_at_max": float(d[k])})
    if transitions is not None and "exit_d" in transitions and np.isfinite(float(transitions.exit_d)):
        g = float(transitions.exit_d)
        rows.append({"d_lo": g, "d_hi": g, "motion": f"1:1 exit: {str(transitions.exit_kind.values)} (the 1:1 motion "
                     f"leaves its family; clearance {float(transitions.exit_clearance):.1e})",
                     "points": 0, "lyap1_min": math.nan, "lyap1_max": math.nan, "d_at_max": math.nan})
    return pd.DataFrame(rows).sort_values(["d_lo", "points"]).reset_index(drop=True)


def between_markdown(named: dict[str, tuple[xr.Dataset, xr.Dataset | None]]) -> str:
    """:func:`between_2to1_and_1to1` of every sweep, as Markdown (one table per sweep, d increasing)."""
    out = []
    for name, (sw, tr) in named.items():
        df = between_2to1_and_1to1(sw, tr)
        if df.empty:
            continue
        step = float(np.max(np.diff(sw.d.values))) if sw.sizes["point"] > 1 else math.nan
        out += [f"**{name}** ({_pi_name(float(sw.attrs['beta']))}, {sw.attrs['vary']} swept; points {step:.1e} apart "
                "in d):", "", "| d | motion (d decreasing) | points | λ₁ per impact | largest at d |",
                "|---|---|---|---|---|"]
        for _, r in df.iterrows():
            span = f"{r.d_lo:.4f}" if r.d_lo == r.d_hi else f"[{r.d_lo:.4f}, {r.d_hi:.4f}]"
            lam = ("—" if not np.isfinite(r.lyap1_max) else f"{r.lyap1_min:.3f}" if r.lyap1_min == r.lyap1_max
                   else f"{r.lyap1_min:.3f} – {r.lyap1_max:.3f}")
            at = f"{r.d_at_max:.4f}" if r.points > 1 and np.isfinite(r.lyap1_max) else ""
            out.append(f"| {span} | {r.motion} | {r.points or ''} | {lam} | {at} |")
        out.append("")
    return "\n".join(out) + "\n"


def largest_window_difference(outputs: pd.DataFrame) -> str:
    """One sentence: the largest relative difference between the paper's fixed-window averages and the long
    run's over every chaotic point (:func:`chaotic_outputs`)."""
    best = None
    for q in ("U_T", "U_I"):
        rel = (outputs[f"{q}_diff"] / outputs[f"{q}_long"]).abs() if len(outputs) else pd.Series(dtype=float)
        if rel.notna().any():
            i = rel.idxmax()
            if best is None or rel[i] > best[0]:
                best = (float(rel[i]), q, outputs.loc[i])
    if best is None:
        return "No chaotic point: no window to compare with a long run.\n"
    rel, q, r = best
    return (f"Over every chaotic point of every sweep ({len(outputs)}), the paper's fixed window is off the long run's "
            f"mean by up to {100 * rel:.1f} % ({ {'U_T': 'Ū_T', 'U_I': 'Ū_I'}[q]}, {r.sweep} {r.direction}, d = {r.d:.4f}: "
            f"{r[f'{q}_diff_se']:+.0f} of the long run's standard errors).\n")


def chaos_markdown(windows: pd.DataFrame, outputs: pd.DataFrame, between: str = "") -> str:
    """The chaotic windows and what a chaotic device delivers, as Markdown: per window, lambda_1 and, at
    the window's middle point, the paper's window averages beside the long run's with its 95 % interval;
    the largest difference over the window in the long run's standard errors; then ``between``
    (:func:`between_markdown`), the motions between the 2:1 and the 1:1 along each down sweep."""
    lines = ["| sweep | β | direction | chaotic for d in | points | swept | λ₁ per impact: median (range) | "
             "lowest lower end | λ₁ per unit time (median) |", "|---|---|---|---|---|---|---|---|---|"]
    for _, w in windows.iterrows():
        v = w.vary
        unit = "m" if v == "s" else "N"
        lines.append(f"| {w.sweep} | {_pi_name(w.beta)} | {w.direction} | [{w.d_lo:.4f}, {w.d_hi:.4f}] ± {w.step:.1e} | "
                     f"{w.points} | {v} in [{w[f'{v}_lo']:.4g}, {w[f'{v}_hi']:.4g}] {unit} | "
                     f"{w.lyap1_median:.3f} ({w.lyap1_min:.3f} – {w.lyap1_max:.3f}) | {w.lyap1_low_min:.3f} | "
                     f"{w.lyap1_time_median:.3f} |")
    lines += ["", "What a chaotic device delivers: at the middle point of each window, Ū_T and Ū_I of the paper's "
              "fixed window (its length in non-dimensional time) beside the long run's mean ± its 95 % interval; "
              "the last columns give the largest |window − long run| over all the window's points, in the long "
              "run's standard errors.", "",
              "| sweep | direction | d | window | Ū_T window (V) | Ū_T long run (V) | Ū_I window (V) | "
              "Ū_I long run (V) | largest Ū_T difference | largest Ū_I difference |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for _, w in windows.iterrows():
        pts = outputs[(outputs.sweep == w.sweep) & (outputs.direction == w.direction) & (outputs.d >= w.d_lo - 1e-12)
                      & (outputs.d <= w.d_hi + 1e-12)].sort_values("d")
        if pts.empty:
            continue
        m = pts.iloc[len(pts) // 2]
        big = {q: pts.loc[pts[f"{q}_diff_se"].abs().idxmax()] if pts[f"{q}_diff_se"].notna().any() else None
               for q in ("U_T", "U_I")}

        def largest(q, big=big):
            r = big[q]
            if r is None:
                return "—"
            rel = 100 * r[f"{q}_diff"] / r[f"{q}_long"]
            return f"{r[f'{q}_diff']:+.4g} V ({rel:+.1f} %, {r[f'{q}_diff_se']:+.0f} SE) at d = {r.d:.4f}"

        lines.append(f"| {w.sweep} | {w.direction} | {m.d:.4f} | {m.window_time:.3g} | {m.U_T_window:.4g} | "
                     f"{m.U_T_long:.4g} ± {m.U_T_long_ci:.2g} | {m.U_I_window:.4g} | {m.U_I_long:.4g} ± "
                     f"{m.U_I_long_ci:.2g} | {largest('U_T')} | {largest('U_I')} |")
    lines += ["", largest_window_difference(outputs)]
    if between:
        lines += ["Between the 2:1 and the 1:1 motions, along each sweep's down direction (the attractor followed "
                  "with d decreasing; runs of one motion, λ₁ over each run; the 1:1 exit in its place):", "", between]
    return "\n".join(lines) + "\n"


#: the random search the knock map's runs are compared with: Attractors.jl's MCSBruteForce default samples
BRUTE_FORCE_RUNS = 20_000


def _design_name(d: dict | None, x: str, y: str) -> str:
    if d is None:
        return "none"
    fmt = {"s": lambda v: f"s = {v:.3f} m", "F": lambda v: f"F = {v:.2f} N", "beta": lambda v: f"β = {v:.3f} rad"}
    return f"{fmt[x](d[x])}, {fmt[y](d[y])}"


def knocks_table(choices: dict, km: xr.Dataset) -> pd.DataFrame:
    """The knock map's designs: for each set of designs ``choices`` names (``"whole map"``, or a value of the
    map's y axis) what :func:`vibroimpact.analysis.robust.robust_choice` picked, the best design regardless of
    knocks and the best whose highest-output motion survives the knock; two rows each."""
    x, y = km.attrs["x"], km.attrs["y"]
    out = []
    for at, ch in choices.items():
        for which, d in (("best output", ch["best"]), ("survives the knock", ch["robust"])):
            r = {"among": at, "design": which, "found": d is not None, x: np.nan, y: np.nan, "motion": "",
                 "U_T": np.nan, "shock": np.nan, "knock": ch["knock"], "unit": ch["unit"], "designs": ch["designs"],
                 "survive": ch["survive"]}
            out.append(r | ({k: d[k] for k in (x, y, "motion", "U_T", "shock")} if d is not None else {}))
    return pd.DataFrame(out)


def knocks_markdown(df: pd.DataFrame, km: xr.Dataset, seconds: float | None = None) -> str:
    """The knock map's table: its two designs, then what the map holds and what its shocks cost (runs per motion
    against the random search's, and the job's time in ``seconds`` where given: whole job, its design map
    included)."""
    x, y, unit = km.attrs["x"], km.attrs["y"], km.attrs["knock_unit"]
    among = lambda a: "whole map" if a == "whole map" else f"{y} = {_pi_name(a) if y == 'beta' else a}"
    rows = [{"among": among(r["among"]), "design": r["design"], "where": _design_name(r if r["found"] else None, x, y),
             "highest-output motion": r["motion"], "Ū_T (kV)": f"{r.U_T / 1e3:.2f}" if r["found"] else "",
             f"its critical shock ({unit})": ("∞" if np.isinf(r.shock) else f"{r.shock:.3g}") if r["found"] else "",
             "designs surviving": f"{r.survive} of {r.designs}"}
            for _, r in df.iterrows()]
    runs = km["shock_runs"].values[km["shock_runs"].values > 0]
    missing = km["top_reason"].values[np.isnan(km["top_shock"].values)]
    reasons = pd.Series(missing).value_counts()
    out = (f"The knock: {float(km.attrs['knock']):g} {unit} ({km.attrs['knock_kind']} of the ball relative to the "
           "cylinder).\n\n")
    out += pd.DataFrame(rows).to_markdown(index=False) + "\n\n"
    out += (f"{runs.size} motions knocked, {int(np.median(runs)) if runs.size else 0} runs per motion (median), "
            f"{int(runs.max(initial=0))} at most, against {BRUTE_FORCE_RUNS} for a random search "
            "(Attractors.jl's MCSBruteForce default)")
    if seconds is not None:
        workers = int(km.attrs.get("workers", 1))
        out += (f"; the whole job (its design map of {km['top'].size} designs included) took {seconds:.0f} s on "
                f"{workers} thread{'s' * (workers != 1)}")
    out += ".\n"
    for why, n in reasons.items():
        out += f"\n- no critical shock at {n} design(s): {why}"
    return out + ("\n" if len(reasons) else "")
