"""Property tests over random parameters and initial conditions (hypothesis)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import vibroimpact as vi
from vibroimpact.kernels import GRAZING, IMPACT

pytestmark = pytest.mark.filterwarnings("ignore:gbar = .* >= 1")

params = st.builds(
    vi.Params,
    d=st.floats(0.05, 1.0),
    gbar=st.floats(0.0, 1.5),
    r=st.floats(0.0, 0.95),
)
phases = st.floats(0.0, 2 * math.pi)
speeds = st.floats(0.0, 2.0)


@settings(max_examples=60, deadline=None)
@given(params, phases, speeds, st.integers(0, 2**31 - 1))
def test_ball_stays_in_the_cylinder(p, phi, v0, seed):
    ds = vi.simulate(p, phi, v0, n_impacts=150, t_end=200.0)
    t = ds["t"].values
    if t[-1] <= t[0]:
        return
    times = np.random.default_rng(seed).uniform(t[0], t[-1], 2000)
    z = vi.trajectory(ds, times).Z.values
    assert np.all(np.abs(z) <= p.d / 2 + 1e-12)


@settings(max_examples=60, deadline=None)
@given(params, phases, speeds)
def test_impacts_point_into_the_wall_and_lose_energy(p, phi, v0):
    ds = vi.simulate(p, phi, v0, n_impacts=150, t_end=200.0)
    kind = ds["kind"].values
    hits = (kind == IMPACT) | (kind == GRAZING)
    vm = ds["v_minus"].values[hits]
    vp = ds["v_plus"].values[hits]
    wall = ds["wall"].values[hits]
    assert np.all(wall * vm >= 0)  # into the wall: positive at the bottom, negative at the top
    assert np.all(vp**2 <= vm**2)  # the relative kinetic energy is never gained at an impact
    assert np.all(np.diff(ds["t"].values) >= 0)
    assert np.all(np.abs(ds["z"].values) <= p.d / 2)


@settings(max_examples=25, deadline=None)
@given(params, phases, speeds)
def test_batch_equals_single_runs(p, phi, v0):
    b = vi.simulate_batch([p.d, p.d], p.gbar, p.r, [phi, phi], [v0, v0], n_impacts=60)
    s = vi.simulate(p, phi, v0, n_impacts=60)
    n = int(b["n_events"][0])
    assert n == s.sizes["impact"]
    np.testing.assert_array_equal(b["t"].values[0, :n], s["t"].values)
    np.testing.assert_array_equal(b["v_minus"].values[1, :n], s["v_minus"].values)
