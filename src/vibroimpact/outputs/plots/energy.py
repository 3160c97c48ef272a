"""Voltages (Figures 2 and 9, drawn by :func:`fig_energy`: rows ``fig0`` and ``fig5`` of
:mod:`vibroimpact.outputs.registry`) and design guidance."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D

from ...analysis.energy import delivered
from .. import layout
from ._common import (
    BOTTOM,
    RUNS_NOTE,
    SIM_COLOR,
    TOP,
    beta_label,
    branch_line,
    located_marks,
    mark_handles,
    mark_located,
    motion_runs,
    name_marks,
    panel_title,
    point_info,
    record_motions,
    rows_of_names,
    secondary_axis,
    sim_points,
    sweep_step,
    use_style,
    wellposed,
    word_ratio,
)

U_I_COLOR = "tab:red"
U_T_COLOR = "tab:cyan"
KV = 1e-3  # volts to kilovolts


def _analytic(ax, branches, var, *, averages=False, scale=1.0):
    """Analytic 1:1 and 2:1 lines (admissible stretches; stable solid, unstable dashed), drawn over the
    simulated points."""
    for br in branches:
        if not br.sizes.get("point", 0):
            continue
        m = br.admissible.values
        d = br.d.values[m]
        st = br.stable.values[m]
        if averages:
            branch_line(ax, d, br.U_I.values[m] * scale, st, U_I_COLOR, lw=0.9, zorder=4)
            branch_line(ax, d, br.U_T.values[m] * scale, st, U_T_COLOR, lw=0.9, zorder=4)
            continue
        for j in range(br.sizes["impact"]):
            y = np.abs(br[var].values[m, j]) * scale
            branch_line(ax, d, y, st, BOTTOM if br.wall.values[j] == 1 else TOP, zorder=4)


def _point_markers(ax, en, var, fmt, scale, **style):
    """``var`` (U_T or U_I) at every point of the down sweep, with what the check compares."""
    dn = en.sel(direction="down")
    line = ax.plot(dn.d, dn[var] * scale, fmt, ls="none", **style)[0]
    record_motions(line, point_info(dn, np.arange(dn.sizes["point"]), var), scale)
    return line


def _energy_legend(fig, velocities, note=None, names=()):

    h = [Line2D([], [], color=BOTTOM, label="analytic, bottom impacts"),
         Line2D([], [], color=TOP, label="analytic, top impacts"),
         Line2D([], [], color="0.3", ls="-", label="stable"), Line2D([], [], color="0.3", ls="--", label="unstable"),
         Line2D([], [], color=SIM_COLOR, marker="o", mfc="none", ls="", label="simulated, d decreasing"),
         Line2D([], [], color=SIM_COLOR, marker="+", ls="", label="simulated, d increasing"),
         Line2D([], [], color=U_T_COLOR, marker="D", mfc="none", ls="", label=r"$\overline{U}_T$ simulated (per unit time)"),
         Line2D([], [], color=U_I_COLOR, marker="*", ls="", label=r"$\overline{U}_I$ simulated (per impact)"),
         Line2D([], [], color=U_T_COLOR, label=r"$\overline{U}_T$ of the analytic 1:1 / 2:1 orbit"),
         Line2D([], [], color=U_I_COLOR, label=r"$\overline{U}_I$ of the analytic 1:1 / 2:1 orbit"),
         *mark_handles(names)]
    leg = fig.legend(handles=h, loc="outside lower center", ncol=4 if velocities else 3, fontsize=6, title=note,
                     title_fontsize=6)
    layout.style_keys(leg, "stable", "unstable")  # solid and dashed, in the branches' colours


def fig_energy(panels, sweeps, energies, branch_sets, *, velocities=False, orbit_sets=None, transitions=None):
    """Output voltage U_k - U_in in kV (analytic 1:1 and 2:1 lines over the simulated points; stable
    solid, unstable dashed), the averages U_I (red stars) and U_T (cyan diamonds) of the down sweep with
    the analytic orbits' averages as lines, against d (the swept s or force on the top axis); with
    ``velocities`` also |Zdot_k| (Figure 2 (a), (c)).  The motion found along each sweep is written
    over each panel (:func:`motion_runs`, what its names mean in the note under the legend: :data:`RUNS_NOTE`);
    d_graz and G1 of the continued 2:1 branch (``orbit_sets``) and the 1:1 exit of each sweep's located
    ``transitions`` are marked (:func:`located_marks`).  An analytic branch that failed (another device may not have it) is not drawn,
    and the note under the figure says which, in which panels, and why."""

    use_style()
    n = len(panels)
    if velocities:
        fig, axes = plt.subplots(n, 2, figsize=(10, 3.6 * n + 0.6), squeeze=False)
        pairs = [(row[0], row[1]) for row in axes]
    else:
        ncol = 2 if n > 1 else 1
        nrow = int(np.ceil(n / ncol))
        fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 3.6 * nrow + 0.6), squeeze=False)
        pairs = [(None, ax) for ax in axes.ravel()[:n]]
        for ax in axes.ravel()[n:]:
            ax.remove()
    letters = iter("abcdefghijklmnop")
    orbit_sets = orbit_sets or [[] for _ in panels]
    transitions = transitions or [None for _ in panels]
    drawn, missing, todo = set(), {}, []
    for k, ((vax, uax), sw, en, brs, obs, tr) in enumerate(zip(pairs, sweeps, energies, branch_sets, orbit_sets,
                                                              transitions, strict=True)):
        for br in obs:
            if br.attrs.get("status") == "failed":
                why = f"analytic {word_ratio(str(br.attrs.get('word', '')))}: {br.attrs.get('reason', '')}"
                here = "abcdefghijklmnop"[2 * k:2 * k + 2] if velocities else "abcdefghijklmnop"[k]
                missing.setdefault(why, []).extend(f"({c})" for c in here)
        marks = located_marks(obs, tr)
        drawn |= {name for name, _ in marks}
        if vax is not None:
            sim_points(vax, sw, "v_minus")
            _analytic(vax, brs, "v_minus")
            vax.set_xlabel("d")
            vax.set_ylabel(r"$|\dot Z_k|$ (non-dimensional)")
            vax.set_title(panel_title(sw, next(letters)))
        sim_points(uax, en, "gain", KV)
        _analytic(uax, brs, "gain", scale=KV)
        _analytic(uax, brs, "gain", averages=True, scale=KV)
        _point_markers(uax, en, "U_T", "D", KV, mfc="none", color=U_T_COLOR, ms=3, mew=0.6, zorder=3)
        _point_markers(uax, en, "U_I", "*", KV, color=U_I_COLOR, ms=3, zorder=3)
        uax.set_xlabel("d")
        uax.set_ylabel(r"$U_k-U_{in}$, $\overline{U}_I$, $\overline{U}_T$ (kV)")
        uax.set_title(panel_title(sw, next(letters)))
        for ax in (vax, uax):
            if ax is None:
                continue
            motion_runs(ax, sw)
            todo += mark_located(ax, marks, sweep_step(sw))
            secondary_axis(ax, sw)
            ax.set_ylim(top=ax.get_ylim()[1] * 1.1)  # room for the motions written over the top
    a = energies[0].attrs
    note = RUNS_NOTE
    if "membrane_K" in a:
        note = ("Voltages from the membrane model with assumed constants (h = {h:g}, K = {K:.4g} SI, R = {R:g} m, "
                "r_b = {rb:g} m, U_in = {U:g} V, ball mass {m:g} kg; docs/guide/model.md):\nthe voltage scale rests on "
                "them, the shapes and jumps do not.  ").format(h=a["membrane_h"], K=a["membrane_K"], R=a["membrane_R"],
                                                             rb=a["membrane_r_b"], U=a["membrane_U_in"],
                                                             m=a["membrane_m"]) + note
    if missing:

        width = 150 if velocities or n > 1 else 90
        note = (note + "\n" if note else "") + "Not drawn:\n" + "\n".join(
            textwrap.fill(f"{', '.join(panels_)}: {why}", width) for why, panels_ in missing.items())
    _energy_legend(fig, velocities, note, drawn)
    rows_of_names(fig)
    name_marks(fig, todo)
    return fig


def fig_design(s_sets, F_sets, table):
    """What a device delivers (:func:`vibroimpact.analysis.energy.delivered`: the exact cycle's U_T and U_I where
    the motion is periodic, the long run's where it is not; a gap where a transient outlasts the cap)
    against s at fixed force and against F at fixed s, per incline, U_T solid and U_I dashed (kV), with the
    maxima of the design table marked; one legend below both panels says what each line and mark is."""


    use_style()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4))
    colors = plt.get_cmap("tab10").colors
    for ax, sets, vary in ((axes[0], s_sets, "s"), (axes[1], F_sets, "F")):
        for k, e in enumerate(sets):
            dn = e.sel(direction="down")
            c = colors[k % 10]
            every = np.arange(dn.sizes["point"])
            down = list(e.direction.values).index("down")
            for q, style, lw, label in (("U_T", "-", 1.0, beta_label(e.attrs["beta"]) + r": $\overline{U}_T$"),
                                        ("U_I", "--", 0.8, None)):
                value, se = delivered(e, q)
                info = point_info(dn, every, q) | {"mean": value[down] * KV, "se": se[down] * KV}
                wellposed(ax.plot(e[vary], value[down] * KV, style, color=c, lw=lw, label=label)[0], "motions", **info)
            rows = table[(table.vary == vary) & (abs(table.beta - float(e.attrs["beta"])) < 1e-9)]
            for _, r in rows.iterrows():
                value, se = (r.U_T, r.U_T_se) if r.maximise == "U_T" else (r.U_I, r.U_I_se)
                mark = ax.plot(r.best, value * KV, "o" if r.maximise == "U_T" else "s", mfc="none", color=c, ms=8)[0]
                # a maximum where no period is found is the long run's mean, known to its standard error
                wellposed(mark, "motions", motion=[r.motion], settled=[se == 0], unsettled=[False], mean=[value * KV],
                          se=[se * KV])
        ax.set_xlabel("cylinder length s (m)" if vary == "s" else "forcing amplitude ||F|| (N)")
        ax.set_ylabel("average output voltage (kV)")
        ax.set_title("(a) length sweep at fixed force" if vary == "s" else "(b) force sweep at s = 0.85 m")
    handles = [Line2D([], [], color=colors[k % 10], label=beta_label(e.attrs["beta"])) for k, e in enumerate(s_sets)]
    handles += [Line2D([], [], color="0.3", ls="-", label=r"$\overline{U}_T$ (per unit time)"),
                Line2D([], [], color="0.3", ls="--", lw=0.8, label=r"$\overline{U}_I$ (per impact)"),
                Line2D([], [], color="0.3", marker="o", mfc="none", ls="", ms=8, label=r"largest $\overline{U}_T$"),
                Line2D([], [], color="0.3", marker="s", mfc="none", ls="", ms=8, label=r"largest $\overline{U}_I$")]
    leg = fig.legend(handles=handles, loc="outside lower center", ncol=4, fontsize=7, title_fontsize=7,
                     title="periodic motion: the exact cycle's average; no period (chaotic, quasi-periodic): the long "
                           "run's; a gap: a transient longer than the cap")
    # line styles and marks, drawn in each incline's colour
    layout.style_keys(leg, *(h.get_label() for h in handles[len(s_sets):]))
    return fig


