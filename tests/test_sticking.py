"""Chattering, sticking and release (docs/guide/model.md), against a bounce-by-bounce reference.

The reference (:func:`vibroimpact.dynamics.reference.bounce_by_bounce`) chains every bounce of every
chattering sequence as an exact flight in 60-digit arithmetic, down to rebound speeds of 1e-25,
and finds the release as a sampled root of the acceleration: it uses neither the accumulation
rule nor the release formula of the simulator.  Everything the simulator records with a speed
above 1e-8 (all bounces the rule does not sum), and every stick and release, must match it.
"""

import math

import numpy as np
import pytest
from conftest import TOL_T

import vibroimpact as vi
from vibroimpact.dynamics import kernels as K
from vibroimpact.dynamics.reference import bounce_by_bounce

#: bounces with |Zdot-| above this are never summed by the rule (rebound r |Zdot-| >> v_chatter = 1e-9)
V_SUMMED = 1e-8


def kernel_run(p, wall, phase, v_minus, t_end):
    """The event loop from an impact on ``wall`` (either wall) at ``phase``; events as tuples."""
    cap = 20_000
    bufs = K.EventBuffers(t=np.zeros(cap), wall=np.zeros(cap, np.int8), v_minus=np.zeros(cap), v_plus=np.zeros(cap),
                          phase=np.zeros(cap), kind=np.zeros(cap, np.int8), z=np.zeros(cap))
    start = K.Start(0.0, phase, wall * p.d / 2, v_minus, K.IMPACT, wall)
    settings = K.Settings(t_end=t_end, v_chatter=1e-9, detect=False, tol=1e-9)
    n, status, _ = K.advance(K.Model(p.d, p.gbar, p.r), start, 0, settings, np.zeros(65, np.int64), bufs)
    events = [(K.KIND_NAMES[bufs.kind[i]], bufs.t[i], int(bufs.wall[i]), bufs.v_minus[i]) for i in range(1, n)]
    return events, K.STATUS_NAMES[status]


def dataset_events(ds):
    kinds = [K.KIND_NAMES[k] for k in ds.kind.values]
    return list(zip(kinds[1:], ds.t.values[1:], ds.wall.values[1:].astype(int), ds.v_minus.values[1:], strict=True))


def assert_same_motion(sim, ref):
    """Stick and release events and every bounce faster than V_SUMMED agree one to one, to TOL_T."""
    def keep(events):
        out = []
        for kind, t, wall, v in events:
            kind = "impact" if kind == "grazing" else kind
            if kind != "impact" or abs(float(v)) > V_SUMMED:
                out.append((kind, float(t), int(wall), float(v)))
        return out

    s, r = keep(sim), keep(ref)
    # the simulator stops at t_end; the reference may have one event more at the same end
    r = [e for e in r if e[1] <= s[-1][1] + TOL_T] if s else r
    assert [(k, w) for k, _, w, _ in s] == [(k, w) for k, _, w, _ in r]
    for (_, ts, _, vs), (_, tr, _, vr) in zip(s, r, strict=True):
        assert abs(ts - tr) <= TOL_T * max(1.0, tr)
        assert abs(vs - vr) <= TOL_T
    return s


@pytest.mark.parametrize("wall", [1, -1])
@pytest.mark.parametrize("delta", [1e-3, 1e-4, 3e-5, 1e-5, 1e-6, 1e-8, 1e-10, 1e-12])
def test_a_slow_impact_just_before_the_release_sticks_only_if_its_bounces_accumulate_first(wall, delta):
    """An impact ``delta`` before the release phase with rebound 5e-10 (below v_chatter): where the
    bounces accumulate before the release (delta >= 1e-4 here) the ball sticks and is released at the
    release phase; where they do not (delta <= 1e-5) it keeps bouncing and leaves the wall.  Never is
    it held past the release (the rule once held it for up to a forcing period)."""
    p = vi.Params(d=0.3, gbar=0.122, r=0.5)
    alpha = math.acos(-p.gbar)
    release = alpha if wall == 1 else 2 * math.pi - alpha  # where wall * Z'' turns negative
    phase = release - math.pi * delta
    v_minus = wall * 1e-9
    t_end = delta + 3.0
    sim, status = kernel_run(p, wall, phase, v_minus, t_end)
    ref = bounce_by_bounce(phase, wall * p.d / 2, -p.r * v_minus, p.d, p.gbar, p.r, t_end=t_end)
    events = assert_same_motion(sim, ref)
    sticks = [e for e in events if e[0] == "stick"]
    assert len(sticks) == (1 if delta >= 1e-4 else 0)  # the reference decides; this pins the scene
    assert sum(e[0] == "impact" for e in events) >= 3  # the motion goes on after the release
    assert status == "t_end"


@pytest.mark.parametrize("gbar, r, v0, t_end",
                         [(0.9, 0.5, 0.5, 8.0), (0.97, 0.8, 0.05, 4.0), (0.5, 0.0, 0.5, 8.0), (0.6, 0.3, 0.5, 8.0)])
def test_chattering_into_sticking_and_release_match_the_reference(gbar, r, v0, t_end):
    """Whole runs with chattering sequences, sticks and releases, from an impact at phase 0.3."""
    p = vi.Params(d=0.3, gbar=gbar, r=r)
    ds = vi.simulate(p, 0.3, v0, t_end=t_end)
    ref = bounce_by_bounce(0.3, p.d / 2, -r * v0, p.d, p.gbar, p.r, t_end=t_end)
    events = assert_same_motion(dataset_events(ds), ref)
    assert sum(e[0] == "stick" for e in events) >= 2 and sum(e[0] == "release" for e in events) >= 2


def test_gbar_at_least_one_never_leaves_the_bottom():
    p = vi.Params(d=0.3, gbar=1.2, r=0.5)
    with pytest.warns(UserWarning, match="never"):
        ds = vi.simulate(p, 0.3, 0.5, n_impacts=1000)
    assert ds.attrs["status"] == "stuck_forever"
    ref = bounce_by_bounce(0.3, p.d / 2, -0.25, p.d, p.gbar, p.r, t_end=10.0)
    assert ref[-1][0] == "stick"  # the reference finds no release either
    assert_same_motion(dataset_events(ds), ref)


def test_growing_buffers_do_not_change_the_run():
    """A run bounded by t_end grows its buffers in chunks; the events equal a single-buffer run."""
    sticky = vi.Params(d=0.3, gbar=0.9, r=0.5)
    chunked = vi.simulate(sticky, 0.3, 0.5, t_end=800.0)
    n = chunked.sizes["impact"]
    assert n > 4096  # crossed at least one buffer boundary
    whole = vi.simulate(sticky, 0.3, 0.5, n_impacts=n + 1)
    np.testing.assert_array_equal(chunked["t"].values, whole["t"].values[:n])
    np.testing.assert_array_equal(chunked["kind"].values, whole["kind"].values[:n])


def test_at_rest_where_the_acceleration_turns_into_the_wall_the_ball_sticks_and_time_goes_on():
    """gbar one ulp below 1, r = 0: the release window is 3e-8 wide in phase and the excursion in it
    ~1e-32, below rounding, so the return is found at the zero of the acceleration itself. At rest
    there, with the acceleration into the wall exactly zero and turning positive, the ball sticks
    (a flight from there meets the wall at once, and would repeat at the same time for ever), and no
    hit arrives out of its wall (found by hypothesis)."""
    p = vi.Params(d=1.0, gbar=0.9999999999999999, r=0.0)
    ds = vi.simulate(p, 0.0, 0.0, n_impacts=150, t_end=200.0)
    kind = ds["kind"].values
    hits = (kind == K.IMPACT) | (kind == K.GRAZING)
    assert np.all(ds["wall"].values[hits] * ds["v_minus"].values[hits] >= 0)
    assert np.all(np.abs(ds["v_minus"].values[hits]) < TOL_T)  # contacts at rest, not impacts
    assert np.all(np.diff(ds["t"].values) >= 0) and float(ds["t"][-1]) > 90  # one stick per forcing period
    assert (kind == K.STICK).sum() >= 49 and (kind == K.RELEASE).sum() >= 49
