"""What a referee sees first: texts that overprint, texts cut off, legends over data.

:func:`layout_problems` draws a figure and reads the window extent of every artist it drew
(:func:`problems_of_the_draw` reads them from a draw made anyway, a ``savefig``'s):

* two texts (titles, axis and tick labels, annotations, suptitles, ...) whose extents overlap or come
  closer than :data:`TOLERANCE_PT`;
* a text that leaves the figure, and a text placed in an axes (an annotation) that crosses the axes'
  frame (a note set wholly beside the axes is fine);
* a legend whose box covers a text other than its own entries (they are laid out by the legend), or
  data of an axes under it: a marker, a point of a scatter, or a drawn line crossing the box (a reference
  line such as lambda = -1 or a wall is data the reader must see, and a curve under a half-transparent
  frame is hidden all the same).  A marker counts when its centre is under the box (one whose centre is
  outside stays at least half visible).  Filled areas and maps (images, meshes, polygons) are not
  checked: a legend over a shaded band or a map's cells is a choice of the figure, not a hidden point;
* a text (a label, a name written in a panel, a title) over plotted markers: a marker of a line or a point of
  a scatter, inside its axes, whose centre the text's own box covers (lines and areas under a text are not
  counted: a name set over a curve still reads);
* a legend entry that draws nothing: its marker (shape and colour) or its line (style and colour) or its
  filled patch (colour) is not drawn by any artist of the figure.  An entry that keys a style rather than a
  thing drawn in its colour ("stable: solid", in grey, over lines of every colour) is declared so by
  :func:`style_keys` and matches that style in any colour.

Only what the renderer drew counts: invisible artists, empty strings, tick labels beyond the view
limits and annotations clipped away are never drawn, so never reported.  Artists are named as in the
figure's saved data (:func:`vibroimpact.outputs.figdata.figure_data`): axes ``a<i>``, line ``a<i>_line<j>``.
"""

from __future__ import annotations

import json
import sys
import weakref
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.collections import Collection, LineCollection, PathCollection
from matplotlib.colors import to_hex, to_rgba, to_rgba_array
from matplotlib.legend import Legend
from matplotlib.lines import Line2D
from matplotlib.markers import MarkerStyle
from matplotlib.patches import Patch
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from .figdata import record_wellposed

#: texts closer than this (points) overprint: an extent is the box of a text's advance and line height,
#: so two labels set less than a point apart read as one word ("h=0.02h=0.01"); a text crosses an edge,
#: or a legend covers something, only by more than this: extents are rounded out to whole pixels (a
#: point is 1.5 to 2 pixels at the 110 to 150 dpi figures are drawn and saved at)
TOLERANCE_PT = 1.0

#: the attribute of a figure's saved data (:func:`vibroimpact.outputs.plots._common.save`) with its verdict
ATTRIBUTE = "layout_problems"


@contextmanager
def _drawn_texts():
    """The texts drawn while the context is open (every ``Text.draw`` call, ``Annotation`` included)."""
    drawn = {}
    original = Text.draw

    def draw(self, renderer):
        drawn[id(self)] = self
        return original(self, renderer)

    Text.draw = draw
    try:
        yield drawn
    finally:
        Text.draw = original


def _owners(fig):
    """Each artist's parent (by id), walking the figure's tree of children."""
    parent, stack = {}, [fig]
    while stack:
        a = stack.pop()
        for c in a.get_children():
            if id(c) not in parent:
                parent[id(c)] = a
                stack.append(c)
    return parent


def _ancestor(artist, parent, kind):
    while artist is not None and not isinstance(artist, kind):
        artist = parent.get(id(artist))
    return artist


def _axes_name(ax) -> str:
    """``axes a<i> '<first line of its title>'``: ``i`` as in the figure's saved data."""
    i = ax.figure.get_axes().index(ax)
    title = " ".join(t for t in (ax.get_title("left"), ax.get_title(), ax.get_title("right")) if t)
    return f"axes a{i}" + (f" '{_short(title)}'" if title else "")


def _short(s: str, n: int = 40) -> str:
    s = s.split("\n")[0]
    return s if len(s) <= n else s[: n - 3] + "..."


def _describe(t, parent) -> str:
    """A drawn text for a reader: its string and what it is (title, tick label, ...) of which axes."""
    s = _short(t.get_text())
    leg = _ancestor(t, parent, Legend)
    ax = _ancestor(t, parent, Axes)
    where = _axes_name(ax) if ax is not None else "the figure"
    if leg is not None:
        return f"'{s}' (legend of {where})"
    if ax is None:
        return f"'{s}' (figure text)"
    role = "text"
    if t in (ax.title, ax._left_title, ax._right_title):
        role = "title"
    for name, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
        if t is axis.label:
            role = f"{name} label"
        elif t is axis.offsetText:
            role = f"{name} offset"
        elif _ancestor(t, parent, type(axis)) is axis:
            role = f"{name} tick label"
    return f"'{s}' ({role} of {where})"


def _legend_name(leg, parent) -> str:
    ax = _ancestor(leg, parent, Axes)
    return f"legend of {_axes_name(ax)}" if ax is not None else "figure legend"


def _overlap(a, b):
    """Width and height of the intersection of two extents (negative where they are apart)."""
    return min(a.x1, b.x1) - max(a.x0, b.x0), min(a.y1, b.y1) - max(a.y0, b.y0)


def _extents(boxes):
    """Extents (``Bbox``) as rows ``x0, y0, x1, y1`` of an (n, 4) array, for :func:`_overlaps`."""
    return np.array([[b.x0, b.y0, b.x1, b.y1] for b in boxes], dtype=float).reshape(-1, 4)


def _overlaps(boxes, others=None):
    """:func:`_overlap`'s smaller side for every pair of extents: ``boxes`` (n, 4) and ``others`` (m, 4), rows
    ``x0, y0, x1, y1`` (by default ``boxes`` itself); an (n, m) array."""
    others = boxes if others is None else others
    (x0, y0, x1, y1), (u0, v0, u1, v1) = boxes.T[:, :, None], others.T[:, None, :]
    return np.minimum(np.minimum(x1, u1) - np.maximum(x0, u0), np.minimum(y1, v1) - np.maximum(y0, v0))


def _corners(box):
    return np.array([[box.x0, box.y0], [box.x1, box.y0], [box.x1, box.y1], [box.x0, box.y1]])


def _polygon(t, box, renderer):
    """The corners of a drawn text's own rectangle: its extent where it is set level or upright, else its
    unrotated extent turned about the centre (the extent of a slanted text is a much larger level box)."""
    angle = t.get_rotation()
    if angle % 90 == 0:
        return _corners(box)
    t.set_rotation(0)
    flat = Text.get_window_extent(t, renderer)
    t.set_rotation(angle)
    a = np.radians(angle)
    turn = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    half = 0.5 * np.array([[-flat.width, -flat.height], [flat.width, -flat.height], [flat.width, flat.height],
                           [-flat.width, flat.height]])
    return half @ turn.T + [0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1)]


def _separation(p, q):
    """How far apart two convex polygons (corner arrays) are along the edge normal that parts them most:
    negative where they overlap (then minus the depth of the overlap)."""
    best = -np.inf
    for poly in (p, q):
        edges = np.roll(poly, -1, axis=0) - poly
        normals = np.column_stack([-edges[:, 1], edges[:, 0]]) / np.hypot(*edges.T)[:, None]
        a, b = p @ normals.T, q @ normals.T
        best = max(best, np.max(np.maximum(a.min(axis=0) - b.max(axis=0), b.min(axis=0) - a.max(axis=0))))
    return float(best)


def _inside(xy, box, tol):
    return ((xy[:, 0] > box.x0 + tol) & (xy[:, 0] < box.x1 - tol)
            & (xy[:, 1] > box.y0 + tol) & (xy[:, 1] < box.y1 - tol))


def _crosses(xy, box, tol):
    """Whether the polyline ``xy`` (display coordinates, NaN breaking it) enters ``box`` shrunk by ``tol``:
    each segment clipped against the box (Liang-Barsky)."""
    if len(xy) < 2:
        return False
    p, q = xy[:-1], xy[1:]
    ok = np.isfinite(p).all(axis=1) & np.isfinite(q).all(axis=1)
    p, dp = p[ok], (q - p)[ok]
    lo, hi = np.zeros(len(p)), np.ones(len(p))
    for k, (a, b) in enumerate(((box.x0 + tol, box.x1 - tol), (box.y0 + tol, box.y1 - tol))):
        with np.errstate(divide="ignore", invalid="ignore"):
            t0, t1 = (a - p[:, k]) / dp[:, k], (b - p[:, k]) / dp[:, k]
        flat = dp[:, k] == 0
        inside = (p[:, k] > a) & (p[:, k] < b)
        lo = np.where(flat, np.where(inside, lo, np.inf), np.maximum(lo, np.minimum(t0, t1)))
        hi = np.where(flat, hi, np.minimum(hi, np.maximum(t0, t1)))
    return bool(np.any(lo < hi))


def _label(artist) -> str:
    label = artist.get_label()
    return f" '{label}'" if label and not label.startswith("_") else ""


def _data_under(ax, box, tol):
    """What of ``ax``'s data lies under ``box`` (display coordinates): one phrase per artist."""
    found = []
    i = ax.figure.get_axes().index(ax)
    for j, line in enumerate(ax.get_lines()):
        if not line.get_visible():
            continue
        xy = line.get_transform().transform(np.column_stack([line.get_xdata(orig=False), line.get_ydata(orig=False)]))
        name = f"a{i}_line{j}{_label(line)}"  # as in the figure's saved data (figdata.figure_data)
        has_marker = line.get_marker() not in (None, "None", "none", "", " ")
        n = int(_inside(xy[np.isfinite(xy).all(axis=1)], box, tol).sum())
        if has_marker and n:
            found.append(f"{n} marker(s) of {name}")
        elif line.get_linestyle() not in ("None", "none", "", " ") and (n or _crosses(xy, box, tol)):
            found.append(f"line {name}")
    for j, coll in enumerate(ax.collections):
        if not coll.get_visible():
            continue
        if isinstance(coll, PathCollection) and len(coll.get_offsets()):
            xy = coll.get_offset_transform().transform(np.asarray(coll.get_offsets(), float))
            n = int(_inside(xy[np.isfinite(xy).all(axis=1)], box, tol).sum())
            if n:
                found.append(f"{n} point(s) of collection {j}{_label(coll)}")
        elif isinstance(coll, LineCollection):
            trans = coll.get_transform()
            if any(_crosses(trans.transform(seg), box, tol) for seg in coll.get_segments() if len(seg)):
                found.append(f"lines of collection {j}{_label(coll)}")
    return found


def _has_marker(line) -> bool:
    return line.get_marker() not in (None, "None", "none", "", " ")


def markers(ax) -> list[tuple[str, np.ndarray]]:
    """The markers ``ax`` draws, per artist: ``(name, centres)`` in display coordinates, inside the axes' frame
    (the rest is clipped away): the markers of its lines and the points of its scatters, named as in the
    figure's saved data (``a<i>_line<j>``; a scatter by its collection index)."""
    found = []
    i = ax.figure.get_axes().index(ax)
    frame = ax.bbox
    for j, line in enumerate(ax.get_lines()):
        if line.get_visible() and _has_marker(line):
            xy = line.get_transform().transform(np.column_stack([line.get_xdata(orig=False),
                                                                 line.get_ydata(orig=False)]))
            found.append((f"a{i}_line{j}{_label(line)}", xy))
    for j, coll in enumerate(ax.collections):
        if coll.get_visible() and isinstance(coll, PathCollection) and len(coll.get_offsets()):
            xy = coll.get_offset_transform().transform(np.asarray(coll.get_offsets(), float))
            found.append((f"collection {j}{_label(coll)}", xy))
    return [(name, xy[np.isfinite(xy).all(axis=1) & _inside(np.nan_to_num(xy), frame, 0.0)]) for name, xy in found]


def markers_under(ax, box, tol: float = 0.0) -> list[str]:
    """What of ``ax``'s markers (:func:`markers`) lies under ``box`` (display coordinates, shrunk by ``tol``):
    ``"<n> marker(s) of <artist>"`` per artist."""
    out = []
    for name, xy in markers(ax):
        n = int(_inside(xy, box, tol).sum()) if len(xy) else 0
        if n:
            out.append(f"{n} marker(s) of {name}")
    return out


def _text_over_markers(fig, texts, parent, tol):
    """Texts whose own box covers the centre of a marker drawn in an axes (any axes the text lies over)."""
    problems = []
    axes = [ax for ax in fig.get_axes() if ax.get_visible()]
    for t, b, leg, _ in texts:
        if leg is not None:  # a legend's texts: the legend's box is checked
            continue
        for ax in axes:
            if min(_overlap(b, ax.bbox)) <= tol:
                continue
            problems += [f"text over data: {_describe(t, parent)} covers {what} of {_axes_name(ax)}"
                         for what in markers_under(ax, b, tol)]
    return problems


#: the legends' entries declared style keys (:func:`style_keys`), by legend
_STYLE_KEYS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def style_keys(legend, *labels: str):
    """Declare entries of ``legend`` (by their labels) keys of a style rather than of a thing drawn in their colour
    ("stable" solid and "unstable" dashed in grey, over branches of every colour): the check of legend entries
    (:func:`layout_problems`) matches them to that line style or marker in any colour.  Returns the legend."""
    missing = set(labels) - {t.get_text() for t in legend.texts}
    if missing:
        raise ValueError(f"style_keys: {sorted(missing)} are not entries of the legend; allowed: its labels "
                         f"{[t.get_text() for t in legend.texts]}")
    _STYLE_KEYS.setdefault(legend, set()).update(labels)
    return legend


def _same_color(a, colors) -> bool:
    """Whether the RGBA ``a`` is one of ``colors`` (an array of RGBA rows) to 1/255."""
    colors = np.atleast_2d(np.asarray(colors, float))
    return bool(len(colors) and np.any(np.all(np.abs(colors - np.asarray(a, float)) < 1.5 / 255, axis=1)))


#: the line style of a collection's dashed lines (matplotlib keeps their dash pattern, not its name)
DASHED = "dashed"


def _marker_path(marker):
    m = MarkerStyle(marker)
    return m.get_path().transformed(m.get_transform()).vertices


def _drawn(fig):
    """What the figure's axes draw, for matching legend entries: markers as (shape vertices, colours), lines as
    (line style, colour), filled areas as face colours (RGBA)."""
    marks, lines, faces = [], [], []
    for ax in fig.get_axes():
        if not ax.get_visible():
            continue
        for line in ax.get_lines():
            if not line.get_visible() or not np.isfinite(np.column_stack([line.get_xdata(orig=False),
                                                                          line.get_ydata(orig=False)])).all(axis=1).any():
                continue
            colors = [to_rgba(c, line.get_alpha()) for c in (line.get_markeredgecolor(), line.get_markerfacecolor())
                      if str(c).lower() != "none"]
            if _has_marker(line):
                marks.append((_marker_path(line.get_marker()), colors))
            if line.get_linestyle() not in ("None", "none", "", " "):
                lines.append((line.get_linestyle(), to_rgba(line.get_color(), line.get_alpha())))
        for coll in ax.collections:
            if not coll.get_visible():
                continue
            edge, face = coll.get_edgecolors(), coll.get_facecolors()
            if isinstance(coll, PathCollection) and len(coll.get_offsets()):
                # point i: path i, edge colour i and face colour i, each cycled (matplotlib's rule)
                paths, shown = coll.get_paths(), {}
                for i in range(len(coll.get_offsets())):
                    path = paths[i % len(paths)]
                    seen = shown.setdefault(id(path), (path.vertices, []))[1]
                    seen += [c[i % len(c)] for c in (edge, face) if len(c)]
                marks += [(v, np.asarray(c)) for v, c in shown.values()]
            elif isinstance(coll, LineCollection) and len(coll.get_segments()):
                dashed = any(dash is not None for _, dash in coll.get_linestyles())
                lines += [(DASHED if dashed else "-", tuple(c)) for c in (edge if len(edge) else face)]
            elif isinstance(coll, Collection):
                faces += [tuple(c) for c in face]
        for patch in ax.patches:
            if patch.get_visible() and patch.get_fill():
                faces.append(to_rgba(patch.get_facecolor()))
        for image in ax.images:  # a map's cells, in the colours its colormap gives their values
            if image.get_visible() and image.get_array() is not None:
                rgba = np.asarray(image.to_rgba(image.get_array(), bytes=False), float).reshape(-1, 4)
                faces += [tuple(c) for c in np.unique(np.round(rgba, 6), axis=0)]
    return marks, lines, faces


def _describe_color(rgba) -> str:
    return to_hex(rgba, keep_alpha=rgba[3] < 1)


def _entry_problems(handle, marks, lines, faces, style) -> list[str]:
    """What of a legend entry's handle no drawn artist shows (empty: all of it is drawn)."""
    missing = []
    if isinstance(handle, Line2D):
        if _has_marker(handle):
            shape = _marker_path(handle.get_marker())
            color = [to_rgba(c, handle.get_alpha()) for c in (handle.get_markeredgecolor(), handle.get_markerfacecolor())
                     if str(c).lower() != "none"][:1]
            ok = any(v.shape == shape.shape and np.allclose(v, shape, atol=1e-6)
                     and (style or not color or _same_color(color[0], colors)) for v, colors in marks)
            if not ok:
                missing.append(f"no marker '{handle.get_marker()}'"
                               + ("" if style or not color else f" in {_describe_color(color[0])}"))
        ls = handle.get_linestyle()
        if ls not in ("None", "none", "", " "):
            color = to_rgba(handle.get_color(), handle.get_alpha())
            # a collection's dashes are not named: any dashed line of it matches a dashed, dotted or dash-dotted entry
            ok = any((s == ls or s == DASHED and ls != "-") and (style or _same_color(color, [c])) for s, c in lines)
            if not ok:
                missing.append(f"no line '{ls}'" + ("" if style else f" in {_describe_color(color)}"))
    elif isinstance(handle, Patch) and handle.get_fill():
        color = to_rgba(handle.get_facecolor())
        if not (style or _same_color(color, faces if faces else np.zeros((0, 4)))):
            missing.append(f"no area in {_describe_color(color)}")
    elif isinstance(handle, PathCollection):
        for path in handle.get_paths():
            colors = to_rgba_array(handle.get_edgecolors() if len(handle.get_edgecolors()) else handle.get_facecolors())
            if not any(v.shape == path.vertices.shape and np.allclose(v, path.vertices, atol=1e-6)
                       and (style or not len(colors) or _same_color(colors[0], c)) for v, c in marks):
                missing.append("no such scatter marker")
    return missing


def _legend_entry_problems(fig, parent):
    problems = []
    marks, lines, faces = _drawn(fig)
    legends = {id(a): a for a in fig.findobj(Legend) if a.get_visible()}
    for leg in legends.values():
        keys = _STYLE_KEYS.get(leg, set())
        for handle, text in zip(leg.legend_handles, leg.texts, strict=False):
            label = text.get_text()
            missing = _entry_problems(handle, marks, lines, faces, label in keys)
            if missing:
                problems.append(f"legend entry draws nothing: '{_short(label)}' ({_legend_name(leg, parent)}): "
                                + "; ".join(missing))
    return problems


def layout_problems(fig, tolerance_pt: float = TOLERANCE_PT) -> list[str]:
    """The layout problems of ``fig``, one sentence each (empty: none), as described in this module.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, laid out here as when it is saved (:meth:`~matplotlib.figure.Figure.draw_without_rendering`:
        its layout engine and every artist's draw run, nothing is rasterized).
    tolerance_pt : float
        The least distance between two texts and the most a text or legend may pass an edge (points):
        :data:`TOLERANCE_PT`.

    Returns
    -------
    list of str
        ``overlap: ...`` (two texts), ``outside: ...`` (a text leaving the figure), ``crosses the frame:
        ...`` (an annotation across its axes' edge), ``legend over text: ...``, ``legend over data: ...``,
        ``text over data: ...`` (a text over markers), ``legend entry draws nothing: ...``.
    """
    with _drawn_texts() as drawn:
        fig.draw_without_rendering()
    return _verdict(fig, drawn, fig.canvas.get_renderer(), tolerance_pt)


@contextmanager
def problems_of_the_draw(fig, tolerance_pt: float = TOLERANCE_PT):
    """:func:`layout_problems` of the first draw of ``fig`` made inside the context, found while it is drawn:
    around a ``savefig``, the layout of the image written, at the resolution it is written at, without a draw
    of its own.  Yields a list, filled by that draw; raises ``RuntimeError`` if the context drew nothing."""
    found, seen = [], []

    def on_draw(event):
        if not seen:  # the first draw lays the figure out (a savefig's second only renders it)
            seen.append(True)
            found.extend(_verdict(fig, dict(drawn), event.renderer, tolerance_pt))

    with _drawn_texts() as drawn:
        cid = fig.canvas.mpl_connect("draw_event", on_draw)
        try:
            yield found
        finally:
            fig.canvas.mpl_disconnect(cid)
    if not seen:
        raise RuntimeError("problems_of_the_draw: the figure was not drawn inside the context")


def _verdict(fig, drawn, renderer, tolerance_pt):
    """The problems of the texts ``drawn`` (:func:`_drawn_texts`) as ``renderer`` laid them out."""
    tol = tolerance_pt * fig.dpi / 72
    parent = _owners(fig)
    texts = []
    for t in drawn.values():
        # the text itself: an annotation's extent would include its leader line
        b = Text.get_window_extent(t, renderer) if t.get_visible() and t.get_text().strip() else None
        if b is not None and np.isfinite(b.bounds).all() and b.width > 0 and b.height > 0:
            texts.append((t, b, _ancestor(t, parent, Legend), _polygon(t, b, renderer)))
    return (_text_problems(fig, texts, parent, tol) + _legend_problems(fig, texts, parent, renderer, tol)
            + _text_over_markers(fig, texts, parent, tol) + _legend_entry_problems(fig, parent))


def _text_problems(fig, texts, parent, tol):
    problems = []
    free = [(t, b, poly) for t, b, leg, poly in texts if leg is None]  # a legend's texts: checked through its box
    near = _overlaps(_extents(b for _, b, _ in free)) > -tol
    for i, j in zip(*np.nonzero(np.triu(near, 1)), strict=True):  # each pair once, in the texts' order
        (t, b, p), (u, c, q) = free[i], free[j]
        if (sep := _separation(p, q)) < tol:
                size = f"{-sep:.1f} px deep" if sep < 0 else f"less than {tol:.1f} px apart"
                problems.append(f"overlap: {_describe(t, parent)} and {_describe(u, parent)} ({size})")
    page = fig.bbox
    for t, b, _ in free:
        out = {"left": page.x0 - b.x0, "right": b.x1 - page.x1, "bottom": page.y0 - b.y0, "top": b.y1 - page.y1}
        side = max(out, key=out.get)
        if out[side] > tol:
            problems.append(f"outside: {_describe(t, parent)} leaves the figure at the {side} by {out[side]:.0f} px")
        ax = _ancestor(t, parent, Axes)
        if ax is not None and t in ax.texts and min(_overlap(b, ax.bbox)) > tol:
            past = max(ax.bbox.x0 - b.x0, b.x1 - ax.bbox.x1, ax.bbox.y0 - b.y0, b.y1 - ax.bbox.y1)
            if past > tol:
                problems.append(f"crosses the frame: {_describe(t, parent)} sticks out of its axes by {past:.0f} px")
    return problems


def _legend_problems(fig, texts, parent, renderer, tol):
    problems = []
    legends = {id(a): a for a in fig.findobj(Legend) if a.get_visible()}  # one added as an artist is found twice
    for leg in legends.values():
        box = leg.get_window_extent(renderer)
        name = _legend_name(leg, parent)
        covered = [_describe(t, parent) for t, b, owner, poly in texts
                   if owner is not leg and min(_overlap(box, b)) > tol and _separation(_corners(box), poly) < -tol]
        if covered:
            problems.append(f"legend over text: {name} covers {', '.join(covered)}")
        for ax in fig.get_axes():
            if ax.get_visible() and min(_overlap(box, ax.bbox)) > tol:
                region = Bbox.intersection(box, ax.bbox)
                problems += [f"legend over data: {name} covers {what} of {_axes_name(ax)}"
                             for what in _data_under(ax, region, tol)]
    return problems


#: a label set farther than this (points) from its anchor is tied to it by a thin line
LEADER_PT = 9.0
#: candidate offsets (points) of a point's name, for :func:`place_labels`: beside it, then farther (with a leader)
AROUND = [(3, 3), (3, -3), (-3, 3), (-3, -3), (0, 7), (0, -7), (7, 0), (-7, 0),
          (8, 12), (-8, 12), (8, -12), (-8, -12), (0, 18), (0, -18), (16, 0), (-16, 0)]


def place_labels(fig, labels, gap_pt: float = 3.0) -> list:
    """Annotate each label at the first of its candidate places that clears what is already drawn.

    The figure is drawn once (its layout is then fixed: the labels are kept out of it) and each label,
    in turn, takes the first candidate that keeps ``gap_pt`` from every text, legend and label placed
    before it, stays inside its axes, comes near no other marker (a name beside another point reads as
    that point's) and crosses no line; failing that, the candidate with the fewest such conflicts (texts
    and the frame first, then markers, then lines, then a leader line: a label farther than
    :data:`LEADER_PT` from its anchor is tied to it by one).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    labels : iterable of (ax, text, candidates, style)
        ``candidates``: ``(xy, (dx, dy))`` pairs, an anchor (in ``style``'s ``xycoords``, data by default)
        and an offset in points; the text is set beside the anchor on the offset's side.  ``style``:
        keyword arguments of :meth:`matplotlib.axes.Axes.annotate`.
    gap_pt : float
        Least distance (points) to other texts: about a word space at a label's 6-7 points, so that two
        neighbours read as two words (and :func:`layout_problems`, at :data:`TOLERANCE_PT`, finds nothing).

    Returns
    -------
    list of matplotlib.text.Annotation
    """
    with _drawn_texts() as drawn:
        fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    gap = gap_pt * fig.dpi / 72
    taken = [Text.get_window_extent(t, renderer) for t in drawn.values() if t.get_visible() and t.get_text().strip()]
    taken += [leg.get_window_extent(renderer) for leg in fig.findobj(Legend) if leg.get_visible()]
    taken = _extents(taken)
    drawn_lines = {}
    placed = []
    for ax, text, candidates, style in labels:
        if ax not in drawn_lines:  # in display coordinates: (markers, polylines)
            lines = [(line, line.get_transform().transform(line.get_xydata())) for line in ax.get_lines()
                     if line.get_visible()]
            dots = [xy for _, xy in markers(ax)]
            drawn_lines[ax] = (np.concatenate(dots) if dots else np.zeros((0, 2)),
                               [xy for line, xy in lines if line.get_linestyle() not in ("None", "none", "", " ")])
        dots, polylines = drawn_lines[ax]
        best = None
        for xy, (dx, dy) in candidates:
            far = bool(np.hypot(dx, dy) > LEADER_PT)
            ann = ax.annotate(text, xy, xytext=(dx, dy), textcoords="offset points",
                              ha="left" if dx > 0 else "right" if dx < 0 else "center",
                              va="bottom" if dy > 0 else "top" if dy < 0 else "center",
                              arrowprops=dict(arrowstyle="-", lw=0.4, color="0.4", shrinkA=1, shrinkB=2) if far else None,
                              **style)
            ann.set_in_layout(False)
            ann.update_positions(renderer)
            b = Text.get_window_extent(ann, renderer)  # the text, without its leader
            frame = ax.bbox
            clash = (int(np.count_nonzero(_overlaps(_extents([b]), taken) > -gap))
                     + (b.x0 < frame.x0 or b.x1 > frame.x1 or b.y0 < frame.y0 or b.y1 > frame.y1))
            # a name next to another point's marker reads as that point's: count the markers near the text
            near = b.expanded(1.0, 1.0).padded(gap)
            own = np.all(np.abs(dots - ann._get_xy_display()) < 1.0, axis=1)
            score = (clash, int((_inside(dots, near, 0.0) & ~own).sum()), sum(_crosses(xy, b, 0.0) for xy in polylines),
                     far)
            if best is None or score < best[0]:
                if best is not None:
                    best[1].remove()
                best = (score, ann, b)
            else:
                ann.remove()
            if not any(score):
                break
        taken = np.vstack([taken, _extents([best[2]])])
        placed.append(best[1])
        # where the candidates' anchors differ, the one taken is the layout's choice, which moves with what is
        # drawn: the figure check compares the other coordinate only
        free = "".join(axis for k, axis in enumerate("xy") if len({float(xy[k]) for xy, _ in candidates}) > 1)
        if free:
            record_wellposed(best[1], "placed", provenance="layout", free=free)
    return placed


def to_attribute(problems: list[str]) -> str:
    """``problems`` as the JSON string saved in a figure's data (netCDF attributes hold no lists of strings)."""
    return json.dumps(problems, ensure_ascii=False)


def from_attribute(ds) -> list[str] | None:
    """The layout problems recorded in a figure's saved data ``ds`` (None: no verdict recorded)."""
    value = ds.attrs.get(ATTRIBUTE)
    return None if value is None else json.loads(value)


def check_results(results_dir) -> dict[str, list[str]]:
    """The recorded layout problems of every figure whose data is in ``results_dir``/figures/data, by
    figure; a figure saved without a verdict gets the problem 'no layout verdict recorded'."""


    out = {}
    for nc in sorted(Path(results_dir, "figures", "data").glob("*.nc")):
        with xr.open_dataset(nc, engine="scipy") as ds:
            problems = from_attribute(ds)
        out[nc.stem] = ["no layout verdict recorded (saved before the layout check)"] if problems is None else problems
    return out


def main(argv=None) -> int:
    """``python -m vibroimpact.outputs.layout [results]``: print each figure's recorded layout problems;
    exit status 1 if there are any, or no figure data at all."""

    argv = sys.argv[1:] if argv is None else argv
    found = check_results(argv[0] if argv else "results")
    for fig, problems in found.items():
        print(f"{fig}: {'ok' if not problems else f'{len(problems)} problem(s)'}")
        for p in problems:
            print(f"  {p}")
    if not found:
        print("no figure data found")
    return int(any(found.values()) or not found)


if __name__ == "__main__":
    raise SystemExit(main())
