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
