"""Where the motion is chaotic: the largest Lyapunov exponent lambda_1 of every sweep point aligned under
the velocity bifurcation diagram (Figure 2 (a), (c) and Figure 9's inclines; rows ``lyapunov``, ``fig0`` and
``fig5`` of :mod:`vibroimpact.outputs.registry`)."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.markers import MarkerStyle

from ...analysis.lyapunov import t_quantile
from ...analysis.motions import APERIODIC, CHAOTIC, NO_PERIOD_LABELS, QUASI_PERIODIC, UNSETTLED, no_period
from ...analysis.settled import LONG_BATCHES
from ...dynamics.impact import exponent_sum
from ._common import (
    RUNS_NOTE,
    located_marks,
    mark_handles,
    mark_located,
    motion_color,
    motion_runs,
    name_marks,
    panel_title,
    point_info,
    rows_of_names,
    secondary_axis,
    sim_points,
    sweep_step,
    use_style,
    wellposed,
)

#: colour of lambda_1 of a point with a period (exact, of a Newton-solved cycle); a point with no period is drawn in
#: its motion's colour (:func:`~vibroimpact.outputs.plots._common.motion_color`, as in every figure)
PERIODIC_COLOR = "k"
#: a point whose lambda_1 is -inf (a sticking cycle, a ball at rest) is drawn this far below ln r
MINUS_INF_BELOW = 0.35
MINUS_INF_COLOR = "tab:blue"
MINUS_INF_MARKER = "v"
#: a point whose lambda_1 was not estimated (no long run: its lyap1_source says why), this far below that
NOT_ESTIMATED_BELOW = 0.12
NOT_ESTIMATED_COLOR = "0.8"


def critical_marks(orbit_branches, transitions=None):
    """The period doublings B of the continued 1:1 and 2:1 branches and the folds of the 1:1 (admissible ones), with
    d_graz (the 2:1 fold), the 1:1 exit and G1 of :func:`~vibroimpact.outputs.plots._common.located_marks`:
    ``[(name, d)]``."""
    marks = list(located_marks(orbit_branches, transitions))
    names = {"BT": "1:1", "BBT": "2:1"}
    for br in orbit_branches:
        if br.attrs.get("status") == "failed" or "critical_d" not in br:
            continue
        word = names.get(br.attrs.get("word"))
        kinds, crit, adm = br.critical_kind.values.astype(str), br.critical_d.values, br.critical_admissible.values
        # the 2:1 fold of largest d is d_graz, marked under that name
        for kind in ("B", "fold") if word != "2:1" else ("B",):
            for d in crit[(kinds == kind) & adm]:
                marks.append((f"{kind} ({word})", float(d)))
    return marks


def minus_inf_level(r: float) -> float:
    """Where lambda_1 = -inf is drawn: below every finite value.  Without sticking the exponents sum to
    2 ln r per impact (up to the ends of the run; the impact law's :func:`~vibroimpact.dynamics.impact.exponent_sum`,
    which refuses a law whose restitution is not constant) and lambda_1 >= lambda_2, so lambda_1 >= ln r."""
    return (exponent_sum(r) / 2 if r > 0 else -np.inf) - MINUS_INF_BELOW


def _lyapunov_points(ax, sw, direction, marker):
    """lambda_1 per impact of every point of one sweep direction, in one artist (so that a point whose
    motion changes under rounding stays the same point for the check): exact on Newton-solved cycles, the
    long runs' estimates with their 95 % intervals (a collection of bars), coloured by motion; -inf as a
    triangle at :func:`minus_inf_level` (open for d decreasing, filled for d increasing)."""


    s = sw.sel(direction=direction)
    idx = np.arange(s.sizes["point"])
    d, lam = s.d.values, s.lyap1.values
    lo, hi = s.lyap1_low.values, s.lyap1_high.values
    lab = s.label.values.astype(str)
    info = point_info(s, idx, "lyap1")
    exact = (lo == hi) | np.isneginf(lam)  # a solved cycle's value, or -inf: no interval
    info["settled"] = info["settled"] | exact
    # a long run's estimate is a statistic: its standard error from the interval (Student's t, batch means)
    crit = t_quantile(0.975, LONG_BATCHES - 1)
    info["mean"] = np.where(exact, np.nan, lam)
    with np.errstate(invalid="ignore"):  # -inf - -inf where lambda_1 = -inf: exact, no standard error
        info["se"] = np.where(exact, np.nan, (hi - lo) / (2 * crit))
    # an exact value's sensitivity to its monodromy matrix (the check scales its tolerance by it)
    info["sensitivity"] = s.lyap1_sensitivity.values if "lyap1_sensitivity" in s else np.zeros(idx.size)
    colors = np.array([motion_color(x) if no_period(x) else PERIODIC_COLOR for x in lab], dtype=object)
    colors[np.isneginf(lam)] = MINUS_INF_COLOR
    colors[np.isnan(lam)] = NOT_ESTIMATED_COLOR
    # every point is drawn, so that the check finds the same points whatever their motion: -inf and a
    # value not estimated (lyap1_source says why) at fixed levels below every finite value
    floor = minus_inf_level(float(sw.attrs.get("r", 0.5)))
    y = np.where(np.isneginf(lam), floor, np.where(np.isnan(lam), floor - NOT_ESTIMATED_BELOW, lam))
    info["settled"] = info["settled"] | np.isnan(lam)
    bars = np.flatnonzero(no_period(lab) & np.isfinite(lo) & np.isfinite(hi) & ~exact)
    if bars.size:
        ax.vlines(d[bars], lo[bars], hi[bars], colors=list(colors[bars]), lw=0.5, zorder=2)
    style = dict(s=5, facecolors="none", edgecolors=list(colors)) if marker == "o" else dict(s=7, c=list(colors))
    art = ax.scatter(d, y, marker=marker, linewidths=0.5, zorder=3, **style)
    # -inf: a triangle pointing down at the foot (one artist still: a path per point)
    shapes = [MarkerStyle(MINUS_INF_MARKER if np.isneginf(v) else marker) for v in lam]
    art.set_paths([m.get_path().transformed(m.get_transform()) for m in shapes])
    if marker != "o":
        art.set_facecolors(list(colors))
    wellposed(art, "motions", **info, low=lo, high=hi)
    # what was drawn, for the legend: the kinds of points, and the kinds with an interval bar
    kinds = {"-inf" if np.isneginf(v) else "not estimated" if np.isnan(v) else x if x in NO_PERIOD_LABELS else "exact"
             for x, v in zip(lab, lam, strict=True)}
    return kinds | {f"{x} interval" for x in set(lab[bars])}


def fig_lyapunov(sweeps, orbit_sets, transitions=None, *, ncols=3):
    """For each sweep: the impact velocities |Zdot_k| of the last period of every point (the bifurcation
    diagram of Figure 2 (a), (c) and Figure 9; o: d decreasing, +: d increasing), and under it, on the same d
    axis, the largest Lyapunov exponent lambda_1 per impact (:func:`vibroimpact.lyapunov`): exact on a
    Newton-solved cycle (black), the long run's estimate with its 95 % interval where no period was found
    (in the motions' colours: near black chaotic, dark grey quasi-periodic, light grey unsettled), -inf
    (sticking, at rest) as triangles at the foot.
    The period doublings B, d_graz (the 2:1 fold) and G1 of the continued 1:1 and 2:1 branches (``orbit_sets``) and
    the 1:1 exit of each sweep's located ``transitions`` are marked (:func:`critical_marks`), named in the lambda_1
    panels where they cover no data; the legend lists only the kinds of point drawn (:func:`lyapunov_handles`)."""

    use_style()
    n = len(sweeps)
    nrows = int(np.ceil((n + 1) / ncols))  # a slot for the legend
    fig = plt.figure(figsize=(4.4 * ncols, 4.6 * nrows))
    outer = fig.add_gridspec(nrows, ncols, hspace=0.42, wspace=0.28)
    letters = iter("abcdefghijklmnop")
    drawn, kinds, todo = set(), set(), []
    transitions = transitions or [None for _ in sweeps]
    for k, (sw, obs, tr) in enumerate(zip(sweeps, orbit_sets, transitions, strict=True)):
        inner = outer[k // ncols, k % ncols].subgridspec(2, 1, hspace=0.06, height_ratios=[1.0, 0.8])
        vax = fig.add_subplot(inner[0])
        lax = fig.add_subplot(inner[1], sharex=vax)
        marks = critical_marks(obs, tr)
        drawn |= {name for name, _ in marks}
        sim_points(vax, sw, "v_minus", every=True)
        vax.set_ylabel(r"$|\dot Z_k|$", fontsize=7)
        vax.set_title(panel_title(sw, next(letters)), fontsize=7)
        vax.tick_params(labelbottom=False)
        motion_runs(vax, sw)
        secondary_axis(vax, sw)
        vax.set_ylim(top=vax.get_ylim()[1] * 1.15)
        for direction, marker in (("down", "o"), ("up", "+")):
            kinds |= _lyapunov_points(lax, sw, direction, marker)
        lax.axhline(0.0, color="0.3", lw=0.6, zorder=1)
        lax.set_xlabel("d")
        lax.set_ylabel(r"$\lambda_1$ per impact", fontsize=7)
        # the marks' names in the lambda_1 panel (under the velocities they would cover the motions' names)
        mark_located(vax, marks, sweep_step(sw), names=False)
        todo += mark_located(lax, marks, sweep_step(sw))
    ax = fig.add_subplot(outer[(n) // ncols, n % ncols]) if n % ncols else None
    note = ("Largest Lyapunov exponent of each sweep point, per impact\n(long runs: batch means over "
            f"{int(sweeps[0].attrs.get('long_impacts', 0))} impacts, transient 1/10 discarded;\n"
            r"a focus, complex multipliers: $\lambda_1 = \lambda_2 = \ln r$)" + "\n"
            + "\n".join(textwrap.wrap(RUNS_NOTE.replace("\n", " ").replace("each panel", "each panel of velocities"), 64)))
    h = lyapunov_handles(kinds) + mark_handles(drawn)
    for handle in h:  # the legend keeps to its slot's width
        handle.set_label("\n".join(textwrap.wrap(handle.get_label(), 58, subsequent_indent="  ")))
    if ax is not None:
        ax.axis("off")
        ax.legend(handles=h, loc="center", fontsize=6, title=note, title_fontsize=6, frameon=False)
    else:
        fig.legend(handles=h, loc="outside lower center", ncol=3, fontsize=6, title=note, title_fontsize=6)
    rows_of_names(fig)
    name_marks(fig, todo, fontsize=5)
    return fig


def lyapunov_handles(kinds) -> list:
    """The legend entries of the points :func:`fig_lyapunov` drew (``kinds``: what :func:`_lyapunov_points`
    returned), in a fixed order, only those drawn: a kind drawn with its interval as a bar has a line."""
    interval = r"95 % interval of $\lambda_1$"
    entries = [
        ("exact", PERIODIC_COLOR, "o", r"$\lambda_1 = \ln\max|\mu| / N$ of the Newton-solved cycle (exact)"),
        (CHAOTIC, motion_color(CHAOTIC), "o", f"{CHAOTIC}: {interval} above 0"),
        (QUASI_PERIODIC, motion_color(QUASI_PERIODIC), "o", f"{QUASI_PERIODIC}: {interval} contains 0"),
        (UNSETTLED, motion_color(UNSETTLED), "o", f"{UNSETTLED}: a transient longer than the cap"),
        (APERIODIC, motion_color(APERIODIC), "o", f"{APERIODIC}, not split (no long run)"),
        ("-inf", MINUS_INF_COLOR, MINUS_INF_MARKER,
         rf"$\lambda_1 = -\infty$ (sticking, at rest), drawn at $\ln r - {MINUS_INF_BELOW:g}$ (filled: d increasing)"),
        ("not estimated", NOT_ESTIMATED_COLOR, "o",
         rf"not estimated (no long run), drawn at $\ln r - {MINUS_INF_BELOW + NOT_ESTIMATED_BELOW:g}$"),
    ]
    h = [Line2D([], [], color="0.45", marker="o", mfc="none", ls="", label="simulated, d decreasing"),
         Line2D([], [], color="0.45", marker="+", ls="", label="simulated, d increasing")]
    h += [Line2D([], [], color=color, marker=marker, mfc="none", ls="-" if f"{kind} interval" in kinds else "",
                 label=label) for kind, color, marker, label in entries if kind in kinds]
    return h
