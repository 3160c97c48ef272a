"""The design map's figure data are what it draws: every cell at the grid point whose value it shows,
also on the rows inserted for the design table's inclines."""

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from vibroimpact.analysis.design import grid_axes
from vibroimpact.outputs.figdata import figure_data
from vibroimpact.outputs.plots import fig_design_map


def synthetic_design():
    """A design map over (s, beta) with the table's inclines pi/6 and pi/4 inserted between grid rows, and
    an output that tells every point apart."""
    spec = {"x": "s", "x_range": [0.2, 0.7], "y": "beta", "y_range": [0.05, math.pi / 2]}
    xs, ys = grid_axes(spec, [6, 5], table_betas=[math.pi / 6, math.pi / 4, math.pi / 2])
    E = 1e3 * (xs[None, :] + 10 * ys[:, None])
    dims = ("beta", "s")
    ds = xr.Dataset({"E_U_T": (dims, E), "worst_U_T": (dims, E / 2), "multistable": (dims, np.zeros(E.shape, bool)),
                     "label": ((*dims, "attractor"), np.full((*E.shape, 1), "1:1 period-2")),
                     "count": ((*dims, "attractor"), np.full((*E.shape, 1), 8))},
                    coords={"s": xs, "beta": ys},
                    attrs=dict(x="s", y="beta", min_share=0.01, starts=8, distribution="rest", F=5.0, tolerance_s=0.01))
    curves = xr.Dataset({"s": ("point", [0.3, 0.3]), "beta": ("point", [0.0, 1.6]), "curve_index": ("point", [0, 0]),
                         "admissible": ("point", [True, True]), "curve_kind": ("curve", ["fold"]),
                         "curve_word": ("curve", ["BBT"])}, attrs={"params": "s beta"})
    return ds, curves


def test_the_table_rows_are_off_the_regular_grid():
    from vibroimpact.outputs.plots.design import inserted_rows

    ds, _ = synthetic_design()
    assert np.flatnonzero(inserted_rows(ds.beta.values)).tolist() == [2, 3]  # pi/6 and pi/4, in one grid interval; pi/2 is a grid row


@pytest.mark.parametrize("panel, field", [(0, "E_U_T"), (1, "worst_U_T")])
def test_every_saved_cell_is_a_grid_point_with_its_value(panel, field):
    ds, curves = synthetic_design()
    fig = fig_design_map(ds, curves, [])
    data = figure_data(fig)
    plt.close(fig)
    bases = sorted({v.rsplit("_", 1)[0] for v in data.data_vars if v.startswith(f"a{panel}_points") and v.endswith("_c")})
    x = np.concatenate([data[b + "_x"].values for b in bases])
    y = np.concatenate([data[b + "_y"].values for b in bases])
    c = np.concatenate([data[b + "_c"].values for b in bases])
    xs, ys = ds.s.values, ds.beta.values
    i = np.abs(y[:, None] - ys[None, :]).argmin(axis=1)
    j = np.abs(x[:, None] - xs[None, :]).argmin(axis=1)
    np.testing.assert_allclose(y, ys[i], rtol=0, atol=1e-12)  # the drawn rows, not averages of neighbours
    np.testing.assert_allclose(x, xs[j], rtol=0, atol=1e-12)
    np.testing.assert_allclose(c, ds[field].values[i, j] / 1e3, rtol=1e-12)
    assert sorted(zip(i.tolist(), j.tolist(), strict=True)) == [(a, b) for a in range(ys.size) for b in range(xs.size)]
