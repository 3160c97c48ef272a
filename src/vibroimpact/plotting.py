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
