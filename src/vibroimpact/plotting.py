"""Figures drawn from saved datasets. One style for all (Agg backend, shared conventions):
analytic branches solid where stable and dashed where unstable, simulation as open markers,
bottom wall blue and top wall green as in the paper."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

BOTTOM = "tab:blue"
TOP = "tab:green"
BALL = "tab:red"

STYLE = {
    "figure.dpi": 110,
    "savefig.dpi": 150,
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 7,
    "lines.linewidth": 1.0,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "figure.constrained_layout.use": True,
}


def use_style() -> None:
    plt.rcParams.update(STYLE)


def save(fig, stem, *, data=None, attrs=None) -> list[Path]:
    """Save ``stem.pdf`` and ``stem.png`` and, with ``data``, the arrays the figure draws (netCDF,
    :func:`vibroimpact.figdata.figure_data`, with ``attrs`` such as the config); returns the paths."""
    from .datasets import write_netcdf
    from .figdata import figure_data

    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".pdf"), stem.with_suffix(".png")]
    for p in paths:
        fig.savefig(p)
    if data is not None:
        write_netcdf(figure_data(fig, attrs), data, fmt="NETCDF3_64BIT")
        paths.append(Path(data))
    plt.close(fig)
    return paths


#: an orbit whose interior loop comes within this fraction of d of a wall is titled "near grazing"
NEAR_GRAZING = 0.01


def _pi_tex(x, fmt=".4g"):
    """``x`` in TeX as a fraction of pi when it is one (``\\pi/6``, ``5\\pi``), else formatted with ``fmt``."""
    import math

    for den in (1, 2, 3, 4, 6):
        num = x * den / math.pi
        if abs(num - round(num)) < 1e-9 and round(num):
            n = int(round(num))
            top = r"\pi" if n == 1 else f"{n}\\pi"
            return top if den == 1 else f"{top}/{den}"
    return format(x, fmt)


def _pi_label(x, unit=""):
    tex = _pi_tex(x)
    return (f"${tex}$" if "\\pi" in tex else tex) + unit


def _title(ds, panel):
    a = ds.attrs
    head = f"({panel}) {a['motion']}, d={a['d']:.4g}"
    clearance = a.get("orbit_clearance")
    if clearance is not None and np.isfinite(clearance):
        near = " near grazing" if clearance < NEAR_GRAZING * a["d"] else ""
        head += f",{near} clearance {clearance:.1e}"
    line2 = r"$\dot Z(t_0)$" f"={a['v0']:.4g}, " r"$\varphi$" f"={a['phi']:.4g}"
    if "beta" in a:
        line2 = (r"$\beta$=" + _pi_label(float(a["beta"])) + (rf", $\|\hat F\|$={a['F']:g} N" if "F" in a else "")
                 + (r", $\omega$=" + _pi_label(float(a["omega"]), " rad/s") if "omega" in a else "") + "\n" + line2)
    return head + "\n" + line2


def time_series(ax, ds):
    """Cylinder ends X*(t) +- d/2 and ball x*(t) (paper Fig 0b)."""
    d = ds.attrs["d"]
    t = ds["time"].values
    ax.plot(t, ds["X"] + d / 2, color=BOTTOM, label=r"$X^*\pm d/2$")
    ax.plot(t, ds["X"] - d / 2, color=BOTTOM)
    ax.plot(t, ds["x"], color=BALL, label=r"$x^*$ (ball)")
    if "wall" in ds and "impact" in ds.dims:
        # the impacts in the window, at the wall they hit: count the bottom impacts per period
        tk = ds["t"].values
        hit = np.isfinite(tk) & (tk <= t[-1]) & np.isin(ds["kind"].values, (0, 1))
        # the bottom wall (Z = d/2) is the end at X - d/2 in the absolute frame: x* = X - Z
        xk = np.interp(tk[hit], t, ds["X"].values) - ds["wall"].values[hit] * d / 2
        for w, col, mk, name in ((1, BOTTOM, "v", "bottom impact"), (-1, TOP, "^", "top impact")):
            sel = ds["wall"].values[hit] == w
            ax.plot(tk[hit][sel], xk[sel], mk, color=col, ms=5, ls="none", label=name)
    ax.set_xlabel("t")
    ax.set_ylabel("displacement")


def phase_portrait(ax, ds):
    """Zdot against Z, walls dashed, impacts marked (paper Figs 4, FN2, BiS)."""
    d = ds.attrs["d"]
    ax.plot(ds["Z"], ds["Zdot"], color="k", lw=0.7)
    for w, col, name in ((1, BOTTOM, "bottom wall"), (-1, TOP, "top wall")):
        ax.axvline(w * d / 2, color=col, ls="--", lw=0.8, label=name)
    if "cycle_v_minus" in ds:
        w = ds["cycle_wall"].values
        ax.plot(w * d / 2, ds["cycle_v_minus"], "o", mfc="none", color="tab:orange", ms=5, label="attractor impacts")
    ax.set_xlabel("Z")
    ax.set_ylabel(r"$\dot Z$")
    ax.xaxis.set_major_locator(plt.MaxNLocator(5))


def fig0b(datasets):
    """Time series of 1:1, 2:1 and 3:1 motions."""
    use_style()
    fig, axes = plt.subplots(1, len(datasets), figsize=(3.8 * len(datasets), 3.4), squeeze=False)
    for ax, ds, panel in zip(axes[0], datasets, "abcdefg", strict=False):
        time_series(ax, ds)
        ax.set_title(_title(ds, panel))
    # one legend for all panels, below them, clear of the data
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside lower center", ncol=4)
    return fig


def figFN2(datasets):
    """Phase portraits along 1:1 -> period doubling -> grazing -> 2:1 (paper Fig FN2): the part of
    each run after its first forcing period, so that the attractor is drawn."""
    use_style()
    n = len(datasets)
    ncol = 4
    nrow = (n + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.2 * ncol, 2.9 * nrow), squeeze=False)
    for ax, ds, panel in zip(axes.ravel(), datasets, "abcdefghij", strict=False):
        keep = ds.time.values >= 2.0
        sub = ds.isel(time=keep)
        phase_portrait(ax, sub)
        ax.set_title(_title(ds, panel) + ("\n" + r"$\bar g$" + f"={ds.attrs['gbar']:.4f}"), fontsize=7)
    axes[0, 0].legend(loc="center", fontsize=6, framealpha=0.85)
    for ax in axes.ravel()[n:]:
        ax.remove()
    return fig


def fig4(datasets):
    """Phase portrait, Z(t) and the time series for each orbit: one row each."""
    use_style()
    n = len(datasets)
    fig, axes = plt.subplots(n, 3, figsize=(10, 2.6 * n), squeeze=False)
    letters = iter("abcdefghijkl")
    for row, ds in zip(axes, datasets, strict=True):
        a, b, c = next(letters), next(letters), next(letters)
        phase_portrait(row[0], ds)
        row[0].set_title(_title(ds, a))
        d = ds.attrs["d"]
        row[1].plot(ds["time"], ds["Z"], color="k")
        row[1].axhline(d / 2, color=BOTTOM, ls="--", lw=0.8)
        row[1].axhline(-d / 2, color=TOP, ls="--", lw=0.8)
        row[1].set_xlabel("t")
        row[1].set_ylabel("Z")
        row[1].set_title(f"({b}) relative position")
        time_series(row[2], ds)
        row[2].set_title(f"({c}) cylinder ends and ball")
    axes[0, 0].legend(loc="center", fontsize=6, framealpha=0.85)
    axes[0, 2].legend(loc="lower right", fontsize=6, framealpha=0.85)
    return fig


# ---------------------------------------------------------------------------------------------
# Branches (paper Figs 2, 3)
# ---------------------------------------------------------------------------------------------

def _beta_label(beta):
    return "$\\beta=" + _pi_tex(beta, ".4f") + "$"


def branch_line(ax, d, y, stable, color, lw=1.2):
    """Solid where stable, dashed where unstable (admissible points only are passed in)."""
    import numpy as np

    ys = np.where(stable, y, np.nan)
    yu = np.where(~stable, y, np.nan)
    # overlap one point so that the two styles join
    edge = np.flatnonzero(np.diff(stable.astype(int)) != 0)
    for e in edge:
        yu[e:e + 2] = y[e:e + 2]
    ax.plot(d, ys, "-", color=color, lw=lw)
    ax.plot(d, yu, "--", color=color, lw=lw * 0.8)


def _scene_mask(br, d_lo, d_hi):
    return (br.admissible & (br.d >= d_lo) & (br.d <= d_hi)).values


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
    import numpy as np

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


def _branch_legend(ax, with_sim=True, with_critical=True):
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=BOTTOM, label="bottom impacts"), Line2D([], [], color=TOP, label="top impacts"),
               Line2D([], [], color="0.3", ls="-", label="stable"), Line2D([], [], color="0.3", ls="--", label="unstable")]
    if with_sim:
        handles.append(Line2D([], [], color="k", marker="o", mfc="none", ls="", ms=4, label="simulated attractor"))
    if with_critical:
        handles.append(Line2D([], [], color="k", marker="D", ls="", ms=4, label="critical point"))
    ax.legend(handles=handles, loc="best", fontsize=6, framealpha=0.8)


def fig2(branches, sims, d_ranges, grazing=None):
    """2:1 branches: Zdot_k, Delta t_j / 2, phi_k vs d for each incline (rows)."""
    import numpy as np

    use_style()
    n = len(branches)
    fig, axes = plt.subplots(n, 3, figsize=(10, 2.3 * n), squeeze=False, sharex="row")
    labels = iter("abcdefghijklmnopqrstuvwxyz")
    for r_i, (row, br, sim, (lo, hi)) in enumerate(zip(axes, branches, sims, d_ranges, strict=True)):
        if br.attrs.get("status") == "failed":
            row[0].set_title(f"failed: {br.attrs['reason']}")
            continue
        m = _scene_mask(br, lo, hi)
        d = br.d.values[m]
        st = br.stable.values[m]
        walls = br.wall.values
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
                    if j == 0:
                        ax.annotate(name, (dc, yc), xytext=(3, 4), textcoords="offset points", fontsize=7)
            if grazing is not None and abs(br.attrs["beta"] - grazing["beta"]) < 1e-9:
                for key, color, dx in (("G1", "k", -13), ("G2", "tab:red", 2)):
                    ax.axvline(grazing[key], color=color, ls="-.", lw=0.8)
                    ax.annotate(key, (grazing[key], 0.0), xycoords=("data", "axes fraction"), xytext=(dx, 3),
                                textcoords="offset points", fontsize=7, color=color)
            if col == 0 and r_i == 0:
                _branch_legend(ax)
            ax.set_ylabel(ylabel + (" (magnitude)" if var == "v_minus" else ""))
            ax.set_xlabel("d")
            ax.set_title(f"({next(labels)}) {_beta_label(br.attrs['beta'])}")
            ax.set_xlim(lo, hi)
    return fig


def fig3(branches, d_ranges):
    """Delta = Tr^2 - 4 Det (left) and eigenvalues (right) along the 2:1 branches.  Stable stretches
    solid, unstable dashed, stretches that cross a wall (not admissible) grey; A (node <-> focus,
    Delta = 0) and B (lambda = -1) marked and named."""
    import numpy as np
    from matplotlib.lines import Line2D

    use_style()
    n = len(branches)
    fig, axes = plt.subplots(n, 2, figsize=(8, 2.3 * n), squeeze=False)
    labels = iter("abcdefghijklmnop")
    for row, br, (lo, hi) in zip(axes, branches, d_ranges, strict=True):
        if br.attrs.get("status") == "failed":
            row[0].set_title(f"failed: {br.attrs['reason']}")
            continue
        d = br.d.values
        inside = (d >= lo) & (d <= hi)
        adm, st = br.admissible.values & inside, br.stable.values
        disc = br.discriminant.values
        real = disc >= 0

        def draw(ax, y, color, lw=1.0):
            # NaN outside each stretch, so no line joins separate stretches
            for sel, style, c in ((adm & st, "-", color), (adm & ~st, "--", color), (inside & ~adm, "-", "0.75")):
                ax.plot(d, np.where(sel, y, np.nan), style, color=c, lw=lw)

        draw(row[0], disc, "tab:blue")
        row[0].axhline(0, color="tab:red", ls="-.", lw=0.8)
        row[0].set_ylabel(r"$\Delta=\mathrm{Tr}^2-4\,\mathrm{Det}$")
        for e, col in ((0, "tab:blue"), (1, "tab:green")):
            draw(row[1], np.where(real, br.eig_real.values[:, e], np.nan), col, lw=0.8)
        draw(row[1], np.where(~real, br.eig_real.values[:, 0], np.nan), "tab:purple", lw=2.0)
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
            ax.set_title(f"({next(labels)}) {_beta_label(br.attrs['beta'])}")
        for name, dc, _k, _t in critical_markers(br, lo, hi, admissible_only=False):
            if name.startswith("A"):
                row[0].plot([dc], [0.0], "s", mfc="none", color="tab:red", ms=6)
                row[0].annotate(name, (dc, 0.0), xytext=(3, 5), textcoords="offset points", fontsize=7)
            elif name == "B":
                row[1].plot([dc], [-1.0], "o", mfc="none", color="tab:red", ms=7)
                row[1].annotate("B", (dc, -1.0), xytext=(4, -11), textcoords="offset points", fontsize=7)
    handles = [Line2D([], [], color="tab:blue", label=r"real $\lambda_1$ (stable: solid, unstable: dashed)"),
               Line2D([], [], color="tab:green", lw=0.8, label=r"real $\lambda_2$"),
               Line2D([], [], color="tab:purple", lw=2.0, label=r"Re $\lambda$ (complex pair)"),
               Line2D([], [], color="0.75", label="not admissible (crosses a wall)"),
               Line2D([], [], color="tab:red", marker="o", mfc="none", ls="", label=r"B: $\lambda=-1$"),
               Line2D([], [], color="tab:red", marker="s", mfc="none", ls="", label=r"A: $\Delta=0$ (node $\leftrightarrow$ focus)")]
    axes[0, 1].legend(handles=handles, loc="lower right", fontsize=6, framealpha=0.85)
    return fig


# ---------------------------------------------------------------------------------------------
# Sweeps, bistability, basins, regime maps
# ---------------------------------------------------------------------------------------------


def _last_events(ds, var, direction="down", labels=False):
    """(d, values) of every point's last period of events in one sweep direction (its last 24 events
    where no period was found); ``var="dt"`` gives the time since the previous event.  With
    ``labels``, also each value's point's identified motion."""
    import numpy as np

    s = ds.sel(direction=direction)
    xs, ys, ls = [], [], []
    for i in range(s.sizes["point"]):
        t = s["t"].values[i] if "t" in s else s[var].values[i]
        m = int(np.isfinite(t).sum())
        n = (int(s["period_events"].values[i]) if "period_events" in s else 0) or min(m, 24)
        v = np.diff(t[max(m - n - 1, 0):m]) if var == "dt" else s[var].values[i, m - n:m]
        v = v[np.isfinite(v)]
        xs.append(np.full(v.size, float(s.d[i])))
        ys.append(v)
        if labels:
            ls.append(np.full(v.size, str(s["label"].values[i]), dtype=object))
    if labels:
        return np.concatenate(xs), np.concatenate(ys), np.concatenate(ls).astype(str)
    return np.concatenate(xs), np.concatenate(ys)


def fig_bis(sw, transitions, portraits, branches):
    """Bistable 2:1 and 3:1 near grazing (paper Fig BiS): the last period of every sweep point,
    coloured by the motion identified there (2:1 black, 3:1 blue, other grey) and marked by the sweep
    direction (o: d decreasing, +: d increasing), over the analytic branches (2:1 grey, 3:1 blue;
    stable solid, unstable dashed), with G1 and G2; below, the closed orbits at G1, d_mid (both) and
    G2 over one period."""
    import numpy as np
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
            x, y, lab = _last_events(sw, var, direction, labels=True)
            y = np.abs(y) if var == "v_minus" else y
            for motion in sorted(set(lab)):
                sel = lab == motion
                ax.plot(x[sel], y[sel], marker, mfc="none", color=motion_color.get(motion, "0.7"), ms=3.5, ls="none")
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


def _class_image(ax, da, x, y, legend, n_show=9):
    """Draw integer attractor codes with a discrete colormap; the n_show most frequent named."""
    import numpy as np
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    codes = np.where(da.values < n_show, da.values, n_show)
    colors = list(plt.get_cmap("tab10").colors[:n_show]) + [(0.85, 0.85, 0.85)]
    names = list(legend[:n_show]) + (["other"] if len(legend) > n_show else [])
    cmap = ListedColormap(colors[: len(names)])
    norm = BoundaryNorm(np.arange(len(names) + 1) - 0.5, len(names))
    ax.pcolormesh(x, y, codes, cmap=cmap, norm=norm, shading="nearest")
    ax.legend(handles=[Patch(color=colors[i], label=names[i]) for i in range(len(names))], loc="upper left",
              bbox_to_anchor=(1.01, 1.0), fontsize=6)


def fig_basins(b):
    import json

    use_style()
    fig, ax = plt.subplots(figsize=(7, 4))
    _class_image(ax, b.attractor.T, b.phi.values, b.v0.values, json.loads(b.attrs["legend"]))
    ax.set_xlabel(r"phase $\varphi$ of the first bottom impact")
    ax.set_ylabel(r"pre-impact velocity $\dot Z(t_0)$")
    ax.set_title(f"Basins of attraction, d = {b.attrs['d']:.4g}, " r"$\bar g$" f" = {b.attrs['gbar']:.4g}")
    return fig


def fig_regime_map(maps):
    """Regime maps side by side, one colour per motion across all panels."""
    import numpy as np

    use_style()
    labels, counts = np.unique(np.concatenate([m.label.values.ravel() for m in maps]), return_counts=True)
    legend = list(labels[np.argsort(-counts, kind="stable")])
    index = {lab: i for i, lab in enumerate(legend)}
    fig, axes = plt.subplots(1, len(maps), figsize=(6.2 * len(maps), 3.8), squeeze=False)
    for ax, m in zip(axes[0], maps, strict=True):
        ydim, xdim = m.label.dims
        codes = m.label.copy(data=np.vectorize(index.__getitem__)(m.label.values))
        _class_image(ax, codes, m[xdim].values, m[ydim].values, legend)
        ax.set_xlabel(f"{m[xdim].attrs.get('long_name', xdim)} ({m[xdim].attrs.get('units', '')})")
        ax.set_ylabel(f"{m[ydim].attrs.get('long_name', ydim)} ({m[ydim].attrs.get('units', '')})")
        fixed = {k: m.attrs[k] for k in ("beta", "F", "s") if k in m.attrs and k not in (xdim, ydim)}
        ax.set_title("Attractor from one start; " + ", ".join(f"{k}={v:.4g}" for k, v in fixed.items()))
    return fig


# ---------------------------------------------------------------------------------------------
# Energy (paper Figs 0 and 5) and design guidance
# ---------------------------------------------------------------------------------------------

U_I_COLOR = "tab:red"
U_T_COLOR = "tab:cyan"


def _analytic(ax, branches, var, *, averages=False):
    import numpy as np

    for br in branches:
        if not br.sizes.get("point", 0):
            continue
        m = br.admissible.values
        d = br.d.values[m]
        st = br.stable.values[m]
        if averages:
            branch_line(ax, d, br.U_I.values[m], st, U_I_COLOR, lw=0.8)
            branch_line(ax, d, br.U_T.values[m], st, U_T_COLOR, lw=0.8)
            continue
        for j in range(br.sizes["impact"]):
            y = np.abs(br[var].values[m, j])
            branch_line(ax, d, y, st, BOTTOM if br.wall.values[j] == 1 else TOP)


def _panel_title(sw, letter):
    vary = sw.attrs["vary"]
    rng = sw[vary].values
    fixed = f"||F||={sw.F.values[0]:g} N" if vary == "s" else f"s={sw.s.values[0]:g} m"
    return f"({letter}) {_beta_label(sw.attrs['beta'])}, {rng.min():g} < {vary} < {rng.max():g}, {fixed}"


def fig_energy(panels, sweeps, energies, branch_sets, *, velocities=False):
    """Output voltage U_k - U_in (analytic 1:1 and 2:1 lines, stable solid / unstable dashed;
    simulated points: open circles), U_I (red stars) and U_T (cyan diamonds) against d; with
    ``velocities`` also |Zdot_k| (paper Fig 0 (a), (c))."""
    import numpy as np

    use_style()
    n = len(panels)
    if velocities:
        fig, axes = plt.subplots(n, 2, figsize=(10, 3.3 * n), squeeze=False)
        pairs = [(row[0], row[1]) for row in axes]
    else:
        ncol = 2 if n > 1 else 1
        nrow = int(np.ceil(n / ncol))
        fig, axes = plt.subplots(nrow, ncol, figsize=(5.2 * ncol, 3.3 * nrow), squeeze=False)
        pairs = [(None, ax) for ax in axes.ravel()[:n]]
        for ax in axes.ravel()[n:]:
            ax.remove()
    letters = iter("abcdefghijklmnop")
    for (vax, uax), sw, en, brs in zip(pairs, sweeps, energies, branch_sets, strict=True):
        if vax is not None:
            _analytic(vax, brs, "v_minus")
            x, y = _last_events(sw, "v_minus")
            vax.plot(x, abs(y), "o", mfc="none", color="k", ms=2.5, ls="none")
            vax.set_xlabel("d")
            vax.set_ylabel(r"$|\dot Z_k|$")
            vax.set_title(_panel_title(sw, next(letters)))
        _analytic(uax, brs, "gain")
        _analytic(uax, brs, "gain", averages=True)
        x, y = _last_events(en, "gain")
        uax.plot(x, y, "o", mfc="none", color="k", ms=2.5, ls="none", label=r"$U_k-U_{in}$ (simulated)")
        dn = en.sel(direction="down")
        uax.plot(dn.d, dn.U_T, "D", mfc="none", color=U_T_COLOR, ms=3.5, ls="none", label=r"$\overline{U}_T$")
        uax.plot(dn.d, dn.U_I, "*", color=U_I_COLOR, ms=3, ls="none", zorder=5, label=r"$\overline{U}_I$")
        uax.set_xlabel("d")
        uax.set_ylabel("output voltage (V)")
        uax.set_title(_panel_title(sw, next(letters)))
    pairs[0][1].legend(loc="best")
    return fig


def fig_design(s_sets, F_sets, table):
    """U_T (solid) and U_I (dashed) against s at fixed force and against F at fixed s, per incline,
    with the maxima of the design table marked."""
    use_style()
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    colors = plt.get_cmap("tab10").colors
    for ax, sets, vary in ((axes[0], s_sets, "s"), (axes[1], F_sets, "F")):
        for k, e in enumerate(sets):
            dn = e.sel(direction="down")
            c = colors[k % 10]
            ax.plot(e[vary], dn.U_T, "-", color=c, lw=1.0, label=_beta_label(e.attrs["beta"]) + r": $\overline{U}_T$")
            ax.plot(e[vary], dn.U_I, "--", color=c, lw=0.8)
            rows = table[(table.vary == vary) & (abs(table.beta - float(e.attrs["beta"])) < 1e-9)]
            for _, r in rows.iterrows():
                ax.plot(r.best, r.U_T if r.maximise == "U_T" else r.U_I, "o" if r.maximise == "U_T" else "s",
                        mfc="none", color=c, ms=8)
        ax.set_xlabel("cylinder length s (m)" if vary == "s" else "forcing amplitude ||F|| (N)")
        ax.set_ylabel("average output voltage (V)")
        ax.set_title(("(a) length sweep at fixed force" if vary == "s" else "(b) force sweep at s = 0.85 m")
                     + r"; dashed: $\overline{U}_I$; circles/squares: maxima")
    axes[0].legend(loc="best", fontsize=6)
    return fig


# ---------------------------------------------------------------------------------------------
# Speed against accuracy
# ---------------------------------------------------------------------------------------------

FAMILY_STYLE = {
    "exact": ("k", "*", "exact (numba)"),
    "python": ("0.5", "*", "same algorithm, plain Python"),
    "ivp-RK45": ("tab:blue", "o", "solve_ivp RK45"),
    "ivp-DOP853": ("tab:orange", "s", "solve_ivp DOP853"),
    "ivp-LSODA": ("tab:green", "^", "solve_ivp LSODA"),
    "ivp-Radau": ("tab:purple", "v", "solve_ivp Radau"),
    "rk4": ("tab:red", "D", "RK4 + bisection"),
}


def fig_work_precision(wp):
    """Error in impact times against cost per impact, log-log, one line per method (tolerance or
    step ladder); a cross at the top where the method put impacts on the wrong walls."""
    import numpy as np

    use_style()
    scenes = list(wp.scene.values)
    fig, axes = plt.subplots(1, len(scenes), figsize=(3.6 * len(scenes), 3.6), squeeze=False, sharey=True)
    top = 1.0
    for ax, sc in zip(axes[0], scenes, strict=True):
        sub = wp.sel(scene=sc)
        for fam, (color, marker, label) in FAMILY_STYLE.items():
            m = sub.family.values == fam
            if not m.any():
                continue
            x, y = sub.us_per_impact.values[m], sub.err_t.values[m]
            finite = np.isfinite(y)
            ax.loglog(x[finite], np.maximum(y[finite], 1e-17), marker=marker, color=color, lw=1, ms=5, label=label)
            if (~finite).any():
                ax.plot(x[~finite], np.full((~finite).sum(), top), "x", color=color, ms=7)
        ax.set_title(f"{sc} motion")
        ax.set_xlabel("cost per impact (µs)")
        ax.axhline(top, color="0.7", lw=0.6, ls=":")
    axes[0, 0].set_ylabel("largest impact-time error\n(first 20 impacts; x: wrong walls)")
    axes[0, -1].legend(loc="lower right", fontsize=6)
    return fig


def fig_failure_map(fm):
    import numpy as np
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    from .workprecision import OUTCOMES

    use_style()
    colors = ["#4daf4a", "#ffd92f", "#e41a1c", "#984ea3", "#ff7f00", "#377eb8", "#000000"]
    codes = np.vectorize(OUTCOMES.index)(fm.outcome.values)
    fig, ax = plt.subplots(figsize=(12, 4.2))
    ax.imshow(codes, cmap=ListedColormap(colors), vmin=-0.5, vmax=len(OUTCOMES) - 0.5, aspect="auto")
    ax.set_yticks(range(fm.sizes["solver"]), fm.solver.values, fontsize=7)
    ax.set_xticks(range(fm.sizes["case"]), fm.case.values, rotation=70, ha="right", fontsize=7)
    ax.legend(handles=[Patch(color=c, label=o) for c, o in zip(colors, OUTCOMES, strict=True)],
              loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
    ax.set_title("Where each method fails: near-grazing flights (extremum eps inside a wall: no impact; "
                 "eps past it: an impact), chattering into sticking, a long chaotic run", fontsize=8)
    return fig


def fig_analytics_accuracy(a):
    """Located vs grid-only critical points (continuation step) and grazing points (sweep points),
    error against cost."""
    use_style()
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    ax = axes[0]
    for k, (kind, color) in enumerate((("B", "tab:blue"), ("fold", "tab:orange"))):
        x = a.branch_seconds.values
        ax.loglog(x, a.branch_grid_err.values[:, k].clip(1e-17), "o--", color=color, mfc="none", label=f"{kind}: grid only")
        ax.loglog(x, a.branch_located_err.values[:, k].clip(1e-17), "o-", color=color, label=f"{kind}: located")
        for xi, h, y in zip(x, a.step.values, a.branch_grid_err.values[:, k], strict=True):
            if k == 0:
                ax.annotate(f"{h:g}", (xi, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("continuation time (s)")
    ax.set_ylabel("error in d")
    ax.set_title(r"(a) 2:1 branch, $\beta=\pi/3$: by arclength step (labels)")
    ax.legend(fontsize=6)
    ax = axes[1]
    for k, (kind, color) in enumerate((("G1", "k"), ("G2", "tab:red"))):
        x = a.sweep_seconds.values.sum(axis=1)
        ax.loglog(x, a.sweep_grid_err.values[:, k], "s--", color=color, mfc="none", label=f"{kind}: grid only")
        ax.loglog(x, a.sweep_located_err.values[:, k], "s-", color=color, label=f"{kind}: located")
        if k == 0:
            for xi, n, y in zip(x, a.points.values, a.sweep_grid_err.values[:, k], strict=True):
                ax.annotate(str(n), (xi, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("sweep + location time (s)")
    ax.set_title(r"(b) grazing points from sweeps, $\beta=\pi/6$: by sweep points (labels)")
    ax.legend(fontsize=6)
    return fig
