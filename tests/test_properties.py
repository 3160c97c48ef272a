"""Property tests over random parameters and initial conditions (hypothesis)."""

import math

import numpy as np
import pytest
from conftest import TOL_T, flight_state
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

import vibroimpact as vi
from vibroimpact.dynamics.kernels import GRAZING, IMPACT, RELEASE, STICK

pytestmark = pytest.mark.filterwarnings("ignore:gbar = .* >= 1")

params = st.builds(
    vi.Params,
    d=st.floats(0.05, 1.0),
    gbar=st.floats(0.0, 1.5),
    r=st.floats(0.0, 0.95),
)
phases = st.floats(0.0, 2 * math.pi)
speeds = st.floats(0.0, 2.0)


def flight_starts(ds):
    """Indices of the events that start a free flight: not a stuck span, and not a chattering
    sequence summed to its accumulation point (the only way a STICK event is reached)."""
    t, kind = ds["t"].values, ds["kind"].values
    return [j for j in range(len(t) - 1) if kind[j] != STICK and kind[j + 1] != STICK and t[j + 1] > t[j]]


@settings(max_examples=60, deadline=None)
@given(params, phases, speeds)
def test_nothing_crosses_a_wall_between_recorded_impacts(p, phi, v0):
    """Each flight, propagated from its recorded start by the closed form written in the tests
    (conftest.flight_state), keeps every interior extremum inside the cylinder: the zeros of the
    velocity are bracketed on 64 samples and refined by Brent's method.  An impact the event finder
    missed, or a flight ended early or late, would show here."""
    ds = vi.simulate(p, phi, v0, n_impacts=150, t_end=200.0)
    t, z, u, phase = (ds[v].values for v in ("t", "z", "v_plus", "phase"))
    for j in flight_starts(ds):
        tau = np.linspace(0.0, t[j + 1] - t[j], 65)
        zs, vs = flight_state(phase[j], z[j], u[j], p.gbar, tau)
        peaks = list(zs[1:-1])
        for k in np.flatnonzero(np.sign(vs[1:-2]) * np.sign(vs[2:-1]) < 0) + 1:
            tk = brentq(lambda x, j=j: flight_state(phase[j], z[j], u[j], p.gbar, x)[1], tau[k], tau[k + 1], xtol=1e-15)
            peaks.append(flight_state(phase[j], z[j], u[j], p.gbar, tk)[0])
        assert np.all(np.abs(peaks) <= p.d / 2 + TOL_T)
        # and the flight ends on the wall it is recorded to hit (or at the run's end)
        if ds["kind"].values[j + 1] != RELEASE:
            z_end = flight_state(phase[j], z[j], u[j], p.gbar, t[j + 1] - t[j])[0]
            assert abs(z_end - z[j + 1]) <= TOL_T


@settings(max_examples=30, deadline=None)
@given(params, phases, speeds)
@example(vi.Params(d=1.0, gbar=1.0, r=5e-324), 1.0, 2.0)  # a rebound of 1e-323 summed into sticking
def test_energy_along_a_flight_is_the_work_of_the_forcing(p, phi, v0):
    """The package's dense output obeys the equation of motion: on each flight the relative kinetic
    energy changes by the work of the force per unit mass, ``gbar + cos(pi t + phi)``, along the
    displacement, and the displacement is the integral of the velocity (Gauss-Legendre quadrature,
    24 nodes per unit of time: exact to rounding for these smooth integrands)."""
    ds = vi.simulate(p, phi, v0, n_impacts=40, t_end=50.0)
    phi0 = float(ds.attrs["phi"])
    t = ds["t"].values
    x, w = np.polynomial.legendre.leggauss(24)
    for j in flight_starts(ds)[:20]:
        a, b = t[j] + 1e-3 * (t[j + 1] - t[j]), t[j + 1] - 1e-3 * (t[j + 1] - t[j])  # inside the flight
        edges = np.linspace(a, b, int(np.ceil(b - a)) + 1)
        half = np.diff(edges)[:, None] / 2
        nodes = (edges[:-1, None] + half * (1 + x[None, :])).ravel()
        tr = vi.trajectory(ds, np.concatenate([[a, b], nodes]))
        (za, zb), (va, vb) = tr.Z.values[:2], tr.Zdot.values[:2]
        vel = tr.Zdot.values[2:].reshape(half.shape[0], -1)
        force = p.gbar + np.cos(np.pi * nodes.reshape(vel.shape) + phi0)
        work = float(np.sum(half * (w * force * vel)))
        shift = float(np.sum(half * (w * vel)))
        assert abs((vb**2 - va**2) / 2 - work) <= TOL_T * max(1.0, abs(work))
        assert abs((zb - za) - shift) <= TOL_T * max(1.0, abs(shift))


@settings(max_examples=60, deadline=None)
@given(params, phases, speeds)
def test_impacts_arrive_into_the_wall_in_time_order(p, phi, v0):
    ds = vi.simulate(p, phi, v0, n_impacts=150, t_end=200.0)
    kind = ds["kind"].values
    hits = (kind == IMPACT) | (kind == GRAZING)
    assert np.all(ds["wall"].values[hits] * ds["v_minus"].values[hits] >= 0)  # positive at the bottom
    assert np.all(np.diff(ds["t"].values) >= 0)


@settings(max_examples=25, deadline=None)
@given(params, phases, speeds)
def test_batch_equals_single_runs(p, phi, v0):
    b = vi.simulate_batch([p.d, p.d], p.gbar, p.r, [phi, phi], [v0, v0], n_impacts=60)
    s = vi.simulate(p, phi, v0, n_impacts=60)
    n = int(b["n_events"][0])
    assert n == s.sizes["impact"]
    np.testing.assert_array_equal(b["t"].values[0, :n], s["t"].values)
    np.testing.assert_array_equal(b["v_minus"].values[1, :n], s["v_minus"].values)
