"""The rules of the figure regeneration check (vibroimpact.outputs.figcheck), on figures drawn for the purpose:
each rule passes what is well-posed and fails what is not."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from vibroimpact.outputs.figcheck import Z_CRIT
from vibroimpact.outputs.figdata import compare, figure_data, image_allowance
from vibroimpact.outputs.plots._common import wellposed

RTOL, ATOL = 1e-9, 1e-12


def _cloud(values, motions, settled, mean=None, se=None, unsettled=None):
    """A sweep's cloud: at d = 0, 1, 2, ... the values of each point (a list per point)."""
    fig, ax = plt.subplots()
    x = np.concatenate([np.full(len(v), float(i)) for i, v in enumerate(values)])
    y = np.concatenate([np.asarray(v, float) for v in values])
    per = lambda a: np.concatenate([np.full(len(v), a[i]) for i, v in enumerate(values)])
    n = len(values)
    line = ax.plot(x, y, "o", ls="none")[0]
    wellposed(line, "motions", motion=per(np.asarray(motions)), settled=per(np.asarray(settled, bool)),
              unsettled=per(np.asarray(unsettled if unsettled is not None else [False] * n, bool)),
              mean=per(np.asarray(mean if mean is not None else [np.nan] * n, float)),
              se=per(np.asarray(se if se is not None else [np.nan] * n, float)))
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def _check(new, ref):
    return compare(new, ref, rtol=RTOL, atol=ATOL).set_index("variable")


N = np.nan
BASE = dict(values=[[0.3, 0.5], [0.31, 0.52], [0.32, 0.53], [0.33, 0.54], [0.1, 0.2, 0.7], [0.33], [0.34]],
            motions=["2:1"] * 4 + ["no period found", "1:1", "1:1"], settled=[True] * 4 + [False, True, True],
            mean=[N] * 4 + [0.4, N, N], se=[N] * 4 + [0.01, N, N])


def _at(i, value, base):
    out = list(base)
    out[i] = value
    return out


def _variant(**change):
    return _cloud(**(BASE | change))


def test_motions_passes_settled_values_in_any_order_and_a_chaotic_cloud_within_its_statistics():
    ref = _variant()
    values = _at(4, [0.65, 0.05, 0.3, 0.22], _at(0, [0.5, 0.3], BASE["values"]))
    new = _variant(values=values, mean=_at(4, 0.4 + 5 * 0.01, BASE["mean"]))
    df = _check(new, ref)
    assert set(df.status) == {"pass"} and set(df.rule) == {"motions"}
    assert "6 exact values, 1 statistics" in df.detail.iloc[0]


@pytest.mark.parametrize("change, words", [
    (dict(values=_at(0, [0.3, 0.5 + 1e-7], BASE["values"])), "values differ"),
    (dict(mean=_at(4, 0.4 + (Z_CRIT + 1) * 0.01 * 2**0.5, BASE["mean"])), "standard errors"),
    (dict(motions=_at(1, "3:1", BASE["motions"])), "inside its region"),
])
def test_motions_fails_a_moved_value_a_moved_statistic_and_a_changed_motion_inside_its_region(change, words):
    df = _check(_variant(**change), _variant())
    assert (df.status == "fail").all() and words in df.detail.iloc[0], df.detail.iloc[0]


def test_motions_accepts_a_changed_motion_at_a_boundary_or_a_transient_longer_than_the_cap():
    ref = _variant()
    # point 5 sits beside the aperiodic point 4: its motion may change there
    assert set(_check(_variant(motions=_at(5, "1:1 period-4", BASE["motions"])), ref).status) == {"pass"}
    # and point 2 may take the aperiodic motion, whose region lies two points away
    assert set(_check(_variant(motions=_at(2, "no period found", BASE["motions"]),
                               settled=_at(2, False, BASE["settled"])), ref).status) == {"pass"}
    # point 1, inside the 2:1 region, may only change where one of the two is an unsettled transient
    flip = dict(motions=_at(1, "4:1", BASE["motions"]), settled=_at(1, False, BASE["settled"]))
    assert set(_check(_variant(**flip), ref).status) == {"fail"}
    df = _check(_variant(**flip, unsettled=_at(1, True, [False] * 7)), ref)
    assert set(df.status) == {"pass"} and "boundary, 1 at a transient longer than the cap" in df.detail.iloc[0]


def test_motions_fails_when_the_sweep_points_move():
    ref = _variant()
    fig, ax = plt.subplots()
    x = np.concatenate([np.full(len(v), float(i)) for i, v in enumerate(BASE["values"])])
    x[-1] = 6.5
    ax.plot(x, np.concatenate(BASE["values"]), "o")
    new = figure_data(fig)
    plt.close(fig)
    for k, v in ref.data_vars.items():
        if "_wp_" in k:
            new[k] = v
        else:  # drawn under the same rule
            new[k].attrs.update(wellposed=v.attrs["wellposed"], provenance=v.attrs["provenance"])
    df = _check(new, ref)
    assert "the points moved" in df.detail.iloc[0] and set(df.status) == {"fail"}


def test_a_declared_rule_applies_whatever_was_measured_and_an_array_declaring_none_is_compared_pointwise():
    """The chaotic point's cloud moved within its statistics: its declared rule passes it, on any machine; the
    same arrays drawn without a declared rule are compared pointwise, and fail."""
    ref = _variant()
    moved = _variant(values=_at(4, [0.65, 0.05, 0.3], BASE["values"]))
    assert set(_check(moved, ref).status) == {"pass"}
    assert set(_check(moved, ref).rule) == {"motions"} and set(_check(moved, ref).provenance) == {"simulation"}
    bare = [ds.drop_vars([v for v in ds.data_vars if "_wp_" in v]) for ds in (moved, ref)]
    for ds in bare:
        for v in ds.data_vars:
            ds[v].attrs.pop("wellposed")
    assert set(_check(*bare).status) == {"pass", "fail"}  # pointwise: the chaotic point moved
    assert set(_check(*bare).rule) == {"strict"}


def _curve(n, shift=0.0, drop_end=False):
    fig, ax = plt.subplots()
    s = np.linspace(0.0 + shift, 1.0, n)
    if drop_end:
        s = s[:-1]
    wellposed(ax.plot(np.cos(3 * s), np.sin(3 * s), "-")[0], "curve")
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_curve_passes_the_same_curve_sampled_elsewhere_and_one_step_shorter():
    ref = _curve(200)
    for new in (_curve(180), _curve(200, shift=0.5 / 199), _curve(200, drop_end=True)):
        assert set(compare(new, ref, rtol=RTOL, atol=ATOL).status) == {"pass"}


def test_curve_fails_a_moved_or_a_shortened_curve():
    ref = _curve(200)
    fig, ax = plt.subplots()
    s = np.linspace(0.0, 1.0, 200)
    wellposed(ax.plot(1.001 * np.cos(3 * s), 1.001 * np.sin(3 * s), "-")[0], "curve")
    bigger = figure_data(fig)
    plt.close(fig)
    assert "fail" in set(compare(bigger, ref, rtol=RTOL, atol=ATOL).status)
    assert "fail" in set(compare(_curve(200, shift=0.2), ref, rtol=RTOL, atol=ATOL).status)


def _map(labels, extra=()):
    """A 6 x 4 map of motions at x = 0 .. 5, y = 10 .. 13, and boundary markers at ``extra`` (x, y - 10)."""
    fig, ax = plt.subplots()
    xs, ys = np.arange(6.0), 10.0 + np.arange(4.0)
    codes = np.zeros((4, 6))
    mesh = ax.pcolormesh(xs, ys, codes, shading="nearest")
    wellposed(mesh, "motions", motion=np.asarray(labels).ravel())
    if len(extra):
        wellposed(ax.plot(*(np.asarray(extra, float) + [0.0, 10.0]).T, ".", ls="")[0], "boundary")
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_a_map_of_motions_changes_only_at_boundaries_and_its_boundary_markers_with_it():
    lab = np.array([["A"] * 3 + ["B"] * 3] * 4)
    ref = _map(lab, extra=[(2.5, y) for y in range(4)])
    edge = lab.copy()
    edge[1, 3] = "A"  # a cell beside the boundary
    new = _map(edge, extra=[(2.5, 0), (3.5, 1), (2.5, 2), (2.5, 3)])
    assert set(compare(new, ref, rtol=RTOL, atol=ATOL).status) == {"pass"}
    inside = lab.copy()
    inside[1, 0] = "B"  # deep inside A
    df = compare(_map(inside, extra=[(2.5, y) for y in range(4)]), ref, rtol=RTOL, atol=ATOL)
    assert "fail" in set(df.status)
    # a boundary marker with no changed cell beside it
    df = compare(_map(lab, extra=[(2.5, 0), (2.5, 1), (2.5, 2), (0.5, 3)]), ref, rtol=RTOL, atol=ATOL)
    assert "fail" in set(df.set_index("variable").loc[["a0_line0_x"], "status"])


def test_the_image_allowance_is_twice_the_measured_spread_and_at_least_one_point():
    import pandas as pd

    from vibroimpact.outputs.checks import IMAGE_ROW

    cond = pd.DataFrame([dict(figure="f", variable=IMAGE_ROW, conditioning="ill-conditioned", spread=3.0),
                         dict(figure="f", variable="a0_line0_y", conditioning="ill-conditioned", spread=1.0),
                         dict(figure="f", variable="a0_line1_y", conditioning="ill-conditioned", spread=1.0),
                         dict(figure="g", variable=IMAGE_ROW, conditioning="strict", spread=0.0),
                         dict(figure="h", variable="a0_line0_y", conditioning="strict", spread=0.0)])
    assert image_allowance(cond, "f", 0)[0] == 6 and "2 ill-conditioned arrays" in image_allowance(cond, "f", 0)[1]
    assert image_allowance(cond, "g", 0)[0] == 2 and "0 ill-conditioned arrays" in image_allowance(cond, "g", 0)[1]
    assert image_allowance(cond, "h", 0) == (2, "image: <= 2 bits (twice the 0 measured, at least 2; "
                                                 "0 ill-conditioned arrays)")
    assert image_allowance(None, "g", 0)[0] == 0


def _texts(x, step):
    fig, ax = plt.subplots()
    ax.set_xlim(0, 10)
    wellposed(ax.text(x, 0.9, "2:1 T=2"), "run", step=step)
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_a_run_s_name_may_move_by_one_sweep_step_and_no_more():
    """The motion named over a sweep, at the middle of its run: each end of the run is known to one
    point, so the name moves by up to one step; the step travels with the figure data."""
    ref = _texts(5.0, 0.25)
    assert ref["a0_text0_xy"].attrs["wp_step"] == 0.25
    assert set(compare(_texts(5.2, 0.25), ref, rtol=RTOL, atol=ATOL).status) == {"pass"}
    assert set(compare(_texts(5.3, 0.25), ref, rtol=RTOL, atol=ATOL).status) == {"fail"}
    bare = [ds.copy(deep=True) for ds in (_texts(5.2, 0.25), ref)]
    for ds in bare:
        ds["a0_text0_xy"].attrs.pop("wellposed")
    assert set(compare(*bare, rtol=RTOL, atol=ATOL).status) == {"fail"}  # declaring no rule: pointwise


def _events(points, n=200, s=None):
    """A curve (a circle's arc, sampled at n points, or at ``s``) and event markers on it."""
    fig, ax = plt.subplots()
    s = np.linspace(0.0, 1.0, n) if s is None else s
    wellposed(ax.plot(np.cos(3 * s), np.sin(3 * s), "-")[0], "curve")
    ax.plot(np.cos(3 * s), 0.5 + 0 * s, ":")  # another line of the axes: not a curve the events lie on
    p = np.asarray(points, float)
    wellposed(ax.plot(np.cos(3 * p), np.sin(3 * p), "x", ls="")[0], "on curve")
    ax.plot([1.0], [1.0])  # the axes' extent is the curves' and the events' together
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_points_on_a_sampled_curve_may_move_within_their_segment_and_no_more():
    ref = _events([0.2, 0.7])
    step = 1.0 / 199
    ill = ("a0_line2_x", "a0_line2_y")  # the events

    def status(new, old=ref):
        return set(compare(new, old, rtol=RTOL, atol=ATOL).set_index("variable").loc[list(ill), "status"])

    assert status(_events([0.2 + 0.5 * step, 0.7])) == {"pass"}
    df = compare(_events([0.2 + 0.5 * step, 0.7]), ref, rtol=RTOL, atol=ATOL).set_index("variable")
    assert df.loc["a0_line2_x", "max_difference"] < 0.01  # of the axes extent
    assert status(_events([0.2 + 3 * step, 0.7])) == {"fail"}
    assert status(_events([0.2])) == {"fail"}
    nan = _events([np.nan, 0.7])
    assert status(nan, nan) == {"pass"}
    assert status(_events([0.2, 0.7]), nan) == {"fail"}


def _line(xs, ys):
    """The figure data of one line drawn as a well-posed curve."""
    fig, ax = plt.subplots()
    wellposed(ax.plot(xs, ys, "-")[0], "curve")
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_a_curve_with_no_finite_point_matches_only_another_such():
    empty = lambda values: _line(values, values)
    nan = empty([np.nan, np.nan])
    assert set(compare(empty([np.nan, np.nan]), nan, rtol=RTOL, atol=ATOL).status) == {"pass"}
    assert set(compare(empty([0.0, 1.0]), nan, rtol=RTOL, atol=ATOL).status) == {"fail"}


def test_a_coexisting_motion_reaches_two_cells_diagonally_and_no_further():
    """A start in a multistable region goes to whichever basin holds it: a cell may take a motion whose
    region lies within two cells (any direction), not one further away."""
    lab = np.full((4, 6), "A")
    lab[3, 5] = "B"
    ref = _map(lab)
    near = lab.copy()
    near[2, 3] = "B"  # two cells from (5, 3) along x, one along y: not a neighbour, within reach
    assert set(compare(_map(near), ref, rtol=RTOL, atol=ATOL).status) == {"pass"}
    far = lab.copy()
    far[1, 2] = "B"  # three cells away
    assert "fail" in set(compare(_map(far), ref, rtol=RTOL, atol=ATOL).status)


def test_what_a_figure_records_as_well_posed_survives_its_netcdf_file_and_does_not_count_as_drawn(tmp_path):
    """The per-element fields and the rule's scalars are written with the figure data (netCDF3, as the
    workflow writes it) and read back; they are not arrays the figure draws: they are not compared on their
    own, and the data read back passes against the data as drawn."""
    import xarray as xr

    from vibroimpact.datasets import write_netcdf

    ds = _variant()
    runs = _texts(5.0, 0.25)
    both = xr.merge([ds, runs.rename({k: k.replace("a0_", "a1_") for k in runs.data_vars})])
    write_netcdf(both, tmp_path / "f.nc", fmt="NETCDF3_64BIT")
    back = xr.load_dataset(tmp_path / "f.nc")
    assert back["a1_text0_xy"].attrs["wp_step"] == 0.25 and back["a0_line0_y"].attrs["wellposed"] == "motions"
    assert list(back["a0_line0_wp_motion"].values.astype(str)) == list(ds["a0_line0_wp_motion"].values.astype(str))
    assert "wp_rule" not in back["a0_line0_y"].attrs and "wp_motion" not in back["a0_line0_y"].attrs
    df = compare(back, both, rtol=RTOL, atol=ATOL)
    assert set(df.status) == {"pass"} and not df.variable.str.contains("_wp_").any()
    assert len(df) == len([v for v in both.data_vars if "_wp_" not in v])


def test_an_event_is_allowed_the_length_of_the_segment_it_lies_on():
    """On a curve sampled with growing steps (continuation doubles its step after each success), an event
    may move by its own segment's length, not by its shorter neighbour's."""
    lengths = 0.01 * 1.5 ** np.arange(8)
    s = np.concatenate([[0.0], np.cumsum(lengths)])
    k = 5
    at = s[k] + 0.4 * lengths[k]  # nearer the segment's start, whose other segment is 1.5 times shorter
    ref = _events([at], s=s)
    ill = ("a0_line2_x", "a0_line2_y")  # the event
    new = _events([at + 0.8 * lengths[k]], s=s)  # within its own segment's length, beyond the shorter one
    got = compare(new, ref, rtol=RTOL, atol=ATOL).set_index("variable").loc[list(ill), "status"]
    assert set(got) == {"pass"}


def test_a_line_that_changed_length_fails_with_its_shapes():
    def line(n):
        fig, ax = plt.subplots()
        ax.plot(np.arange(n, dtype=float), np.arange(n, dtype=float))
        ds = figure_data(fig)
        plt.close(fig)
        return ds

    df = compare(line(3), line(2), rtol=RTOL, atol=ATOL).set_index("variable")
    assert list(df.status) == ["fail: shape (3,) != reference (2,)"] * 2


def test_a_statistic_known_exactly_passes_only_within_the_strict_tolerance():
    """A value with a standard error of 0 (a sticking cycle known exactly, say) still passes within the
    strict tolerance of its mean, and fails beyond it."""
    base = dict(settled=_at(4, False, BASE["settled"]), se=_at(4, 0.0, BASE["se"]))
    ref = _variant(**base)
    mean = BASE["mean"][4]
    ok = _variant(**base, mean=_at(4, mean * (1 + 0.5e-9), BASE["mean"]))
    bad = _variant(**base, mean=_at(4, mean * (1 + 2.5e-9), BASE["mean"]))
    assert set(_check(ok, ref).status) == {"pass"} and set(_check(bad, ref).status) == {"fail"}


def test_the_detail_counts_points_of_the_same_motion_with_nothing_else_to_compare():
    same = dict(settled=_at(4, False, BASE["settled"]), mean=_at(4, np.nan, BASE["mean"]),
                se=_at(4, np.nan, BASE["se"]))
    df = _check(_variant(**same), _variant(**same))
    assert "1 same motion" in df.detail.iloc[0]


def _curve_of(points_per_piece):
    fig, ax = plt.subplots()
    xs, ys = [], []
    for angles in points_per_piece:
        a = np.asarray(angles, float)
        xs += [*np.cos(a), np.nan]
        ys += [*np.sin(a), np.nan]
    wellposed(ax.plot(xs[:-1], ys[:-1], "-")[0], "curve")
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_a_curve_in_pieces_and_a_piece_of_three_points():
    """Pieces separated by NaN (admissible stretches) are compared piece by piece; on a piece of three
    points a point of the true curve lies within the chord error of a middle segment."""
    ref = _curve_of([np.linspace(0, 1, 40), np.linspace(2, 3, 40)])
    assert set(compare(_curve_of([np.linspace(0, 1, 31), np.linspace(2, 3, 37)]), ref, rtol=RTOL, atol=ATOL).status) == {"pass"}
    short = _curve_of([[0.7, 0.8, 0.9]])
    assert set(compare(_curve_of([[0.72, 0.8, 0.88]]), short, rtol=RTOL, atol=ATOL).status) == {"pass"}


def test_an_event_near_a_segment_s_end_is_allowed_that_segment_s_length():
    lengths = 0.01 * 1.5 ** np.arange(8)
    s = np.concatenate([[0.0], np.cumsum(lengths)])
    k = 5
    at = s[k] + 0.6 * lengths[k]  # nearer the segment's end, whose next segment is 1.5 times longer
    ref = _events([at], s=s)
    ill = ("a0_line2_x", "a0_line2_y")  # the event
    new = _events([at + 1.2 * lengths[k]], s=s)  # beyond its own segment's length, within the next one's
    got = compare(new, ref, rtol=RTOL, atol=ATOL).set_index("variable").loc[list(ill), "status"]
    assert set(got) == {"fail"}


def test_boundary_markers_with_no_map_in_their_axes_pass_when_unchanged_and_fail_when_moved():
    def markers(points):
        fig, ax = plt.subplots()
        wellposed(ax.plot(*np.asarray(points, float).T, ".", ls="")[0], "boundary")
        ds = figure_data(fig)
        plt.close(fig)
        return ds

    ref = markers([(0.5, 1.0), (1.5, 2.0)])
    same = compare(markers([(0.5, 1.0), (1.5, 2.0)]), ref, rtol=RTOL, atol=ATOL)
    assert set(same.status) == {"pass"} and set(same.max_difference) == {0.0}
    assert set(compare(markers([(0.5, 1.0), (2.5, 2.0)]), ref, rtol=RTOL, atol=ATOL).status) == {"fail"}


def test_a_cell_beside_another_motion_on_either_side_is_on_a_boundary():
    """A single column of B in a map of A: the cells on both sides of it are on a boundary and may take a
    motion seen nowhere else; a cell two columns away may not."""
    lab = np.full((4, 6), "A")
    lab[:, 3] = "B"
    ref = _map(lab)
    for x, ok in ((2, True), (4, True), (0, False)):
        new = lab.copy()
        new[1, x] = "C"
        assert ("fail" not in set(compare(_map(new), ref, rtol=RTOL, atol=ATOL).status)) == ok, x


def test_strict_close_requires_the_same_shape_and_nan_pattern():
    from vibroimpact.outputs.figcheck import strict_close

    assert strict_close([1.0, np.nan], [1.0 + 1e-12, np.nan], RTOL, ATOL)
    assert not strict_close([1.0, 2.0], [1.0, np.nan], RTOL, ATOL)
    assert not strict_close([1.0, np.nan], [1.0, 2.0], RTOL, ATOL)
    assert not strict_close([1.0], [1.0, 1.0], RTOL, ATOL)


def test_a_curve_moved_off_by_more_than_its_chord_error_fails():
    """A 200-point arc moved outward by 2e-4 of its radius: more than the chord error of its segments
    (L theta / 4), so off the curve."""
    ref = _curve(200)
    fig, ax = plt.subplots()
    s = np.linspace(0.0, 1.0, 200)
    wellposed(ax.plot(1.0002 * np.cos(3 * s), 1.0002 * np.sin(3 * s), "-")[0], "curve")
    moved = figure_data(fig)
    plt.close(fig)
    assert "fail" in set(compare(moved, ref, rtol=RTOL, atol=ATOL).status)


def test_events_with_no_finite_point_anywhere_pass_when_both_have_none():
    def nothing():
        fig, ax = plt.subplots()
        wellposed(ax.plot([np.nan], [np.nan], "x", ls="")[0], "on curve")
        ds = figure_data(fig)
        plt.close(fig)
        return ds

    assert set(compare(nothing(), nothing(), rtol=RTOL, atol=ATOL).status) == {"pass"}


def test_a_curve_s_first_and_lone_points_get_no_more_than_their_own_allowance():
    """Only beyond a piece's end is a point allowed a whole segment; inside the first segment, or on a
    piece of one point, it is held to the chord error."""
    ref = _curve(200)
    fig, ax = plt.subplots()
    s = np.linspace(0.0, 1.0, 200)
    radius = np.ones(200)
    radius[1] = 1.0 + 0.1 * 3 / 199  # the second point moved outward by a tenth of a segment
    wellposed(ax.plot(radius * np.cos(3 * s), radius * np.sin(3 * s), "-")[0], "curve")
    bent = figure_data(fig)
    plt.close(fig)
    assert "fail" in set(compare(bent, ref, rtol=RTOL, atol=ATOL).status)
    lone = _curve_of([np.linspace(0, 1, 40), [2.0]])
    moved = _curve_of([np.linspace(0, 1, 40), [2.05]])
    assert "fail" in set(compare(moved, lone, rtol=RTOL, atol=ATOL).status)


def test_the_detail_names_five_failures_and_counts_the_rest():
    values = [[0.1 * i + 0.5] for i in range(8)]
    base = dict(values=values, motions=["1:1"] * 8, settled=[True] * 8)
    moved = dict(base, values=[[v[0] + 1e-6] for v in values])
    detail = _check(_cloud(**moved), _cloud(**base)).detail.iloc[0]
    assert detail.count("values differ") == 5 and detail.endswith("; and 3 more")
    six = dict(base, values=[[v[0] + (1e-6 if i < 6 else 0.0)] for i, v in enumerate(values)])
    detail = _check(_cloud(**six), _cloud(**base)).detail.iloc[0]
    assert detail.endswith("; and 1 more")
    five = dict(base, values=[[v[0] + (1e-6 if i < 5 else 0.0)] for i, v in enumerate(values)])
    assert "more" not in _check(_cloud(**five), _cloud(**base)).detail.iloc[0]


@pytest.mark.parametrize("row, flip, ok", [(1, (2, 2), True), (1, (2, 0), True), (1, (2, 3), False)])
def test_a_cell_above_or_below_another_motion_is_on_a_boundary(row, flip, ok):
    lab = np.full((4, 6), "A")
    lab[row, :] = "B"
    new = lab.copy()
    new[flip[1], flip[0]] = "C"
    assert ("fail" not in set(compare(_map(new), _map(lab), rtol=RTOL, atol=ATOL).status)) == ok


def test_a_coexisting_motion_reaches_two_cells_along_a_row():
    lab = np.full((4, 6), "A")
    lab[1, 5] = "B"
    new = lab.copy()
    new[1, 3] = "B"
    assert set(compare(_map(new), _map(lab), rtol=RTOL, atol=ATOL).status) == {"pass"}


def test_a_boundary_marker_more_than_a_cell_from_a_changed_cell_fails():
    lab = np.array([["A"] * 3 + ["B"] * 3] * 4)
    edge = lab.copy()
    edge[1, 3] = "A"
    ref = _map(lab, extra=[(2.5, y) for y in range(4)])
    far = _map(edge, extra=[(2.5, 0), (4.5, 1), (2.5, 2), (2.5, 3)])  # 1.5 cells from the changed cell
    assert "fail" in set(compare(far, ref, rtol=RTOL, atol=ATOL).status)


def test_a_piece_of_one_segment_may_end_a_step_further_on_either_side():
    ref = _curve_of([np.linspace(0, 1, 40), [2.0, 2.1]])
    for tail in ([2.0, 2.15], [1.95, 2.1]):
        new = _curve_of([np.linspace(0, 1, 40), tail])
        assert set(compare(new, ref, rtol=RTOL, atol=ATOL).status) == {"pass"}, tail


def test_a_vertical_curve_is_compared_along_its_one_extent():
    def vertical(ys):
        fig, ax = plt.subplots()
        wellposed(ax.plot(np.full(len(ys), 0.3), ys, "-")[0], "curve")
        ds = figure_data(fig)
        plt.close(fig)
        return ds

    ref = vertical(np.linspace(0, 1, 50))
    assert set(compare(vertical(np.linspace(0, 1, 41)), ref, rtol=RTOL, atol=ATOL).status) == {"pass"}


def test_a_horizontal_curve_and_a_bent_middle_of_a_short_piece():
    ref = _line(np.linspace(0, 1, 50), np.full(50, 0.3))
    assert set(compare(_line(np.linspace(0, 1, 41), np.full(41, 0.3)), ref, rtol=RTOL, atol=ATOL).status) == {"pass"}
    # the middle of a piece of three points is no piece's end: held to the chord error there
    short = _curve_of([[0.7, 0.8, 0.9]])
    a = np.array([0.7, 0.8, 0.9])
    bent = _line(np.cos(a) * [1.0, 1.03, 1.0], np.sin(a) * [1.0, 1.03, 1.0])
    assert "fail" in set(compare(bent, short, rtol=RTOL, atol=ATOL).status)


def _exact_exponents(values, sensitivity):
    """Exact lambda_1 of solved cycles at d = 0, 1, 2, with each value's sensitivity to its matrix."""
    fig, ax = plt.subplots()
    line = ax.plot(np.arange(len(values), dtype=float), values, "o", ls="none")[0]
    n = len(values)
    wellposed(line, "motions", motion=np.array(["2:1"] * n), settled=np.ones(n, bool), unsettled=np.zeros(n, bool),
              mean=np.full(n, np.nan), se=np.full(n, np.nan), sensitivity=np.asarray(sensitivity, float))
    ds = figure_data(fig)
    plt.close(fig)
    return ds


@pytest.mark.parametrize("sensitivity, move, ok", [
    (0.0, 0.9e-9, True), (0.0, 1.1e-9, False),  # |ref| = 1: the strict tolerance
    (0.5, 1.1e-9, False),  # a sensitivity below |ref| changes nothing
    (1e4, 0.9e-5, True), (1e4, 1.1e-5, False),  # rtol times the sensitivity where it is larger
])
def test_an_exact_value_from_a_matrix_is_held_to_the_strict_tolerance_times_its_sensitivity(sensitivity, move, ok):
    ref = _exact_exponents([-1.0, -0.5, -0.2], [sensitivity] * 3)
    new = _exact_exponents([-1.0 + move, -0.5, -0.2], [sensitivity] * 3)
    df = _check(new, ref)
    assert (set(df.status) == {"pass"}) == ok, df.detail.iloc[0]


def _located(x, y, step_x, sampled=None):
    """Points located along lines of a grid (the 1:1 exit over a plane), with their text at the first one."""
    fig, ax = plt.subplots()
    fields = {"step_x": step_x} | ({} if sampled is None else {"sampled": np.asarray(sampled, bool)})
    wellposed(ax.plot(x, y, "o")[0], "located", **fields)
    wellposed(ax.annotate("1:1 exit", (x[0], 0.02), xycoords=("data", "axes fraction")), "located", step_x=step_x)
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def _located_rows(new, ref):
    df = compare(new, ref, rtol=RTOL, atol=ATOL).set_index("variable")
    assert set(df.rule) == {"located"}
    return df


def test_located_values_pass_within_their_grid_step_and_only_there():
    """x within one grid step (the located value moved inside the bracket it was refined from), y pointwise."""
    ref = _located([0.20, 0.21, np.nan], [0.1, 0.2, 0.3], step_x=0.01)
    same = _located_rows(_located([0.205, 0.2101, np.nan], [0.1, 0.2, 0.3], step_x=0.01), ref)
    assert (same.status == "pass").all(), same
    far = _located_rows(_located([0.2201, 0.21, np.nan], [0.1, 0.2, 0.3], step_x=0.01), ref)
    assert far.status["a0_line0_x"] == "fail" and far.status["a0_text0_xy"] == "fail"
    y_moved = _located_rows(_located([0.20, 0.21, np.nan], [0.1, 0.2 + 1e-6, 0.3], step_x=0.01), ref)
    assert y_moved.status["a0_line0_y"] == "fail"  # no step along y: pointwise
    nan_moved = _located_rows(_located([0.20, np.nan, 0.21], [0.1, 0.2, 0.3], step_x=0.01), ref)
    assert nan_moved.status["a0_line0_x"] == "fail" and "NaN at 2 other places" in nan_moved.detail["a0_line0_x"]


def test_a_classification_from_a_sample_may_change_its_artist():
    """A point drawn among the grazing exits in one run and among the others in another (its kind decided
    from a finite sample of a chaotic motion) is allowed to be missing, where it is marked sampled; a point not
    marked is not."""
    ref = _located([0.20, 0.21, 0.22], [0.1, 0.2, 0.3], step_x=0.01, sampled=[False, True, False])
    flipped = _located_rows(_located([0.20, np.nan, 0.22], [0.1, np.nan, 0.3], step_x=0.01,
                                     sampled=[False, True, False]), ref)
    assert (flipped.status == "pass").all(), flipped
    assert "1 sampled classifications differ" in flipped.detail["a0_line0_x"]
    not_sampled = _located_rows(_located([np.nan, 0.21, 0.22], [np.nan, 0.2, 0.3], step_x=0.01,
                                         sampled=[False, True, False]), ref)
    assert not_sampled.status["a0_line0_x"] == "fail"


def test_a_figure_that_draws_nothing_in_some_panels_is_a_file_the_netcdf_library_reads(tmp_path):
    """Another device's figure may hold several empty lines (a panel with nothing to draw): the classic
    format takes a zero length for its one unlimited dimension, so the file is written as NETCDF4 and the
    netCDF library reads it back; a figure without empty lines keeps the classic format."""
    import numpy as np
    import xarray as xr

    from vibroimpact.datasets import write_netcdf

    empty = xr.Dataset({f"a0_line{i}_{c}": (f"a0_line{i}_{c}_dim0", np.zeros(0)) for i in range(2) for c in "xy"}
                       | {"a1_line0_x": ("a1_line0_x_dim0", np.arange(3.0))})
    write_netcdf(empty, tmp_path / "e.nc", fmt="NETCDF3_64BIT")
    back = xr.load_dataset(tmp_path / "e.nc", engine="netcdf4")
    assert back.sizes["a0_line1_y_dim0"] == 0 and back["a1_line0_x"].values.tolist() == [0.0, 1.0, 2.0]
    write_netcdf(empty[["a1_line0_x"]], tmp_path / "c.nc", fmt="NETCDF3_64BIT")
    assert (tmp_path / "c.nc").read_bytes()[:4] == b"CDF\x02"


def test_the_details_report_the_largest_move():
    """A check's row reports what it compared: the largest statistic's move in standard errors (here 0.35: a
    batch mean moved by half its standard error), and a located value's largest move (0.005 of a 0.01 step)."""
    new = _variant(mean=_at(4, 0.4 + 0.5 * 0.01, BASE["mean"]))
    df = _check(new, _variant())
    assert set(df.status) == {"pass"} and "(largest 0.4 SE)" in df.detail.iloc[0], df.detail.iloc[0]
    ref = _located([0.20, 0.21, np.nan], [0.1, 0.2, 0.3], step_x=0.01)
    same = _located_rows(_located([0.205, 0.2101, np.nan], [0.1, 0.2, 0.3], step_x=0.01), ref)
    assert same.max_difference["a0_line0_x"] == pytest.approx(0.005, rel=1e-9)


def test_an_isolated_curve_point_does_not_capture_the_events():
    """A curve drawn with an isolated point (a piece of one point: a segment of length 0) beside its arc: an
    event that moved within its arc segment passes, as without the isolated point."""
    def events(points, n=200):
        fig, ax = plt.subplots()
        s = np.linspace(0.0, 1.0, n)
        wellposed(ax.plot(np.append(np.cos(3 * s), [np.nan, 0.5]), np.append(np.sin(3 * s), [np.nan, 0.5]),
                          "-")[0], "curve")
        p = np.asarray(points, float)
        wellposed(ax.plot(np.cos(3 * p), np.sin(3 * p), "x", ls="")[0], "on curve")
        ds = figure_data(fig)
        plt.close(fig)
        return ds

    ill = ("a0_line1_x", "a0_line1_y")  # the events
    df = compare(events([0.2 + 0.5 / 199, 0.7]), events([0.2, 0.7]), rtol=RTOL, atol=ATOL)
    assert set(df.set_index("variable").loc[list(ill), "status"]) == {"pass"}, df


def _errors(y, x=(1.0, 2.0, 3.0), floor=1e-13, text=False):
    """An error-against-cost line (its errors recorded as magnitudes above ``floor``, its costs as timings),
    and a label placed on its last point."""
    fig, ax = plt.subplots()
    wellposed(ax.loglog(x, y, "o-")[0], "magnitude", timed=("x",), floor=floor)
    if text:
        wellposed(ax.annotate("rtol=1e-11", (x[-1], y[-1])), "magnitude", floor=floor)
    ax.set_xlabel("cost per impact (µs)")
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_errors_are_compared_as_orders_of_magnitude_above_their_rounding_floor_and_costs_not_at_all():
    """An error of an integrator compared by its order of magnitude: the reference's 7.5145e-11 and another
    machine's 7.5193e-11 (its BLAS summed in another order along a chaotic run) agree, and so do errors that
    rounding alone sets (any count of ulps below the floor); an error ten times larger fails, and so does
    a point on the wrong walls (infinite) where the reference has a finite error.  The costs (timings) are
    not compared: the same line twice as slow passes."""
    ref = _errors([1e-5, 1e-8, 7.5145e-11], text=True)
    df = compare(_errors([1e-5, 1e-8, 7.5193e-11], x=(2.0, 4.0, 6.0), text=True), ref, rtol=RTOL,
                 atol=ATOL).set_index("variable")
    assert set(df.status) == {"pass", "excluded"} and df.status["a0_line0_x"] == "excluded"
    assert df.rule["a0_line0_x"] == "timing" and df.rule["a0_line0_y"] == "magnitude"
    assert df.provenance["a0_line0_y"] == "method error" and df.provenance["a0_line0_x"] == "timing"
    at_floor = compare(_errors([1e-5, 1e-8, 2e-15]), _errors([1e-5, 1e-8, 9e-14]), rtol=RTOL, atol=ATOL)
    assert set(at_floor.status) == {"pass", "excluded"}
    for worse in ([1e-5, 1e-8, 7.6e-10], [1e-4 * 1.01, 1e-8, 7.5e-11], [1e-5, np.inf, 7.5e-11]):
        df = compare(_errors(worse, text=True), ref, rtol=RTOL, atol=ATOL).set_index("variable")
        assert df.status["a0_line0_y"] == "fail", worse
    assert compare(_errors([1e-5, 1e-8, 7.6e-10], text=True), ref, rtol=RTOL,
                   atol=ATOL).set_index("variable").status["a0_text0_xy"] == "fail"  # the label on the point
    # without a floor a zero error has no magnitude: it fails, naming why
    df = compare(_errors([1e-5, 1e-8, 0.0], floor=0.0), _errors([1e-5, 1e-8, 1e-16], floor=0.0), rtol=RTOL,
                 atol=ATOL).set_index("variable")
    assert df.status["a0_line0_y"] == "fail" and "no rounding floor" in df.detail["a0_line0_y"]


def _outcomes(codes, sensitive):
    fig, ax = plt.subplots()
    codes = np.asarray(codes, float)
    sensitive = np.asarray(sensitive, bool)
    wellposed(ax.imshow(codes), "outcome", provenance="chaotic run", sensitive=sensitive.ravel())
    for (i, j), c in np.ndenumerate(codes):
        wellposed(ax.text(j, i, "M" if c else ""), "outcome", provenance="chaotic run", sensitive=bool(sensitive[i, j]))
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_an_outcome_may_change_only_in_a_cell_its_producer_found_sensitive_to_the_last_bit():
    """A map of outcomes (codes, and a mark in each cell with a glyph): a cell whose outcome a start one ulp away
    changed (a chaotic run's) may differ, mark included; any other cell may not."""
    ref = _outcomes([[0, 1], [1, 0]], [[False, False], [False, True]])
    flipped = _outcomes([[0, 1], [1, 1]], [[False, False], [False, True]])
    df = compare(flipped, ref, rtol=RTOL, atol=ATOL).set_index("variable")
    assert set(df.status) == {"pass"} and "1 of them sensitive" in df.detail["a0_image0_z"]
    assert "a0_text3_xy" in df.index  # the new mark of the sensitive cell passes
    df = compare(_outcomes([[1, 1], [1, 0]], [[False, False], [False, True]]), ref, rtol=RTOL,
                 atol=ATOL).set_index("variable")
    assert df.status["a0_image0_z"] == "fail" and df.status["a0_text0_xy"].startswith("fail: new")


def test_a_rule_and_a_provenance_are_recorded_only_from_their_lists():
    fig, ax = plt.subplots()
    (line,) = ax.plot([0, 1], [0, 1])
    with pytest.raises(ValueError, match="rule = 'pointwise'; allowed: motions"):
        wellposed(line, "pointwise")
    with pytest.raises(ValueError, match="provenance = 'luck'; allowed: exact"):
        wellposed(line, "magnitude", provenance="luck")
    with pytest.raises(ValueError, match="timed"):
        wellposed(line, "magnitude", timed=("z",))
    wellposed(line, "curve")
    ds = figure_data(fig)
    plt.close(fig)
    assert ds["a0_line0_y"].attrs["provenance"] == "continuation" and ds["a0_line0_y"].attrs["wellposed"] == "curve"


def test_an_array_whose_declared_rule_changed_fails_until_the_reference_is_remade():
    ref = _errors([1e-5, 1e-8, 7.5e-11])
    new = ref.copy(deep=True)
    new["a0_line0_y"].attrs["wellposed"] = "located"
    df = compare(new, ref, rtol=RTOL, atol=ATOL).set_index("variable")
    assert df.status["a0_line0_y"] == "fail: declares rule 'located', the reference 'magnitude'"


def _named_line(x, y_place, step_x=0.0, free="y"):
    fig, ax = plt.subplots()
    ax.axvline(x)
    wellposed(ax.annotate("1:1 exit", (x, y_place), xycoords=("data", "axes fraction")), "placed", free=free,
              step_x=step_x)
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_a_line_s_name_may_take_another_place_up_the_line_but_not_leave_it():
    """A name the layout placed at one of several heights beside its line (clear of markers that move): another
    height passes, the line's d held to its grid step (pointwise without one); the layout's records it so."""
    ref = _named_line(0.2, 0.02, step_x=0.01)
    df = compare(_named_line(0.205, 0.6, step_x=0.01), ref, rtol=RTOL, atol=ATOL).set_index("variable")
    assert df.status["a0_text0_xy"] == "pass" and df.provenance["a0_text0_xy"] == "layout"
    assert compare(_named_line(0.212, 0.02, step_x=0.01), ref, rtol=RTOL, atol=ATOL).set_index(
        "variable").status["a0_text0_xy"] == "fail"
    exact = _named_line(0.2, 0.02)
    assert compare(_named_line(0.2 + 1e-6, 0.4), exact, rtol=RTOL, atol=ATOL).set_index(
        "variable").status["a0_text0_xy"] == "fail"
    assert compare(_named_line(0.2, 0.4), exact, rtol=RTOL, atol=ATOL).set_index(
        "variable").status["a0_text0_xy"] == "pass"
    # place_labels records the rule where its candidates' anchors differ in height, and not where they share one
    from vibroimpact.outputs.layout import place_labels

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1], "o")
    a, b = place_labels(fig, [(ax, "up the line", [((0.5, y), (2, 1)) for y in (0.02, 0.5)],
                               dict(xycoords=("data", "axes fraction"))),
                              (ax, "at a point", [((0.5, 0.5), off) for off in ((3, 3), (-3, -3))], {})])
    ds = figure_data(fig)
    plt.close(fig)
    assert ds["a0_text0_xy"].attrs["wellposed"] == "placed" and ds["a0_text0_xy"].attrs["wp_free"] == "y"
    assert "wellposed" not in ds["a0_text1_xy"].attrs


def test_a_name_of_merged_short_runs_may_change_its_motions_but_not_its_place():
    """Short runs merged under one name list motions that interleave where they meet (which, and in what order,
    moves with any point there): such a name may change, within one sweep step of its place; a run of one
    motion keeps its name."""
    def name(text, x, merged):
        fig, ax = plt.subplots()
        wellposed(ax.text(x, 0.9, text), "run", step=0.25, merged=merged)
        ds = figure_data(fig)
        plt.close(fig)
        return ds

    ref = name("chaotic, unsettled, …", 5.0, True)
    assert set(compare(name("unsettled, chaotic, …", 5.2, True), ref, rtol=RTOL, atol=ATOL).status) == {"pass"}
    assert set(compare(name("unsettled, chaotic, …", 5.3, True), ref, rtol=RTOL, atol=ATOL).status) == {"fail"}
    one = name("2:1 T=2", 5.0, False)
    assert set(compare(name("2:1 T=4", 5.0, False), one, rtol=RTOL, atol=ATOL).status) == {"fail"}


def test_a_sweep_point_s_abscissa_is_one_point_within_the_strict_tolerance_of_its_own_magnitude():
    """One of the three values at d = 4 carries its d rounded otherwise, moved by 2e-10 of it (within the strict
    tolerance 1e-9 |d|, far beyond its atol 1e-12): still one point of seven, as in the reference, whatever the
    sweep's first d (here 0); moved by 2e-9 of it, beyond the tolerance, it is a point of its own."""
    def moved(rel):
        ds = _variant()
        x = ds["a0_line0_x"].values.copy()
        assert x[9] == 4.0  # points 0-3 hold two values each: point 4's are 8, 9, 10
        x[9] = 4.0 * (1 + rel)
        ds["a0_line0_x"].values = x
        return ds

    df = _check(moved(2e-10), _variant())
    assert set(df.status) == {"pass"} and df.detail.iloc[0].startswith("7 points: 6 exact values, 1 statistics")
    df = _check(moved(2e-9), _variant())
    assert set(df.status) == {"fail"} and "the points moved (8 points, reference 7)" in df.detail.iloc[0]


def test_the_detail_counts_the_motions_changed_at_a_boundary():
    """Two points take another motion, each at a boundary of its own in the reference (point 5 beside the
    aperiodic point 4, point 2 two points from it): the detail counts both, and no transient."""
    new = _variant(motions=_at(5, "1:1 period-4", _at(2, "no period found", BASE["motions"])),
                   settled=_at(2, False, BASE["settled"]))
    df = _check(new, _variant())
    assert set(df.status) == {"pass"}
    assert "2 motion changed at a boundary, 0 at a transient longer than the cap" in df.detail.iloc[0], df.detail.iloc[0]


def test_an_error_where_the_reference_has_none_or_an_infinite_one_fails():
    """An error compared by its magnitude: a finite error where the reference has no error (NaN: no run reached
    the tolerance) or an infinite one (the wrong walls) fails, as does the converse."""
    ref = [1e-5, 1e-8, 7.5e-11]
    for a, b in (([1e-5, np.nan, 7.5e-11], ref), ([1e-5, np.inf, 7.5e-11], ref), (ref, [1e-5, np.nan, 7.5e-11])):
        df = compare(_errors(b), _errors(a), rtol=RTOL, atol=ATOL).set_index("variable")
        assert df.status["a0_line0_y"] == "fail", (a, b)
        assert "NaN or infinite errors at other places" in df.detail["a0_line0_y"], df.detail["a0_line0_y"]


@pytest.mark.parametrize("block", [1, 15, 10**6])
def test_each_point_s_distance_to_a_curve_is_its_distance_to_the_nearest_segment_in_blocks_of_any_size(block,
                                                                                                     monkeypatch):
    """_distance_ok takes points in blocks against every segment at once: whatever the block, each point's
    distance is the smallest of its distances to the segments, written here as the nearer end or the foot of
    the perpendicular where it falls inside, and it is within a segment's allowance exactly where that
    distance is (the segments here are straight: no chord error; a piece's first and last segment allow their
    own length beyond the piece's end)."""
    import vibroimpact.outputs.figcheck as fc

    monkeypatch.setattr(fc, "_BLOCK", block)
    rng = np.random.default_rng(7)
    piece = np.column_stack([np.linspace(0.0, 1.0, 6), np.zeros(6)])  # a straight piece: no turning, no sag
    segs = fc._segments([piece])
    points = rng.uniform(-0.5, 1.5, size=(53, 2))
    atol = 0.05
    ok, dist = fc._distance_ok(points, segs, atol)

    def to_segment(p, a, b):
        ab, ap = b - a, p - a
        foot = (ap @ ab) / (ab @ ab)
        if 0.0 < foot < 1.0:
            return abs(ab[0] * ap[1] - ab[1] * ap[0]) / np.hypot(*ab)
        return min(np.hypot(*(p - a)), np.hypot(*(p - b)))

    expected = np.array([min(to_segment(p, a, b) for a, b, *_ in segs) for p in points])
    np.testing.assert_allclose(dist, expected, rtol=1e-12, atol=1e-15)
    # inside the x range of the piece the allowance is atol; beyond its ends one segment's length (0.2) more
    beyond = np.maximum(np.maximum(-points[:, 0], points[:, 0] - 1.0), 0.0)
    allowed = np.where(beyond > 0.0, atol + 0.2, atol)
    clear = np.abs(expected - allowed) > 1e-6  # away from the allowance's edge
    assert clear.sum() > 40
    np.testing.assert_array_equal(ok[clear], (expected <= allowed)[clear])


def test_each_key_s_rows_are_gathered_whatever_their_order():
    """_per_key on rows of interleaved keys: per key the motion, mean and se of its first row, settled when all
    its rows are, unsettled when any is, the largest sensitivity (at least 0, NaN ignored) and its finite values
    sorted, as each key's rows picked out one by one give them."""
    import xarray as xr

    import vibroimpact.outputs.figcheck as fc

    rng = np.random.default_rng(3)
    n, n_keys = 40, 9
    index = rng.permutation(np.arange(n) % n_keys)
    values = rng.normal(size=n)
    values[::7] = np.nan
    sens = rng.uniform(-1.0, 2.0, size=n)
    sens[::5] = np.nan
    sens[index == 4] = np.nan  # a key with no sensitivity at all: 0
    base = "a0_line0"
    ds = xr.Dataset({f"{base}_wp_{k}": ("i", v) for k, v in dict(
        motion=np.array([f"m{k}" for k in range(n)]), settled=rng.uniform(size=n) < 0.8,
        unsettled=rng.uniform(size=n) < 0.1, mean=rng.normal(size=n), se=rng.uniform(size=n),
        sensitivity=sens).items()})
    got = fc._per_key(ds, base, index, n_keys, values)
    assert len(got) == n_keys
    for u, row in enumerate(got):
        sel = [i for i in range(n) if index[i] == u]
        assert row["motion"] == f"m{sel[0]}"
        assert row["mean"] == ds[f"{base}_wp_mean"].values[sel[0]] and row["se"] == ds[f"{base}_wp_se"].values[sel[0]]
        assert row["settled"] == all(ds[f"{base}_wp_settled"].values[sel])
        assert row["unsettled"] == any(ds[f"{base}_wp_unsettled"].values[sel])
        finite = [s for s in sens[sel] if not np.isnan(s)]
        assert row["sensitivity"] == max([0.0, *finite])
        np.testing.assert_array_equal(row["values"], sorted(v for v in values[sel] if np.isfinite(v)))
    assert got[4]["sensitivity"] == 0.0
