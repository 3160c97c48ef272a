"""The chaotic windows and chaotic outputs tables (vibroimpact.outputs.tables) and the lambda_1 figure
(vibroimpact.outputs.plots.chaos), on datasets whose answers are known by hand and on a real sweep."""

import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from scipy.stats import t as student

from vibroimpact.analysis.settled import LONG_BATCHES
from vibroimpact.outputs.tables import chaos_markdown, chaotic_outputs, chaotic_windows

K_S = 0.6225  # d = K_S s at the paper's force


def synthetic_sweep(labels, lam, d):
    """A sweep of one direction (listed in decreasing d, as a down sweep is) with labels and lambda_1."""
    lam = np.asarray(lam, float)
    dims = ("direction", "point")
    return xr.Dataset({
        "label": (dims, np.array([labels])), "lyap1": (dims, lam[None]), "lyap1_low": (dims, lam[None] - 0.01),
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
    ys = np.concatenate([ds[v].values for v in lam_axes])
    for direction in ("down", "up"):
        s = across_chaos.sel(direction=direction)
        keep = 0 if direction == "down" else 1
        for v in s.lyap1.values[keep::2]:
            assert np.any(np.isclose(ys, v, rtol=0, atol=1e-15)), v
    exact = [v for v in lam_axes if ds[v].attrs.get("wellposed") == "motions"]
    assert exact
    base = exact[0].removesuffix("_y")
    assert f"{base}_wp_settled" in ds and f"{base}_wp_se" in ds
    chaos = across_chaos.sel(direction="up").isel(point=1)  # the up sweep's points are the odd ones
    estimates = [v.removesuffix("_y") for v in lam_axes if np.isclose(ds[v].values, float(chaos.lyap1)).any()]
    se = ds[f"{estimates[0]}_wp_se"].values
    crit = student.ppf(0.975, LONG_BATCHES - 1)
    assert se[np.isfinite(se)] == pytest.approx((float(chaos.lyap1_high) - float(chaos.lyap1_low)) / (2 * crit))


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
    m = xr.Dataset({"label": (("beta", "s"), labels)},
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
