"""Trajectories of single orbits: Figures 4, 7 and 3 (:func:`fig0b`, :func:`fig4`, :func:`figFN2`, named by the
paper's LaTeX labels; rows of :mod:`vibroimpact.outputs.registry`)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ...dynamics import kernels as K
from ..portraits import GRAZING_XTOL
from ._common import BALL, BOTTOM, TOP, pi_label, use_style

#: an orbit whose margin to grazing is below this fraction of d is titled "near grazing"
NEAR_GRAZING = 0.01
#: the orbit drawn at its located grazing point
GRAZING_COLOR = "tab:red"
#: what the titles' margin is (:func:`vibroimpact.analysis.grazing.admissibility`'s clearance), said once per figure
MARGIN_NOTE = ("margin to grazing: the smaller of the slowest impact speed and the least distance of a flight's "
               "turning point from a wall (non-dimensional; 0 at grazing)")


def _title(ds, panel):
    a = ds.attrs
    head = f"({panel}) {a['motion']}, d={a['d']:.4g}"
    margin = a.get("orbit_clearance")
    if margin is not None and np.isfinite(margin):
        near = "near grazing, " if margin < NEAR_GRAZING * a["d"] else ""
        head += f", {near}margin {margin:.1e}"
    if a.get("grazing_status") == "located":
        # the margin there is zero to the location's tolerance (its printed digits would be rounding's)
        head += f"\ngrazes at d={a['grazing_d']:.5f} (located to {a.get('grazing_xtol', GRAZING_XTOL):.0e} in d)"
    elif "grazing_status" in a:
        head += f"\ngrazing not located: {a['grazing_status']}"
    line2 = r"$\dot Z(t_0)$" f"={a['v0']:.4g}, " r"$\varphi$" f"={a['phi']:.4g}"
    if "beta" in a:
        line2 = (r"$\beta$=" + pi_label(float(a["beta"])) + (rf", $\|\hat F\|$={a['F']:g} N" if "F" in a else "")
                 + (r", $\omega$=" + pi_label(float(a["omega"]), " rad/s") if "omega" in a else "") + "\n" + line2)
    return head + "\n" + line2


def _figure_legend(fig, axes, title=MARGIN_NOTE, ncol=4):
    """One legend below the panels, with every labelled line of ``axes`` once (a legend inside a panel hides
    data), titled with the definition of the titles' margin."""
    handles = {}
    for ax in axes:
        for h, label in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(label, h)
    fig.legend(list(handles.values()), list(handles), loc="outside lower center", ncol=ncol, fontsize=7,
               title=title, title_fontsize=7)


def time_series(ax, ds):
    """Cylinder ends X*(t) +- d/2 and ball x*(t) (Figure 4)."""
    d = ds.attrs["d"]
    t = ds["time"].values
    ax.plot(t, ds["X"] + d / 2, color=BOTTOM, label=r"$X^*\pm d/2$")
    ax.plot(t, ds["X"] - d / 2, color=BOTTOM)
    ax.plot(t, ds["x"], color=BALL, label=r"$x^*$ (ball)")
    if "wall" in ds and "impact" in ds.dims:
        # the impacts in the window, at the wall they hit: count the bottom impacts per period
        tk = ds["t"].values
        hit = np.isfinite(tk) & (tk <= t[-1]) & K.hits(ds["kind"].values)
        # the bottom wall (Z = d/2) is the end at X - d/2 in the absolute frame: x* = X - Z
        xk = np.interp(tk[hit], t, ds["X"].values) - ds["wall"].values[hit] * d / 2
        for w, col, mk, name in ((1, BOTTOM, "v", "bottom impact"), (-1, TOP, "^", "top impact")):
            sel = ds["wall"].values[hit] == w
            ax.plot(tk[hit][sel], xk[sel], mk, color=col, ms=5, ls="none", label=name)
    ax.set_xlabel("t")
    ax.set_ylabel("displacement")


def phase_portrait(ax, ds):
    """Zdot against Z, walls dashed, impacts marked (Figures 7, 3 and 8)."""
    d = ds.attrs["d"]
    ax.plot(ds["Z"], ds["Zdot"], color="k", lw=0.7)
    for w, col, name in ((1, BOTTOM, "bottom wall"), (-1, TOP, "top wall")):
        ax.axvline(w * d / 2, color=col, ls="--", lw=0.8, label=name)
    if "grazing_Z" in ds:  # the caption shows grazing behaviour: the same orbit where it does graze
        ax.plot(ds["grazing_Z"], ds["grazing_Zdot"], color=GRAZING_COLOR, lw=0.7,
                label="the same orbit where it grazes (d in the panel's title)")
    if "cycle_v_minus" in ds:
        w = ds["cycle_wall"].values
        ax.plot(w * d / 2, ds["cycle_v_minus"], "o", mfc="none", color="tab:orange", ms=5, label="attractor impacts")
    ax.set_xlabel("Z")
    ax.set_ylabel(r"$\dot Z$")
    ax.xaxis.set_major_locator(plt.MaxNLocator(5))


def fig0b(datasets):
    """Time series of 1:1, 2:1 and 3:1 motions."""
    use_style()
    fig, axes = plt.subplots(1, len(datasets), figsize=(3.8 * len(datasets), 3.8), squeeze=False)
    for ax, ds, panel in zip(axes[0], datasets, "abcdefg", strict=False):
        time_series(ax, ds)
        ax.set_title(_title(ds, panel))
    _figure_legend(fig, axes[0, :1])
    betas = {round(float(ds.attrs["beta"]), 9) for ds in datasets if ds.attrs.get("beta_assumed")}
    if len(betas) == 1:  # the caption gives no incline (config `beta_assumed`): say which one is assumed
        fig.suptitle(r"$\beta$ = " + pi_label(betas.pop()) + " assumed: the paper's caption gives none; "
                     "it reproduces all three orbits", fontsize=8)
    return fig


def figFN2(datasets):
    """Phase portraits along 1:1 -> period doubling -> grazing -> 2:1 (Figure 3): the part of
    each run after its first forcing period, so that the attractor is drawn.  A panel whose caption states
    its own force (Figure 3 (a)-(c): 61 N) is titled with the caption's device; its d is the caption's and
    gbar follows from that force (config ``captions``), which the figure says."""
    use_style()
    n = len(datasets)
    ncol = 4
    nrow = (n + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.2 * ncol, 3.0 * nrow + 0.6), squeeze=False)
    for ax, ds, panel in zip(axes.ravel(), datasets, "abcdefghij", strict=False):
        keep = ds.time.values >= 2.0
        sub = ds.isel(time=keep)
        phase_portrait(ax, sub)
        ax.set_title(_title(ds, panel) + ("\n" + r"$\bar g$" + f"={ds.attrs['gbar']:.4f}"), fontsize=7)
    forces = [float(ds.attrs.get("F", np.nan)) for ds in datasets]
    usual = max(set(forces), key=forces.count)
    own = [p for p, f in zip("abcdefghij", forces, strict=False) if f != usual]
    note = MARGIN_NOTE
    if own:  # the captions that state their own device (config `captions`)
        force = forces["abcdefghij".index(own[0])]
        note += (f"\n({own[0]})" + (f"-({own[-1]})" if len(own) > 1 else "") + f": the caption's device ({force:g} N); "
                 "its d as stated (the caption's s would give another), " r"$\bar g$" f" from {force:g} N "
                 r"($\omega$ enters neither the motion nor $\bar g$)")
    _figure_legend(fig, axes.ravel()[:n], title=note)
    for ax in axes.ravel()[n:]:
        ax.remove()
    return fig


def fig4(datasets):
    """Phase portrait, Z(t) and the time series for each orbit: one row each."""
    use_style()
    n = len(datasets)
    fig, axes = plt.subplots(n, 3, figsize=(10, 2.6 * n + 0.6), squeeze=False)
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
    _figure_legend(fig, [axes[0, 0], *axes[:, 0], axes[0, 2]])
    return fig
