"""Chattering, sticking and release (MODEL.md section 7)."""

import math
import warnings

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.kernels import IMPACT, RELEASE, STICK


@pytest.fixture
def sticky():
    # gravity strong relative to the forcing: the ball chatters to rest on the bottom every period
    return vi.Params(d=0.3, gbar=0.9, r=0.5)


def test_chattering_then_sticking_then_release(sticky):
    ds = vi.simulate(sticky, 0.3, 0.5, n_impacts=400)
    kind = ds["kind"].values
    assert ds.attrs["status"] == "n_events"  # ran to the requested count, no stall
    sticks = np.flatnonzero(kind == STICK)
    releases = np.flatnonzero(kind == RELEASE)
    assert len(sticks) >= 5 and len(releases) >= 5
    g = sticky.gbar
    for i in sticks:
        # a chattering sequence with shrinking speeds precedes each stick
        v = np.abs(ds["v_minus"].values[i - 5:i])
        assert np.all(np.diff(v) < 0) and v[-1] < 1e-8
        # at the accumulation point the relative acceleration pushes the ball into the wall
        assert math.cos(ds["phase"].values[i]) + g > 0
        assert ds["v_minus"].values[i] == 0.0
    for i in releases:
        # released exactly where Z'' changes sign: cos(phase) = -gbar
        assert math.cos(ds["phase"].values[i]) == pytest.approx(-g, abs=1e-12)
        assert kind[i - 1] == STICK
    # while stuck the ball rests on the wall
    i = sticks[0]
    t = np.linspace(ds["t"].values[i], ds["t"].values[i + 1], 50)
    tr = vi.trajectory(ds, t)
    assert np.all(tr.Z.values == sticky.d / 2) and np.all(tr.Zdot.values == 0)


def test_accumulation_point_agrees_with_bouncing_it_out(sticky):
    """The summed accumulation time equals the one reached by simulating the bounces much further."""
    coarse = vi.simulate(sticky, 0.3, 0.5, n_impacts=80, v_chatter=1e-6)
    fine = vi.simulate(sticky, 0.3, 0.5, n_impacts=200, v_chatter=1e-13)
    t_c = coarse["t"].values[coarse["kind"].values == STICK][0]
    t_f = fine["t"].values[fine["kind"].values == STICK][0]
    # the rule's error is of order v_chatter^2
    assert abs(t_c - t_f) < 1e-10


def test_high_restitution_chatter_terminates():
    p = vi.Params(d=0.3, gbar=0.97, r=0.8)  # ~60 bounces per chattering sequence
    ds = vi.simulate(p, 0.3, 0.5, t_end=40.0)
    assert ds.attrs["status"] == "t_end"
    assert (ds["kind"].values == STICK).sum() >= 5


def test_gbar_at_least_one_never_leaves_the_bottom():
    p = vi.Params(d=0.3, gbar=1.2, r=0.5)
    with pytest.warns(UserWarning, match="never"):
        ds = vi.simulate(p, 0.3, 0.5, n_impacts=1000)
    assert ds.attrs["status"] == "stuck_forever"
    assert ds["kind"].values[-1] == STICK
    assert ds.sizes["impact"] < 1000
    assert (ds["wall"].values[ds["kind"].values == IMPACT] == 1).all()


def test_plastic_impact_sticks_at_once():
    p = vi.Params(d=0.3, gbar=0.5, r=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = vi.simulate(p, 0.0, 0.3, n_impacts=50)
    kind = ds["kind"].values
    # with r = 0 every bottom impact where the acceleration pushes in is followed by a stick at once
    for i in np.flatnonzero((kind == IMPACT) & (ds["wall"].values == 1))[:-1]:
        if math.cos(ds["phase"].values[i]) + p.gbar > 0:
            assert kind[i + 1] == STICK and ds["t"].values[i + 1] == ds["t"].values[i]


def test_growing_buffers_do_not_change_the_run(sticky):
    """A run bounded by t_end grows its buffers in chunks; the events equal a single-buffer run."""
    chunked = vi.simulate(sticky, 0.3, 0.5, t_end=400.0)
    n = chunked.sizes["impact"]
    assert n > 4096  # crossed at least one buffer boundary
    whole = vi.simulate(sticky, 0.3, 0.5, n_impacts=n + 1)
    np.testing.assert_array_equal(chunked["t"].values, whole["t"].values[:n])
    np.testing.assert_array_equal(chunked["kind"].values, whole["kind"].values[:n])
