"""What every figure shares: the style file, the colours of the paper's conventions (one colour and one name per
motion), saving a figure with the arrays it draws, labels with fractions of pi, and the parts several figures
draw: the simulated points of a sweep, its panels along d with the motions named over them and the points marked
on the d axis, and the curves of the bifurcation sets.  A figure module imports its helpers from here only, never
from another figure module.

Conventions (all figures): analytic branches solid where stable and dashed where unstable, simulated
points as open markers, the bottom wall blue and the top wall green as in the paper."""

from __future__ import annotations

import io
import logging
import math
import subprocess
import weakref
import zlib
from collections import Counter
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from matplotlib.transforms import blended_transform_factory

from ...analysis.d_graz import branch_d_graz
from ...analysis.motions import (
    APERIODIC,
    CHAOTIC,
    QUASI_PERIODIC,
    THREE_ONE,
    TWO_ONE,
    UNSETTLED,
    Motion,
    motion_without_period,
    no_period,
    periodic_motion,
)
from ...analysis.windows import window_motions
from ...datasets import write_netcdf
from .. import layout
from ..figdata import figure_data, image_hash, record_wellposed
from ..paper import pi_tex
from ..tables import stable_interval

#: the one matplotlib style file of all figures
STYLE_FILE = Path(__file__).with_name("vibroimpact.mplstyle")

BOTTOM = "tab:blue"
TOP = "tab:green"
#: the 1:1 exit's colour in every figure that marks it (where the 1:1 motion, followed with d decreasing, leaves its
#: family); d_graz's is the 2:1 period-2 motion's (:data:`D_GRAZ_COLOR`, below the motions' colours)
EXIT_COLOR = "tab:purple"
BALL = "tab:red"


def use_style() -> None:
    plt.style.use(STYLE_FILE)


#: file formats a figure can be written in; PNG always (the report and the image check read it)
FORMATS = ("png", "pdf", "svg")


def save(fig, stem, *, data=None, attrs=None, formats=("png", "pdf")) -> list[Path]:
    """Save ``stem.png`` (the committed file kept where the image is the same, :func:`keep_committed_png`) and
    ``stem.<f>`` for the other ``formats`` and, with ``data``, the arrays the
    figure draws (netCDF, :func:`vibroimpact.outputs.figdata.figure_data`, with ``attrs`` such as the config)
    and its layout verdict (attribute ``layout_problems``, :mod:`vibroimpact.outputs.layout`, of the PNG as
    drawn when saved: recorded and logged, never fatal, so the figure is always written; the tests fail on it);
    returns the paths."""

    bad = [f for f in formats if f not in FORMATS]
    if bad or "png" not in formats:
        raise ValueError(f"formats = {list(formats)!r}; allowed: png and any of {FORMATS[1:]}")
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".png")] + [stem.with_suffix(f".{f}") for f in formats if f != "png"]
    # the PNG's layout verdict is found while the PNG is drawn (the layout of the image written)
    with layout.problems_of_the_draw(fig) as problems:
        fig.savefig(paths[0])
    for p in paths[1:]:
        fig.savefig(p)
    keep_committed_png(paths[0])
    if data is not None:
        ds = figure_data(fig, attrs)
        ds.attrs["png_phash"] = image_hash(paths[0])  # the image layer of the regeneration check
        ds.attrs[layout.ATTRIBUTE] = layout.to_attribute(problems)
        for p in problems:
            logging.getLogger(__name__).warning("%s: %s", stem.name, p)
        write_netcdf(ds, data, fmt="NETCDF3_64BIT")
        paths.append(Path(data))
    plt.close(fig)
    return paths


#: grey levels (of 255) by which a pixel may differ and the image still be the same: data moved at rounding
#: level shift an antialiased edge by a fraction of a pixel, which changes its pixels by a level or two
#: (measured: 4 pixels of Figure 5 by one level under another OpenBLAS kernel set)
SAME_IMAGE_LEVELS = 2


def same_image(a: bytes | Path, b: bytes | Path) -> bool:
    """Whether two PNGs (bytes or files) show the same image: the same size, and no pixel of one differs from
    the other's by more than :data:`SAME_IMAGE_LEVELS` grey levels in any channel."""
    from PIL import Image

    def pixels(x):
        with Image.open(io.BytesIO(x) if isinstance(x, bytes) else x) as im:
            return np.asarray(im.convert("RGBA"), dtype=np.int16)

    pa, pb = pixels(a), pixels(b)
    return pa.shape == pb.shape and int(np.abs(pa - pb).max(initial=0)) <= SAME_IMAGE_LEVELS


def committed(path: Path) -> bytes | None:
    """The content git holds at ``HEAD`` for ``path`` (None outside a git work tree, or for a file git does not
    track)."""
    path = Path(path)
    try:
        res = subprocess.run(["git", "-C", str(path.parent), "show", f"HEAD:./{path.name}"], capture_output=True,
                             timeout=60)
    except (OSError, subprocess.SubprocessError):
        return None
    return res.stdout if res.returncode == 0 else None


def keep_committed_png(png: Path) -> bool:
    """Put back the committed bytes of ``png`` where the figure just drawn shows the same image
    (:func:`same_image`): a run that changes no figure leaves a clean clone clean.  Returns whether the file holds the
    committed bytes now.  Most redrawn figures are written byte for byte as committed: those are not decoded."""
    old = committed(png)
    if old is None:
        return False
    new = Path(png).read_bytes()
    if new == old:
        return True
    if not same_image(old, new):
        return False
    Path(png).write_bytes(old)
    return True


def save_outputs(fig, output, *, data=None, attrs=None) -> list[Path]:
    """:func:`save` into a Snakemake rule's named outputs: ``png`` and whichever of the other
    :data:`FORMATS` the rule declares (the quality preset's ``figure_formats``)."""
    formats = [f for f in FORMATS if hasattr(output, f)]
    return save(fig, str(output.png).removesuffix(".png"), data=data, attrs=attrs, formats=formats)


def wellposed(artist, rule: str, *, provenance: str | None = None, timed=(), **fields):
    """Record for a drawn ``artist`` what produced its data and what is well-posed about it, for the figure
    regeneration check (:mod:`vibroimpact.outputs.figcheck`, which compares the artist's arrays by ``rule``,
    whatever one machine measures); :func:`vibroimpact.outputs.figdata.figure_data` saves it beside the
    artist's arrays.  ``provenance``: what produced the data (:data:`vibroimpact.outputs.figcheck.PROVENANCE`;
    by default the rule's); ``timed``: the artist's parts that are timings (not compared).  ``rule``:

    * ``"motions"``: values at simulated attractors; per element ``motion`` (its label), ``settled``
      (the value is exact: a Newton-solved or sticking cycle), ``unsettled`` (no period found but the motion
      settles later: a transient longer than the cap) and ``mean``, ``se`` (the long-run statistic of the
      quantity drawn, where no period was found), each aligned with the artist's points;
    * ``"run"``: a text naming a run of one motion along a sweep, placed at its middle; ``step``: the
      sweep's spacing (each end of the run is known to one point); ``merged``: it names merged short runs,
      whose motions interleave (its text is not compared);
    * ``"placed"``: a text the layout placed at one of several anchors; ``free``: the coordinates the layout
      chose (``"x"``, ``"y"``), not compared; ``step_x``, ``step_y``: the others' grid steps
      (:func:`vibroimpact.outputs.layout.place_labels` records it where the candidates' anchors differ);
    * ``"located"``: values located between neighbouring points of a grid (a transition along a sweep,
      the 1:1 exit); ``step_x``, ``step_y``: the grid's step along each coordinate (none: pointwise);
    * ``"curve"``: a curve sampled by continuation (its points lie on the curve; where they lie along it
      depends on the step control);
    * ``"on curve"``: points located on sampled curves (events, crossings), known to within a segment;
    * ``"boundary"``: points between grid cells whose motions differ;
    * ``"magnitude"``: errors against a reference, as orders of magnitude; ``floor``: the rounding level
      below which an error is a count of ulps;
    * ``"outcome"``: categorical outcomes (codes of an image, or a cell's mark); ``sensitive``: the cells whose
      outcome a start one ulp away changed;
    * ``"timing"``: a wall-clock time, not compared.
    """
    return record_wellposed(artist, rule, provenance=provenance, timed=timed, **fields)


def pi_label(x, unit=""):
    tex = pi_tex(x)
    return (f"${tex}$" if "\\pi" in tex else tex) + unit



def beta_label(beta):
    return "$\\beta=" + pi_tex(beta, ".4f") + "$"


def branch_line(ax, d, y, stable, color, lw=1.2, zorder=2):
    """Solid where stable, dashed where unstable (admissible points only are passed in)."""

    ys = np.where(stable, y, np.nan)
    yu = np.where(~stable, y, np.nan)
    # overlap one point so that the two styles join
    edge = np.flatnonzero(np.diff(stable.astype(int)) != 0)
    for e in edge:
        yu[e:e + 2] = y[e:e + 2]
    ax.plot(d, ys, "-", color=color, lw=lw, zorder=zorder)
    ax.plot(d, yu, "--", color=color, lw=lw * 0.8, zorder=zorder)


# ---- one colour and one name per motion, the same in every figure (regime maps, bifurcation sets, basins,
# Figure 8, the lambda_1 figure) ----------------------------------------------------------------------------------
#: the motions the paper names and the most frequent others, each a :class:`~vibroimpact.analysis.motions.Motion`
#: (its name is its label): colour-blind-safe colours (Okabe-Ito, Tol), a period doubling lighter or of a
#: neighbouring hue; 3:1 blue as in the paper's Figure 8, close to the bottom wall's (BOTTOM): where both appear
#: (Figure 8) the walls are shaded, not lines; the bottom stick-release cycle brown, as every motion with sticking.
#: The motions with no period are greys (darker the surer the chaos).
MOTION_COLORS: dict[Motion, str] = {
    periodic_motion(1, 1): "#009E73", periodic_motion(1, 1, 2): "#56B4E9", periodic_motion(1, 1, 4): "#CC79A7",
    periodic_motion(2, 1): "#D55E00", periodic_motion(2, 1, 2): "#E69F00", periodic_motion(2, 1, 4): "#F0E442",
    periodic_motion(3, 1): "#0072B2", periodic_motion(3, 1, 2): "#332288", periodic_motion(4, 1): "#882255",
    periodic_motion(2, 2): "#999933", periodic_motion(2, 2, 2): "#117733", periodic_motion(3, 2): "#AA4499",
    Motion(period=2, bottom=1, top=0, sticking=True): "#8C510A",
    motion_without_period(APERIODIC): "#EBEBEB", motion_without_period(CHAOTIC): "#262626",
    motion_without_period(QUASI_PERIODIC): "#737373", motion_without_period(UNSETTLED): "#BFBFBF",
}
#: the legend entry of the motions a figure does not name, and its colour (beige)
OTHER, OTHER_COLOR = "other", "#DDCCA8"
#: the colour of each motion of :data:`MOTION_COLORS` by its name, and of :data:`OTHER`
COLOR_BY_LABEL = {m.label: c for m, c in MOTION_COLORS.items()} | {OTHER: OTHER_COLOR}
#: d_graz, the largest d of 2:1 period-2 (the 2:1 branch's fold), in every figure that marks it: the 2:1 period-2
#: motion's colour, as the 2:1 fold's curve in the bifurcation sets (the same point followed in two parameters)
D_GRAZ_COLOR = MOTION_COLORS[TWO_ONE]

#: the points figures mark on a d axis (:func:`located_marks`), each in one colour and
#: line style and under one name in every figure: name -> (colour, line style, legend entry)
MARKS = {
    "d_graz": (D_GRAZ_COLOR, ":", rf"$d_{{\rm graz}}$: the largest d of {TWO_ONE.label} (the 2:1 branch's fold)"),
    "1:1 exit: grazing": (EXIT_COLOR, "-.", "1:1 exit: grazing (the 1:1 motion, d decreasing, grazes the bottom wall "
                                           "and leaves its family)"),
    "1:1 exit: jump": (EXIT_COLOR, "--", "1:1 exit: jump (the 1:1 motion, d decreasing, leaves its family clear of "
                                        "the walls)"),
    "G1": ("k", "-.", "G1: the 2:1 orbit grazes, 3:1 born"),
}

#: the names the captions and pages give the colours and line styles things are drawn in (tested against the drawing)
COLOR_NAMES = {MOTION_COLORS[TWO_ONE]: "vermillion", MOTION_COLORS[THREE_ONE]: "blue", EXIT_COLOR: "purple",
               "k": "black", "tab:brown": "brown"}
STYLE_NAMES = {"-": "solid", "--": "dashed", ":": "dotted", "-.": "dash-dotted"}

#: colours of the other periodic motions, and of the other motions with sticking (browns), by :func:`motion_color`
EXTRA_COLORS = ("#CC6677", "#BBCC33", "#EE8866", "#FFAABB", "#E7298A", "#99DDFF")
STICKING_COLORS = ("#BF812D", "#6B3A07")


def motion_color(motion: Motion | str, sticking: bool = False) -> str:
    """The colour of a motion, whichever figure draws it and however often it occurs there.

    Parameters
    ----------
    motion : Motion or str
        A motion, or its label (:attr:`vibroimpact.analysis.motions.Motion.label`, as the datasets hold it), or
        :data:`OTHER`.
    sticking : bool
        Whether the motion's cycle sticks to a wall (the datasets' ``sticking``, :func:`sticking_motions`); a
        :class:`~vibroimpact.analysis.motions.Motion` says so itself.

    Returns
    -------
    str
        Its colour in :data:`MOTION_COLORS` (or :data:`OTHER_COLOR`) where listed; else one of ``STICKING_COLORS``
        (a motion with sticking) or of ``EXTRA_COLORS``, chosen by the label's CRC-32, so the same on every run and
        machine.  Two unlisted motions can share one: a figure that names motions names only the more frequent of
        them.
    """

    if isinstance(motion, Motion):
        label, sticking = motion.label, motion.sticking
    else:
        label = str(motion)
    if label in COLOR_BY_LABEL:
        return COLOR_BY_LABEL[label]
    pool = STICKING_COLORS if sticking else EXTRA_COLORS
    return pool[zlib.crc32(label.encode()) % len(pool)]


def sticking_motions(*datasets) -> frozenset[str]:
    """The labels of the motions with sticking in ``datasets`` (each with ``label`` and ``sticking``)."""
    return frozenset(str(lab) for ds in datasets
                     for lab in np.asarray(ds["label"].values)[np.asarray(ds["sticking"].values, dtype=bool)])


# ---------------------------------------------------------------------------------------------------------------------
# Names and ticks
# ---------------------------------------------------------------------------------------------------------------------


def word_ratio(word: str) -> str:
    """The paper's name ``n:m`` of an orbit word (``"BBT"`` -> ``"2:1"``: bottom and top impacts per period)."""
    return f"{word.count('B')}:{word.count('T')}"


def pi_ticks(ax, lo, hi):
    """Ticks of an angle axis at the fractions of pi inside [lo, hi]."""
    ticks = [f * math.pi for f in (1 / 12, 1 / 6, 1 / 4, 1 / 3, 5 / 12, 1 / 2) if lo <= f * math.pi <= hi]
    ax.set_yticks(ticks, [pi_label(t) for t in ticks])


# ---------------------------------------------------------------------------------------------------------------------
# The simulated points of a sweep, and what the figure check compares of them
# ---------------------------------------------------------------------------------------------------------------------


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


def last_events(ds, var, direction="down", labels=False, info=False):
    """(d, values) of every point's last period of events in one sweep direction: its exact cycle from
    the canonical first impact where the sweep settled it (:func:`vibroimpact.analysis.settled.settle_attractors`), else the
    recorded last period (the last 24 events where no period was found); ``var="dt"`` gives the time
    since the previous event.  With ``labels``, also each value's point's identified motion; with
    ``info``, a dict per element (:func:`point_info`) instead."""

    s = ds.sel(direction=direction)
    cyc = _CYCLE.get(var)
    have = cyc is not None and cyc in s
    # the arrays once, as numpy's (indexing xarray point by point costs a figure seconds)
    cycles = s[cyc].values if have else None
    period = s["period"].values if "period" in s else None
    times = s["t"].values if "t" in s else None
    values = s[var].values if var in s else None
    period_events = s["period_events"].values if "period_events" in s else None
    d = s.d.values
    xs, ys, pts = [], [], []
    for i in range(s.sizes["point"]):
        c = cycles[i] if have else None
        if have and np.isfinite(c).any() and (var != "dt" or period is not None):
            if var == "dt":
                tt = c[np.isfinite(c)]
                v = np.diff(np.concatenate([[tt[-1] - 2.0 * float(period[i])], tt]))
            else:
                v = c[np.isfinite(c)]
        else:
            t = times[i] if times is not None else values[i]
            m = int(np.isfinite(t).sum())
            n = (int(period_events[i]) if period_events is not None else 0) or min(m, 24)
            v = np.diff(t[max(m - n - 1, 0):m]) if var == "dt" else values[i, m - n:m]
            v = v[np.isfinite(v)]
        xs.append(np.full(v.size, float(d[i])))
        ys.append(v)
        pts.append(np.full(v.size, i))
    x, y, pts = np.concatenate(xs), np.concatenate(ys), np.concatenate(pts)
    if info:
        return x, y, point_info(s, pts, var)
    if labels:
        return x, y, s["label"].values.astype(str)[pts]
    return x, y


# ---------------------------------------------------------------------------------------------------------------------
# Panels of a sweep along d
# ---------------------------------------------------------------------------------------------------------------------


#: simulated points: grey, under the analytic lines
SIM_COLOR = "0.45"


def sweep_step(sw) -> float:
    """The largest spacing in d of a sweep's points."""
    return float(np.max(np.diff(sw.d.values))) if sw.sizes["point"] > 1 else 0.0


def secondary_axis(ax, sw):
    """The physical parameter the sweep varies on a second x axis: s = d ||F|| / k is linear in d, and
    ||F|| = k s / d its inverse (d = k s / ||F||, k = M omega^2 / pi^2; the constant from the sweep's
    own s, F and d)."""
    vary = sw.attrs["vary"]
    with np.errstate(divide="ignore", invalid="ignore"):
        if vary == "s":
            c = float(np.median(sw.s.values / sw.d.values))
            fwd, inv = (lambda v: c * np.asarray(v, float)), (lambda v: np.asarray(v, float) / c)
        else:
            c = float(np.median(sw.F.values * sw.d.values))

            def fwd(v):
                v = np.asarray(v, float)
                return np.divide(c, v, out=np.full_like(v, np.inf), where=v != 0)

            inv = fwd
    sec = ax.secondary_xaxis("top", functions=(fwd, inv))
    if vary == "F":  # 1/d crowds evenly spaced forces at small d: ticks at round forces in the sweep's range
        F = sw.F.values
        sec.set_xticks([f for f in (4, 5, 6, 7, 8, 10, 12, 15, 18, 22, 26, 30) if F.min() <= f <= F.max()])
    sec.set_xlabel("cylinder length s (m)" if vary == "s" else r"forcing amplitude $\|\hat F\|$ (N)", fontsize=7)
    sec.tick_params(labelsize=6)


def panel_title(sw, letter):
    """A sweep panel's title: its letter, incline and the range of the parameter it varies, the other held."""
    vary = sw.attrs["vary"]
    rng = sw[vary].values
    if vary == "s":
        span, fixed = f"{rng.min():g} < s < {rng.max():g} m", rf"$\|\hat F\|$ = {sw.F.values[0]:g} N"
    else:
        span, fixed = rf"{rng.min():g} < $\|\hat F\|$ < {rng.max():g} N", f"s = {sw.s.values[0]:g} m"
    return f"({letter}) {beta_label(sw.attrs['beta'])}, {span}, {fixed}"


def sim_points(ax, sw, var, scale=1.0, *, every=False):
    """The last period of events of every sweep point (24 events where no period was found): the down sweep
    (d decreasing, o) and the up sweep (+), thinned to every other point each (the down sweep's even points,
    the up sweep's odd ones), or with ``every`` at every point both."""
    for direction, marker, keep in (("down", "o", 0), ("up", "+", 1)):
        sub = sw if every else sw.isel(point=slice(keep, None, 2))
        x, y, info = last_events(sub, var, direction, info=True)
        line = ax.plot(x, np.abs(y) * scale, marker, mfc="none", color=SIM_COLOR, ms=2.2, mew=0.5, ls="none",
                       zorder=2)[0]
        record_motions(line, info, scale)


def record_motions(artist, info, scale=1.0):
    """What the check compares of simulated points (:func:`vibroimpact.outputs.plots._common.wellposed`), in the
    units drawn."""
    wellposed(artist, "motions", **(info | {"mean": info["mean"] * scale, "se": info["se"] * scale}))


# ---------------------------------------------------------------------------------------------------------------------
# The motions named over a sweep panel
# ---------------------------------------------------------------------------------------------------------------------


#: the ``gid`` of a motion's name written over a panel (:func:`motion_runs`), which :func:`rows_of_names` places
RUN_NAME = "motion-run-name"


#: each such name's run: its first and last d (the name is kept beside it)
RUN_SPANS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


#: a run of one motion along a sweep is named over its panel when it holds at least this many points
MIN_POINTS = 5


#: the most motions a name of merged short runs lists (the most frequent first)
MAX_NAMED = 3


#: how a name of merged short runs lists the periodic motions without a short name (k:m over n forcing periods)
WINDOWS = "periodic windows"


#: what the names over a panel say (:func:`motion_runs`), for its legend
RUNS_NOTE = ("Over each panel: the down sweep's motion (T = its period in t; chaotic: no period, $\\lambda_1$ above 0; "
             "unsettled: no period within the cap,\nits transient still converging; a gap between names: fewer than "
             f"{MIN_POINTS} points of one motion, or of short runs together).")


def motion_blocks(labels, min_points=MIN_POINTS, names=None):
    """The runs of one motion along a sweep that a panel names, as ``[(first, end, name)]`` (point indices,
    ``end`` exclusive).

    Consecutive points with one label make a run.  A run of at least ``min_points`` points is named by its
    motion: a periodic one by ``names[label]`` (its :attr:`~vibroimpact.analysis.motions.Motion.short_label`; the
    label where ``names`` lacks it), one with no period by its label (chaotic, quasi-periodic, unsettled, no
    period found), the same name for the same motion in every panel.  Consecutive shorter runs are merged; a
    merged block of at least ``min_points`` points is named by the motions it holds, the most frequent first
    (:data:`MAX_NAMED` of them, "…" for the others; the periodic motions without a short name together as
    :data:`WINDOWS`); a shorter one is not named (the gap :data:`RUNS_NOTE` explains)."""

    lab = np.asarray(labels).astype(str)
    if not lab.size:
        return []
    edges = np.flatnonzero(lab[1:] != lab[:-1]) + 1
    starts, ends = np.r_[0, edges], np.r_[edges, lab.size]
    long_ = (ends - starts) >= min_points
    blocks, k = [], 0
    while k < starts.size:
        if long_[k]:
            a, b = starts[k], ends[k]
            blocks.append((int(a), int(b), (names or {}).get(lab[a], lab[a])))
            k += 1
            continue
        j = k
        while j < starts.size and not long_[j]:
            j += 1
        a, b = starts[k], ends[j - 1]
        if b - a >= min_points:
            # a periodic motion by its short name where it has one (n:1 T=k), else among the "periodic windows"
            held = list(dict.fromkeys(m if no_period(m) or " over " not in (names or {}).get(m, m) else WINDOWS
                                      for m, _ in Counter(lab[a:b].tolist()).most_common()))
            shown = [(names or {}).get(m, m) for m in held[:MAX_NAMED]]
            blocks.append((int(a), int(b), ", ".join(shown) + (", …" if len(held) > MAX_NAMED else "")))
        k = j
    return blocks


def motion_runs(ax, sw, direction="down", min_points=MIN_POINTS):
    """The motion identified along the sweep, written over the top of the panel where it holds for
    at least ``min_points`` points (:func:`motion_blocks`), so every cloud of points can be read
    against it."""

    d = sw.d.values
    tr = blended_transform_factory(ax.transData, ax.transAxes)
    step = sweep_step(sw)
    s = sw.sel(direction=direction)
    names = {m.label: m.short_label for m in window_motions(s)}
    for a, b, name in motion_blocks(s.label.values, min_points, names):
        single = len(set(s.label.values[a:b].astype(str))) == 1
        ax.annotate("", (d[a], 0.985), (d[b - 1], 0.985), xycoords=tr, arrowprops=dict(arrowstyle="|-|", lw=0.5,
                    color="0.4", shrinkA=0, shrinkB=0, mutation_scale=2))
        text = ax.text(0.5 * (d[a] + d[b - 1]), 0.965, name, transform=tr, ha="center", va="top", fontsize=5,
                       color="0.25")
        text.set_gid(RUN_NAME)  # placed in rows by rows_of_names once the figure is laid out
        RUN_SPANS[text] = (float(d[a]), float(d[b - 1]))
        # a name of merged short runs lists motions that interleave where they meet: which, and in what order,
        # moves with any point there
        wellposed(text, "run", step=step, merged=not single)


#: how much an axis' top is raised at a time to clear its motion names of markers, and at most how often
RAISE, MAX_RAISE = 0.05, 20


def rows_of_names(fig, row_height=0.045, pad=3.0):
    """Once the figure is laid out (drawn once): each panel's motion names (:func:`motion_runs`), left to
    right, each in the highest row where it comes within ``pad`` pixels of no name already placed, at its run's
    middle or moved sideways by up to its width while it stays over its run and inside the panel; then the
    panel's top raised (by :data:`RAISE` of its height at a time) until no name covers a marker."""
    home = {t: t.get_position() for ax in fig.axes for t in ax.texts if t.get_gid() == RUN_NAME}
    # a raised top changes the tick labels and so the layout: the names are placed again in the new one
    for _ in range(3):
        if not _place_names(fig, home, row_height, pad):
            break


def _place_names(fig, home, row_height, pad) -> bool:
    """One pass of :func:`rows_of_names` from the names' first places ``home``: whether a panel's top was raised."""
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    raised = False
    for ax in fig.axes:
        names = sorted((t for t in ax.texts if t.get_gid() == RUN_NAME), key=lambda t: home[t][0])
        for t in names:
            t.set_position(home[t])
        frame = ax.get_window_extent(renderer)
        to_px = ax.transData.transform
        placed = []  # the extents of the names placed
        for text in names:
            box = text.get_window_extent(renderer)
            span = [to_px((x, 0.0))[0] for x in RUN_SPANS.get(text, (text.get_position()[0],) * 2)]
            x0, y0 = text.get_position()
            w = box.width
            shifts = [k * w / 3 for k in (0, 1, -1, 2, -2, 3, -3)]
            ok = [dx for dx in shifts if box.x0 + dx >= frame.x0 + pad and box.x1 + dx <= frame.x1 - pad
                  and box.x1 + dx > span[0] - pad and box.x0 + dx < span[1] + pad]
            if not ok:  # a name wider than the room at an end of the axis: flush with that end
                ok = [frame.x0 + pad - box.x0 if box.x0 < frame.x0 + pad else frame.x1 - pad - box.x1]
            for row in range(len(names) + 1):
                here = [box.translated(dx, -row * row_height * frame.height) for dx in ok]
                free = [dx for dx, c in zip(ok, here, strict=True)
                        if not any(c.padded(pad).overlaps(q) for q in placed)]
                if free:
                    break
            x_px = to_px((x0, 0.0))[0] + free[0]
            text.set_x(ax.transData.inverted().transform((x_px, 0.0))[0])
            text.set_y(y0 - row_height * row)
            placed.append(text.get_window_extent(renderer))
        # room for the names: the axis' top raised until no name covers a marker (the names stay where they are, at
        # fractions of the axes' height, so their extents too; the data move down)
        for _ in range(MAX_RAISE):
            if not any(layout.markers_under(ax, box) for box in placed):
                break
            lo_y, hi_y = ax.get_ylim()
            ax.set_ylim(lo_y, hi_y + RAISE * (hi_y - lo_y))
            raised = True
    return raised


# ---------------------------------------------------------------------------------------------------------------------
# Points marked on a d axis
# ---------------------------------------------------------------------------------------------------------------------


def located_marks(orbit_branches, transitions=None):
    """The points Figures 2 and 9 mark on the d axis, by their names in :data:`~vibroimpact.outputs.plots._common.MARKS`:
    d_graz, the largest d of 2:1 period-2 (the continued 2:1 branch's fold, :func:`vibroimpact.branch_d_graz`);
    the 1:1 exit, where the 1:1 motion followed with d decreasing leaves the 1:1 family (the sweep's located
    ``transitions``, :func:`vibroimpact.sweep_family_exit`: ``"1:1 exit: grazing"`` or ``"1:1 exit: jump"``); and
    G1, the lower end of the 2:1 orbit's stable interval when a grazing ends it (the 3:1 orbit is born).
    ``[(name, d)]``."""

    marks = []
    for br in orbit_branches:
        if br.attrs.get("word") == "BBT" and br.attrs.get("status") != "failed" and "critical_d" in br:
            d, _ = branch_d_graz(br)
            if np.isfinite(d):
                marks.append(("d_graz", d))
    if transitions is not None and "exit_d" in transitions and np.isfinite(float(transitions.exit_d)):
        marks.append((f"1:1 exit: {str(transitions.exit_kind.values)}", float(transitions.exit_d)))
    for br in orbit_branches:
        if br.attrs.get("status") == "failed" or "critical_d" not in br or br.attrs.get("word") != "BBT":
            continue
        lo, _hi, cause_lo, _ = stable_interval(br)
        if cause_lo == "grazing":
            marks.append(("G1", lo))
    return marks


#: the text naming a marked line in a panel, where it is not the mark's name itself
MARK_TEXT = {"d_graz": r"$d_{\rm graz}$"}


def mark_style(name: str) -> tuple[str, str, str]:
    """Colour, line style and legend entry of a marked point (:data:`~vibroimpact.outputs.plots._common.MARKS`; the
    period doublings B and folds of the continued branches, ``"B (1:1)"``, ``"fold (1:1)"``, dotted brown and
    olive)."""
    if name in MARKS:
        return MARKS[name]
    if name.startswith("B ("):
        return "tab:brown", ":", "B: period doubling (1:1 or 2:1 branch)"
    return "tab:olive", ":", f"{name.split(' (')[0]} of the {name.split('(')[-1].rstrip(')')} branch"


def mark_located(ax, marks, step=0.0, *, names=True):
    """Vertical lines at the points ``marks`` (:func:`located_marks`; ``[(name, d)]``), each in its colour and line
    style (:func:`mark_style`).  Returns the names to write beside them once the figure is laid out
    (:func:`name_marks`; none with ``names=False``).  The 1:1 exit is located along the sweep (``step``: its grid
    step, to which the check holds it where its location is ill-conditioned); d_graz, G1 and the branches' points
    are analytic."""
    todo = []
    for name, d in marks:
        color, ls, _ = mark_style(name)
        line = ax.axvline(d, color=color, ls=ls, lw=0.8, zorder=3)
        if name.startswith("1:1 exit"):
            wellposed(line, "located", step_x=step)
        if names:
            todo.append((ax, name, d, step))
    return todo


#: where a marked line's name may go, in order of preference (a place up the line, in axes fraction, from which
#: the upright name rises; its side and distance, in points): beside the line from the foot up, then farther off
#: with a leader line to it where the data leave no room beside it
NAME_PLACES = [(y, (dx, 1)) for dx in (2, -2, 14, -14, 26, -26) for y in (0.02, 0.2, 0.4, 0.6)]


def name_marks(fig, todo, fontsize=5.5):
    """Write each marked line's name (:func:`mark_located`) upright beside it, where it covers no text, marker or
    line (:func:`vibroimpact.outputs.layout.place_labels`); call once the figure is laid out."""
    requests = [(ax, MARK_TEXT.get(name, name), [((d, y), off) for y, off in NAME_PLACES],
                 dict(xycoords=("data", "axes fraction"), fontsize=fontsize, color=mark_style(name)[0], rotation=90))
                for ax, name, d, _ in todo]
    for text, (_, name, _, step) in zip(layout.place_labels(fig, requests), todo, strict=True):
        if name.startswith("1:1 exit"):  # located along the sweep: its d to a grid step, its place the layout's
            wellposed(text, "placed", provenance="layout", free="y", step_x=step)


def mark_handles(names):
    """Legend entries of the marks drawn (:func:`located_marks`' and :func:`mark_style`'s names), one per kind."""
    entries = {}
    for name in sorted(names, key=lambda n: (list(MARKS).index(n) if n in MARKS else len(MARKS), n)):
        color, ls, label = mark_style(name)
        entries.setdefault(label, Line2D([], [], color=color, ls=ls, label=label))
    return list(entries.values())


# ---------------------------------------------------------------------------------------------------------------------
# The curves of the bifurcation sets
# ---------------------------------------------------------------------------------------------------------------------


#: line style per kind of codimension-one point, and colour per orbit family
_CURVE_STYLE = {"B": "--", "fold": ":", "grazing": "-", "A": "-."}


_CURVE_NAME = {"B": "period doubling B", "fold": "fold", "grazing": "grazing", "A": "node-focus A"}


_WORD_COLOUR = {"BT": "#000000", "BBT": MOTION_COLORS[TWO_ONE], "BBBT": MOTION_COLORS[THREE_ONE]}


WORD_NAME = {"BT": "1:1", "BBT": "2:1", "BBBT": "3:1"}


def curve_pieces(curves, xname, yname):
    """Each curve of a bifurcation set (:func:`vibroimpact.analysis.bifurcation.curve_set`) as drawn: its points in
    the plane ``(xname, yname)``, where its orbit is admissible, and its line style (by kind), colour (by
    orbit family) and legend label."""
    for c in range(curves.sizes["curve"]):
        sel = curves.curve_index.values == c
        if not sel.any():
            continue
        kind, word = str(curves.curve_kind.values[c]), str(curves.curve_word.values[c])
        label = f"{WORD_NAME.get(word, word)} {_CURVE_NAME.get(kind, kind)}"
        if kind == "grazing" and "curve_start_stable" in curves and not bool(curves.curve_start_stable.values[c]):
            label += " (of an unstable orbit)"  # a grazing no attractor meets
        if (word, kind) == D_GRAZ_CURVE:
            label += " = " + D_GRAZ_NAME
        yield (curves[xname].values[sel], curves[yname].values[sel], curves.admissible.values[sel],
               _CURVE_STYLE.get(kind, "-"), _WORD_COLOUR.get(word, "0.3"), label)


#: the curve of the bifurcation sets that is the paper's d_graz followed in two parameters: the 2:1 fold (the largest d
#: of 2:1 period-2), named so in the legend
D_GRAZ_CURVE = ("BBT", "fold")


D_GRAZ_NAME = rf"$d_{{\rm graz}}$ (largest d of {TWO_ONE.label})"
