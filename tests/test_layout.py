"""Figures a referee accepts: no text overprints another, none is cut off, no legend hides data
(vibroimpact.outputs.layout), on small figures built to have each fault, and on every figure the workflow draws."""

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from vibroimpact.outputs import layout
from vibroimpact.outputs.plots._common import save, use_style

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def fig():
    use_style()
    f, ax = plt.subplots(figsize=(4, 3))
    ax.plot([0.0, 1.0], [0.0, 1.0], "-", label="a curve")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_title("(a) a panel")
    yield f
    plt.close(f)


def test_a_clean_figure_has_no_problems(fig):
    ax = fig.axes[0]
    ax.plot([0.2, 0.8], [0.2, 0.8], "o", mfc="none", label="points")
    ax.text(0.1, 0.8, "a note")
    ax.legend(loc="lower right")
    assert layout.layout_problems(fig) == []


def test_overlapping_texts_are_named(fig):
    ax = fig.axes[0]
    ax.annotate("A2", (0.9, 0.9))
    ax.annotate("F", (0.91, 0.9))
    problems = layout.layout_problems(fig)
    assert len(problems) == 1 and problems[0].startswith("overlap: 'A2' (text of axes a0 '(a) a panel') and 'F'"), problems


def _kinds(problems):
    """The problems without their measures (in pixels, which differ with the resolution drawn at)."""
    return sorted(p.split(" (")[0] if p.startswith("overlap") else p.split(" by ")[0] for p in problems)


def test_the_verdict_found_while_a_png_is_saved_is_the_verdict_of_a_draw_of_its_own(fig, tmp_path):
    """save() judges the layout of the PNG it writes while writing it (no draw of its own): the same problems as
    layout_problems() finds by drawing, at the resolution the PNG is saved at; none where there are none."""
    ax = fig.axes[0]
    ax.annotate("A2", (0.9, 0.9))
    ax.annotate("F", (0.91, 0.9))
    ax.text(1.02, 0.5, "a note running past the figure's right edge", transform=ax.transAxes)
    drawn = layout.layout_problems(fig)
    with layout.problems_of_the_draw(fig) as found:
        fig.savefig(tmp_path / "f.png")
    assert len(drawn) == 2 and _kinds(found) == _kinds(drawn), (found, drawn)
    for t in ax.texts:
        t.set_visible(False)
    with layout.problems_of_the_draw(fig) as found:
        fig.savefig(tmp_path / "g.png")
    assert found == [] and layout.layout_problems(fig) == []


def test_the_overlaps_of_many_extents_are_each_pair_s_overlap():
    """_overlaps (every pair at once, as the verdict and the label placement use it) against _overlap (one pair),
    on extents that overlap, touch, lie apart along one axis only or both, and are flipped."""
    from matplotlib.transforms import Bbox

    rng = np.random.default_rng(20261128)
    corners = np.round(rng.uniform(0, 10, size=(40, 4)), 0)  # whole numbers: touching and shared edges occur
    boxes = [Bbox.from_extents(*c) for c in corners]
    many = layout._overlaps(corners, corners[:25])
    assert many.shape == (40, 25)
    expect = np.array([[min(layout._overlap(a, b)) for b in boxes[:25]] for a in boxes])
    np.testing.assert_array_equal(many, expect)
    assert (many > 0).any() and (many < 0).any() and (many == 0).any()


def test_a_verdict_with_no_draw_is_refused(fig):
    with pytest.raises(RuntimeError, match="not drawn"):
        with layout.problems_of_the_draw(fig):
            pass


@pytest.mark.parametrize("gap_pt, reported", [(0.0, True), (0.5, True), (2.0, False)])
def test_texts_set_flush_read_as_one_word(fig, gap_pt, reported):
    """Two labels less than TOLERANCE_PT apart (paper units: points) are reported ("h=0.02h=0.01"), two
    points apart they are not."""
    ax = fig.axes[0]
    first = ax.text(0.3, 0.5, "h=0.02")
    fig.canvas.draw()
    x = first.get_window_extent().x1 + gap_pt * fig.dpi / 72
    ax.text(x, first.get_window_extent().y0, "h=0.01", transform=None)
    problems = layout.layout_problems(fig)
    assert bool(problems) == reported, problems
    assert not problems or problems[0].startswith("overlap: 'h=0.02' (text of axes a0 '(a) a panel') and 'h=0.01'")


def test_an_annotation_across_the_frame_is_named(fig):
    """A label of a point at the axes' edge that sticks out across the frame; one wholly beside the axes is a
    margin note and is fine."""
    ax = fig.axes[0]
    ax.annotate("h=0.0002", (1.0, 0.5), xytext=(3, 3), textcoords="offset points")
    ax.annotate("a margin note", (1.02, 0.0), xycoords="axes fraction", fontsize=5)
    problems = layout.layout_problems(fig)
    assert len(problems) == 1 and problems[0].startswith("crosses the frame: 'h=0.0002' (text of axes a0"), problems


def test_a_text_leaving_the_figure_is_named(fig):
    fig.text(0.97, 0.5, "cut off at the edge")
    problems = layout.layout_problems(fig)
    assert len(problems) == 1 and problems[0].startswith("outside: 'cut off at the edge' (figure text) leaves the "
                                                        "figure at the right by"), problems


def test_a_legend_over_a_marker_is_named(fig):
    ax = fig.axes[0]
    ax.plot([0.05], [0.95], "o", label="corner point")
    ax.legend(loc="upper left")
    problems = layout.layout_problems(fig)
    assert problems == ["legend over data: legend of axes a0 '(a) a panel' covers 1 marker(s) of a0_line1 'corner point' "
                        "of axes a0 '(a) a panel'"], problems


def test_a_legend_over_a_reference_line_is_named(fig):
    """A line with no marker under the legend (lambda = -1, a wall) is hidden data too."""
    ax = fig.axes[0]
    ax.axhline(0.99, color="r")
    ax.legend(loc="upper left")
    problems = layout.layout_problems(fig)
    assert problems == ["legend over data: legend of axes a0 '(a) a panel' covers line a0_line1 of axes a0 '(a) a panel'"], problems


def test_a_legend_over_a_scatter_and_a_text_is_named(fig):
    ax = fig.axes[0]
    ax.scatter([0.02, 0.5], [0.98, 0.5])
    ax.text(0.02, 0.97, "hidden")
    ax.legend(loc="upper left")
    problems = layout.layout_problems(fig)
    assert sorted(problems) == sorted([
        "legend over text: legend of axes a0 '(a) a panel' covers 'hidden' (text of axes a0 '(a) a panel')",
        "legend over data: legend of axes a0 '(a) a panel' covers 1 point(s) of collection 0 of axes a0 '(a) a panel'"]), problems


def test_what_is_not_drawn_is_not_reported(fig):
    """Invisible texts, empty strings and tick labels beyond the view limits are never drawn."""
    ax = fig.axes[0]
    ax.text(0.5, 0.5, "invisible").set_visible(False)
    ax.text(0.5, 0.5, "")
    ax.text(0.5, 0.5, "drawn")
    ax.set_xticks([-5.0, 0.0, 0.5, 1.0, 5.0])  # the outer two lie beyond the limits
    ax.set_xlim(0, 1)
    assert layout.layout_problems(fig) == []


def test_save_records_the_verdict_beside_the_figure(fig, tmp_path):
    fig.axes[0].annotate("A2", (0.9, 0.9))
    fig.axes[0].annotate("F", (0.91, 0.9))
    save(fig, tmp_path / "figures" / "f", data=tmp_path / "figures" / "data" / "f.nc")
    with xr.open_dataset(tmp_path / "figures" / "data" / "f.nc", engine="scipy") as ds:
        problems = layout.from_attribute(ds)
    assert len(problems) == 1 and problems[0].startswith("overlap: 'A2'")
    assert layout.check_results(tmp_path) == {"f": problems}
    assert layout.main([str(tmp_path)]) == 1


def _problems_text(found):
    return "\n".join(f"{name}: {p}" for name, ps in found.items() for p in ps)


def test_figures_already_built_here_have_a_clean_layout():
    """The figures built in this checkout's results/ (quick, while working; skipped when none are built).
    The same is asserted over a fresh clone's default target by the slow test below."""
    found = layout.check_results(ROOT / "results")
    if not found:
        pytest.skip("no figure data in results/figures/data: build some figures first")
    assert not any(found.values()), _problems_text(found)


@pytest.mark.slow
def test_every_figure_of_the_default_target_has_a_clean_layout(default_run):
    """Every figure the default target draws (its saved data under results/figures/data) records no layout
    problem: no overlapping texts, none leaving the figure, no legend over data."""
    clone, _ = default_run
    found = layout.check_results(clone / "results")
    assert len(found) >= 15, sorted(found)
    assert not any(found.values()), _problems_text(found)


def test_the_attribute_is_json_of_the_problems():
    assert json.loads(layout.to_attribute(["a β", "b"])) == ["a β", "b"]
    assert layout.from_attribute(xr.Dataset(attrs={"layout_problems": "[]"})) == []
    assert layout.from_attribute(xr.Dataset()) is None
    assert np.isscalar(layout.TOLERANCE_PT)


@pytest.mark.parametrize("dx_px, reported", [(6, True), (25, False)])
def test_slanted_labels_are_compared_as_slanted(fig, dx_px, reported):
    """Two labels turned by 70 degrees (a failure map's case names), ``dx_px`` apart side by side: at 25 px their
    level boxes overlap but the glyphs stand well apart (no problem); at 6 px the labels themselves overlap."""
    ax = fig.axes[0]
    style = dict(rotation=70, ha="center", va="center", transform=None)
    a = ax.text(150, 150, "a slanted case name", **style)
    b = ax.text(150 + dx_px, 150, "a slanted case name", **style)
    fig.canvas.draw()
    ba, bb = a.get_window_extent(), b.get_window_extent()
    assert min(ba.x1, bb.x1) - max(ba.x0, bb.x0) > 10  # their level boxes overlap
    problems = layout.layout_problems(fig)
    assert bool(problems) == reported, problems


def test_placed_names_overprint_nothing(fig):
    """Two points closer than their names are wide, at the frame's edge (Fig 2's A2 and F at the fold): each name
    takes a place clear of the other, of the markers and of the frame."""
    ax = fig.axes[0]
    ax.set_xlim(0, 1)
    ax.plot([0.975, 0.99], [0.5, 0.5], "D", color="k")
    labels = [(ax, name, [((x, 0.5), off) for off in layout.AROUND], dict(fontsize=7))
              for name, x in (("A2", 0.975), ("F", 0.99))]
    placed = layout.place_labels(fig, labels)
    assert [a.get_text() for a in placed] == ["A2", "F"] and ax.texts[:] == placed
    assert layout.layout_problems(fig) == []


def test_a_text_over_markers_is_named(fig):
    """A label written over plotted points hides them (the lambda_1 figure's "fold (2:1)" over its red chaotic
    markers); one beside them, or over a line alone, is fine."""
    ax = fig.axes[0]
    ax.plot([0.45, 0.5, 0.55], [0.2, 0.2, 0.2], "o", mfc="none", label="points")
    ax.scatter([0.8], [0.5])
    ax.text(0.5, 0.2, "fold (2:1)", ha="center", va="center")
    ax.text(0.8, 0.5, "x", ha="center", va="center")
    ax.text(0.2, 0.6, "over a line only")  # the curve y = x passes under it: a name set over a curve still reads
    ax.text(0.5, 0.3, "beside")
    problems = sorted(layout.layout_problems(fig))
    assert problems == [
        "text over data: 'fold (2:1)' (text of axes a0 '(a) a panel') covers 3 marker(s) of a0_line1 'points' of "
        "axes a0 '(a) a panel'",
        "text over data: 'x' (text of axes a0 '(a) a panel') covers 1 marker(s) of collection 0 of axes a0 '(a) a panel'"
    ], problems


def test_markers_clipped_away_or_beyond_the_frame_are_not_under_a_text(fig):
    """A marker outside the view limits is not drawn: a text there covers nothing."""
    ax = fig.axes[0]
    ax.plot([2.0], [0.5], "o")
    ax.set_xlim(0, 1)
    ax.annotate("a margin note", (1.02, 0.5), xycoords="axes fraction", fontsize=5)
    assert layout.layout_problems(fig) == []


def test_a_legend_entry_that_draws_nothing_is_named(fig):
    """The lambda_1 figure listed lambda_1 = -inf (a blue triangle) where no point was -inf: an entry whose marker,
    line or area no artist of the figure draws is named, with what is missing; entries that match (the marker in
    its colour, a scatter's points, a line's style, a shaded area) are not."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    ax = fig.axes[0]
    ax.scatter([0.2, 0.4], [0.3, 0.3], marker="o", facecolors="none", edgecolors=["k", "tab:red"])
    ax.axvspan(0.6, 0.7, color="tab:blue", alpha=0.25)
    ax.axvline(0.9, color="tab:purple", ls="-.")
    handles = [Line2D([], [], color="k", marker="o", mfc="none", ls="", label="exact"),
               Line2D([], [], color="tab:red", marker="o", mfc="none", ls="", label="chaotic"),
               Line2D([], [], color="tab:blue", marker="v", mfc="none", ls="", label="minus infinity"),
               Line2D([], [], color="tab:purple", ls="-.", label="1:1 exit: grazing"),
               Line2D([], [], color="tab:purple", ls="--", label="1:1 exit: jump"),
               Line2D([], [], color="tab:orange", ls="-", label="orange curve"),
               Patch(facecolor="tab:blue", alpha=0.25, label="wall"), Patch(facecolor="tab:green", alpha=0.25, label="top")]
    fig.legend(handles=handles, loc="outside right upper")
    problems = [p for p in layout.layout_problems(fig) if p.startswith("legend entry")]
    assert problems == ["legend entry draws nothing: 'minus infinity' (figure legend): no marker 'v' in #1f77b4",
                        "legend entry draws nothing: '1:1 exit: jump' (figure legend): no line '--' in #9467bd",
                        "legend entry draws nothing: 'orange curve' (figure legend): no line '-' in #ff7f0e",
                        "legend entry draws nothing: 'top' (figure legend): no area in #2ca02c40"], problems


def test_an_entry_keying_a_style_matches_it_in_any_colour(fig):
    """"stable: solid", "unstable: dashed" in grey over branches of every colour: declared style keys, they match
    their line style in any colour; undeclared, they draw nothing grey; a key of a style nothing draws is named."""
    from matplotlib.lines import Line2D

    ax = fig.axes[0]
    ax.plot([0.1, 0.9], [0.8, 0.2], "--", color="tab:green")
    keys = [Line2D([], [], color="0.3", ls="-", label="stable"), Line2D([], [], color="0.3", ls="--", label="unstable"),
            Line2D([], [], color="0.3", ls=":", label="dotted: nothing"),
            Line2D([], [], color="0.3", marker="s", ls="", label="squares: nothing")]
    leg = fig.legend(handles=keys, loc="outside right upper")
    assert len([p for p in layout.layout_problems(fig) if p.startswith("legend entry")]) == 4
    layout.style_keys(leg, "stable", "unstable", "dotted: nothing", "squares: nothing")
    assert [p for p in layout.layout_problems(fig) if p.startswith("legend entry")] == [
        "legend entry draws nothing: 'dotted: nothing' (figure legend): no line ':'",
        "legend entry draws nothing: 'squares: nothing' (figure legend): no marker 's'"]
    with pytest.raises(ValueError, match="not entries of the legend"):
        layout.style_keys(leg, "solid")


def test_placed_names_keep_off_a_scatter_s_points(fig):
    """place_labels counts a scatter's points as markers (the lambda_1 panels draw their points as one scatter)."""
    ax = fig.axes[0]
    ax.set_xlim(0, 1)
    ax.scatter(np.full(9, 0.5) + 0.02, np.linspace(0.1, 0.9, 9))
    ax.axvline(0.5)
    cands = [((0.5, y), (dx, 1)) for dx in (2, -2) for y in (0.1, 0.5)]
    (ann,) = layout.place_labels(fig, [(ax, "a name", cands, dict(xycoords=("data", "axes fraction"), rotation=90))])
    assert ann.get_horizontalalignment() == "right"  # left of the line, off the points right of it
    assert layout.layout_problems(fig) == []
