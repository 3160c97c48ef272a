"""Numerical sweeps: hysteresis, located transitions, agreement with the analytic orbits, basins, maps."""

import math

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.orbits import find_orbit
from vibroimpact.sweeps import (
    basins,
    bistable_intervals,
    locate_transitions,
    parameter_grid,
    regime_map,
    sweep,
)

K_S = 0.1245 * (5 * math.pi) ** 2 / (5 * math.pi**2)  # d = K_S s at the paper's force
G1_ANALYTIC = 0.1376002140  # tests/test_orbits.py: 2:1 grazing point (beta = pi/6)
G2_ANALYTIC = 0.1419540498  # 3:1 fold


@pytest.fixture(scope="module")
def pi6():
    sw = sweep("s", np.linspace(0.125, 0.16, 36) / K_S, beta=math.pi / 6, phi=5.855, v0=0.4185)
    return sw, locate_transitions(sw, xtol=1e-9)


def test_sweep_dataset_shape_and_hysteresis(pi6):
    sw, _ = pi6
    assert list(sw.direction.values) == ["up", "down"]
    assert np.all(np.diff(sw.d.values) > 0)
    np.testing.assert_allclose(sw.d.values, sw.s.values * K_S, rtol=1e-12)
    up, down = sw.label.values
    # hysteresis: at d = 0.14 the up sweep is on 3:1, the down sweep on 2:1
    i = int(np.argmin(np.abs(sw.d.values - 0.14)))
    assert (up[i], down[i]) == ("3:1 period-2", "2:1 period-2")
    for var in ("v_minus", "phase", "t", "wall", "label", "period", "n_bottom", "n_top", "n_events"):
        assert var in sw and "long_name" in sw[var].attrs


def test_transitions_G1_and_G2_located_and_agree_with_the_analytic_points(pi6):
    sw, tr = pi6
    down = tr.where(tr.direction == "down", drop=True)
    up = tr.where(tr.direction == "up", drop=True)
    (g1,) = down.d.values
    (g2,) = up.d.values
    assert str(down.kind.values[0]) == "grazing: extra bottom impact"
    assert (str(down.before.values[0]), str(down.after.values[0])) == ("2:1 period-2", "3:1 period-2")
    assert str(up.after.values[0]) == "2:1 period-2"
    assert abs(g1 - G1_ANALYTIC) < 1e-6 and abs(g2 - G2_ANALYTIC) < 1e-6
    # the paper's simulated values: G1 = 0.1378, G2 = 0.1419
    assert g1 == pytest.approx(0.1378, abs=3e-4) and g2 == pytest.approx(0.1419, abs=1e-4)
    iv = bistable_intervals(sw, tr)
    assert iv.sizes["interval"] == 1
    assert float(iv.d_lo[0]) == pytest.approx(g1, abs=1e-12) and float(iv.d_hi[0]) == pytest.approx(g2, abs=1e-12)
    assert (str(iv.label_up.values[0]), str(iv.label_down.values[0])) == ("3:1 period-2", "2:1 period-2")


def test_swept_points_agree_with_the_analytic_orbit(pi6):
    """Where a stable analytic 2:1 orbit exists, the sweep's attractor equals it to 1e-8."""
    sw, _ = pi6
    down = sw.sel(direction="down")
    checked = 0
    for i in np.flatnonzero(down.label.values == "2:1 period-2"):
        n = int(down.period_events[i])
        ev = down.isel(point=i)
        m = int(np.isfinite(ev.t.values).sum())
        vm, ph, wall = ev.v_minus.values[m - n:m], ev.phase.values[m - n:m], ev.wall.values[m - n:m]
        b = int(np.flatnonzero(wall == 1)[0])
        p = vi.Params(d=float(down.d[i]), gbar=float(down.gbar[i]), r=0.5)
        o = find_orbit(p, "BBT", ph[b], vm[b])
        assert np.min(np.abs(o.v_minus[:, None] - vm[None, :]), axis=1).max() < 1e-8
        checked += 1
    assert checked >= 15


def test_period_doubling_of_1to1_located_near_the_analytic_point():
    """beta = pi/3: 1:1 period-2 above d_B = 0.324189 (analytic), period-doubled below."""
    sw = sweep("s", np.linspace(0.28, 0.36, 9) / K_S, beta=math.pi / 3, phi=0.42, v0=0.87)
    assert sw.label.values[0, 0] == "1:1 period-4" and sw.label.values[1, -1] == "1:1 period-2"
    tr = locate_transitions(sw, xtol=1e-8)
    for d in tr.d.values:
        assert abs(d - 0.3241885) < 2e-4  # convergence within the allowed transient limits this
    assert set(tr.before.values) == {"1:1 period-4", "1:1 period-2"}


def test_force_sweep_grid():
    d, gbar, s, F = parameter_grid("F", [6.0, 12.0, 22.0], beta=math.pi / 2, s=0.85)
    np.testing.assert_allclose(d * F, 0.85 * K_S * 5.0, rtol=1e-12)
    np.testing.assert_allclose(gbar * F, 0.1245 * 9.8, rtol=1e-12)
    assert np.all(s == 0.85)
    with pytest.raises(ValueError, match="vary"):
        parameter_grid("x", [1.0], beta=1.0)
    with pytest.raises(ValueError, match="F = "):
        parameter_grid("F", [0.0], beta=1.0)


def test_basins_at_the_bistable_point_hold_both_motions():
    p = vi.Params.from_physical(s=0.14 / K_S, beta=math.pi / 6)
    b = basins(p, np.linspace(0, 2 * np.pi, 24, endpoint=False), np.linspace(0.05, 1.0, 16))
    assert b.attractor.shape == (24, 16)
    labels = set(np.unique(b.label.values))
    assert {"2:1 period-2", "3:1 period-2"} <= labels
    assert "legend" in b.attractor.attrs


def test_regime_map_over_length_and_incline():
    m = regime_map("s", np.linspace(0.2, 0.7, 6), "beta", [math.pi / 6, math.pi / 3])
    assert m.label.dims == ("beta", "s") and m.label.shape == (2, 6)
    p = vi.Params.from_physical(s=0.7, beta=math.pi / 3)
    assert float(m.d.sel(beta=math.pi / 3, s=0.7)) == pytest.approx(p.d)
    # long cylinders give the 1:1 motion, short ones asymmetric n:1 motions (paper Fig 0)
    assert str(m.label.sel(beta=math.pi / 3, s=0.7).values) == "1:1 period-2"
    assert str(m.label.sel(beta=math.pi / 6, s=0.2).values).startswith(("3:1", "4:1"))
