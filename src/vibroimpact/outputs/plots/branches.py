"""Analytic branches: Figures 5 and 6 (:func:`fig2`, :func:`fig3`, named by the paper's LaTeX labels; rows of
:mod:`vibroimpact.outputs.registry`)."""

from __future__ import annotations

import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D

from .. import layout
from ..checks import transition_name
from ..layout import AROUND, place_labels
from ._common import BOTTOM, TOP, beta_label, branch_line, use_style, wellposed, word_ratio


def _scene_mask(br, d_lo, d_hi):
    return (br.admissible & (br.d >= d_lo) & (br.d <= d_hi)).values


def _missing(br, d_lo, d_hi) -> str:
    """Why a row of a branch figure has nothing to draw ("" where it has): a failed branch, or none of its
    admissible points in the row's d range (another device maps the row's s range to other d)."""

    name = f"{word_ratio(str(br.attrs.get('word', '')))} branch"
    if br.attrs.get("status") == "failed" or not br.sizes.get("point", 0):
        return f"not drawn: no {name} ({br.attrs.get('reason', 'no point')})"
    if not _scene_mask(br, d_lo, d_hi).any():
        adm = br.d.values[br.admissible.values]
        span = f"d in [{adm.min():.4g}, {adm.max():.4g}]" if adm.size else "no d"
        return (f"not drawn: the {name} has no admissible point in this row's d range [{d_lo:.4g}, {d_hi:.4g}] "
                f"(its s range for this device); it is admissible for {span}")
    return ""


def _not_drawn(row, labels, br, why):
    """A row of panels with nothing to draw: titled as the others, its axes off, why across the middle one."""

    for ax in row:
        ax.set_title(f"({next(labels)}) {beta_label(br.attrs['beta'])}")
        ax.axis("off")
    mid = row[len(row) // 2]
    mid.text(0.5, 0.5, textwrap.fill(why, 60), transform=mid.transAxes, ha="center", va="center", fontsize=7,
             color="tab:red")


CRITICAL_TEST = {  # quantity that changes sign at each kind of critical point (picks the branch stretch)
    "A": lambda br: br.discriminant.values,
    "B": lambda br: br.eig_real.values.min(axis=1) + 1.0,
    "fold": lambda br: br.eig_real.values.max(axis=1) - 1.0,
    "grazing": lambda br: br.clearance.values,
}


def critical_markers(br, d_lo, d_hi, admissible_only=True):
    """Admissible critical points of a branch inside [d_lo, d_hi] as (name, d, k, t): the point lies
    between branch points k and k + 1 at fraction t.  Names as in the paper: A1, A2, ... (node <->
    focus, by increasing d), B (period doubling), F (fold), G (grazing)."""

    d = br.d.values
    out = []
    if "critical_d" not in br:
        return out
    for kind, c, adm in zip(br.critical_kind.values.astype(str), br.critical_d.values, br.critical_admissible.values,
                            strict=True):
        if not ((adm or not admissible_only) and d_lo <= c <= d_hi):
            continue
        seg = np.flatnonzero((d[:-1] - c) * (d[1:] - c) <= 0)
        if not seg.size:  # a fold lies just beyond the branch points: mark the turning point
            k = int(np.argmin(np.abs(d - c)))
            out.append([kind, float(c), min(k, len(d) - 2), 0.0 if k < len(d) - 1 else 1.0])
            continue
        q = CRITICAL_TEST.get(kind, lambda b: np.full(len(d), np.nan))(br)
        change = [k for k in seg if np.isfinite(q[k]) and np.isfinite(q[k + 1]) and q[k] * q[k + 1] <= 0]
        k = int(change[0] if change else seg[0])
        t = 0.0 if d[k + 1] == d[k] else float((c - d[k]) / (d[k + 1] - d[k]))
        out.append([kind, float(c), k, t])
    a_count = 0
    for m in sorted(out, key=lambda m: m[1]):
        if m[0] == "A":
            a_count += 1
            m[0] = f"A{a_count}"
        else:
            m[0] = {"fold": "F", "grazing": "G"}.get(m[0], m[0])
    return [tuple(m) for m in out]


#: the names of the critical points, as the figures define them (paper Table 1 and Figure 5's caption)
CRITICAL_NAMES = {"A": r"A1, A2, ...: node $\leftrightarrow$ focus ($\Delta=0$)", "B": r"B: period doubling ($\lambda=-1$)",
                  "F": "F: fold", "G": "G: grazing (a flight touches a wall)"}


def _branch_legend(fig, grazing=None):
    """One legend for all panels, below them: every line, marker and name the panels use."""

    blank = dict(color="none", ls="", marker="")
    handles = [Line2D([], [], color=BOTTOM, label="bottom impacts"), Line2D([], [], color=TOP, label="top impacts"),
               Line2D([], [], color="0.3", ls="-", label="stable"), Line2D([], [], color="0.3", ls="--", label="unstable"),
               Line2D([], [], color="k", marker="o", mfc="none", ls="", ms=4, label="simulated attractor"),
               Line2D([], [], color="k", marker="D", ls="", ms=4, label="critical point:")]
    handles += [Line2D([], [], **blank, label=name) for name in CRITICAL_NAMES.values()]
    handles.append(Line2D([], [], **blank, label="P1, P2, P3: transitions (bottom to bottom, to top, top to bottom)"))
    if grazing is not None:
        handles += [Line2D([], [], color="k", ls="-.", lw=0.8, label="G1: the 2:1 orbit grazes (2:1 to 3:1 as d decreases)"),
                    Line2D([], [], color="tab:red", ls="-.", lw=0.8, label="G2: the 3:1 branch folds (3:1 to 2:1 as d increases)")]
    leg = fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=7)
    layout.style_keys(leg, "stable", "unstable")  # solid and dashed, in the walls' colours


def fig2(branches, sims, d_ranges, grazing=None):
    """2:1 branches: Zdot_k, Delta t_j / 2, phi_k vs d for each incline (rows).  Every name is set where it
    overprints nothing (:func:`vibroimpact.outputs.layout.place_labels`); a critical point on a grazing line
    is named by the line."""

    use_style()
    n = len(branches)
    fig, axes = plt.subplots(n, 3, figsize=(10, 2.3 * n + 1.0), squeeze=False, sharex="row")
    labels = iter("abcdefghijklmnopqrstuvwxyz")
    names = []  # (ax, text, candidates, style), placed once the layout is fixed
    for row, br, sim, (lo, hi) in zip(axes, branches, sims, d_ranges, strict=True):
        if why := _missing(br, lo, hi):
            _not_drawn(row, labels, br, why)
            continue
        m = _scene_mask(br, lo, hi)
        d = br.d.values[m]
        st = br.stable.values[m]
        walls = br.wall.values
        lines = {}
        if grazing is not None and abs(br.attrs["beta"] - grazing["beta"]) < 1e-9:
            lines = {k: (g, c) for k, g, c in (("G1", grazing["G1"], "k"), ("G2", grazing["G2"], "tab:red"))
                     if np.isfinite(g)}  # another device may have neither
        for col, (var, scale, ylabel) in enumerate(
            [("v_minus", 1.0, r"$\dot Z_k$"), ("dt", 0.5, r"$\Delta t_j/2$"), ("phase", 1.0, r"$\varphi_k$")]
        ):
            ax = row[col]
            for j in range(br.sizes["impact"]):
                color = BOTTOM if walls[j] == 1 else TOP
                y = br[var].values[m, j] * scale
                if var == "v_minus":
                    y = np.abs(y)
                if var == "phase":  # do not draw the jump where the phase wraps at 2 pi
                    y = np.where(np.abs(np.diff(y, prepend=y[0])) > np.pi, np.nan, y)
                branch_line(ax, d, y, st, color)
                # the transition this curve belongs to (paper's P1, P2, P3), on its stable sheet, a quarter of
                # the way along or wherever else along it the name overprints nothing
                ok = np.flatnonzero(np.isfinite(y) & st)
                ok = ok if ok.size else np.flatnonzero(np.isfinite(y))
                if ok.size:
                    spots = [ok[np.argmin(np.abs(d[ok] - d[ok].min() - f * np.ptp(d[ok])))]
                             for f in (0.25, 0.5, 0.1, 0.75, 0.4, 0.6, 0.9, 0.33, 0.66)]
                    names.append((ax, transition_name(walls, j, into=var != "phase"),
                                  [((d[k], y[k]), off) for k in spots for off in ((0, 4), (0, -4))],
                                  dict(fontsize=6, color=color, fontweight="bold")))
                if sim is not None and "v_minus" in sim and sim.sizes.get("sim", 0):
                    ys = sim[var].values[:, j] * scale
                    ax.plot(sim.d, np.abs(ys) if var == "v_minus" else ys, "o", mfc="none", color="k", ms=4)
                # critical points on every impact's curve, named once per panel (at the bottom impact)
                yall = br[var].values[:, j] * scale
                yall = np.abs(yall) if var == "v_minus" else yall
                for name, dc, k, t in critical_markers(br, lo, hi):
                    if var == "phase" and abs(yall[k + 1] - yall[k]) > np.pi:
                        continue  # the phase wraps between these points
                    yc = yall[k] + t * (yall[k + 1] - yall[k])
                    ax.plot([dc], [yc], "D", color="k", ms=3.5, zorder=5)
                    on_line = any(abs(dc - g) <= 1e-9 for g, _ in lines.values())
                    if j == 0 and not on_line:  # a grazing line names its point itself
                        names.append((ax, name, [((dc, yc), off) for off in AROUND], dict(fontsize=7)))
            for key, (g, color) in lines.items():
                ax.axvline(g, color=color, ls="-.", lw=0.8)
                names.insert(0, (ax, key, [((g, y0), (dx, dy)) for y0, dy in ((0.0, 3), (1.0, -3), (0.5, 3), (0.25, 3),
                                                                              (0.75, 3)) for dx in (2, -2)],
                                 dict(xycoords=("data", "axes fraction"), fontsize=7, color=color)))
            ax.set_ylabel(ylabel + (" (magnitude)" if var == "v_minus" else ""))
            ax.set_xlabel("d")
            ax.set_title(f"({next(labels)}) {beta_label(br.attrs['beta'])}")
            ax.set_xlim(lo, hi)
    _branch_legend(fig, grazing)
    place_labels(fig, names)
    return fig


def fig3(branches, d_ranges):
    """Delta = Tr^2 - 4 Det (left) and eigenvalues (right) along the 2:1 branches, in the caption's colours:
    real eigenvalues blue and green (thin), the real part of a complex pair green (thick).  Stable stretches
    solid, unstable dashed, stretches that cross a wall (not admissible) grey; A (node <-> focus,
    Delta = 0) and B (lambda = -1) marked and named, the legend below the panels."""


    use_style()
    n = len(branches)
    fig, axes = plt.subplots(n, 2, figsize=(8, 2.3 * n + 0.7), squeeze=False)
    labels = iter("abcdefghijklmnop")
    names = []
    for row, br, (lo, hi) in zip(axes, branches, d_ranges, strict=True):
        if why := _missing(br, lo, hi):
            _not_drawn(row, labels, br, why)
            continue
        d = br.d.values
        inside = (d >= lo) & (d <= hi)
        adm, st = br.admissible.values & inside, br.stable.values
        disc = br.discriminant.values
        real = disc >= 0

        def draw(ax, y, color, lw=1.0, d=d, adm=adm, st=st, inside=inside):
            # NaN outside each stretch, so no line joins separate stretches; sampled by continuation (a small
            # eigenvalue is known to rounding of the largest, not of itself: compared as a curve)
            for sel, style, c in ((adm & st, "-", color), (adm & ~st, "--", color), (inside & ~adm, "-", "0.75")):
                wellposed(ax.plot(d, np.where(sel, y, np.nan), style, color=c, lw=lw)[0], "curve")

        draw(row[0], disc, "tab:blue")
        row[0].axhline(0, color="tab:red", ls="-.", lw=0.8)
        row[0].set_ylabel(r"$\Delta=\mathrm{Tr}^2-4\,\mathrm{Det}$")
        for e, col in ((0, "tab:blue"), (1, "tab:green")):
            draw(row[1], np.where(real, br.eig_real.values[:, e], np.nan), col, lw=0.8)
        draw(row[1], np.where(~real, br.eig_real.values[:, 0], np.nan), "tab:green", lw=2.2)
        row[1].axhline(-1, color="tab:red", ls="-.", lw=0.8)
        row[1].set_ylabel(r"$\lambda_{1,2}$")
        # scale to the physical stretch: beyond the fold the unstable branch diverges where an impact
        # velocity tends to zero
        phys = adm & st
        if phys.any():
            span = np.ptp(disc[phys]) or 1.0
            row[0].set_ylim(disc[phys].min() - 0.3 * span, disc[phys].max() + 0.3 * span)
        row[1].set_ylim(-2.5, 1.5)
        for ax in row:
            ax.set_xlabel("d")
            ax.set_xlim(lo, hi)
            ax.set_title(f"({next(labels)}) {beta_label(br.attrs['beta'])}")
        for name, dc, _k, _t in critical_markers(br, lo, hi, admissible_only=False):
            if name.startswith("A"):
                row[0].plot([dc], [0.0], "s", mfc="none", color="tab:red", ms=6)
                names.append((row[0], name, [((dc, 0.0), off) for off in AROUND], dict(fontsize=7)))
            elif name == "B":
                row[1].plot([dc], [-1.0], "o", mfc="none", color="tab:red", ms=7)
                names.append((row[1], "B", [((dc, -1.0), off) for off in AROUND[1::2] + AROUND[::2]], dict(fontsize=7)))
    handles = [Line2D([], [], color="tab:blue", lw=0.8, label=r"real $\lambda_1$; $\Delta$"),
               Line2D([], [], color="tab:green", lw=0.8, label=r"real $\lambda_2$"),
               Line2D([], [], color="tab:green", lw=2.2, label=r"Re $\lambda_{1,2}$ (complex pair)"),
               Line2D([], [], color="0.3", ls="-", label="stable"), Line2D([], [], color="0.3", ls="--", label="unstable"),
               Line2D([], [], color="0.75", label="not admissible (crosses a wall)"),
               Line2D([], [], color="tab:red", ls="-.", lw=0.8, label=r"$\Delta=0$, $\lambda=-1$: stability boundaries"),
               Line2D([], [], color="tab:red", marker="s", mfc="none", ls="", label=r"A: $\Delta=0$ (node $\leftrightarrow$ focus)"),
               Line2D([], [], color="tab:red", marker="o", mfc="none", ls="", label=r"B: $\lambda=-1$ (period doubling)")]
    leg = fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=7)
    layout.style_keys(leg, "stable", "unstable")  # solid and dashed, in the eigenvalues' colours
    place_labels(fig, names)
    return fig
