"""The figure regeneration check: data read back from a drawn figure and compared with a reference."""

import math

import numpy as np
import pytest

from vibroimpact import plotting
from vibroimpact.figdata import compare, figure_data


def _figure(shift=0.0, extra=False):
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2)
    x = np.linspace(0, 1, 7)
    a.plot(x, x**2 + shift, label="parabola")
    a.plot(x, np.where(x > 0.5, np.nan, x), "--")
    a.scatter([0.1, 0.2], [1.0, 2.0], c=[3.0, 4.0])
    a.set_title("(a) test")
    a.set_xlabel("d")
    a.set_ylabel("U_T (V)")
    b.imshow(np.arange(6.0).reshape(2, 3))
    b.set_xlabel("cost per impact (µs)")
    if extra:
        a.plot([0, 1], [0, 1])
    return fig


def test_figure_data_is_what_is_drawn(tmp_path):
    fig = _figure()
    paths = plotting.save(fig, tmp_path / "f", data=tmp_path / "data" / "f.nc", attrs={"config": "{}"})
    import xarray as xr

    ds = xr.load_dataset(paths[-1], engine="netcdf4")
    np.testing.assert_array_equal(ds["a0_line0_y"].values, np.linspace(0, 1, 7) ** 2)
    assert ds["a0_line0_y"].attrs["label"] == "parabola" and ds["a0_line0_y"].attrs["units"] == "V"
    assert ds["a0_line0_x"].attrs["units"] == "1" and ds["a0_line0_x"].attrs["axes_title"] == "(a) test"
    assert np.isnan(ds["a0_line1_y"].values[-1])
    np.testing.assert_array_equal(ds["a0_points0_c"].values, [3.0, 4.0])
    assert ds["a1_image0_z"].shape == (2, 3) and ds.attrs["config"] == "{}"


def test_compare_passes_identical_data_and_names_every_difference():
    ref = figure_data(_figure())
    same = compare(figure_data(_figure()), ref, rtol=1e-9, atol=1e-12)
    assert set(same.status) == {"pass"}
    moved = compare(figure_data(_figure(shift=1e-6)), ref, rtol=1e-9, atol=1e-12)
    row = moved.set_index("variable").loc["a0_line0_y"]
    assert row.status == "fail" and row.max_difference == pytest.approx(1e-6, rel=1e-6)
    assert (moved.status == "pass").sum() == len(moved) - 1
    grown = compare(figure_data(_figure(extra=True)), ref, rtol=1e-9, atol=1e-12)
    assert grown.status.str.startswith("fail: new").sum() == 2
    lost = compare(ref, figure_data(_figure(extra=True)), rtol=1e-9, atol=1e-12)
    assert lost.status.str.startswith("fail: missing").sum() == 2


def test_compare_checks_nan_places_and_excludes_timings():
    ref = figure_data(_figure())
    new = ref.copy(deep=True)
    new["a0_line1_y"].values[0] = math.nan
    new["a1_image0_z"].values[:] += 1.0
    df = compare(new, ref, rtol=1e-9, atol=1e-12, exclude=["cost per impact"]).set_index("variable")
    assert df.loc["a0_line1_y", "status"].startswith("fail: NaN")
    assert df.loc["a1_image0_z", "status"] == "excluded"


def test_fig2_marks_and_names_every_admissible_critical_point():
    """Fig 2's data, read back from the drawn figure: a diamond at each located admissible critical
    point in range on each impact's curve, named once per panel (A1, A2, ... by increasing d)."""
    import vibroimpact as vi
    from vibroimpact.continuation import continue_orbit

    p = vi.Params.from_physical(s=0.14 / vi.Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    br = continue_orbit(vi.find_orbit(p, "BBT", 5.855, 0.4185), vary="s", d_range=(0.13, 0.21), step=2e-3)
    br.attrs["beta"] = math.pi / 6  # as the workflow records it
    lo, hi = 0.134, 0.205
    crit = {(str(k), round(float(d), 9)) for k, d, a in
            zip(br.critical_kind.values, br.critical_d.values, br.critical_admissible.values, strict=True)
            if a and lo <= d <= hi}
    assert {k for k, _ in crit} >= {"A", "grazing"}
    ds = figure_data(plotting.fig2([br], [None], [(lo, hi)]))
    for col in range(3):
        xs = [float(ds[v].values[0]) for v in ds.data_vars
              if v.startswith(f"a{col}_line") and v.endswith("_x") and ds[v].attrs["marker"] == "D"]
        assert sorted(round(x, 9) for x in xs) == sorted(d for _, d in crit for _ in range(3))
        names = sorted(ds[v].attrs["label"] for v in ds.data_vars if v.startswith(f"a{col}_text"))
        n_a = sum(k == "A" for k, _ in crit)
        assert names == sorted([f"A{i + 1}" for i in range(n_a)] + ["G"] * sum(k == "grazing" for k, _ in crit))
