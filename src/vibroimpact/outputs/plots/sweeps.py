"""Sweeps, bistability (Figure 8, :func:`fig_bis`), basins and regime maps."""

from __future__ import annotations

import json
import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ...analysis.motions import NO_PERIOD_LABELS, THREE_ONE, TWO_ONE, orbit_motion
from ...dynamics import kernels as K
from ...dynamics.params import Params
from ...dynamics.runs import simulate
from .. import layout
from ._common import (
    BOTTOM,
    EXIT_COLOR,
    MARKS,
    OTHER,
    TOP,
    WORD_NAME,
    beta_label,
    branch_line,
    curve_pieces,
    last_events,
    motion_color,
    pi_label,
    pi_ticks,
    sticking_motions,
    use_style,
    wellposed,
    word_ratio,
)


#: the marker of each motion in Figure 8 (the paper's caption: 2:1 open circles, 3:1 crosses); any other "x"
BIS_MARKERS = {TWO_ONE.label: "o", THREE_ONE.label: "+"}
#: simulated points drawn per sweep direction and panel: more merge into bands at the panel's width
BIS_POINTS = 20


def fold_evidence(branch, near: float) -> dict:
    """What makes the located fold of a continued branch nearest ``near`` a fold and not a grazing point.

    Parameters
    ----------
    branch : xarray.Dataset
        A continued branch (:func:`vibroimpact.analysis.continuation.continue_orbit`) with critical points.
    near : float
        The d the fold is looked for at (e.g. G2 located by the sweeps).

    Returns
    -------
    dict
        ``d``: the fold's d; ``lam_before``, ``lam_after``: the largest real multiplier at the two branch points
        between which it crosses +1; ``d_before``, ``d_after``: their d, and ``d_turns`` whether d rises to the
        crossing and falls after it (the branch turns back); ``v_min``: the slowest impact speed, interpolated
        to the crossing (0 at a grazing point).
    """
    sel = branch.critical_kind.values == "fold"
    folds = branch.critical_d.values[sel]
    if not folds.size:
        raise ValueError(f"branch {branch.attrs.get('word')!r} has no located fold; allowed: a branch with one")
    d_fold = float(folds[np.argmin(np.abs(folds - near))])
    real = np.where(np.abs(branch.eig_imag.values) > 0, np.nan, branch.eig_real.values)
    lam = np.nanmax(np.where(np.isnan(real), -np.inf, real), axis=1)
    d = branch.d.values
    cross = np.flatnonzero((lam[:-1] - 1.0) * (lam[1:] - 1.0) <= 0)
    if not cross.size:
        raise ValueError(f"branch {branch.attrs.get('word')!r}: no multiplier crosses +1; allowed: a branch through its fold")
    i = int(cross[np.argmin(np.abs(d[cross] - d_fold))])
    slow = np.min(np.abs(branch.v_minus.values[i:i + 2]), axis=1)
    w = (1.0 - lam[i]) / (lam[i + 1] - lam[i])
    turns = bool(i >= 1 and i + 2 < d.size and d[i - 1] < d[i] and d[i + 2] < d[i + 1])
    return dict(d=d_fold, lam_before=float(lam[i]), lam_after=float(lam[i + 1]), d_before=float(d[i]),
                d_after=float(d[i + 1]), d_turns=turns, v_min=float(slow[0] + w * (slow[1] - slow[0])))


def _portrait_impacts(p, gbar, r):
    """Wall and pre-impact velocity of every impact of one portrait's closed period-2 orbit over its period
    (from its bottom impact at t0, exactly)."""

    run = simulate(Params(d=float(p.d), gbar=gbar, r=r), float(p.phi), float(p.v0), t_end=2.5)
    one = (run.t.values < 2.0 - 1e-6) & K.hits(run.kind.values)
    return run.wall.values[one], run.v_minus.values[one]


def _bis_points(ax, sw, var, stride, y_of=None):
    """Each sweep direction's last period of events at every ``stride``-th point (the up sweep's points half a
    stride on, so the two interleave), the marker and colour by the motion found.  With ``y_of``, drawn at
    that height per direction instead of the values (the panel of the sweeps)."""
    sticky = sticking_motions(sw)
    for direction, offset, name in (("down", 0, "d decreasing"), ("up", stride // 2, "d increasing")):
        sub = sw.isel(point=slice(offset, None, stride))
        x, y, info = last_events(sub, var, direction, info=True)
        y = np.abs(y) if var == "v_minus" else y
        lab = info["motion"]
        for motion in sorted(set(lab)):
            sel = lab == motion
            yy = np.full(sel.sum(), y_of[direction]) if y_of else y[sel]
            line = ax.plot(x[sel], yy, BIS_MARKERS.get(motion, "x"), mfc="none", color=motion_color(motion, motion in sticky), ms=4.5,
                           mew=0.9, ls="none", label=f"_{motion}, {name}", zorder=3)[0]
            wellposed(line, "motions", **{k: v[sel] for k, v in info.items()})


def fig_bis(sw, transitions, portraits, branches):
    """Bistable 2:1 and 3:1 near grazing (Figure 8).

    (a)-(c): the last period of sweep points of both directions (thinned to :data:`BIS_POINTS` per
    direction), the marker and colour by the motion identified there (2:1 open circles, 3:1 crosses, in the
    colours of :func:`~vibroimpact.outputs.plots._common.motion_color`), over the analytic branches in the
    same colours (stable solid, unstable dashed), with G1 and G2; (h) the motion each sweep finds along d,
    which shows the direction; (d)-(g) the closed orbits at G1, d_mid (both) and G2 over one period, their
    impacts marked as in (a)-(c), the walls shaded in their colours.  Panel (g) gives the evidence that G2
    is a fold (:func:`fold_evidence`): the multiplier crossing +1 where d turns back, the slowest impact
    speed there.  What another device lacks (a failed branch, no G1 or G2, a portrait not drawn: the
    portraits' ``status``) is left out and said under the legend and in the portrait's panel.
    """


    use_style()
    fig = plt.figure(figsize=(12, 7.4))
    gs = fig.add_gridspec(2, 4)
    g1, g2 = portraits.attrs["G1"], portraits.attrs["G2"]
    failed = [br.attrs.get("status") == "failed" for br in branches]
    missing = [f"analytic {word_ratio(str(br.attrs.get('word', '')))}: {br.attrs.get('reason', '')}"
               for br, no in zip(branches, failed, strict=True) if no]
    fold = None
    if np.isfinite(g2) and not failed[1]:
        try:
            fold = fold_evidence(branches[1], g2)
        except ValueError as err:  # no located fold, or no multiplier crossing +1, near G2
            missing.append(f"the fold at G2: {err}")
    status = portraits["status"].values.astype(str) if "status" in portraits else ["drawn"] * portraits.sizes["panel"]
    if not (np.isfinite(g1) and np.isfinite(g2)):
        missing.append(f"G1, G2: {portraits.attrs.get('G_missing') or 'not located'}")
    branches = [br for br, no in zip(branches, failed, strict=True) if not no]
    lo, hi = float(sw.d.min()), float(sw.d.max())
    stride = max(1, int(np.ceil(sw.sizes["point"] / BIS_POINTS)))
    names = [orbit_motion(str(br.attrs["word"]), int(br.attrs["k"])).label for br in branches]

    def jumps(ax, label=True):
        for g, name in ((g1, "G1"), (g2, "G2")):
            if not np.isfinite(g):
                continue
            ax.axvline(g, color="k", ls="-.", lw=0.8, zorder=1)
            if label:
                ax.annotate(name, (g, 1.0), xycoords=("data", "axes fraction"), xytext=(0, 2), ha="center",
                            textcoords="offset points", fontsize=7, va="bottom")

    for col, (var, ylabel) in enumerate([("v_minus", r"$|\dot Z_k|$"), ("phase", r"$\varphi_k$ (rad)"),
                                         ("dt", r"$\Delta t_k$")]):
        ax = fig.add_subplot(gs[0, col])
        for br, motion in zip(branches, names, strict=True):
            m = (br.admissible & (br.d >= lo) & (br.d <= hi)).values
            for j in range(br.sizes["impact"]):
                y = br[var].values[m, j]
                y = np.abs(y) if var == "v_minus" else y
                branch_line(ax, br.d.values[m], y, br.stable.values[m], motion_color(motion), lw=0.7)
        _bis_points(ax, sw, var, stride)
        jumps(ax)
        ax.set_xlabel("d")
        ax.set_ylabel(ylabel)
        ax.set_title(f"({'abc'[col]})", loc="left")
    right = gs[0, 3].subgridspec(2, 1, height_ratios=[1, 2.2])
    strip = fig.add_subplot(right[0])
    _bis_points(strip, sw, "v_minus", stride, y_of={"down": 1.0, "up": 0.0})
    jumps(strip, label=False)
    strip.set_ylim(-0.6, 1.6)
    strip.set_yticks([0.0, 1.0], [r"d increasing $\rightarrow$", r"$\leftarrow$ d decreasing"], fontsize=7)
    strip.set_xlabel("d")
    strip.xaxis.set_major_locator(plt.MaxNLocator(3))
    strip.set_title("(h) the two sweeps", loc="left")
    strip.grid(False)
    key = fig.add_subplot(right[1])  # the legend gets its own slot, clear of the data
    key.axis("off")
    leg = key.legend(handles=[
        *(Line2D([], [], color=motion_color(n), marker=BIS_MARKERS.get(n, "x"), mfc="none", ls="", label=f"{n} (simulated)")
          for n in names),
        *(Line2D([], [], color=motion_color(n), label=f"analytic {n}") for n in names),
        Line2D([], [], color="0.4", ls="--", label="dashed: unstable"),
        Line2D([], [], color="k", ls="-.", label="G1: 2:1 grazes, 3:1 born\nG2: 3:1 fold (not grazing, (g))"),
        Patch(facecolor=BOTTOM, alpha=0.25, label="(d)-(g): bottom wall"), Patch(facecolor=TOP, alpha=0.25, label="top wall")],
        loc="upper center" if missing else "center", fontsize=7)
    layout.style_keys(leg, "dashed: unstable")  # the branches' dashes, in their motions' colours
    if missing:
        key.text(0.5, 0.0, "\n".join(textwrap.fill("not drawn: " + m, 38) for m in missing), transform=key.transAxes,
                 ha="center", va="bottom", fontsize=6, color="tab:red")
    gbar, r = float(portraits.attrs["gbar"]), float(portraits.attrs["r"])
    for k in range(portraits.sizes["panel"]):
        _bis_portrait(fig.add_subplot(gs[1, k]), portraits.isel(panel=k), "defg"[k], status[k], gbar, r, fold)
    return fig


def _bis_portrait(ax, p, letter, status, gbar, r, fold):
    """Panel (d)-(g) of Figure 8: the closed orbit of ``p`` (a portrait) over one period, its impacts marked as in
    (a)-(c), the walls shaded; at G2 the evidence that it is a fold (``fold``, :func:`fold_evidence`)."""
    d = float(p.d)
    ratio = word_ratio(str(p.word.values))
    motion = orbit_motion(str(p.word.values)).label  # the branches' orbits: one forcing period
    name = str(p.panel.values)
    heads = {"G1": "grazing point G1", "G2": "G2, fold of 3:1"}
    if status != "drawn":
        ax.axis("off")
        ax.set_title(f"({letter}) {heads.get(name, ratio + ' motion')}", fontsize=8)
        ax.text(0.5, 0.5, textwrap.fill(str(status), 40), transform=ax.transAxes, ha="center", va="center",
                fontsize=7, color="tab:red")
        return
    ax.plot(p.Z, p.Zdot, color="k", lw=0.8)
    ax.axvspan(d / 2, d / 2 * 1.08, color=BOTTOM, alpha=0.25, lw=0)
    ax.axvspan(-d / 2 * 1.08, -d / 2, color=TOP, alpha=0.25, lw=0)
    wall, v = _portrait_impacts(p, gbar, r)
    ax.plot(wall * d / 2, v, BIS_MARKERS.get(motion, "x"), mfc="none", color=motion_color(motion), ms=6, mew=1.2,
            ls="none", label=f"_impacts of {motion}", zorder=4)
    ax.set_xlim(-d / 2 * 1.08, d / 2 * 1.08)
    head = f"({letter}) {heads.get(name, ratio + ' motion')}, d={d:.6f}"
    head += "\n" + r"$\dot Z(t_0)$" + f"={float(p.v0):.4f}, " + r"$\varphi$" + f"={float(p.phi):.4f}"
    if name == "G2" and fold is not None:
        head += (f"\nfold at d={fold['d']:.6f}: multiplier\n{fold['lam_before']:.3f} to {fold['lam_after']:.3f}"
                 + (", d turns back;" if fold["d_turns"] else ";") + "\nslowest impact " + r"$|\dot Z|$"
                 + f"={fold['v_min']:.3f} > 0:\nno grazing")
    ax.set_title(head, fontsize=8)
    ax.set_xlabel("Z")
    ax.set_ylabel(r"$\dot Z$")
    ax.xaxis.set_major_locator(plt.MaxNLocator(5))


#: what the motion labels mean, printed with every legend of motions
MOTION_KEY = ("n:m = bottom:top impacts per period;\nperiod-k = period k in t (2 = one forcing period);\n"
              "no period within the cap, by the largest Lyapunov\nexponent of its long run: chaotic (interval above 0),\n"
              "quasi-periodic (contains 0), unsettled (below 0,\nor a longer transient); no period found: not split")
#: added to :data:`MOTION_KEY` where a motion with sticking is named
STICKING_KEY = ("with sticking: chatters to rest on a wall, sticks until\nthe forcing releases it, its chatter counted as one\n"
                "impact (1:0: the stick-release cycle on the bottom)")


def motion_key(names, sticky=frozenset()) -> str:
    """:data:`MOTION_KEY`, with :data:`STICKING_KEY` where one of ``names`` is a motion with sticking (one of
    ``sticky``, :func:`~vibroimpact.outputs.plots._common.sticking_motions`)."""
    sticking = any(str(n) in sticky for n in names)
    return (MOTION_KEY + (";\n" + STICKING_KEY if sticking else "")).replace("; ", ";\n")


def _class_colors(names, sticky):
    """A colour per motion name: its colour in every figure (:func:`~vibroimpact.outputs.plots._common.motion_color`;
    ``sticky`` the names of the motions with sticking)."""
    return [motion_color(n, n in sticky) for n in names]


def _shown_classes(legend, sticky=frozenset(), n_show=9):
    """Which of the motions ``legend`` lists (most frequent first) a map names: every label of a motion with
    no period (chaotic, quasi-periodic, unsettled, no period found: never folded into "other") and the
    ``n_show`` most frequent periodic ones whose colour no more frequent named motion has (two motions
    without a colour of their own can share one, :func:`~vibroimpact.outputs.plots._common.motion_color`), in
    the legend's order; the rest "other" (``sticky``: the names of the motions with sticking).  Returns the names and, per legend entry, its index among them."""
    special = [i for i, n in enumerate(legend) if n in NO_PERIOD_LABELS]
    taken = {motion_color(legend[i]) for i in special}  # no period: never sticking
    periodic = []
    for i, n in enumerate(legend):
        color = motion_color(n, n in sticky)
        if n in NO_PERIOD_LABELS or len(periodic) == n_show or color in taken:
            continue
        taken.add(color)
        periodic.append(i)
    shown = sorted(special + periodic)
    names = [legend[i] for i in shown] + ([OTHER] if len(shown) < len(legend) else [])
    lut = np.full(len(legend), len(shown), dtype=int)
    lut[shown] = np.arange(len(shown))
    return names, lut


def _class_image(ax, da, x, y, legend, sticky, n_show=9, *, key=True):
    """Draw integer attractor codes (indices into ``legend``) with a discrete colormap, named as
    :func:`_shown_classes` says (``sticky``: the names of the motions with sticking).  Returns the legend handles (drawn beside the axes with ``key``)."""

    names, lut = _shown_classes(list(legend), sticky, n_show)
    codes = lut[np.asarray(da.values, dtype=int)]
    colors = _class_colors(names, sticky)
    cmap = ListedColormap(colors)
    norm = BoundaryNorm(np.arange(len(names) + 1) - 0.5, len(names))
    mesh = ax.pcolormesh(x, y, codes, cmap=cmap, norm=norm, shading="nearest")
    # the check compares the motion in each cell (the colour codes follow the legend's order, which
    # depends on how many cells each motion has)
    wellposed(mesh, "motions", motion=np.asarray(names, dtype=object)[np.asarray(codes).ravel()].astype(str))
    ax.grid(False)
    handles = [Patch(color=colors[i], label=names[i]) for i in range(len(names))]
    if key:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=6)
    return handles


def fig_basins(b):
    """Basins of attraction (:func:`vibroimpact.analysis.basins.basins`): the motion reached from each first
    bottom impact, in the motions' colours of every figure; the title gives the incline and the device
    (length, force, mass, frequency) where the dataset records them, and d, gbar."""


    use_style()
    fig, ax = plt.subplots(figsize=(7.4, 4.2))
    _class_image(ax, b.attractor.T, b.phi.values, b.v0.values, json.loads(b.attrs["legend"]), sticking_motions(b))
    ax.set_xlabel(r"phase $\varphi$ of the first bottom impact (rad)")
    ax.set_ylabel(r"pre-impact velocity $\dot Z(t_0)$")
    a = b.attrs
    device = [beta_label(float(a["beta"]))] if "beta" in a else []
    device += [fmt.format(float(a[key])) for key, fmt in (("s", "s = {:.4g} m"), ("F", r"$\|\hat F\|$ = {:g} N"),
                                                          ("M", "M = {:g} kg")) if key in a]
    device += [r"$\omega$ = " + pi_label(float(a["omega"]), " rad/s")] if "omega" in a else []
    ax.set_title(f"Basins of attraction, d = {a['d']:.4g}, " r"$\bar g$" f" = {a['gbar']:.4g}, r = {a['r']:g}"
                 + ("\n" + ", ".join(device) if device else ""))
    return fig


def fig_knock_section(sec):
    """The basins a knock crosses (:func:`vibroimpact.analysis.robust.knock_section`): the motion reached from each
    state of the ``(Z, Zdot)`` section at the forcing phase of a critical shock, in the motions' colours; the state
    the knock hits (filled circle) and the knocked state (open circle) joined by the knock (arrow); the title
    gives the design, the knock and the two motions' outputs."""

    use_style()
    fig, ax = plt.subplots(figsize=(7.4, 4.4))
    handles = _class_image(ax, sec.attractor, sec.Z.values, sec.Zdot.values, json.loads(sec.attrs["legend"]),
                           sticking_motions(sec), key=False)
    a = sec.attrs
    ax.set_xlabel(r"position $Z$ (non-dimensional; $+d/2$: bottom membrane)")
    ax.set_ylabel(r"velocity $\dot Z$ (non-dimensional)")
    title = (f"Basins at the forcing phase {a['phase']:.3f} rad, s = {a['s']:.3g} m, " + beta_label(float(a["beta"]))
             + f", d = {a['d']:.4g}")
    if not a.get("reason") and "size" in a:
        start = (float(a["Z_state"]), float(a["Zdot_state"]))
        end = (float(a["Z_knocked"]), float(a["Zdot_knocked"]))
        ax.plot(*zip(start, end, strict=True), "-", color="k", lw=1.2, zorder=5)  # the knock, its head below
        ax.annotate("", xy=end, xytext=start, arrowprops=dict(arrowstyle="->", color="k", lw=1.2), zorder=5)
        ax.plot(*start, "o", color="k", ms=5, zorder=6)
        ax.plot(*end, "o", mfc="w", mec="k", ms=5, zorder=6)
        handles += [Line2D([], [], ls="", marker="o", color="k", ms=5, label="state the knock hits"),
                    Line2D([], [], ls="", marker="o", mfc="w", mec="k", ms=5, label="knocked state"),
                    Line2D([], [], color="k", lw=1.2, label="the critical shock")]
        title += (f"\ncritical shock {a['size_si']:.3g} {a['size_unit']} drops the {a['motion']} "
                  f"({float(a['U_T']) / 1e3:.1f} kV)\nto the {a['reached']} ({float(a['reached_U_T']) / 1e3:.1f} kV)")
        span = float(sec.Z.values[-1] - sec.Z.values[0])
        ax.set_xlim(float(sec.Z.values[0]) - 0.03 * span, float(sec.Z.values[-1]) + 0.03 * span)  # a state on a wall shows
    else:
        title += f"\nno critical shock drawn: {a.get('reason', '')}"
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=6)
    ax.set_title(title, fontsize=8)
    return fig


def _scan_lines(m, xdim, ydim, scans):
    """The paper's sweeps that lie in the plane of map ``m``: (name, xs, ys) for each."""
    fixed = [k for k in ("beta", "F", "s") if k not in (xdim, ydim) and k in m.attrs]
    out = []
    for name, sc in scans.items():
        vals = {"beta": sc["beta"], sc["vary"]: tuple(sc["range"])}
        vals.update({k: sc[k] for k in ("F", "s") if k in sc and k != sc["vary"]})
        if any(not isinstance(vals.get(k), float | int) or abs(vals[k] - float(m.attrs[k])) > 1e-9 for k in fixed):
            continue
        xs, ys = vals.get(xdim), vals.get(ydim)
        if xs is None or ys is None:
            continue
        xs = xs if isinstance(xs, tuple) else (xs, xs)
        ys = ys if isinstance(ys, tuple) else (ys, ys)
        out.append((name, xs, ys))
    return out


def fig_regime_map(maps, scans=None):
    """Regime maps side by side, one colour per motion across all panels, one legend (with what the
    labels mean); the paper's sweeps that lie in a map's plane drawn over it as lines (``scans``: the
    sweep scenes of the config)."""

    use_style()
    labels, counts = np.unique(np.concatenate([m.label.values.ravel() for m in maps]), return_counts=True)
    legend = list(labels[np.argsort(-counts, kind="stable")])
    index = {lab: i for i, lab in enumerate(legend)}
    sticky = sticking_motions(*maps)
    fig, axes = plt.subplots(1, len(maps), figsize=(5.6 * len(maps), 4.6), squeeze=False)
    names = {"beta": r"incline $\beta$", "s": "cylinder length s", "F": r"forcing amplitude $\|\hat F\|$",
             "d": "non-dimensional gap d", "gbar": r"non-dimensional gravity $\bar g$", "r": "restitution r"}
    for ax, m in zip(axes[0], maps, strict=True):
        ydim, xdim = m.label.dims
        codes = m.label.copy(data=np.vectorize(index.__getitem__)(m.label.values))
        handles = _class_image(ax, codes, m[xdim].values, m[ydim].values, legend, sticky, key=False)
        ax.set_xlabel(f"{names.get(xdim, xdim)} ({m[xdim].attrs.get('units', '')})")
        ax.set_ylabel(f"{names.get(ydim, ydim)} ({m[ydim].attrs.get('units', '')})")
        if ydim == "beta":
            pi_ticks(ax, float(m.beta.min()), float(m.beta.max()))
        nondim = {xdim, ydim} & {"d", "gbar"}
        fixed = [k for k in (("d", "gbar", "r") if nondim else ("beta", "F", "s")) if k in m.attrs and k not in (xdim, ydim)]
        text = {"beta": lambda v: r"$\beta$=" + pi_label(v), "F": lambda v: rf"$\|\hat F\|$={v:g} N",
                "s": lambda v: f"s={v:g} m", "d": lambda v: f"d={v:.4g}", "gbar": lambda v: rf"$\bar g$={v:.4g}",
                "r": lambda v: f"r={v:g}"}
        ax.set_title("Attractor from one start " + rf"($\varphi$={m.attrs['phi']:g}, $\dot Z(t_0)$={m.attrs['v0']:g}); "
                     + ", ".join(text[k](float(m.attrs[k])) for k in fixed))
        x0, x1, y0, y1 = (float(m[xdim].min()), float(m[xdim].max()), float(m[ydim].min()), float(m[ydim].max()))
        outside = []
        for name, xs, ys in _scan_lines(m, xdim, ydim, scans or {}):
            if max(xs) < x0 or min(xs) > x1 or max(ys) < y0 or min(ys) > y1:
                outside.append(f"{name} ({xdim}={xs[0]:g})" if xs[0] == xs[1] else f"{name} ({ydim}={ys[0]:g})")
                continue
            ax.plot(xs, ys, "-", color="k", lw=1.6)
            ax.plot(xs, ys, "--", color="w", lw=0.9)
            top = min(ys) >= y1  # a sweep on the map's upper edge is named below it, clear of the title
            ax.annotate(name, (0.5 * (xs[0] + xs[1]), 0.5 * (ys[0] + ys[1])), fontsize=6, xytext=(0, -3 if top else 2),
                        textcoords="offset points", ha="center", va="top" if top else "bottom")
        if outside:
            ax.annotate("outside this map: " + ", ".join(outside), (0.0, -0.16), xycoords="axes fraction", fontsize=6,
                        va="top")

    if scans:
        handles = [*handles, Line2D([], [], color="k", lw=1.6, label="the paper's sweeps (config names)")]
    fig.legend(handles=handles, loc="outside right upper", fontsize=6, title=motion_key((h.get_label() for h in handles), sticky),
               title_fontsize=6)
    return fig


def _exit_curve(ax, c, xname, handles):
    """The 1:1 exit over the plane (:func:`vibroimpact.family_exit_curve`): where the 1:1 motion, followed
    with d decreasing along each line, leaves the 1:1 family; filled where it grazes, open where it jumps."""


    if not c.sizes.get("line", 0):
        return
    along, other = c.attrs["along"], c.attrs["other"]
    xs, ys = (c["at"].values, c[other].values) if along == xname else (c[other].values, c["at"].values)
    grazes = c.exit_kind.values.astype(str) == "grazing"
    # located along each line between its grid points: the check holds each to that step
    grid = float(c.attrs.get("grid_step", 0.0))
    steps = {"step_x": grid} if along == xname else {"step_y": grid}
    wellposed(ax.plot(xs, ys, "-", color="w", lw=2.6, zorder=6)[0], "located", **steps)
    wellposed(ax.plot(xs, ys, "-", color=EXIT_COLOR, lw=1.4, zorder=6.1)[0], "located", **steps)
    # where the kind comes from a sample of a motion with no period, another run may decide it otherwise
    sampled = c.exit_sampled.values.astype(bool) if "exit_sampled" in c else np.zeros(xs.size, bool)
    for sel, fill, name in ((grazes, EXIT_COLOR, "1:1 exit: grazing"), (~grazes, "w", "1:1 exit: jump")):
        wellposed(ax.plot(np.where(sel, xs, np.nan), np.where(sel, ys, np.nan), "o", color=EXIT_COLOR, mfc=fill,
                          ms=4, mew=1.0, zorder=6.2)[0], "located", sampled=sampled, **steps)
        if sel.any():
            handles.append(Line2D([], [], color=EXIT_COLOR, marker="o", mfc=fill, lw=1.4,
                                  label=_wrap(MARKS[name][2], 44)))


def _wrap(text, width):
    return "\n".join(textwrap.wrap(text, width))


def fig_bifurcation_set(m, curves, boundaries=None, exits=None):
    """The regime map ``m`` (brute force, one start per point) with the bifurcation curves of
    :func:`vibroimpact.analysis.bifurcation.curve_set` over it: line style by kind, colour by orbit family,
    thin where the orbit on the curve is not admissible; crosses where a curve meets another set.
    With ``boundaries`` (:func:`vibroimpact.analysis.bifurcation.map_boundaries`), the simulated boundaries on no
    curve are marked by their cause, and the footnote counts them; with ``exits``
    (:func:`vibroimpact.family_exit_curve`), the 1:1 exit is drawn as a curve of the plane.  The 2:1 fold's curve is
    the paper's d_graz (the largest d of 2:1 period-2), named so."""

    fig = fig_regime_map([m])
    fig.set_size_inches(10.5, 6.2)
    ax = fig.axes[0]
    xname, yname = curves.attrs["params"].split()
    handles = []
    for xs, ys, adm, style, colour, label in curve_pieces(curves, xname, yname):
        for line in (ax.plot(xs, ys, style, color="w", lw=2.6, zorder=4)[0],
                     ax.plot(np.where(adm, xs, np.nan), np.where(adm, ys, np.nan), style, color=colour, lw=1.6, zorder=5)[0],
                     ax.plot(np.where(adm, np.nan, xs), np.where(adm, np.nan, ys), style, color=colour, lw=0.6, zorder=5)[0]):
            wellposed(line, "curve")
        if label not in [h.get_label() for h in handles]:
            handles.append(Line2D([], [], ls=style, color=colour, lw=1.6, label=label))
    if exits is not None:
        _exit_curve(ax, exits, xname, handles)
    if curves.sizes["event"]:
        cusp = curves.event_kind.values == "cusp"
        for sel, marker, label in ((~cusp, "x", "a curve meets another set of its orbit"),
                                   (cusp, "^", "cusp: the curve turns back in the plane")):
            if sel.any():
                wellposed(ax.plot(curves[f"event_{xname}"].values[sel], curves[f"event_{yname}"].values[sel], marker,
                                  color="k", ms=5, mew=1.2, mfc="none", zorder=6)[0], "on curve")
                handles.append(Line2D([], [], ls="", marker=marker, color="k", mfc="none", label=label))
    if curves.sizes.get("crossing", 0):
        wellposed(ax.plot(curves[f"crossing_{xname}"].values, curves[f"crossing_{yname}"].values, "o", color="k", ms=6,
                          mfc="none", mew=1.2, zorder=6)[0], "on curve")
        handles.append(Line2D([], [], ls="", marker="o", color="k", mfc="none",
                              label="two curves cross (where 2:1 grazing\nmeets 3:1 fold, [G1, G2] closes)"))
    counts = ""
    if boundaries is not None:
        bx, by = boundaries[xname].values, boundaries[yname].values
        for cause, marker, ms, colour, text in (
                ("aperiodic", ".", 2.5, "0.1", "boundary on no curve:\nbeside no period found"),
                ("jump", "+", 4.0, "#CC0066", "boundary on no curve:\nbetween periodic motions")):
            sel = boundaries.cause.values == cause
            wellposed(ax.plot(bx[sel], by[sel], marker, ls="", color=colour, ms=ms, mew=0.8, zorder=3.5)[0], "boundary")
            handles.append(Line2D([], [], ls="", marker=marker, color=colour, ms=ms + 1, label=text))
        n = {c: int((boundaries.cause.values == c).sum()) for c in ("on a curve", "aperiodic", "jump")}
        counts = (f"simulated boundaries (label changes between neighbouring grid points): {n['on a curve']} within "
                  f"{boundaries.attrs['cells']:g} cells of a curve; on no curve, {n['aperiodic']} beside motion with no "
                  f"period (chaos or a long transient: no curve of periodic orbits bounds it) and {n['jump']} between "
                  "two periodic motions (the one start falls into another basin where motions coexist, or an orbit not "
                  "in the set bifurcates).\n")
    failed = [f"{WORD_NAME.get(str(w), w)} {k}" for w, k, st in
              zip(curves.curve_word.values, curves.curve_kind.values, curves.curve_status.values, strict=True)
              if st != "ok"]
    note = "thin: the orbit on the curve is not admissible (crosses a wall)"
    if curves.attrs.get("coincide"):
        note += "; one set, drawn twice: " + ", ".join(
            " ".join(WORD_NAME.get(w, w) for w in part.split(" from ")[0].split())
            for part in curves.attrs["coincide"].split("; "))
    if failed:
        note += "; not followed (see the dataset's curve_reason): " + ", ".join(failed)

    # wrapped: a footnote wider than the map would make the layout shrink the map to fit it
    foot = "\n".join(textwrap.fill(line, 140) for line in (counts + note).splitlines())
    ax.annotate(foot, (0.0, -0.11), xycoords="axes fraction", fontsize=6, va="top")
    # in the right-hand column under the motions' legend, so the map keeps the figure's width
    fig.legend(handles=handles, loc="outside right lower", fontsize=6, title="analytic curves", title_fontsize=6)
    title = ax.get_title()
    ax.set_title("Analytic bifurcation curves over the brute-force map:\n" + title[0].lower() + title[1:], fontsize=8)
    return fig
