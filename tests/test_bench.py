"""The benchmark machinery works and its solve_ivp baseline is a faithful event loop (no timing asserts)."""

import math

import numpy as np

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
