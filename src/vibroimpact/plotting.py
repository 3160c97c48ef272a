"""Figures drawn from saved datasets. One style for all (Agg backend, shared conventions):
analytic branches solid where stable and dashed where unstable, simulation as open markers,
bottom wall blue and top wall green as in the paper."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

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


def save(fig, stem) -> list[Path]:
    """Save ``stem.pdf`` and ``stem.png``; returns the paths."""
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".pdf"), stem.with_suffix(".png")]
    for p in paths:
        fig.savefig(p)
    plt.close(fig)
    return paths


def _title(ds, panel):
    a = ds.attrs
    return (f"({panel}) {a['motion']}, d={a['d']:.4g}\n" r"$\dot Z(t_0)$" f"={a['v0']:.4g}, " r"$\varphi$" f"={a['phi']:.4g}")


def time_series(ax, ds):
    """Cylinder ends X*(t) +- d/2 and ball x*(t) (paper Fig 0b)."""
    d = ds.attrs["d"]
    t = ds["time"].values
    ax.plot(t, ds["X"] + d / 2, color=BOTTOM, label=r"$X^*\pm d/2$")
    ax.plot(t, ds["X"] - d / 2, color=BOTTOM)
    ax.plot(t, ds["x"], color=BALL, label=r"$x^*$ (ball)")
    ax.set_xlabel("t")
    ax.set_ylabel("displacement")


def phase_portrait(ax, ds):
    """Zdot against Z, walls dashed, impacts marked (paper Figs 4, FN2, BiS)."""
    d = ds.attrs["d"]
    ax.plot(ds["Z"], ds["Zdot"], color="k", lw=0.7)
    for w, col in ((1, BOTTOM), (-1, TOP)):
        ax.axvline(w * d / 2, color=col, ls="--", lw=0.8)
    if "cycle_v_minus" in ds:
        w = ds["cycle_wall"].values
        ax.plot(w * d / 2, ds["cycle_v_minus"], "o", mfc="none", color="tab:orange", ms=5, label="attractor impacts")
    ax.set_xlabel("Z")
    ax.set_ylabel(r"$\dot Z$")


def fig0b(datasets):
    """Time series of 1:1, 2:1 and 3:1 motions."""
    use_style()
    fig, axes = plt.subplots(1, len(datasets), figsize=(3.3 * len(datasets), 2.8), squeeze=False)
    for ax, ds, panel in zip(axes[0], datasets, "abcdefg", strict=False):
        time_series(ax, ds)
        ax.set_title(_title(ds, panel))
    axes[0, 0].legend(loc="lower left")
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
    return fig


# ---------------------------------------------------------------------------------------------
# Branches (paper Figs 2, 3)
# ---------------------------------------------------------------------------------------------

BETA_NAMES = {90.0: r"\pi/2", 60.0: r"\pi/3", 45.0: r"\pi/4", 30.0: r"\pi/6"}


def _beta_label(beta):
    import math

    return "$\\beta=" + BETA_NAMES.get(round(math.degrees(beta), 6), f"{beta:.4f}") + "$"


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


def fig2(branches, sims, d_ranges, grazing=None):
    """2:1 branches: Zdot_k, Delta t_j / 2, phi_k vs d for each incline (rows)."""
    import numpy as np

    use_style()
    n = len(branches)
    fig, axes = plt.subplots(n, 3, figsize=(10, 2.3 * n), squeeze=False, sharex="row")
    labels = iter("abcdefghijklmnopqrstuvwxyz")
    for row, br, sim, (lo, hi) in zip(axes, branches, sims, d_ranges, strict=True):
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
            if grazing is not None and abs(br.attrs["beta"] - grazing["beta"]) < 1e-9:
                ax.axvline(grazing["G1"], color="k", ls="-.", lw=0.8)
                ax.axvline(grazing["G2"], color="tab:red", ls="-.", lw=0.8)
            ax.set_ylabel(ylabel + (" (magnitude)" if var == "v_minus" else ""))
            ax.set_xlabel("d")
            ax.set_title(f"({next(labels)}) {_beta_label(br.attrs['beta'])}")
            ax.set_xlim(lo, hi)
    return fig


def fig3(branches, d_ranges):
    """Delta = Tr^2 - 4 Det (left) and eigenvalues (right) along the 2:1 branches."""
    import numpy as np

    use_style()
    n = len(branches)
    fig, axes = plt.subplots(n, 2, figsize=(8, 2.3 * n), squeeze=False)
    labels = iter("abcdefghijklmnop")
    for row, br, (lo, hi) in zip(axes, branches, d_ranges, strict=True):
        if br.attrs.get("status") == "failed":
            continue
        m = _scene_mask(br, lo, hi)
        d = br.d.values[m]
        st = br.stable.values[m]
        disc = br.discriminant.values[m]
        branch_line(row[0], d, disc, st, "tab:blue")
        row[0].axhline(0, color="tab:red", ls="-.", lw=0.8)
        row[0].set_ylabel(r"$\Delta$")
        real = disc >= 0
        for e, col in ((0, "tab:blue"), (1, "tab:green")):
            row[1].plot(d, np.where(real, br.eig_real.values[m, e], np.nan), color=col, lw=0.8)
        row[1].plot(d, np.where(~real, br.eig_real.values[m, 0], np.nan), color="tab:green", lw=2.2,
                    label=r"Re $\lambda$ (complex pair)")
        row[1].axhline(-1, color="tab:red", ls="-.", lw=0.8)
        row[1].set_ylabel(r"$\lambda_{1,2}$")
        # scale to the stable part: the unstable branch beyond the fold diverges where an impact
        # velocity tends to zero
        if st.any():
            span = np.ptp(disc[st]) or 1.0
            row[0].set_ylim(disc[st].min() - 0.3 * span, disc[st].max() + 0.3 * span)
        row[1].set_ylim(-2.5, 1.5)
        for ax in row:
            ax.set_xlabel("d")
            ax.set_xlim(lo, hi)
            ax.set_title(f"({next(labels)}) {_beta_label(br.attrs['beta'])}")
        kinds, crit = br.critical_kind.values, br.critical_d.values
        for kind, mk in (("B", "o"), ("A", "s")):
            for x in crit[(kinds == kind) & (crit >= lo) & (crit <= hi)]:
                row[1 if kind == "B" else 0].plot(x, -1 if kind == "B" else 0, mk, mfc="none", color="tab:red", ms=6)
    axes[0, 1].legend(loc="best")
    return fig


# ---------------------------------------------------------------------------------------------
# Sweeps, bistability, basins, regime maps
# ---------------------------------------------------------------------------------------------


def _last_events(ds, var, direction="down"):
    """(d, values) of every point's last period of events in one sweep direction (its last 24 events
    where no period was found); ``var="dt"`` gives the time since the previous event."""
    import numpy as np

    s = ds.sel(direction=direction)
    xs, ys = [], []
    for i in range(s.sizes["point"]):
        t = s["t"].values[i] if "t" in s else s[var].values[i]
        m = int(np.isfinite(t).sum())
        n = (int(s["period_events"].values[i]) if "period_events" in s else 0) or min(m, 24)
        v = np.diff(t[max(m - n - 1, 0):m]) if var == "dt" else s[var].values[i, m - n:m]
        v = v[np.isfinite(v)]
        xs.append(np.full(v.size, float(s.d[i])))
        ys.append(v)
    return np.concatenate(xs), np.concatenate(ys)


def fig_bis(sw, transitions, portraits, branches):
    """Bistable 2:1 (down sweep, circles) and 3:1 (up sweep, crosses) near grazing with the analytic
    branches, and the phase portraits at G1, d = 0.14 (both) and G2 (paper Fig BiS)."""
    import numpy as np

    use_style()
    fig = plt.figure(figsize=(11, 6))
    gs = fig.add_gridspec(2, 4)
    g1, g2 = portraits.attrs["G1"], portraits.attrs["G2"]
    lo, hi = float(sw.d.min()), float(sw.d.max())
    for col, (var, ylabel) in enumerate([("v_minus", r"$|\dot Z_k|$"), ("phase", r"$\varphi_k$"), ("dt", r"$\Delta t_k$")]):
        ax = fig.add_subplot(gs[0, col])
        for br, color in zip(branches, ("0.6", "tab:blue"), strict=True):
            m = (br.admissible & (br.d >= lo) & (br.d <= hi)).values
            for j in range(br.sizes["impact"]):
                y = br[var].values[m, j]
                y = np.abs(y) if var == "v_minus" else y
                branch_line(ax, br.d.values[m], y, br.stable.values[m], color, lw=0.8)
        for direction, marker, color, lab in (("down", "o", "k", "2:1 (d decreasing)"), ("up", "+", "tab:blue", "3:1 (d increasing)")):
            x, y = _last_events(sw, var, direction)
            y = np.abs(y) if var == "v_minus" else y
            ax.plot(x, y, marker, mfc="none", color=color, ms=3.5, ls="none", label=lab)
        for g, c in ((g1, "k"), (g2, "tab:red")):
            ax.axvline(g, color=c, ls="-.", lw=0.8)
        ax.set_xlabel("d")
        ax.set_ylabel(ylabel)
        ax.set_title(f"({'abc'[col]})")
    fig.axes[0].legend(loc="best")
    for k in range(portraits.sizes["panel"]):
        ax = fig.add_subplot(gs[1, k])
        p = portraits.isel(panel=k)
        d = float(p.d)
        ax.plot(p.Z, p.Zdot, color="k", lw=0.8)
        ax.axvline(d / 2, color=BOTTOM, ls="--", lw=0.8)
        ax.axvline(-d / 2, color=TOP, ls="--", lw=0.8)
        ax.set_title(f"({'defg'[k]}) {str(p.panel.values)}: {str(p.word.values)}, d={d:.6f}")
        ax.set_xlabel("Z")
        ax.set_ylabel(r"$\dot Z$")
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
