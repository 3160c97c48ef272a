"""The rules of the figure regeneration check (vibroimpact.figcheck), on figures drawn for the purpose:
each rule passes what is well-posed and fails what is not."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from vibroimpact.figcheck import Z_CRIT
from vibroimpact.figdata import compare, figure_data, image_allowance
from vibroimpact.plots._common import wellposed

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


def _check(new, ref, ill=("a0_line0_x", "a0_line0_y")):
    return compare(new, ref, rtol=RTOL, atol=ATOL, ill=ill).set_index("variable")


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
    assert set(_check(_variant(**flip, unsettled=_at(1, True, [False] * 7)), ref).status) == {"pass"}


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
    assert "the points moved" in _check(new, ref).detail.iloc[0]


def test_an_ill_conditioned_array_without_a_rule_is_compared_pointwise_and_a_well_conditioned_one_always():
    ref = _variant()
    moved = _variant(values=_at(4, [0.65, 0.05, 0.3], BASE["values"]))
    assert set(_check(moved, ref, ill=()).status) == {"pass", "fail"}  # pointwise: the chaotic point moved
    assert set(_check(moved, ref).status) == {"pass"}


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
    ill = ("a0_line0_x", "a0_line0_y")
    for new in (_curve(180), _curve(200, shift=0.5 / 199), _curve(200, drop_end=True)):
        assert set(compare(new, ref, rtol=RTOL, atol=ATOL, ill=ill).status) == {"pass"}


def test_curve_fails_a_moved_or_a_shortened_curve():
    ref = _curve(200)
    ill = ("a0_line0_x", "a0_line0_y")
    fig, ax = plt.subplots()
    s = np.linspace(0.0, 1.0, 200)
    wellposed(ax.plot(1.001 * np.cos(3 * s), 1.001 * np.sin(3 * s), "-")[0], "curve")
    bigger = figure_data(fig)
    plt.close(fig)
    assert "fail" in set(compare(bigger, ref, rtol=RTOL, atol=ATOL, ill=ill).status)
    assert "fail" in set(compare(_curve(200, shift=0.2), ref, rtol=RTOL, atol=ATOL, ill=ill).status)


def _map(labels, extra=()):
    fig, ax = plt.subplots()
    xs, ys = np.arange(6.0), np.arange(4.0)
    codes = np.zeros((4, 6))
    mesh = ax.pcolormesh(xs, ys, codes, shading="nearest")
    wellposed(mesh, "motions", motion=np.asarray(labels).ravel())
    if len(extra):
        wellposed(ax.plot(*np.asarray(extra, float).T, ".", ls="")[0], "boundary")
    ds = figure_data(fig)
    plt.close(fig)
    return ds


def test_a_map_of_motions_changes_only_at_boundaries_and_its_boundary_markers_with_it():
    lab = np.array([["A"] * 3 + ["B"] * 3] * 4)
    ref = _map(lab, extra=[(2.5, y) for y in range(4)])
    ill = ("a0_points0_c", "a0_points0_x", "a0_points0_y", "a0_line0_x", "a0_line0_y")
    edge = lab.copy()
    edge[1, 3] = "A"  # a cell beside the boundary
    new = _map(edge, extra=[(2.5, 0), (3.5, 1), (2.5, 2), (2.5, 3)])
    assert set(compare(new, ref, rtol=RTOL, atol=ATOL, ill=ill).status) == {"pass"}
    inside = lab.copy()
    inside[1, 0] = "B"  # deep inside A
    df = compare(_map(inside, extra=[(2.5, y) for y in range(4)]), ref, rtol=RTOL, atol=ATOL, ill=ill)
    assert "fail" in set(df.status)
    # a boundary marker with no changed cell beside it
    df = compare(_map(lab, extra=[(2.5, 0), (2.5, 1), (2.5, 2), (0.5, 3)]), ref, rtol=RTOL, atol=ATOL, ill=ill)
    assert "fail" in set(df.set_index("variable").loc[["a0_line0_x"], "status"])


def test_the_image_allowance_is_twice_the_measured_spread_and_at_least_one_point():
    import pandas as pd

    from vibroimpact.checks import IMAGE_ROW

    cond = pd.DataFrame([dict(figure="f", variable=IMAGE_ROW, conditioning="ill-conditioned", spread=3.0),
                         dict(figure="f", variable="a0_line0_y", conditioning="ill-conditioned", spread=1.0),
                         dict(figure="g", variable=IMAGE_ROW, conditioning="strict", spread=0.0)])
    assert image_allowance(cond, "f", 0)[0] == 6
    assert image_allowance(cond, "g", 0)[0] == 2
    assert image_allowance(None, "g", 0)[0] == 0
