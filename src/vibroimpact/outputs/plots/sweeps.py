"""Sweeps, bistability (paper Fig BiS), basins and regime maps."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ...analysis.sweeps import NO_PERIOD_LABELS, no_period
from ._common import BOTTOM, TOP, branch_line, motion_color, use_style, wellposed

#: the statistic of a motion with no period that each drawn quantity is compared by (the long run's)
_LONG_STAT = {"v_minus": ("abs_v_mean", "abs_v_se"), "gain": ("U_I_long", "U_I_long_se"),
              "U_T": ("U_T_long", "U_T_long_se"), "U_I": ("U_I_long", "U_I_long_se")}
_CYCLE = {"v_minus": "cycle_v_minus", "phase": "cycle_phase", "gain": "cycle_gain", "dt": "cycle_t"}


def point_info(s, idx, var):
    """Per element drawn from points ``idx`` of one sweep direction ``s``: the motion, whether the value is
    exact (``settled``), whether the motion is a transient longer than the cap (``unsettled``: no period
    found, but its long run settles), and the long-run ``mean`` and ``se`` of ``var`` where no period was
    found (NaN elsewhere).  What the figure check compares where the values are not well-posed."""
    idx = np.asarray(idx, dtype=int)
    lab = s["label"].values.astype(str)[idx]
    settled = s["settled"].values[idx] if "settled" in s else np.zeros(idx.size, bool)
    long = s["long_status"].values.astype(str)[idx] if "long_status" in s else np.full(idx.size, "")
    unsettled = no_period(lab) & (long != "aperiodic")
    m, e = _LONG_STAT.get(var, (None, None))
    mean = s[m].values[idx] if m in s else np.full(idx.size, np.nan)
    se = s[e].values[idx] if e in s else np.full(idx.size, np.nan)
    return dict(motion=lab, settled=np.asarray(settled, bool), unsettled=unsettled, mean=mean, se=se)


def _last_events(ds, var, direction="down", labels=False, info=False):
    """(d, values) of every point's last period of events in one sweep direction: its exact cycle from
    the canonical first impact where the sweep settled it (:func:`vibroimpact.analysis.sweeps.settle`), else the
    recorded last period (the last 24 events where no period was found); ``var="dt"`` gives the time
    since the previous event.  With ``labels``, also each value's point's identified motion; with
    ``info``, a dict per element (:func:`point_info`) instead."""

    s = ds.sel(direction=direction)
    cyc = _CYCLE.get(var)
    have = cyc is not None and cyc in s
    xs, ys, pts = [], [], []
    for i in range(s.sizes["point"]):
        c = s[cyc].values[i] if have else None
        if have and np.isfinite(c).any() and (var != "dt" or "period" in s):
            if var == "dt":
                tt = c[np.isfinite(c)]
                v = np.diff(np.concatenate([[tt[-1] - 2.0 * float(s["period"].values[i])], tt]))
            else:
                v = c[np.isfinite(c)]
        else:
            t = s["t"].values[i] if "t" in s else s[var].values[i]
            m = int(np.isfinite(t).sum())
            n = (int(s["period_events"].values[i]) if "period_events" in s else 0) or min(m, 24)
            v = np.diff(t[max(m - n - 1, 0):m]) if var == "dt" else s[var].values[i, m - n:m]
            v = v[np.isfinite(v)]
        xs.append(np.full(v.size, float(s.d[i])))
        ys.append(v)
        pts.append(np.full(v.size, i))
    x, y, pts = np.concatenate(xs), np.concatenate(ys), np.concatenate(pts)
    if info:
        return x, y, point_info(s, pts, var)
    if labels:
        return x, y, s["label"].values.astype(str)[pts]
    return x, y


def fig_bis(sw, transitions, portraits, branches):
    """Bistable 2:1 and 3:1 near grazing (paper Fig BiS): the last period of every sweep point,
    coloured by the motion identified there (2:1 black, 3:1 blue, other grey) and marked by the sweep
    direction (o: d decreasing, +: d increasing), over the analytic branches (2:1 grey, 3:1 blue;
    stable solid, unstable dashed), with G1 and G2; below, the closed orbits at G1, d_mid (both) and
    G2 over one period."""
    from matplotlib.lines import Line2D

    use_style()
    fig = plt.figure(figsize=(11, 6.3))
    gs = fig.add_gridspec(2, 4)
    g1, g2 = portraits.attrs["G1"], portraits.attrs["G2"]
    lo, hi = float(sw.d.min()), float(sw.d.max())
    motion_color = {"2:1 period-2": "k", "3:1 period-2": "tab:blue"}
    for col, (var, ylabel) in enumerate([("v_minus", r"$|\dot Z_k|$"), ("phase", r"$\varphi_k$ (rad)"),
                                         ("dt", r"$\Delta t_k$")]):
        ax = fig.add_subplot(gs[0, col])
        for br, color in zip(branches, ("0.6", "tab:blue"), strict=True):
            m = (br.admissible & (br.d >= lo) & (br.d <= hi)).values
            for j in range(br.sizes["impact"]):
                y = br[var].values[m, j]
                y = np.abs(y) if var == "v_minus" else y
                branch_line(ax, br.d.values[m], y, br.stable.values[m], color, lw=0.8)
        for direction, marker in (("down", "o"), ("up", "+")):
            x, y, info = _last_events(sw, var, direction, info=True)
            y = np.abs(y) if var == "v_minus" else y
            lab = info["motion"]
            for motion in sorted(set(lab)):
                sel = lab == motion
                line = ax.plot(x[sel], y[sel], marker, mfc="none", color=motion_color.get(motion, "0.7"), ms=3.5,
                               ls="none")[0]
                wellposed(line, "motions", **{k: v[sel] for k, v in info.items()})
        for g, c, name, dx in ((g1, "k", "G1", -13), (g2, "tab:red", "G2", 2)):
            ax.axvline(g, color=c, ls="-.", lw=0.8)
            ax.annotate(name, (g, 1.0), xycoords=("data", "axes fraction"), xytext=(dx, -10), textcoords="offset points",
                        fontsize=7, color=c)
        ax.set_xlabel("d")
        ax.set_ylabel(ylabel)
        ax.set_title(f"({'abc'[col]})")
    key = fig.add_subplot(gs[0, 3])  # the legend gets the free slot, clear of the data
    key.axis("off")
    key.legend(handles=[
        Line2D([], [], color="k", marker="s", ls="", label="2:1 period-2"),
        Line2D([], [], color="tab:blue", marker="s", ls="", label="3:1 period-2"),
        Line2D([], [], color="0.7", marker="s", ls="", label="other motion"),
        Line2D([], [], color="k", marker="o", mfc="none", ls="", label="d decreasing"),
        Line2D([], [], color="k", marker="+", ls="", label="d increasing"),
        Line2D([], [], color="0.6", label="analytic 2:1 (dashed: unstable)"),
        Line2D([], [], color="tab:blue", label="analytic 3:1"),
        Line2D([], [], color="k", ls="-.", label="G1: 2:1 grazes"),
        Line2D([], [], color="tab:red", ls="-.", label="G2: 3:1 fold")], loc="center", fontsize=8)
    for k in range(portraits.sizes["panel"]):
        ax = fig.add_subplot(gs[1, k])
        p = portraits.isel(panel=k)
        d = float(p.d)
        ax.plot(p.Z, p.Zdot, color="k", lw=0.8)
        ax.axvline(d / 2, color=BOTTOM, ls="--", lw=0.8, label="bottom wall")
        ax.axvline(-d / 2, color=TOP, ls="--", lw=0.8, label="top wall")
        head = f"({'defg'[k]}) {str(p.panel.values)}: {str(p.word.values)}, d={d:.6f}"
        if "v0" in p:
            head += "\n" + r"$\dot Z(t_0)$" + f"={float(p.v0):.4f}, " + r"$\varphi$" + f"={float(p.phi):.4f}"
        ax.set_title(head)
        ax.set_xlabel("Z")
        ax.set_ylabel(r"$\dot Z$")
        if k == 0:
            ax.legend(loc="lower center", fontsize=6)
    return fig


#: what the motion labels mean, printed with every legend of motions
MOTION_KEY = ("n:m = bottom:top impacts per period;\nperiod-k = period k in t (2 = one forcing period);\n"
              "no period within the cap, by the largest Lyapunov\nexponent of its long run: chaotic (interval above 0),\n"
              "quasi-periodic (contains 0), unsettled (below 0,\nor a longer transient); no period found: not split")
#: added to :data:`MOTION_KEY` where a motion with sticking is named
STICKING_KEY = ("with sticking: chatters to rest on a wall, sticks until\nthe forcing releases it, its chatter counted as one\n"
                "impact (1:0: the stick-release cycle on the bottom)")


def motion_key(names) -> str:
    """:data:`MOTION_KEY`, with :data:`STICKING_KEY` where one of ``names`` is a motion with sticking."""
    sticking = any("with sticking" in str(n) for n in names)
    return (MOTION_KEY + (";\n" + STICKING_KEY if sticking else "")).replace("; ", ";\n")


def _class_colors(names):
    """A colour per motion name: its colour in every figure (:func:`~vibroimpact.outputs.plots._common.motion_color`)."""
    return [motion_color(n) for n in names]


def _shown_classes(legend, n_show=9):
    """Which of the motions ``legend`` lists (most frequent first) a map names: every label of a motion with
    no period (chaotic, quasi-periodic, unsettled, no period found: never folded into "other") and the
    ``n_show`` most frequent periodic ones whose colour no more frequent named motion has (two motions
    without a colour of their own can share one, :func:`~vibroimpact.outputs.plots._common.motion_color`), in
    the legend's order; the rest "other".  Returns the names and, per legend entry, its index among them."""
    special = [i for i, n in enumerate(legend) if n in NO_PERIOD_LABELS]
    taken = {motion_color(legend[i]) for i in special}
    periodic = []
    for i, n in enumerate(legend):
        if n in NO_PERIOD_LABELS or len(periodic) == n_show or motion_color(n) in taken:
            continue
        taken.add(motion_color(n))
        periodic.append(i)
    shown = sorted(special + periodic)
    names = [legend[i] for i in shown] + (["other"] if len(shown) < len(legend) else [])
    lut = np.full(len(legend), len(shown), dtype=int)
    lut[shown] = np.arange(len(shown))
    return names, lut


def _class_image(ax, da, x, y, legend, n_show=9, *, key=True):
    """Draw integer attractor codes (indices into ``legend``) with a discrete colormap, named as
    :func:`_shown_classes` says.  Returns the legend handles (drawn beside the axes with ``key``)."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    names, lut = _shown_classes(list(legend), n_show)
    codes = lut[np.asarray(da.values, dtype=int)]
    colors = _class_colors(names)
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
    """Basins of attraction (:func:`vibroimpact.analysis.sweeps.basins`): the motion reached from each first
    bottom impact, in the motions' colours of every figure; the title gives the incline and the device
    (length, force, mass, frequency) where the dataset records them, and d, gbar."""
    import json

    from ._common import beta_label, pi_label

    use_style()
    fig, ax = plt.subplots(figsize=(7.4, 4.2))
    _class_image(ax, b.attractor.T, b.phi.values, b.v0.values, json.loads(b.attrs["legend"]))
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


def _pi_ticks(ax, lo, hi):
    """Ticks of an angle axis at the fractions of pi inside [lo, hi]."""
    import math

    from ._common import pi_label

    ticks = [f * math.pi for f in (1 / 12, 1 / 6, 1 / 4, 1 / 3, 5 / 12, 1 / 2) if lo <= f * math.pi <= hi]
    ax.set_yticks(ticks, [pi_label(t) for t in ticks])


def fig_regime_map(maps, scans=None):
    """Regime maps side by side, one colour per motion across all panels, one legend (with what the
    labels mean); the paper's sweeps that lie in a map's plane drawn over it as lines (``scans``: the
    sweep scenes of the config)."""
    from ._common import pi_label

    use_style()
    labels, counts = np.unique(np.concatenate([m.label.values.ravel() for m in maps]), return_counts=True)
    legend = list(labels[np.argsort(-counts, kind="stable")])
    index = {lab: i for i, lab in enumerate(legend)}
    fig, axes = plt.subplots(1, len(maps), figsize=(5.6 * len(maps), 4.6), squeeze=False)
    names = {"beta": r"incline $\beta$", "s": "cylinder length s", "F": r"forcing amplitude $\|\hat F\|$",
             "d": "non-dimensional gap d", "gbar": r"non-dimensional gravity $\bar g$", "r": "restitution r"}
    for ax, m in zip(axes[0], maps, strict=True):
        ydim, xdim = m.label.dims
        codes = m.label.copy(data=np.vectorize(index.__getitem__)(m.label.values))
        handles = _class_image(ax, codes, m[xdim].values, m[ydim].values, legend, key=False)
        ax.set_xlabel(f"{names.get(xdim, xdim)} ({m[xdim].attrs.get('units', '')})")
        ax.set_ylabel(f"{names.get(ydim, ydim)} ({m[ydim].attrs.get('units', '')})")
        if ydim == "beta":
            _pi_ticks(ax, float(m.beta.min()), float(m.beta.max()))
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
    from matplotlib.lines import Line2D

    if scans:
        handles = [*handles, Line2D([], [], color="k", lw=1.6, label="the paper's sweeps (config names)")]
    fig.legend(handles=handles, loc="outside right upper", fontsize=6, title=motion_key(h.get_label() for h in handles),
               title_fontsize=6)
    return fig


#: line style per kind of codimension-one point, and colour per orbit family
_CURVE_STYLE = {"B": "--", "fold": ":", "grazing": "-", "A": "-."}
_CURVE_NAME = {"B": "period doubling B", "fold": "fold", "grazing": "grazing", "A": "node-focus A"}
_WORD_COLOUR = {"BT": "#000000", "BBT": "#D55E00", "BBBT": "#0072B2"}
_WORD_NAME = {"BT": "1:1", "BBT": "2:1", "BBBT": "3:1"}


def curve_pieces(curves, xname, yname):
    """Each curve of a bifurcation set (:func:`vibroimpact.analysis.bifurcation.curve_set`) as drawn: its points in
    the plane ``(xname, yname)``, where its orbit is admissible, and its line style (by kind), colour (by
    orbit family) and legend label."""
    for c in range(curves.sizes["curve"]):
        sel = curves.curve_index.values == c
        if not sel.any():
            continue
        kind, word = str(curves.curve_kind.values[c]), str(curves.curve_word.values[c])
        yield (curves[xname].values[sel], curves[yname].values[sel], curves.admissible.values[sel],
               _CURVE_STYLE.get(kind, "-"), _WORD_COLOUR.get(word, "0.3"),
               f"{_WORD_NAME.get(word, word)} {_CURVE_NAME.get(kind, kind)}")


def fig_bifurcation_set(m, curves, boundaries=None):
    """The regime map ``m`` (brute force, one start per point) with the bifurcation curves of
    :func:`vibroimpact.analysis.bifurcation.curve_set` over it: line style by kind, colour by orbit family,
    thin where the orbit on the curve is not admissible; crosses where a curve meets another set.
    With ``boundaries`` (:func:`vibroimpact.analysis.bifurcation.map_boundaries`), the simulated boundaries on no
    curve are marked by their cause, and the footnote counts them."""
    from matplotlib.lines import Line2D

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
    failed = [f"{_WORD_NAME.get(str(w), w)} {k}" for w, k, st in
              zip(curves.curve_word.values, curves.curve_kind.values, curves.curve_status.values, strict=True)
              if st != "ok"]
    note = "thin: the orbit on the curve is not admissible (crosses a wall)"
    if curves.attrs.get("coincide"):
        note += "; one set, drawn twice: " + ", ".join(
            " ".join(_WORD_NAME.get(w, w) for w in part.split(" from ")[0].split())
            for part in curves.attrs["coincide"].split("; "))
    if failed:
        note += "; not followed (see the dataset's curve_reason): " + ", ".join(failed)
    import textwrap

    # wrapped: a footnote wider than the map would make the layout shrink the map to fit it
    foot = "\n".join(textwrap.fill(line, 140) for line in (counts + note).splitlines())
    ax.annotate(foot, (0.0, -0.11), xycoords="axes fraction", fontsize=6, va="top")
    # in the right-hand column under the motions' legend, so the map keeps the figure's width
    fig.legend(handles=handles, loc="outside right lower", fontsize=6, title="analytic curves", title_fontsize=6)
    title = ax.get_title()
    ax.set_title("Analytic bifurcation curves over the brute-force map:\n" + title[0].lower() + title[1:], fontsize=8)
    return fig
