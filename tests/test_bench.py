"""The benchmark machinery works and its solve_ivp baseline is a faithful event loop (no timing asserts)."""

import math

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.benchmarks.bench import report, simulator_benchmark
from vibroimpact.benchmarks.methods import run_ivp


def test_ivp_baseline_follows_the_same_orbit_on_a_stable_2_1():
    p = vi.Params(d=0.16, gbar=0.1245 * 9.8 * math.sin(math.pi / 6) / 5, r=0.5)
    ours = vi.simulate(p, 1.015, 0.1924, n_impacts=31)
    ivp = run_ivp(p, 1.015, 0.1924, 30)
    np.testing.assert_array_equal(ivp.wall, ours["wall"].values[1:])
    np.testing.assert_allclose(ivp.t, ours["t"].values[1:], atol=1e-8)


def test_benchmark_reports_speed_and_accuracy():
    ds = simulator_benchmark(n_impacts=20_000, n_impacts_ivp=20, n_flights_accuracy=12)
    assert float(ds.exact_max_err_t) < 1e-12
    assert int(ds.n_flights_checked) >= 8
    assert "Speed-up per impact" in report(ds)
    # the exponents' run is timed beside the plain run (a ratio, reported, never asserted as a speed)
    assert float(ds.lyapunov_ratio) > 1 and "Lyapunov" in report(ds)


def test_the_trigonometric_floor_replays_each_sine_s_angle_of_the_event_finder():
    """The kernel profile's floor (the sines and cosines alone) replays the angles the event finder takes: its
    plain-Python count records one angle per sine-cosine pair, so twice the angles are the trigonometric calls
    counted; and the compiled chain computes what the same loop written in Python does."""
    import json
    import os
    import subprocess
    import sys

    from vibroimpact.benchmarks.bench import KERNEL_SCENES, _sincos_chain

    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = json.loads(subprocess.run([sys.executable, "-m", "vibroimpact.benchmarks.bench", json.dumps({"n": 30})],
                                    env=env, capture_output=True, text=True, check=True).stdout)
    assert set(out) == set(KERNEL_SCENES)
    for c in out.values():
        assert c["flights"] > 20 and 2 * len(c["sines"]) == round(c["trig"] * c["flights"])
    x = np.array(out["chaotic"]["sines"][:50])
    acc = 0.0
    for _ in range(2):
        for a in x:
            acc = math.sin(a + acc * 0.0) + math.cos(a + acc * 0.0)
    assert _sincos_chain(x, 2) == acc


def test_the_finder_s_replay_finds_each_recorded_impact_to_the_last_bit():
    """The kernel profile's event finder alone (rule bench_simulator, `finder_us_per_impact`) replays the run's
    own flights: from each recorded start it finds the next recorded impact, the time added as the event loop adds
    it equal to the recorded time to the last bit, on both scenes of the kernel table; a run that sticks is
    refused (its flights do not go from impact to impact)."""
    from vibroimpact import Params, simulate
    from vibroimpact.benchmarks.bench import KERNEL_SCENES, _finder_replay, finder_flights
    from vibroimpact.dynamics.device import PAPER

    for beta, d, phi, v0 in KERNEL_SCENES.values():
        p = Params(d=d, gbar=PAPER.gbar(beta), r=PAPER.r)
        flights = finder_flights(p, phi, v0, 3000)
        run = simulate(p, phi, v0, n_impacts=3001)
        tau = np.empty(3000)
        _finder_replay(*flights, p.d, p.gbar, tau)
        t = run.t.values
        np.testing.assert_array_equal(t[:-1] + tau, t[1:])
        np.testing.assert_array_equal(flights[0], run.phase.values[:-1])
    with pytest.raises(ValueError, match="impacts only"):
        finder_flights(Params(d=0.3, gbar=0.9, r=0.5), 0.3, 0.5, 200)
