"""Design maps: the expected and the worst-case output over two design parameters, with the bifurcation
curves of the same plane, the regions where motions coexist and the best robust designs."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import Normalize
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from ._common import curve_pieces, motion_color, pi_label, pi_ticks, use_style, wellposed

_SYMBOL = {"s": "s", "F": "F", "beta": "β"}
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



def _knock_points(km):
    """The designs a knock map draws: flat arrays of output (kV), critical shock, highest-output motion, whether
    each is known (an output and a shock, finite or infinite), and whether its highest-output motion is one of
    several the starts reached (a classification a start near a basin boundary can change)."""
    u = km["top_U_T"].values.ravel() / 1e3
    s = km["top_shock"].values.ravel()
    lab = km["top_label"].values.ravel().astype(str)
    several = (np.sum(km["share"].values > 0, axis=-1) > 1).ravel()
    return u, s, lab, np.isfinite(u) & ~np.isnan(s), several


def fig_knocks(km):
    """Output against critical shock over the designs of a knock map
    (:func:`vibroimpact.analysis.robust.knock_map`): each design's highest-output motion at its critical shock
    (a circle in the motion's colour; at ∞ where no admissible knock drops it), the Pareto front (ringed: no
    design beats one of them on both), the knock the robust design survives (dashed), the best design (diamond)
    and the best that survives the knock (star).  The shock axis is logarithmic; the figure check compares each
    shock to within the factor its fine scan spans (``shock_fine_span``: another machine can find another of the
    thin bands in which impacting basins interleave).  The front and the two designs are the dataset's
    (:func:`vibroimpact.analysis.robust.mark_choices`)."""
    use_style()
    fig, ax = plt.subplots(figsize=(7.4, 4.6))
    u, s, lab, known, several = _knock_points(km)
    knock, unit = float(km.attrs["knock"]), km.attrs["knock_unit"]
    finite = known & np.isfinite(s)
    lo = np.log10(min(float(np.min(s[finite], initial=knock)), knock) / 1.6)
    hi = np.log10(max(float(np.max(s[finite], initial=knock)), knock) * 1.6)
    x_inf = hi + 0.18  # where a design no knock drops is drawn
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(np.isinf(s), x_inf, np.log10(s))
    x, y = np.where(known, x, np.nan), np.where(known, u, np.nan)
    # a shock is the smallest boundary the scan found; where the basins interleave in bands narrower than its
    # steps, another machine's last bits can find another band within the factor the fine scan spans below it
    step = dict(step_x=float(np.log10(km.attrs["shock_fine_span"])), step_y=0.0)
    colours = [motion_color(n) if k else "none" for n, k in zip(lab, known, strict=True)]
    wellposed(ax.scatter(x, y, s=24, c=colours, edgecolor="k", lw=0.3, zorder=3), "located", provenance="simulation",
              sampled=several, **step)
    handles = [Line2D([], [], ls="", marker="o", color=motion_color(n), mec="k", mew=0.3, label=n)
               for n in sorted(set(lab[known]), key=lambda n: (-np.sum(lab[known] == n), n))]  # a tie by name
    front = km["pareto"].values.ravel()
    wellposed(ax.scatter(np.where(front, x, np.nan), np.where(front, y, np.nan), s=90, facecolor="none",
                         edgecolor="k", lw=0.9, zorder=4), "located", provenance="simulation", sampled=several, **step)
    handles.append(Line2D([], [], ls="", marker="o", mfc="none", mec="k", ms=8, label="Pareto front"))
    wellposed(ax.axvline(np.log10(knock), ls="--", color="0.35", lw=1.0, zorder=1), "located", step_x=0.0, step_y=0.0)
    handles.append(Line2D([], [], ls="--", color="0.35", label=f"knock to survive: {knock:g} {unit}"))
    for flag, marker, size, text in (("best", "D", 40, "best output"), ("robust", "*", 150, "best surviving the knock")):
        mark = np.flatnonzero(km[flag].values.ravel())
        at = (x[mark[0]], y[mark[0]]) if mark.size else (np.nan, np.nan)
        wellposed(ax.scatter([at[0]], [at[1]], s=size, marker=marker, facecolor="w" if marker == "D" else "none",
                             edgecolor="k", lw=1.1, zorder=5 if marker == "D" else 6), "located",
                  provenance="simulation", sampled=np.array([True]), **step)
        handles.append(Line2D([], [], ls="", marker=marker, mfc="none", mec="k", ms=8 if marker == "*" else 6, label=text))
    decades = np.arange(np.ceil(lo), np.floor(hi) + 1)
    ax.set_xticks([*decades, x_inf], [*(f"{10 ** k:g}" for k in decades), "∞"])
    ax.set_xlim(lo, x_inf + 0.12)
    ax.set_xlabel(f"critical shock of its highest-output motion ({unit}; ∞: no admissible knock drops it)")
    ax.set_ylabel(r"its output $\bar U_T$ (kV)")
    missing = int(np.sum(np.isfinite(u) & np.isnan(s)))
    x_name, y_name = km.attrs["x"], km.attrs["y"]
    ax.set_title(f"Output against critical shock over the designs of the ({_SYMBOL[x_name]}, {_SYMBOL[y_name]}) plane"
                 + (f"\n{missing} designs without a critical shock (no periodic motion to knock) not drawn"
                    if missing else ""), fontsize=8)
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=6)
    return fig
