"""What every figure shares: the style file, the colours of the paper's conventions, saving a figure with
the arrays it draws, and labels with fractions of pi.

Conventions (all figures): analytic branches solid where stable and dashed where unstable, simulated
points as open markers, the bottom wall blue and the top wall green as in the paper."""

from __future__ import annotations

import io
import logging
import subprocess
import zlib
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from ...datasets import write_netcdf
from .. import layout
from ..figdata import figure_data, image_hash, record_wellposed
from ..paper import pi_tex

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
    and its layout verdict (attribute ``layout_problems``, :mod:`vibroimpact.outputs.layout`: recorded and
    logged, never fatal, so the figure is always written; the tests fail on it); returns the paths."""

    bad = [f for f in formats if f not in FORMATS]
    if bad or "png" not in formats:
        raise ValueError(f"formats = {list(formats)!r}; allowed: png and any of {FORMATS[1:]}")
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [stem.with_suffix(".png")] + [stem.with_suffix(f".{f}") for f in formats if f != "png"]
    for p in paths:
        fig.savefig(p)
    keep_committed_png(paths[0])
    if data is not None:
        ds = figure_data(fig, attrs)
        ds.attrs["png_phash"] = image_hash(paths[0])  # the image layer of the regeneration check
        problems = layout.layout_problems(fig)
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
    (:func:`same_image`): a run that changes no figure leaves a clean clone clean.  Returns whether it did."""
    old = committed(png)
    if old is None or not same_image(old, Path(png)):
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


# ---- one colour per motion, the same in every figure (regime maps, bifurcation sets, basins, Fig BiS) ----------
#: the motions the paper names and the most frequent others: colour-blind-safe colours (Okabe-Ito, Tol), a
#: period doubling lighter or of a neighbouring hue; 3:1 blue as in the paper's Fig BiS, close to the bottom
#: wall's (BOTTOM): where both appear (Fig BiS) the walls are shaded, not lines; the bottom stick-release
#: cycle brown, as every motion with sticking.  Labels of a motion with no period are greys
#: (darker the surer the chaos), "other" (the motions a figure does not name) beige.
MOTION_COLORS = {
    "1:1 period-2": "#009E73", "1:1 period-4": "#56B4E9", "1:1 period-8": "#CC79A7",
    "2:1 period-2": "#D55E00", "2:1 period-4": "#E69F00", "2:1 period-8": "#F0E442",
    "3:1 period-2": "#0072B2", "3:1 period-4": "#332288", "4:1 period-2": "#882255",
    "2:2 period-2": "#999933", "2:2 period-4": "#117733", "3:2 period-2": "#AA4499",
    "1:0 over 2 forcing periods with sticking": "#8C510A",
    "no period found": "#EBEBEB", "chaotic": "#262626", "quasi-periodic": "#737373", "unsettled": "#BFBFBF",
    "other": "#DDCCA8",
}
#: d_graz, the largest d of 2:1 period-2 (the 2:1 branch's fold), in every figure that marks it: the 2:1 period-2
#: motion's colour, as the 2:1 fold's curve in the bifurcation sets (the same point followed in two parameters)
D_GRAZ_COLOR = MOTION_COLORS["2:1 period-2"]

#: the points figures mark on a d axis (:func:`vibroimpact.outputs.plots.energy.located_marks`), each in one colour and
#: line style and under one name in every figure: name -> (colour, line style, legend entry)
MARKS = {
    "d_graz": (D_GRAZ_COLOR, ":", r"$d_{\rm graz}$: the largest d of 2:1 period-2 (the 2:1 branch's fold)"),
    "1:1 exit: grazing": (EXIT_COLOR, "-.", "1:1 exit: grazing (the 1:1 motion, d decreasing, grazes the bottom wall "
                                           "and leaves its family)"),
    "1:1 exit: jump": (EXIT_COLOR, "--", "1:1 exit: jump (the 1:1 motion, d decreasing, leaves its family clear of "
                                        "the walls)"),
    "G1": ("k", "-.", "G1: the 2:1 orbit grazes, 3:1 born"),
}

#: the names the captions and pages give the colours and line styles things are drawn in (tested against the drawing)
COLOR_NAMES = {MOTION_COLORS["2:1 period-2"]: "vermillion", MOTION_COLORS["3:1 period-2"]: "blue", EXIT_COLOR: "purple",
               "k": "black", "tab:brown": "brown"}
STYLE_NAMES = {"-": "solid", "--": "dashed", ":": "dotted", "-.": "dash-dotted"}

#: colours of the other periodic motions, and of the other motions with sticking (browns), by :func:`motion_color`
EXTRA_COLORS = ("#CC6677", "#BBCC33", "#EE8866", "#FFAABB", "#E7298A", "#99DDFF")
STICKING_COLORS = ("#BF812D", "#6B3A07")


def motion_color(label: str, sticking: bool = False) -> str:
    """The colour of a motion, whichever figure draws it and however often it occurs there.

    Parameters
    ----------
    label : str
        A motion's label (:attr:`vibroimpact.analysis.motions.Motion.label`, the no-period labels of
        :mod:`vibroimpact.analysis.motions`, or ``"other"``).
    sticking : bool
        Whether the motion's cycle sticks to a wall (the datasets' ``sticking``, :func:`sticking_motions`).

    Returns
    -------
    str
        ``MOTION_COLORS[label]`` where listed; else one of ``STICKING_COLORS`` (a motion with sticking) or of
        ``EXTRA_COLORS``, chosen by the label's CRC-32, so the same on every run and machine.  Two unlisted
        motions can share one: a figure that names motions names only the more frequent of them.
    """

    label = str(label)
    if label in MOTION_COLORS:
        return MOTION_COLORS[label]
    pool = STICKING_COLORS if sticking else EXTRA_COLORS
    return pool[zlib.crc32(label.encode()) % len(pool)]


def sticking_motions(*datasets) -> frozenset[str]:
    """The labels of the motions with sticking in ``datasets`` (each with ``label`` and ``sticking``)."""
    return frozenset(str(lab) for ds in datasets
                     for lab in np.asarray(ds["label"].values)[np.asarray(ds["sticking"].values, dtype=bool)])
