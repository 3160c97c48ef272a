"""The chaotic windows and chaotic outputs tables (vibroimpact.outputs.tables) and the lambda_1 figure
(vibroimpact.outputs.plots.chaos), on datasets whose answers are known by hand and on a real sweep."""

import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from scipy.stats import t as student

from vibroimpact.analysis.motions import Motion
from vibroimpact.analysis.settled import LONG_BATCHES
from vibroimpact.outputs.tables import chaos_markdown, chaotic_outputs, chaotic_windows

K_S = 0.6225  # d = K_S s at the paper's force


def synthetic_sweep(labels, lam, d):
    """A sweep of one direction (listed in decreasing d, as a down sweep is) with labels and lambda_1."""
    lam = np.asarray(lam, float)
    dims = ("direction", "point")
    return xr.Dataset({
        "label": (dims, np.array([labels])), "sticking": (dims, np.array([[lab.endswith("with sticking") for lab in labels]])),
        "lyap1": (dims, lam[None]), "lyap1_low": (dims, lam[None] - 0.01),
        "lyap1_high": (dims, lam[None] + 0.01), "lyap1_time": (dims, 2 * lam[None]),
    }, coords={"direction": ["down"], "d": ("point", d), "s": ("point", np.asarray(d) / K_S)},
        attrs={"vary": "s", "beta": math.pi / 3})


def test_a_chaotic_window_is_a_run_of_consecutive_chaotic_points_in_d():
    d = np.array([0.30, 0.28, 0.26, 0.24, 0.22, 0.20])[::-1][::-1]  # decreasing, as the down sweep lists them
    sw = synthetic_sweep(["1:1 period-2", "chaotic", "chaotic", "2:1 period-2", "chaotic", "quasi-periodic"],
                         [-0.1, 0.3, 0.1, -0.2, 0.5, 0.0], d)
    w = chaotic_windows({"x": sw}).sort_values("d_lo")
    assert list(w.d_lo) == pytest.approx([0.22, 0.26]) and list(w.d_hi) == pytest.approx([0.22, 0.28])
    assert list(w.points) == [1, 2] and list(w.step) == pytest.approx([0.02, 0.02])
    two = w.iloc[1]
    assert (two.lyap1_median, two.lyap1_min, two.lyap1_max) == pytest.approx((0.2, 0.1, 0.3))
    assert two.lyap1_low_min == pytest.approx(0.09) and two.lyap1_time_median == pytest.approx(0.4)
    assert (two.s_lo, two.s_hi) == pytest.approx((0.26 / K_S, 0.28 / K_S))
    none = synthetic_sweep(["1:1 period-2"] * 3, [-0.1] * 3, d[:3])
    assert chaotic_windows({"x": none}).empty


def test_a_chaotic_output_is_the_window_beside_the_long_run_with_its_interval():
    dims = ("direction", "point")
    en = xr.Dataset({
        "label": (dims, [["chaotic", "2:1 period-2"]]), "window_time": (dims, [[30.5, 30.0]]),
        "U_T": (dims, [[103.0, 50.0]]), "U_T_long": (dims, [[100.0, np.nan]]), "U_T_long_se": (dims, [[2.0, np.nan]]),
        "U_I": (dims, [[90.0, 40.0]]), "U_I_long": (dims, [[95.0, np.nan]]), "U_I_long_se": (dims, [[0.0, np.nan]]),
    }, coords={"direction": ["down"], "d": ("point", [0.23, 0.19]), "s": ("point", [0.37, 0.31])},
        attrs={"vary": "s", "beta": math.pi / 3})
    out = chaotic_outputs({"x": en})
    assert len(out) == 1
    r = out.iloc[0]
    crit = student.ppf(0.975, LONG_BATCHES - 1)
    assert (r.U_T_window, r.U_T_long, r.U_T_diff, r.U_T_diff_se) == pytest.approx((103.0, 100.0, 3.0, 1.5))
    assert r.U_T_long_ci == pytest.approx(2.0 * crit)
    assert r.U_I_diff == pytest.approx(-5.0) and math.isnan(r.U_I_diff_se)  # no spread: no standard errors
    windows = pd.DataFrame([dict(sweep="x", beta=math.pi / 3, vary="s", direction="down", d_lo=0.23, d_hi=0.23,
                                 step=0.04, points=1, s_lo=0.37, s_hi=0.37, lyap1_median=0.2, lyap1_min=0.2,
                                 lyap1_max=0.2, lyap1_low_min=0.19, lyap1_time_median=0.4)])
    md = chaos_markdown(windows, out)
    assert "| x | π/3 | down | [0.2300, 0.2300] ± 4.0e-02 | 1 |" in md
    assert f"100 ± {2.0 * crit:.2g}" in md and "+3 V (+3.0 %, +2 SE) at d = 0.2300" in md


@pytest.fixture(scope="module")
def across_chaos():
    from vibroimpact.analysis.sweeps import sweep

    return sweep("s", np.array([0.20, 0.235, 0.30]) / K_S, beta=math.pi / 3, phi=0.42, v0=0.87, long_impacts=4000)


def test_the_lambda_1_figure_draws_each_point_s_exponent_with_what_the_check_compares(across_chaos):
    """Every point's lambda_1 is drawn once per direction at its d: the exact values of the solved cycles
    as settled motions, the chaotic estimate as a statistic whose standard error is its interval's."""
    from vibroimpact.outputs.figdata import figure_data
    from vibroimpact.outputs.plots import fig_lyapunov

    fig = fig_lyapunov([across_chaos], [[]])
    ds = figure_data(fig)
    lam_axes = [v for v in ds.data_vars if "lambda_1" in ds[v].attrs.get("axis_label", "") and v.endswith("_y")]
    ys = np.concatenate([ds[v].values for v in lam_axes if ds[v].attrs.get("wellposed") == "motions"])
    for direction in ("down", "up"):  # every point of both directions, not every other one
        s = across_chaos.sel(direction=direction)
        for v in s.lyap1.values:
            assert np.any(np.isclose(ys, v, rtol=0, atol=1e-15)), v
    assert ys.size == 2 * across_chaos.sizes["point"]
    exact = [v for v in lam_axes if ds[v].attrs.get("wellposed") == "motions"]
    assert exact
    base = exact[0].removesuffix("_y")
    assert f"{base}_wp_settled" in ds and f"{base}_wp_se" in ds
    chaos = across_chaos.sel(direction="up").isel(point=1)
    estimates = [v.removesuffix("_y") for v in lam_axes if np.isclose(ds[v].values, float(chaos.lyap1)).any()]
    se = ds[f"{estimates[0]}_wp_se"].values
    crit = student.ppf(0.975, LONG_BATCHES - 1)
    assert se[np.isfinite(se)] == pytest.approx((float(chaos.lyap1_high) - float(chaos.lyap1_low)) / (2 * crit))


def test_minus_infinity_is_a_triangle_at_the_foot_and_every_other_point_a_circle_or_cross():
    """The caption: lambda_1 = -inf (sticking, at rest) drawn as a triangle at the panel's foot."""
    import matplotlib.pyplot as plt
    from matplotlib.markers import MarkerStyle

    from vibroimpact.outputs.plots.chaos import MINUS_INF_MARKER, _lyapunov_points, minus_inf_level

    d = np.array([0.30, 0.28, 0.26])
    sw = synthetic_sweep(["1:1 period-2 with sticking", "chaotic", "1:1 period-2"], [-np.inf, 0.2, -0.3], d)
    sw["lyap1_low"] = sw.lyap1_low.where(np.isfinite(sw.lyap1), -np.inf)
    sw["lyap1_high"] = sw.lyap1_high.where(np.isfinite(sw.lyap1), -np.inf)
    sw["lyap1_sensitivity"] = sw.lyap1 * 0
    for v in ("period", "settled", "long_status", "abs_v_mean", "abs_v_se", "n_bottom", "n_top"):
        sw[v] = sw.lyap1 * 0
    sw.attrs["r"] = 0.5
    fig, ax = plt.subplots()
    try:
        _lyapunov_points(ax, sw, "down", "o")
    except KeyError as err:  # point_info needs more of a real sweep
        pytest.skip(f"synthetic sweep lacks {err}")
    art = ax.collections[-1]  # the points (the intervals' bars come first)
    tri = MarkerStyle(MINUS_INF_MARKER)
    tri = tri.get_path().transformed(tri.get_transform())
    paths = art.get_paths()
    assert len(paths) == 3
    assert np.allclose(paths[0].vertices, tri.vertices) and not np.allclose(paths[2].vertices[:3], tri.vertices[:3])
    assert art.get_offsets()[0][1] == pytest.approx(minus_inf_level(0.5))
    plt.close(fig)


def test_a_point_with_no_period_is_drawn_in_its_motions_colour_in_every_figure():
    """One colour per motion: lambda_1 of a chaotic, quasi-periodic or unsettled point is drawn (marker, interval bar,
    legend entry) in the colour the regime maps and the bifurcation sets give that motion; a point with a period in
    black (its exact value)."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_hex

    from vibroimpact.analysis.motions import CHAOTIC, QUASI_PERIODIC, UNSETTLED
    from vibroimpact.outputs.plots._common import motion_color
    from vibroimpact.outputs.plots.chaos import PERIODIC_COLOR, _lyapunov_points, lyapunov_handles

    labels = [CHAOTIC, QUASI_PERIODIC, UNSETTLED, "1:1 period-2"]
    sw = synthetic_sweep(labels, [0.2, 0.0, -0.05, -0.3], np.array([0.30, 0.28, 0.26, 0.24]))
    sw["lyap1_low"] = sw.lyap1_low.where(sw.label != "1:1 period-2", sw.lyap1)  # exact: no interval
    sw["lyap1_high"] = sw.lyap1_high.where(sw.label != "1:1 period-2", sw.lyap1)
    for v in ("lyap1_sensitivity", "settled", "long_status", "abs_v_mean", "abs_v_se"):
        sw[v] = sw.lyap1 * 0
    fig, ax = plt.subplots()
    kinds = _lyapunov_points(ax, sw, "down", "o")
    bars, points = ax.collections
    expected = [motion_color(x) for x in labels[:3]] + [PERIODIC_COLOR]
    assert [to_hex(c) for c in points.get_edgecolors()] == [to_hex(c) for c in expected]
    assert [to_hex(c) for c in bars.get_colors()] == [to_hex(c) for c in expected[:3]]
    legend = {h.get_label().split(":")[0]: to_hex(h.get_color()) for h in lyapunov_handles(kinds)}
    assert {x: legend[x] for x in labels[:3]} == {x: to_hex(motion_color(x)) for x in labels[:3]}
    plt.close(fig)


@pytest.mark.parametrize("labels, expected", [
    # each run of at least min_points is named by its motion, one name per motion: chaotic and unsettled apart
    (["1:1 period-2"] * 10 + ["chaotic"] * 6 + ["unsettled"] * 5 + ["2:1 period-2"] * 12,
     [("1:1 T=2", 10), ("chaotic", 6), ("unsettled", 5), ("2:1 T=2", 12)]),
    # a window of period 4 inside unsettled and chaotic stretches keeps its own name (Fig 9 (d): 12 points of 1:1
    # period-4 between 0.2294 and 0.2476 were under "aperiodic, periodic windows")
    (["1:1 period-2"] * 10 + ["unsettled"] * 5 + ["1:1 period-4"] * 12 + ["unsettled", "unsettled", "1:1 period-8",
                                                                            "1:1 period-8", "unsettled", "chaotic"]
     + ["chaotic"] * 6 + ["2:1 period-2"] * 12,
     [("1:1 T=2", 10), ("unsettled", 5), ("1:1 T=4", 12), ("unsettled, 1:1 T=8", 5), ("chaotic", 7),
      ("2:1 T=2", 12)]),
    # short runs of several motions merged, named by what they hold, the most frequent first; a periodic motion
    # without a short name among the "periodic windows"
    (["1:1 period-2"] * 12 + ["chaotic", "chaotic", "6:3 over 4 forcing periods", "chaotic", "chaotic",
                              "4:2 over 3 forcing periods", "chaotic"] + ["2:1 period-2"] * 12,
     [("1:1 T=2", 12), ("chaotic, periodic windows", 7), ("2:1 T=2", 12)]),
    # a run of exactly min_points is named alone, not merged with the short runs beside it
    (["1:1 period-2"] * 10 + ["unsettled"] * 5 + ["chaotic"] * 2 + ["2:1 period-2"] * 12,
     [("1:1 T=2", 10), ("unsettled", 5), ("2:1 T=2", 12)]),
    # too short to name, even together: a gap
    (["1:1 period-2"] * 12 + ["chaotic", "3:1 period-2"] + ["2:1 period-2"] * 12, [("1:1 T=2", 12), ("2:1 T=2", 12)]),
])
def test_motion_blocks_name_every_run_long_enough_and_short_runs_together(labels, expected):
    """Fig 5 (a), beta = pi/2: chaos in runs of one to five points between periodic windows got no name;
    short runs are merged and named by what they hold.  Fig 9 (d): a 12-point window hidden under a name of
    what surrounds it; "aperiodic" and "chaotic" for one thing.  The names are the motions' names and nothing
    else, and what is left unnamed is shorter than min_points."""
    from vibroimpact.outputs.plots._common import motion_blocks

    names = {m.label: m.short_label for m in (Motion(period=1, bottom=1, top=1), Motion(period=1, bottom=2, top=1),
                                              Motion(period=2, bottom=2, top=2), Motion(period=4, bottom=4, top=4))}
    blocks = motion_blocks(labels, min_points=5, names=names)
    assert [(name, b - a) for a, b, name in blocks] == expected
    assert not any("aperiodic" in name for *_, name in blocks)
    named = np.zeros(len(labels), bool)
    for a, b, _ in blocks:
        named[a:b] = True
    gaps = np.flatnonzero(np.diff(np.r_[0, (~named).astype(int), 0])).reshape(-1, 2)
    assert all(b - a < 5 for a, b in gaps)  # what is not named is shorter than min_points


def test_the_band_between_2to1_and_1to1_lists_every_run_with_its_exponents_and_the_1to1_exit():
    from vibroimpact.outputs.tables import between_2to1_and_1to1, between_markdown

    d = np.array([0.30, 0.28, 0.26, 0.24, 0.22, 0.20, 0.18])
    sw = synthetic_sweep(["1:1 period-2", "1:1 period-4", "chaotic", "chaotic", "5:4 over 4 forcing periods",
                          "2:1 period-2", "2:1 period-2"], [-0.1, -0.3, 0.3, 0.1, -0.08, -0.2, -0.2], d)
    tr = xr.Dataset({"exit_d": ((), 0.25), "exit_kind": ((), "grazing"), "exit_clearance": ((), 1e-8)})
    df = between_2to1_and_1to1(sw, tr)
    assert list(df.motion.str.slice(0, 17)) == ["2:1 period-2", "5:4 over 4 forcin", "chaotic", "1:1 exit: grazing",
                                                "1:1 period-4", "1:1 period-2"]
    chaos = df[df.motion == "chaotic"].iloc[0]
    assert (chaos.d_lo, chaos.d_hi, chaos.points, chaos.lyap1_max, chaos.d_at_max) == pytest.approx(
        (0.24, 0.26, 2, 0.3, 0.26))
    md = between_markdown({"x": (sw, tr)})
    assert "| [0.2400, 0.2600] | chaotic | 2 | 0.100 – 0.300 | 0.2600 |" in md
    assert between_2to1_and_1to1(synthetic_sweep(["1:1 period-2"] * 2, [-0.1] * 2, d[:2])).empty


def test_the_largest_window_difference_is_the_largest_over_every_chaotic_point():
    from vibroimpact.outputs.tables import largest_window_difference

    out = pd.DataFrame({"sweep": ["a", "b"], "direction": ["down", "up"], "d": [0.2, 0.3],
                        "U_T_diff": [1.0, -6.0], "U_T_long": [100.0, 100.0], "U_T_diff_se": [1.0, -12.0],
                        "U_I_diff": [2.0, 0.0], "U_I_long": [50.0, 50.0], "U_I_diff_se": [2.0, 0.0]})
    text = largest_window_difference(out)
    assert "up to 6.0 % (Ū_T, b up, d = 0.3000: -12 of" in text


def test_a_map_names_every_label_of_a_motion_with_no_period_however_rare():
    """The regime map's colours: the nine most frequent periodic motions named (of two with one colour, the
    more frequent), the rest "other"; a
    chaotic, quasi-periodic or unsettled cell is never folded into "other", however few there are, and
    each cell keeps its own motion in what the check compares."""
    import matplotlib.pyplot as plt

    from vibroimpact.outputs.figdata import figure_data
    from vibroimpact.outputs.plots._common import motion_color
    from vibroimpact.outputs.plots.sweeps import fig_regime_map

    periodic = [f"{n}:1 period-2" for n in range(1, 13)]
    # cells per motion: the periodic ones common, then 5 unsettled, one quasi-periodic and one chaotic cell
    cells = [m for i, m in enumerate(periodic) for _ in range(40 - 2 * i)] + ["unsettled"] * 5
    cells += ["quasi-periodic", "chaotic"]
    cells += ["1:1 period-2"] * (30 * 20 - len(cells))
    labels = np.array(cells, dtype=str).reshape(30, 20)
    m = xr.Dataset({"label": (("beta", "s"), labels), "sticking": (("beta", "s"), np.zeros(labels.shape, bool))},
                   coords={"beta": ("beta", np.linspace(0.1, 1.5, 30), {"units": "rad"}),
                           "s": ("s", np.linspace(0.2, 0.7, 20), {"units": "m"})},
                   attrs={"phi": 0.42, "v0": 0.87, "F": 5.0})
    fig = fig_regime_map([m])
    names = [t.get_text() for t in fig.legends[0].get_texts()]
    data = figure_data(fig)
    plt.close(fig)
    assert {"chaotic", "quasi-periodic", "unsettled", "other"} <= set(names)
    # the nine most frequent, in that order, each with a colour no more frequent one has (motion_color)
    named = []
    for n in periodic:
        if len(named) < 9 and motion_color(n) not in {motion_color(m) for m in named}:
            named.append(n)
    assert [n for n in names if n in periodic] == named and named[:4] == periodic[:4]
    motion = data["a0_points0_wp_motion"].values.astype(str)  # per cell, in the mesh's order (beta, s)
    expect = np.where(np.isin(labels, periodic) & ~np.isin(labels, named), "other", labels).ravel()
    assert (motion == expect).all()
