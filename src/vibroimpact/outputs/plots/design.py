"""Design maps: the expected and the worst-case output over two design parameters, with the bifurcation
curves of the same plane, the regions where motions coexist and the best robust designs."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import Normalize
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ._common import curve_pieces, pi_label, pi_ticks, use_style, wellposed

_AXIS = {"s": "cylinder length $s$ (m)", "F": r"forcing amplitude $\|\hat F\|$ (N)", "beta": r"incline $\beta$ (rad)"}


def _curves(ax, curves, xname, yname, handles):
    """The admissible pieces of every bifurcation curve (the margins count only those), styled as in the
    bifurcation-set figures."""
    for xs, ys, adm, style, colour, label in curve_pieces(curves, xname, yname):
        wellposed(ax.plot(np.where(adm, xs, np.nan), np.where(adm, ys, np.nan), color="w", lw=2.4, zorder=4)[0], "curve")
        wellposed(ax.plot(np.where(adm, xs, np.nan), np.where(adm, ys, np.nan), style, color=colour, lw=1.3, zorder=5,
                          label="_" + label)[0], "curve")
        if label not in [h.get_label() for h in handles]:
            handles.append(Line2D([], [], ls=style, color=colour, lw=1.3, label=label))


def _cell_motions(ds):
    """Per grid point (in the order the maps draw them): the attractors reached and by how many starts."""
    lab, cnt = ds["label"].values.astype(str), ds["count"].values
    out = ["; ".join(f"{a} x{c}" for a, c in zip(la, ca, strict=True) if a)
           for la, ca in zip(lab.reshape(-1, lab.shape[-1]), cnt.reshape(-1, cnt.shape[-1]), strict=True)]
    return np.array(out, dtype=str)


def inserted_rows(ys):
    """Where the rows ``ys`` of a map are not on its regular grid (the design table's inclines, which
    :func:`vibroimpact.analysis.design.grid_axes` inserts between grid rows): off the grid from ``ys[0]``
    in steps of the largest spacing (an interval a row was inserted into is split; one is left whole
    while the grid has more rows than the table)."""
    ys = np.asarray(ys, dtype=float)
    if ys.size < 3:
        return np.zeros(ys.size, dtype=bool)
    k = (ys - ys[0]) / np.max(np.diff(ys))
    return np.abs(k - np.round(k)) > 1e-6


def _cells(ax, xs, ys, v, norm, rows, field, info):
    """Draw the map ``v`` (rows ``ys``) so that every cell is centred on the point it shows (what
    :func:`vibroimpact.outputs.figdata.figure_data` saves as the cell's place): the regular rows as one mesh,
    each inserted row (:func:`inserted_rows`) as a band of half a step over it.  ``info``: per point, what
    the figure check compares (:func:`~vibroimpact.outputs.plots._common.wellposed`), or None.  Returns the
    last mesh."""
    extra = inserted_rows(ys)
    step = float(np.max(np.diff(ys))) if ys.size > 1 else 1.0
    xe = np.concatenate([[xs[0] - (xs[1] - xs[0]) / 2], (xs[1:] + xs[:-1]) / 2, [xs[-1] + (xs[-1] - xs[-2]) / 2]])
    groups = [(~extra, None)] + [(np.arange(ys.size) == k, ys[k]) for k in np.flatnonzero(extra)]
    for sel, y in groups:
        if y is None:
            mesh = ax.pcolormesh(xs, ys[sel], v[sel], shading="nearest", norm=norm, cmap="viridis", label=field)
        else:
            mesh = ax.pcolormesh(xe, [y - step / 4, y + step / 4], v[sel], shading="flat", norm=norm, cmap="viridis",
                                 label=f"{field} at {rows} = {y:.6g}", zorder=1.5)
        if info is not None:
            # each cell: the attractors a random sample of starts reached, and statistics over them
            wellposed(mesh, "motions", provenance="random starts", **{k: a[sel].ravel() for k, a in info.items()})
    return mesh


def fig_design_map(ds, curves, best):
    """Panels (a) the expected output E[U_T] from a random switch-on and (b) the worst-case U_T among
    the attractors with share >= min_share, over the map's plane, in kV per unit of non-dimensional
    time; bifurcation curves drawn over both, multistable points hatched, the best robust designs
    (``best``: :func:`vibroimpact.analysis.design.best_designs`) marked with stars.  Every cell is centred on
    the grid point it shows (:func:`_cells`): the rows inserted for the design table are narrow bands."""
    use_style()
    xname, yname = ds.attrs["x"], ds.attrs["y"]
    xs, ys = ds[xname].values, ds[yname].values
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=True)
    fields = (("E_U_T", r"(a) expected output E[$\overline{U}_T$] from switch-on"),
              ("worst_U_T", r"(b) worst case: least $\overline{U}_T$ among attractors with share $\geq$"
                            f" {ds.attrs['min_share']:.0%}"))
    vals = [ds[f].values / 1e3 for f, _ in fields]
    norm = Normalize(np.nanmin(vals), np.nanmax(vals))
    handles = []
    multi = ds["multistable"].values.astype(float)
    motion = _cell_motions(ds)
    for ax, (field, title), v in zip(axes, fields, vals, strict=True):
        info = None
        if "point_settled" in ds:
            # a point with starts that found no period: whether a long transient ends within the cap, and
            # so which motions the starts are counted under, is for rounding to decide
            info = dict(motion=motion.reshape(v.shape), settled=ds["point_settled"].values,
                        unsettled=ds["aperiodic_share"].values > 0, mean=v, se=ds[f"{field}_se"].values / 1e3)
        mesh = _cells(ax, xs, ys, v, norm, yname, field, info)
        ax.grid(False)
        if multi.any():
            ax.contourf(xs, ys, multi, levels=[0.5, 1.5], colors="none", hatches=["////"], zorder=3)
        _curves(ax, curves, xname, yname, handles if ax is axes[0] else [])
        for k, row in enumerate(r for r in best if r.get("found")):
            ax.plot(row[xname], row[yname], "*", color="w", mec="k", ms=11, mew=0.8, zorder=7, clip_on=False,
                    label="best robust design" if k == 0 else "_best robust design")
        ax.set_xlim(xs[0], xs[-1])
        ax.set_ylim(ys[0], ys[-1])
        ax.set_xlabel(_AXIS[xname])
        ax.set_title(title, fontsize=8)
    axes[0].set_ylabel(_AXIS[yname])
    if yname == "beta":
        pi_ticks(axes[0], ys[0], ys[-1])
    fig.colorbar(mesh, ax=axes, label=r"$\overline{U}_T$ (kV per unit of $t$)", shrink=0.9)
    handles += [Patch(facecolor="none", edgecolor="k", hatch="////", label="two or more motions coexist\n"
                      f"(each reached by $\\geq$ {ds.attrs['min_share']:.0%} of the starts)"),
                Line2D([], [], ls="", marker="*", color="w", mec="k", ms=10, label="best robust design\n"
                       "(no curve crosses its tolerance box)")]
    fig.legend(handles=handles, loc="outside lower center", ncols=4, fontsize=6)
    fixed = [(k, float(ds.attrs[k])) for k in ("s", "F", "beta") if k not in (xname, yname) and k in ds.attrs]
    fixed_txt = ", ".join(r"$\beta$ = " + pi_label(v) if k == "beta" else f"{k} = {v:g} {'m' if k == 's' else 'N'}"
                          for k, v in fixed)
    starts = ("ball at rest on the bottom membrane, forcing phase uniform" if ds.attrs.get("distribution") == "rest"
              else "first bottom impact uniform over a box of (phase, velocity)")
    tol = ", ".join(f"{k} ±{ds.attrs[f'tolerance_{k}']:.0%}" if k in ("s", "F") else
                    f"{k} ±{ds.attrs[f'tolerance_{k}']:.3g} rad"
                    for k in (xname, yname) if ds.attrs.get(f"tolerance_{k}", 0) > 0)
    fig.suptitle(f"Design under multistability, {fixed_txt}: {ds.attrs['starts']} starts per point "
                 f"({starts}); tolerance {tol}", fontsize=9)
    return fig

