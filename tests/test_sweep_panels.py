"""What a sweep panel draws besides its curves: each point's last period of simulated events, and the motions'
names over the panel, set in rows that never overprint."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.transforms import blended_transform_factory

from vibroimpact.outputs.plots._common import RUN_NAME, RUN_SPANS, last_events, rows_of_names, use_style

NAN = np.nan


def _sweep():
    """Three points of a sweep, both directions; each value tells its point (hundreds) and event (units), the up
    direction's 1000 more.  Point 0 has an exact cycle (two finite values and a NaN); point 1 none, with a period of
    3 events (and a cycle of times alone, of period 5); point 2 none and no period (its last min(m, 24) events)."""
    n_ev = 30
    recorded = [30, 10, 5]  # events recorded per point
    v = np.full((2, 3, n_ev), NAN)
    t = np.full((2, 3, n_ev), NAN)
    for k in range(2):
        for p, m in enumerate(recorded):
            v[k, p, :m] = 1000 * k + 100 * p + np.arange(m)
            t[k, p, :m] = 0.5 * np.arange(m) ** 2 + p
    cycle_v = np.full((2, 3, 3), NAN)
    cycle_t = np.full((2, 3, 3), NAN)
    cycle_v[:, 0] = [[7.0, NAN, 9.0], [1007.0, NAN, 1009.0]]
    cycle_t[:, 0] = [[1.0, NAN, 4.0], [1.0, NAN, 4.0]]
    cycle_t[:, 1] = [[2.0, 3.0, NAN], [2.0, 3.0, NAN]]  # a cycle of times only: the v_minus panel has none
    dims = ("direction", "point")
    return xr.Dataset(
        {"v_minus": ((*dims, "event"), v), "t": ((*dims, "event"), t),
         "cycle_v_minus": ((*dims, "cycle"), cycle_v), "cycle_t": ((*dims, "cycle"), cycle_t),
         "period": (dims, np.array([[2, 5, 0], [2, 5, 0]])), "period_events": (dims, np.array([[2, 3, 0], [2, 3, 0]]))},
        coords={"direction": ["down", "up"], "d": ("point", [0.1, 0.2, 0.3])})


@pytest.mark.parametrize("direction, base", [("down", 0), ("up", 1000)])
def test_each_point_draws_its_cycle_or_its_last_period_of_events(direction, base):
    x, y = last_events(_sweep(), "v_minus", direction)
    np.testing.assert_array_equal(x, [0.1] * 2 + [0.2] * 3 + [0.3] * 5)
    np.testing.assert_array_equal(y, base + np.array([7, 9, 107, 108, 109, 200, 201, 202, 203, 204]))


def test_the_time_between_events_of_a_cycle_closes_it_over_its_period():
    """``dt``: a cycle's first value is its time since the cycle's last event one period earlier (2 in t per
    forcing period); without a cycle, the differences of the recorded times (point 1's period of events is not
    used: its cycle of times is)."""
    x, dt = last_events(_sweep(), "dt", "down")
    t2 = 0.5 * np.arange(5) ** 2 + 2
    np.testing.assert_array_equal(x, [0.1] * 2 + [0.2] * 2 + [0.3] * 4)
    np.testing.assert_array_equal(dt, np.r_[1.0 - (4.0 - 2.0 * 2), 3.0, 2.0 - (3.0 - 2.0 * 5), 1.0, np.diff(t2)])


def test_crowded_names_take_rows_that_keep_them_apart():
    """Names of neighbouring runs wider than their runs: each is set in a row (or moved sideways) where it keeps
    the pad from every name placed before it."""
    use_style()
    fig, ax = plt.subplots(figsize=(3.5, 2.5))
    ax.plot(np.linspace(0, 1, 50), np.linspace(0, 1, 50), "o", ms=2)
    tr = blended_transform_factory(ax.transData, ax.transAxes)
    names = []
    for k in range(8):
        a, b = k / 8, (k + 1) / 8 - 0.01
        text = ax.text(0.5 * (a + b), 0.965, f"period-{k} motion", transform=tr, ha="center", va="top", fontsize=5)
        text.set_gid(RUN_NAME)
        RUN_SPANS[text] = (a, b)
        names.append(text)
    pad = 3.0
    rows_of_names(fig, pad=pad)
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in names]
    assert len({round(t.get_position()[1], 6) for t in names}) > 1  # crowded: more than one row
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.padded(pad - 0.5).overlaps(b)
    plt.close(fig)
