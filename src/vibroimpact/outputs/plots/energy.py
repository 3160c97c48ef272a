"""Voltages (Figures 2 and 9, drawn by :func:`fig_energy`: rows ``fig0`` and ``fig5`` of
:mod:`vibroimpact.outputs.registry`) and design guidance."""

from __future__ import annotations

import textwrap
import weakref
from collections import Counter

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.transforms import blended_transform_factory

from ...analysis.d_graz import branch_d_graz
from ...analysis.energy import delivered
from ...analysis.motions import no_period
from ...analysis.windows import window_motions
from .. import layout
from ..tables import stable_interval
from ._common import BOTTOM, MARKS, TOP, beta_label, branch_line, use_style, wellposed
from .sweeps import last_events, point_info, word_ratio

U_I_COLOR = "tab:red"
U_T_COLOR = "tab:cyan"
#: simulated points: grey, under the analytic lines
SIM_COLOR = "0.45"
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



def located_marks(orbit_branches, transitions=None):
    """The points Figures 2 and 9 mark on the d axis, by their names in :data:`~vibroimpact.outputs.plots._common.MARKS`:
    d_graz, the largest d of 2:1 period-2 (the continued 2:1 branch's fold, :func:`vibroimpact.branch_d_graz`);
    the 1:1 exit, where the 1:1 motion followed with d decreasing leaves the 1:1 family (the sweep's located
    ``transitions``, :func:`vibroimpact.sweep_family_exit`: ``"1:1 exit: grazing"`` or ``"1:1 exit: jump"``); and
    G1, the lower end of the 2:1 orbit's stable interval when a grazing ends it (the 3:1 orbit is born).
    ``[(name, d)]``."""

    marks = []
    for br in orbit_branches:
        if br.attrs.get("word") == "BBT" and br.attrs.get("status") != "failed" and "critical_d" in br:
            d, _ = branch_d_graz(br)
            if np.isfinite(d):
                marks.append(("d_graz", d))
    if transitions is not None and "exit_d" in transitions and np.isfinite(float(transitions.exit_d)):
        marks.append((f"1:1 exit: {str(transitions.exit_kind.values)}", float(transitions.exit_d)))
    for br in orbit_branches:
        if br.attrs.get("status") == "failed" or "critical_d" not in br or br.attrs.get("word") != "BBT":
            continue
        lo, _hi, cause_lo, _ = stable_interval(br)
        if cause_lo == "grazing":
            marks.append(("G1", lo))
    return marks


#: the ``gid`` of a motion's name written over a panel (:func:`motion_runs`), which :func:`rows_of_names` places
RUN_NAME = "motion-run-name"
#: each such name's run: its first and last d (the name is kept beside it)
RUN_SPANS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


#: a run of one motion along a sweep is named over its panel when it holds at least this many points
MIN_POINTS = 5
#: the most motions a name of merged short runs lists (the most frequent first)
MAX_NAMED = 3
#: how a name of merged short runs lists the periodic motions without a short name (k:m over n forcing periods)
WINDOWS = "periodic windows"
#: what the names over a panel say (:func:`motion_runs`), for its legend
RUNS_NOTE = ("Over each panel: the down sweep's motion (T = its period in t; chaotic: no period, $\\lambda_1$ above 0; "
             "unsettled: no period within the cap,\nits transient still converging; a gap between names: fewer than "
             f"{MIN_POINTS} points of one motion, or of short runs together).")


def motion_blocks(labels, min_points=MIN_POINTS, names=None):
    """The runs of one motion along a sweep that a panel names, as ``[(first, end, name)]`` (point indices,
    ``end`` exclusive).

    Consecutive points with one label make a run.  A run of at least ``min_points`` points is named by its
    motion: a periodic one by ``names[label]`` (its :attr:`~vibroimpact.analysis.motions.Motion.short_label`; the
    label where ``names`` lacks it), one with no period by its label (chaotic, quasi-periodic, unsettled, no
    period found), the same name for the same motion in every panel.  Consecutive shorter runs are merged; a
    merged block of at least ``min_points`` points is named by the motions it holds, the most frequent first
    (:data:`MAX_NAMED` of them, "…" for the others; the periodic motions without a short name together as
    :data:`WINDOWS`); a shorter one is not named (the gap :data:`RUNS_NOTE` explains)."""

    lab = np.asarray(labels).astype(str)
    if not lab.size:
        return []
    edges = np.flatnonzero(lab[1:] != lab[:-1]) + 1
    starts, ends = np.r_[0, edges], np.r_[edges, lab.size]
    long_ = (ends - starts) >= min_points
    blocks, k = [], 0
    while k < starts.size:
        if long_[k]:
            a, b = starts[k], ends[k]
            blocks.append((int(a), int(b), (names or {}).get(lab[a], lab[a])))
            k += 1
            continue
        j = k
        while j < starts.size and not long_[j]:
            j += 1
        a, b = starts[k], ends[j - 1]
        if b - a >= min_points:
            # a periodic motion by its short name where it has one (n:1 T=k), else among the "periodic windows"
            held = list(dict.fromkeys(m if no_period(m) or " over " not in (names or {}).get(m, m) else WINDOWS
                                      for m, _ in Counter(lab[a:b].tolist()).most_common()))
            shown = [(names or {}).get(m, m) for m in held[:MAX_NAMED]]
            blocks.append((int(a), int(b), ", ".join(shown) + (", …" if len(held) > MAX_NAMED else "")))
        k = j
    return blocks


def sweep_step(sw) -> float:
    """The largest spacing in d of a sweep's points."""
    return float(np.max(np.diff(sw.d.values))) if sw.sizes["point"] > 1 else 0.0


def motion_runs(ax, sw, direction="down", min_points=MIN_POINTS):
    """The motion identified along the sweep, written over the top of the panel where it holds for
    at least ``min_points`` points (:func:`motion_blocks`), so every cloud of points can be read
    against it."""

    d = sw.d.values
    tr = blended_transform_factory(ax.transData, ax.transAxes)
    step = sweep_step(sw)
    s = sw.sel(direction=direction)
    names = {m.label: m.short_label for m in window_motions(s)}
    for a, b, name in motion_blocks(s.label.values, min_points, names):
        single = len(set(s.label.values[a:b].astype(str))) == 1
        ax.annotate("", (d[a], 0.985), (d[b - 1], 0.985), xycoords=tr, arrowprops=dict(arrowstyle="|-|", lw=0.5,
                    color="0.4", shrinkA=0, shrinkB=0, mutation_scale=2))
        text = ax.text(0.5 * (d[a] + d[b - 1]), 0.965, name, transform=tr, ha="center", va="top", fontsize=5,
                       color="0.25")
        text.set_gid(RUN_NAME)  # placed in rows by rows_of_names once the figure is laid out
        RUN_SPANS[text] = (float(d[a]), float(d[b - 1]))
        # a name of merged short runs lists motions that interleave where they meet: which, and in what order,
        # moves with any point there
        wellposed(text, "run", step=step, merged=not single)


#: how much an axis' top is raised at a time to clear its motion names of markers, and at most how often
RAISE, MAX_RAISE = 0.05, 20


def rows_of_names(fig, row_height=0.045, pad=3.0):
    """Once the figure is laid out (drawn once): each panel's motion names (:func:`motion_runs`), left to
    right, each in the highest row where it comes within ``pad`` pixels of no name already placed, at its run's
    middle or moved sideways by up to its width while it stays over its run and inside the panel; then the
    panel's top raised (by :data:`RAISE` of its height at a time) until no name covers a marker."""
    home = {t: t.get_position() for ax in fig.axes for t in ax.texts if t.get_gid() == RUN_NAME}
    # a raised top changes the tick labels and so the layout: the names are placed again in the new one
    for _ in range(3):
        if not _place_names(fig, home, row_height, pad):
            break


def _place_names(fig, home, row_height, pad) -> bool:
    """One pass of :func:`rows_of_names` from the names' first places ``home``: whether a panel's top was raised."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    raised = False
    for ax in fig.axes:
        names = sorted((t for t in ax.texts if t.get_gid() == RUN_NAME), key=lambda t: home[t][0])
        for t in names:
            t.set_position(home[t])
        frame = ax.get_window_extent(renderer)
        to_px = ax.transData.transform
        placed = []
        for text in names:
            box = text.get_window_extent(renderer)
            span = [to_px((x, 0.0))[0] for x in RUN_SPANS.get(text, (text.get_position()[0],) * 2)]
            x0, y0 = text.get_position()
            w = box.width
            shifts = [k * w / 3 for k in (0, 1, -1, 2, -2, 3, -3)]
            ok = [dx for dx in shifts if box.x0 + dx >= frame.x0 + pad and box.x1 + dx <= frame.x1 - pad
                  and box.x1 + dx > span[0] - pad and box.x0 + dx < span[1] + pad]
            if not ok:  # a name wider than the room at an end of the axis: flush with that end
                ok = [frame.x0 + pad - box.x0 if box.x0 < frame.x0 + pad else frame.x1 - pad - box.x1]
            for row in range(len(names) + 1):
                here = [box.translated(dx, -row * row_height * frame.height) for dx in ok]
                free = [dx for dx, c in zip(ok, here, strict=True)
                        if not any(c.padded(pad).overlaps(q.get_window_extent(renderer)) for q in placed)]
                if free:
                    break
            x_px = to_px((x0, 0.0))[0] + free[0]
            text.set_x(ax.transData.inverted().transform((x_px, 0.0))[0])
            text.set_y(y0 - row_height * row)
            placed.append(text)
        # room for the names: the axis' top raised until no name covers a marker (the names stay where they are, at
        # fractions of the axes' height; the data move down)
        for _ in range(MAX_RAISE):
            if not any(layout.markers_under(ax, t.get_window_extent(renderer)) for t in placed):
                break
            lo_y, hi_y = ax.get_ylim()
            ax.set_ylim(lo_y, hi_y + RAISE * (hi_y - lo_y))
            raised = True
    return raised


def secondary_axis(ax, sw):
    """The physical parameter the sweep varies on a second x axis: s = d ||F|| / k is linear in d, and
    ||F|| = k s / d its inverse (d = k s / ||F||, k = M omega^2 / pi^2; the constant from the sweep's
    own s, F and d)."""
    vary = sw.attrs["vary"]
    with np.errstate(divide="ignore", invalid="ignore"):
        if vary == "s":
            c = float(np.median(sw.s.values / sw.d.values))
            fwd, inv = (lambda v: c * np.asarray(v, float)), (lambda v: np.asarray(v, float) / c)
        else:
            c = float(np.median(sw.F.values * sw.d.values))

            def fwd(v):
                v = np.asarray(v, float)
                return np.divide(c, v, out=np.full_like(v, np.inf), where=v != 0)

            inv = fwd
    sec = ax.secondary_xaxis("top", functions=(fwd, inv))
    if vary == "F":  # 1/d crowds evenly spaced forces at small d: ticks at round forces in the sweep's range
        F = sw.F.values
        sec.set_xticks([f for f in (4, 5, 6, 7, 8, 10, 12, 15, 18, 22, 26, 30) if F.min() <= f <= F.max()])
    sec.set_xlabel("cylinder length s (m)" if vary == "s" else r"forcing amplitude $\|\hat F\|$ (N)", fontsize=7)
    sec.tick_params(labelsize=6)


def panel_title(sw, letter):
    """A sweep panel's title: its letter, incline and the range of the parameter it varies, the other held."""
    vary = sw.attrs["vary"]
    rng = sw[vary].values
    if vary == "s":
        span, fixed = f"{rng.min():g} < s < {rng.max():g} m", rf"$\|\hat F\|$ = {sw.F.values[0]:g} N"
    else:
        span, fixed = rf"{rng.min():g} < $\|\hat F\|$ < {rng.max():g} N", f"s = {sw.s.values[0]:g} m"
    return f"({letter}) {beta_label(sw.attrs['beta'])}, {span}, {fixed}"


def sim_points(ax, sw, var, scale=1.0, *, every=False):
    """The last period of events of every sweep point (24 events where no period was found): the down sweep
    (d decreasing, o) and the up sweep (+), thinned to every other point each (the down sweep's even points,
    the up sweep's odd ones), or with ``every`` at every point both."""
    for direction, marker, keep in (("down", "o", 0), ("up", "+", 1)):
        sub = sw if every else sw.isel(point=slice(keep, None, 2))
        x, y, info = last_events(sub, var, direction, info=True)
        line = ax.plot(x, np.abs(y) * scale, marker, mfc="none", color=SIM_COLOR, ms=2.2, mew=0.5, ls="none",
                       zorder=2)[0]
        _motions(line, info, scale)


def _motions(artist, info, scale=1.0):
    """What the check compares of simulated points (:func:`vibroimpact.outputs.plots._common.wellposed`), in the
    units drawn."""
    wellposed(artist, "motions", **(info | {"mean": info["mean"] * scale, "se": info["se"] * scale}))


def _point_markers(ax, en, var, fmt, scale, **style):
    """``var`` (U_T or U_I) at every point of the down sweep, with what the check compares."""
    dn = en.sel(direction="down")
    line = ax.plot(dn.d, dn[var] * scale, fmt, ls="none", **style)[0]
    _motions(line, point_info(dn, np.arange(dn.sizes["point"]), var), scale)
    return line


#: the text naming a marked line in a panel, where it is not the mark's name itself
MARK_TEXT = {"d_graz": r"$d_{\rm graz}$"}


def mark_style(name: str) -> tuple[str, str, str]:
    """Colour, line style and legend entry of a marked point (:data:`~vibroimpact.outputs.plots._common.MARKS`; the
    period doublings B and folds of the continued branches, ``"B (1:1)"``, ``"fold (1:1)"``, dotted brown and
    olive)."""
    if name in MARKS:
        return MARKS[name]
    if name.startswith("B ("):
        return "tab:brown", ":", "B: period doubling (1:1 or 2:1 branch)"
    return "tab:olive", ":", f"{name.split(' (')[0]} of the {name.split('(')[-1].rstrip(')')} branch"


def mark_located(ax, marks, step=0.0, *, names=True):
    """Vertical lines at the points ``marks`` (:func:`located_marks`; ``[(name, d)]``), each in its colour and line
    style (:func:`mark_style`).  Returns the names to write beside them once the figure is laid out
    (:func:`name_marks`; none with ``names=False``).  The 1:1 exit is located along the sweep (``step``: its grid
    step, to which the check holds it where its location is ill-conditioned); d_graz, G1 and the branches' points
    are analytic."""
    todo = []
    for name, d in marks:
        color, ls, _ = mark_style(name)
        line = ax.axvline(d, color=color, ls=ls, lw=0.8, zorder=3)
        if name.startswith("1:1 exit"):
            wellposed(line, "located", step_x=step)
        if names:
            todo.append((ax, name, d, step))
    return todo


#: where a marked line's name may go, in order of preference (a place up the line, in axes fraction, from which
#: the upright name rises; its side and distance, in points): beside the line from the foot up, then farther off
#: with a leader line to it where the data leave no room beside it
NAME_PLACES = [(y, (dx, 1)) for dx in (2, -2, 14, -14, 26, -26) for y in (0.02, 0.2, 0.4, 0.6)]


def name_marks(fig, todo, fontsize=5.5):
    """Write each marked line's name (:func:`mark_located`) upright beside it, where it covers no text, marker or
    line (:func:`vibroimpact.outputs.layout.place_labels`); call once the figure is laid out."""
    requests = [(ax, MARK_TEXT.get(name, name), [((d, y), off) for y, off in NAME_PLACES],
                 dict(xycoords=("data", "axes fraction"), fontsize=fontsize, color=mark_style(name)[0], rotation=90))
                for ax, name, d, _ in todo]
    for text, (_, name, _, step) in zip(layout.place_labels(fig, requests), todo, strict=True):
        if name.startswith("1:1 exit"):  # located along the sweep: its d to a grid step, its place the layout's
            wellposed(text, "placed", provenance="layout", free="y", step_x=step)


def mark_handles(names):
    """Legend entries of the marks drawn (:func:`located_marks`' and :func:`mark_style`'s names), one per kind."""
    entries = {}
    for name in sorted(names, key=lambda n: (list(MARKS).index(n) if n in MARKS else len(MARKS), n)):
        color, ls, label = mark_style(name)
        entries.setdefault(label, Line2D([], [], color=color, ls=ls, label=label))
    return list(entries.values())


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


