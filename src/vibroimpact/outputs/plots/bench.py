"""Speed against accuracy: work-precision, failure map, accuracy of the analytics, the largest Lyapunov exponent."""

from __future__ import annotations

import ast
import math
import re

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch
from matplotlib.ticker import NullFormatter

from ...analysis.motions import no_period
from ...benchmarks.lyapunov_precision import summarise
from ...benchmarks.outcomes import OUTCOMES
from ..layout import AROUND, place_labels
from ._common import use_style, wellposed

FAMILY_STYLE = {
    "exact": ("k", "*", "exact (numba)"),
    "python": ("0.5", "*", "same algorithm, plain Python"),
    "ivp-RK45": ("tab:blue", "o", "solve_ivp RK45"),
    "ivp-DOP853": ("tab:orange", "s", "solve_ivp DOP853"),
    "ivp-LSODA": ("tab:green", "^", "solve_ivp LSODA"),
    "ivp-Radau": ("tab:purple", "v", "solve_ivp Radau"),
    "rk4": ("tab:red", "D", "RK4 + bisection"),
    "heyoka": ("tab:brown", "P", "heyoka (Taylor, LLVM)"),
    "siconos-ed": ("tab:pink", "X", "Siconos event-driven (LSODAR)"),
    "siconos-mj": ("tab:olive", "h", "Siconos Moreau-Jean"),
}


def _peers_note(ds):
    """'peers: heyoka 7.13.2; Siconos not installed' from a benchmark dataset's record (a version, or the reason
    a peer is absent, which the dataset keeps in full)."""

    peers = ds.attrs.get("peers")
    if not peers:
        return None
    names = {"siconos": "Siconos"}
    return "peers: " + "; ".join(f"{names.get(k, k)} " + (v if re.fullmatch(r"\d+(\.\d+)*\S*", v) else "not installed")
                                 for k, v in ast.literal_eval(peers).items())

#: Okabe & Ito's colour-blind-safe palette, one colour per outcome of the failure map, with a glyph
#: printed in each cell as a second cue (outcomes in the order of ``outcomes.OUTCOMES``)
OUTCOME_STYLE = {
    "correct": ("#009E73", ""),
    "wrong time": ("#F0E442", "t"),
    "missed impact": ("#D55E00", "M"),
    "spurious impact": ("#CC79A7", "S"),
    "wrong sequence": ("#E69F00", "Q"),
    "stalled": ("#56B4E9", "H"),
    "crashed": ("#000000", "X"),
}


def _setting_name(family):
    return {"rk4": "h", "siconos-mj": "h"}.get(family, "rtol" if family.startswith("ivp") else "tol")


def _setting_label(family, setting):
    if _setting_name(family) == "h":
        return f"h={setting:g}"
    return f"{setting:.0e}".replace("e-0", "e-")


#: an impact-time error within this many ulps of the window's last impact time is rounding: a count of ulps
#: another machine's libm or BLAS may change (the exact closed form's own error is 1 to 4 ulps, its plain-Python
#: run's alike); what the figure check compares it by (:func:`vibroimpact.outputs.figcheck.magnitude`)
ROUNDING_ULPS = 64


def _scene_provenance(wp, scene):
    """What produced a scene's errors: a chaotic run where its start settles on no period, else the methods'
    own errors (:data:`vibroimpact.outputs.figcheck.PROVENANCE`)."""
    motion = str(wp.scene_motion.sel(scene=scene).values) if "scene_motion" in wp else ""
    return "chaotic run" if no_period(motion) else "method error"


def fig_work_precision(wp):
    """Error in impact times against cost per impact, log-log, one line per method (tolerance or
    step ladder, its first and last setting printed at its ends); a cross at the top where the
    method put impacts on the wrong walls.  Each line's errors are recorded for the figure check as
    magnitudes above the scene's rounding level, its costs as timings."""
    use_style()
    names = []  # the ladders' end labels, placed once the layout is fixed
    rules = []  # each end label's rule, recorded once it is placed
    scenes = list(wp.scene.values)
    fig, axes = plt.subplots(1, len(scenes), figsize=(3.6 * len(scenes), 3.9), squeeze=False, sharey=True)
    top = 1.0
    for ax, sc in zip(axes[0], scenes, strict=True):
        sub = wp.sel(scene=sc)
        rule = dict(provenance=_scene_provenance(wp, sc),
                    floor=ROUNDING_ULPS * math.ulp(float(sub.t_window)) if "t_window" in sub else 0.0)
        # first, so that the methods' lines follow in FAMILY_STYLE's order, optional peers last
        ax.axhline(top, color="0.7", lw=0.6, ls=":")
        for fam, (color, marker, label) in FAMILY_STYLE.items():
            m = sub.family.values == fam
            if not m.any():
                continue
            x, y = sub.us_per_impact.values[m], sub.err_t.values[m]
            settings = sub.setting.values[m]
            if np.isfinite(settings).any():
                label += f" ({_setting_name(fam)} {settings[0]:.3g} … {settings[-1]:.3g})"
            finite = np.isfinite(y)
            line = ax.loglog(x[finite], np.maximum(y[finite], 1e-17), marker=marker, color=color, lw=1, ms=5,
                             label=label)[0]
            wellposed(line, "magnitude", timed=("x",), **rule)
            if (~finite).any():
                cross = ax.plot(x[~finite], np.full((~finite).sum(), top), "x", color=color, ms=7,
                                label=f"_{label}: wrong walls")[0]
                wellposed(cross, "magnitude", timed=("x",), **rule)
            # the ladder's ends, so its direction and range can be read off each panel
            ends = [k for k in (0, len(x) - 1) if np.isfinite(settings[k]) and finite[k]]
            for k in ends[: 2 if len(x) > 1 else 1]:
                names.append((ax, _setting_label(fam, settings[k]),
                              [((x[k], max(y[k], 1e-17)), off) for off in AROUND], dict(fontsize=5, color=color)))
                rules.append(rule)
        ax.set_title(f"{sc} motion")
        ax.set_xlabel("cost per impact (µs)")
    axes[0, 0].set_ylabel(f"largest impact-time error vs 40-digit reference\n(first {int(wp.attrs.get('n_err', 20))} impacts; "
                          "x: wrong walls)")
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside lower center", ncol=4, fontsize=6,
               title=_peers_note(wp), title_fontsize=6)
    for text, rule in zip(place_labels(fig, names), rules, strict=True):  # at (cost, error): the error's rule
        wellposed(text, "magnitude", **rule)
    return fig


def fig_failure_map(fm):
    """Outcome of every method (rows) on every hard case (columns), colour-blind-safe colours with a
    glyph per outcome; the thresholds that decide the outcomes are stated under the map."""


    use_style()
    colors = [OUTCOME_STYLE[o][0] for o in OUTCOMES]
    # methods that need a system package (Siconos) in their own panel below: the main panel is the same
    # on every machine
    optional = np.array([str(f).startswith("siconos") for f in fm.family.values]) if "family" in fm else \
        np.zeros(fm.sizes["solver"], bool)
    parts = [(~optional, "")] + ([(optional, "Siconos (system package python3-siconos)")] if optional.any() else [])
    fig, axes = plt.subplots(len(parts), 1, figsize=(12, 2.6 + 0.22 * fm.sizes["solver"]), sharex=True, squeeze=False,
                             height_ratios=[max(int(m.sum()), 1) for m, _ in parts])
    for ax, (rows, title) in zip(axes[:, 0], parts, strict=True):
        sub = fm.isel(solver=np.flatnonzero(rows))
        codes = np.vectorize(OUTCOMES.index)(sub.outcome.values)
        # a chaotic run's outcome is decided by when it parts from the reference: where a start one ulp away
        # changes it, another machine's last bit may too (the figure check allows those cells to differ)
        sensitive = sub.sensitive.values.astype(bool) if "sensitive" in sub else np.zeros(codes.shape, bool)
        im = ax.imshow(codes, cmap=ListedColormap(colors), vmin=-0.5, vmax=len(OUTCOMES) - 0.5, aspect="auto")
        wellposed(im, "outcome", provenance="chaotic run", sensitive=sensitive.ravel())
        ax.grid(False)
        for (i, j), code in np.ndenumerate(codes):
            # a text in every cell (empty where the outcome has no glyph), so that a cell's glyph keeps its name
            glyph = OUTCOME_STYLE[OUTCOMES[code]][1]
            text = ax.text(j, i, glyph, ha="center", va="center", fontsize=6,
                           color="white" if glyph == "X" else "black")
            wellposed(text, "outcome", provenance="chaotic run", sensitive=bool(sensitive[i, j]))
        ax.set_yticks(range(sub.sizes["solver"]), sub.solver.values, fontsize=7)
        if title:
            ax.set_title(title, fontsize=7, loc="left")
    axes[-1, 0].set_xticks(range(fm.sizes["case"]), fm.case.values, rotation=70, ha="right", fontsize=7)
    ax = axes[0, 0]
    ax.set_title("Where each method fails: near-grazing flights at both walls (B: bottom, T: top; extremum eps "
                 "inside the wall: no impact; eps past it: an impact), chattering into sticking, a long chaotic run",
                 fontsize=8)
    a = fm.attrs
    rule = None
    if "time_rtol" in a:
        rule = "\n".join([
            "thresholds:",
            f"correct: right wall, impact time within {a['time_rtol']:g}",
            "  (relative) of the 40-digit reference",
            f"missed: a hit on the other wall or > {a['late']:g} late",
            "spurious: a miss reported as an impact",
            f"chattering: impacts faster than {a['chatter_v']:g}",
            f"  followed to {a['time_rtol']:g} (relative)",
            f"chaotic run: every impact on its wall, within {a['chaos_atol']:g} in t",
            f"flights at d = {a['d']:g}, gbar = {a['gbar']:g}"])
    # the outcomes the map shows (an outcome no method meets would be a key to nothing)
    shown = set(np.asarray(fm.outcome.values).astype(str).ravel())
    ax.legend(handles=[Patch(color=c, label=f"{o} ({OUTCOME_STYLE[o][1]})" if OUTCOME_STYLE[o][1] else o)
                       for c, o in zip(colors, OUTCOMES, strict=True) if o in shown],
              loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, title="outcome")
    if rule:
        ax.annotate(rule, (1.01, 0.0), xycoords="axes fraction", fontsize=6, va="bottom", ha="left")
    return fig


def fig_analytics_accuracy(a):
    """Located vs grid-only critical points (continuation step) and grazing points (sweep points),
    error against cost.  (a) is measured against the finest step's located point (not drawn: it is
    the reference), (b) against the analytic G1 and G2 of the continued branches."""
    use_style()
    names = []  # the points' settings, placed once the layout is fixed
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.9))
    ax = axes[0]
    ref = {k: a.attrs[f"{k}_reference"] for k in ("B", "fold") if f"{k}_reference" in a.attrs}
    x = a.branch_seconds.values
    names += _grid_and_located(ax, x, a.branch_grid_err.values, x[:-1], a.branch_located_err.values[:-1].clip(1e-17),
                               (("B", "tab:blue"), ("fold", "tab:orange")), "o", [f"h={h:g}" for h in a.step.values],
                               {k: f" (reference d = {v:.10f})" for k, v in ref.items()},
                               float(a.attrs.get("branch_xtol", 0.0)))
    ax.set_xlabel("continuation time (s)")
    ax.set_ylabel(f"|d − d(located at finest step h={a.step.values[-1]:g})|\n(zero drawn at 1e-17)")
    ax.set_title(r"(a) 2:1 branch, $\beta=\pi/3$: B and fold by arclength step h")
    ax.legend(fontsize=6)
    ax = axes[1]
    x = a.sweep_seconds.values.sum(axis=1)
    names += _grid_and_located(ax, x, a.sweep_grid_err.values, x, a.sweep_located_err.values,
                               (("G1", "k"), ("G2", "tab:red")), "s", [f"{n} pts" for n in a.points.values],
                               {k: f" (analytic d = {a.attrs[k]:.10f})" for k in ("G1", "G2") if a.attrs.get(k) is not None},
                               float(a.attrs.get("sweep_xtol", 0.0)))
    ax.set_xlabel("sweep + location time (s)")
    ax.set_ylabel("|d − d(analytic branch)|")
    ax.set_title(r"(b) grazing G1 and fold G2 from sweeps, $\beta=\pi/6$, by sweep points")
    ax.legend(fontsize=6)

    for ax in axes:  # decades only: the minor labels of a short log axis overlap
        ax.xaxis.set_minor_formatter(NullFormatter())
    for text, (ax, *_rest) in zip(place_labels(fig, names), names, strict=True):  # at (time, grid error)
        wellposed(text, "magnitude", provenance="method error",
                  floor=float(a.attrs.get("branch_xtol" if ax is axes[0] else "sweep_xtol", 0.0)))
    return fig


def _grid_and_located(ax, x, grid, x_located, located, kinds, marker, point_names, reference, floor):
    """One panel of the analytics' accuracy: per kind (its colour), the error of the grid alone (dashed) and of
    the located point (solid) against the time; the names of the first kind's grid points, to place.  The
    errors are recorded for the figure check as magnitudes above ``floor`` (the location's tolerance: an error
    below it is the location's noise), the times as timings."""
    for k, (kind, color) in enumerate(kinds):
        wellposed(ax.loglog(x, grid[:, k], f"{marker}--", color=color, mfc="none", label=f"{kind}: grid only")[0],
                  "magnitude", provenance="method error", timed=("x",), floor=floor)
        wellposed(ax.loglog(x_located, located[:, k], f"{marker}-", color=color,
                            label=f"{kind}: located" + reference.get(kind, ""))[0],
                  "magnitude", provenance="method error", timed=("x",), floor=floor)
    return [(ax, name, [((xi, y), off) for off in AROUND], dict(fontsize=6))
            for xi, name, y in zip(x, point_names, grid[:, 0], strict=True)]


#: colour and marker of each method of the Lyapunov chart (DOP853: one marker per tolerance, in its order)
LYAP_STYLE = {
    "tangent": ("k", ("*",), "tangent map (vi.lyapunov)"),
    "benettin-exact": ("tab:blue", ("o",), "Benettin, exact flights"),
    "benettin-DOP853": ("tab:orange", ("s", "^", "v", "<", ">"), "Benettin, solve_ivp DOP853"),
    "nolds-lyap_r": ("tab:green", ("D",), "nolds lyap_r (Rosenstein), impact velocities"),
    "nolds-lyap_e": ("tab:purple", ("P",), "nolds lyap_e (Eckmann), impact velocities"),
}
#: errors below this are drawn at it (the log axis' floor)
LYAP_FLOOR = 1e-12


def _lyap_lines(ds):
    """(family, tolerance, label, colour, marker, solver mask) of each line of the Lyapunov chart."""
    out = []
    for fam, (color, markers, name) in LYAP_STYLE.items():
        m = ds.family.values == fam
        if not m.any():
            continue
        tol_all = ds.tolerance.values
        # in the dataset's order, NaN (no tolerance) once
        for k, tol in enumerate(dict.fromkeys(float(t) for t in tol_all[m] if not np.isnan(t)) or [math.nan]):
            sel = m & ((tol_all == tol) | (np.isnan(tol) & np.isnan(tol_all)))
            n = ds.n_impacts.values[sel]
            label = name + ("" if np.isnan(tol) else f" rtol={tol:.0e}") + f" (n = {n.min()} … {n.max()})"
            out.append((fam, tol, label, color, markers[k % len(markers)], sel))
    return out


def fig_lyapunov_precision(ds):
    """Error of each method's largest Lyapunov exponent against the long reference run, against its cost,
    log-log, one panel per motion: the medians over the repeats (a marker per run length), a vertical bar over
    their range, a cross at the top where no repeat gave a finite estimate; the grey band is the reference's
    own 95 % half-width, below which an error is not resolved.  Errors are recorded for the figure check as
    magnitudes above that half-width, costs as timings."""
    use_style()
    s = summarise(ds)
    motions = list(ds.motion.values)
    fig, axes = plt.subplots(1, len(motions), figsize=(3.9 * len(motions), 4.2), squeeze=False, sharey=True)
    top = 10.0
    for ax, mo in zip(axes[0], motions, strict=True):
        sub, ref = s.sel(motion=mo), ds.sel(motion=mo)
        half = 0.5 * float(ref.lambda_ref_high - ref.lambda_ref_low)
        rule = dict(provenance="chaotic run" if np.isnan(float(ref.lambda_floquet)) else "method error", floor=half)
        ax.axhspan(LYAP_FLOOR / 10, half, color="0.85", lw=0)
        for _fam, _tol, label, color, marker, sel in _lyap_lines(ds):
            x, y = sub.seconds.values[sel], sub.error_median.values[sel]
            lo, hi = sub.error_min.values[sel], sub.error_max.values[sel]
            ok = sub.finite.values[sel] > 0
            if ok.any():  # no empty line (its data would have an empty dimension)
                line = ax.loglog(x[ok], np.maximum(y[ok], LYAP_FLOOR), marker=marker, color=color, lw=1, ms=5,
                                 label=label)[0]
                wellposed(line, "magnitude", timed=("x",), **rule)
            for xi, a, b in zip(x[ok], lo[ok], hi[ok], strict=True):
                bar = ax.plot([xi, xi], np.maximum([a, b], LYAP_FLOOR), color=color, lw=0.8, label="_range")[0]
                wellposed(bar, "magnitude", timed=("x",), **rule)
            if (~ok).any():
                cross = ax.plot(x[~ok], np.full((~ok).sum(), top), "x", color=color, ms=7,
                                label=f"_{label}: no finite estimate")[0]
                wellposed(cross, "magnitude", timed=("x",), **rule)
        ax.set_title(f"{mo} ({str(ref.motion_label.values)})", fontsize=8)  # λ₁ itself: the table
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("cost of the estimate, median over the repeats (s)")
        ax.set_ylim(LYAP_FLOOR / 3, top * 3)
    axes[0, 0].set_ylabel("|λ₁ − λ₁ of the reference| per unit t\n(median over the repeats; bar: their range)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    handles.append(Patch(color="0.85"))
    labels.append(f"the reference's 95 % half-width ({int(ds.attrs.get('n_ref', 0))} impacts): not resolved below")
    nolds = " ".join(str(ds.attrs.get("nolds", "nolds")).split()[:2])  # "nolds 0.6.3", or why it is absent
    fig.legend(handles, labels, loc="outside lower center", ncol=3, fontsize=6,
               title=f"{ds.sizes['repeat']} repeats per point (starts apart on the motion); a cross at the top in a "
                     f"method's colour: no finite estimate in any repeat (why: the table); errors below "
                     f"{LYAP_FLOOR:.0e} drawn at it; {nolds}", title_fontsize=6)
    return fig
