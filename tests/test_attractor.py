"""Attractor identification and early stopping."""

import math

import numpy as np
import xarray as xr
import pytest
from conftest import CAPTIONS, TOL_T, flight_state, gbar_of

import vibroimpact as vi


def test_slowly_converging_1_1_is_not_mistaken_for_period_doubled():
    """Fig FN2 (d): a 1:1 orbit with an eigenvalue near -1 converges in alternation; its lag-4
    residuals shrink below tolerance before its lag-2 ones.  It must still be called 1:1 period-2."""
    beta, d, v, phi, *_ = CAPTIONS["figFN2_d"]
    p = vi.Params(d=d, gbar=gbar_of(beta), r=0.5)
    ds = vi.simulate(p, phi, v, n_impacts=50_000, stop_when_periodic=True)
    assert ds.attrs["status"] == "periodic" and ds.attrs["period_events"] == 2
    # a longer run confirms it: lag-2 differences vanish
    long = vi.simulate(p, phi, v, n_impacts=20_000)
    vm = long["v_minus"].values[-200:]
    assert np.max(np.abs(vm[2:] - vm[:-2])) < 1e-12


def test_period_doubled_1_1_is_identified():
    p = vi.Params(d=0.24, gbar=gbar_of(math.pi / 6), r=0.5)
    att = vi.identify_attractor(vi.simulate(p, 0.4, 0.6, n_impacts=20_000))
    assert att.label == "1:1 period-4" and att.period == 2 and att.events == 4


def test_chaotic_motion_is_not_periodic():
    """beta = pi/3, d = 0.235 lies in the chaotic window between 1:1 and 2:1 (paper Fig 0)."""
    p = vi.Params(d=0.235, gbar=gbar_of(math.pi / 3), r=0.5)
    ds = vi.simulate(p, 0.4, 0.6, n_impacts=20_000, stop_when_periodic=True)
    assert ds.attrs["status"] == "n_events"
    assert not vi.identify_attractor(ds).periodic
    # sensitive dependence: two nearby starts separate to order one
    a = vi.simulate(p, 0.4, 0.6, n_impacts=600)
    b = vi.simulate(p, 0.4, 0.6 + 1e-10, n_impacts=600)
    assert np.max(np.abs(a["v_minus"].values - b["v_minus"].values)) > 0.05


def test_stopping_early_gives_the_same_attractor_as_a_long_run(pi6):
    early = vi.simulate(pi6, 1.015, 0.1924, n_impacts=100_000, stop_when_periodic=True)
    assert early.sizes["impact"] < 200
    late = vi.simulate(pi6, 1.015, 0.1924, n_impacts=3000)
    a, b = vi.identify_attractor(early), vi.identify_attractor(late)
    assert a.label == b.label == "2:1 period-2"
    assert sorted(np.round(a.cycle.v_minus.values, 8)) == sorted(np.round(b.cycle.v_minus.values, 8))
    assert a.t_settled <= early["t"].values[-1]


def test_sticking_orbit_label():
    att = vi.identify_attractor(vi.simulate(vi.Params(d=0.3, gbar=0.9, r=0.5), 0.3, 0.5, n_impacts=2000))
    assert att.periodic and att.sticking and att.label.endswith("with sticking") and att.n_top == 0


@pytest.mark.parametrize("bad, match", [
    (dict(phi=float("nan"), v0=0.1), "phi"),
    (dict(phi=0.1, v0=-0.1), "v0"),
    (dict(phi=0.1, v0=0.1, Z0=1.0), "Z0"),
    (dict(phi=0.1, v0=0.1, n_impacts=0), "n_impacts"),
])
def test_simulate_rejects_bad_input(pi6, bad, match):
    kw = dict(n_impacts=10)
    kw.update(bad)
    with pytest.raises(ValueError, match=match):
        vi.simulate(pi6, **kw)


def test_simulate_needs_an_end(pi6):
    with pytest.raises(ValueError, match="needs an end"):
        vi.simulate(pi6, 0.1, 0.1)


def test_dataset_is_self_describing(pi6):
    ds = vi.simulate(pi6, 1.015, 0.1924, n_impacts=20)
    for name in ("t", "wall", "v_minus", "v_plus", "phase", "kind", "dt", "z"):
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs
    assert ds["kind"].attrs["flag_meanings"].split()[:4] == ["impact", "grazing", "stick", "release"]
    assert ds.attrs["d"] == pi6.d and ds.attrs["status"] == "n_events"
    # the paper convention: the first event is the bottom impact at t0 with v0
    assert ds["wall"].values[0] == 1 and ds["v_minus"].values[0] == 0.1924 and ds["t"].values[0] == 0


def test_dense_output_is_continuous_and_consistent(pi6):
    """Each flight of the dense output, evaluated at the *next* event's time (just before it, and by
    the closed form written in the tests), arrives at that event's recorded position and pre-impact
    velocity; the cylinder's dense position has X*'' = cos(pi t + phi)."""
    ds = vi.simulate(pi6, 1.015, 0.1924, n_impacts=30)
    t, z, vm, kind = ds["t"].values, ds["z"].values, ds["v_minus"].values, ds["kind"].values
    for j in range(len(t) - 1):
        dt = t[j + 1] - t[j]
        z_end, v_end = flight_state(ds["phase"].values[j], z[j], ds["v_plus"].values[j], pi6.gbar, dt)
        assert abs(z_end - z[j + 1]) <= TOL_T and abs(v_end - vm[j + 1]) <= TOL_T
        before = vi.trajectory(ds, [t[j + 1] - 1e-9 * dt])  # the package's dense output, same flight
        assert abs(before.Z.values[0] - z[j + 1]) <= abs(vm[j + 1]) * 1e-9 * dt + 1e-9 * dt**2 + TOL_T
    assert set(kind[1:]) == {0}  # all impacts: every event above is the end of a flight
    # the cylinder: X*'' = cos(pi t + phi) by a central second difference with h = 1e-3: truncation
    # h^2 pi^2 / 12 = 8.2e-7, rounding (of t ~ 20 and X) 4 ulp(20) / (pi h^2) = 5e-9
    h, tm = 1e-3, 0.5 * (t[1:] + t[:-1])
    X = [vi.trajectory(ds, tm + k * h).X.values for k in (-1, 0, 1)]
    accel = (X[0] - 2 * X[1] + X[2]) / h**2
    assert np.max(np.abs(accel - np.cos(np.pi * tm + float(ds.attrs["phi"])))) < 8.3e-7
    with pytest.raises(ValueError, match="within the run"):
        vi.trajectory(ds, [t[-1] + 1.0])


def test_batch_runs_in_flight_are_the_simulators_runs():
    """attractor_batch from states in flight (knocks, basin stability) gives each run's events to the last bit
    as vi.simulate from the same state: the batch kernel and the single run share the event loop."""
    p = vi.Params(d=0.13975, gbar=gbar_of(math.pi / 6), r=0.5)
    t0 = np.array([0.3, 0.77, 1.9])
    z0 = np.array([0.01, -0.06, 0.069875])
    v0 = np.array([0.1, -0.4, -0.2])
    ab = vi.attractor_batch(p.d, p.gbar, p.r, phi=1.645, v0=v0, t0=t0, Z0=z0, max_periods=200)
    for k in range(3):
        run = vi.simulate(p, phi=1.645, v0=v0[k], Z0=z0[k], t0=t0[k], stop_when_periodic=True,
                          t_end=t0[k] + 400.0)
        n = int(ab.n_events[k])
        assert run.sizes["impact"] == n and run.attrs["status"] == "periodic"
        last = ab.t.values[k][np.isfinite(ab.t.values[k])]
        assert np.array_equal(run.t.values[n - last.size:], last)
        assert ab.label.values[k] == vi.identify_attractor(run).label



def test_runs_in_flight_on_one_thread_are_the_runs_on_two_and_the_simulator_s():
    """flight_window_batch on one numba thread (the runs one after the other in the calling thread, without the
    GIL) gives every window, status, period and event count it gives on all the cores (one block of runs per
    thread) to the last bit, and each run's events those of vi.simulate from the same state in flight."""
    import numba

    from vibroimpact.analysis.windows import empty_windows, window_limits
    from vibroimpact.dynamics import kernels as K

    p = vi.Params(d=0.13975, gbar=gbar_of(math.pi / 6), r=0.5)
    t0, z0, v0 = np.linspace(0.3, 1.9, 7), np.linspace(-0.06, 0.069875, 7), np.linspace(-0.5, 0.4, 7)
    full = lambda x: np.full(t0.size, x)
    batch = K.FlightBatch(full(p.d), full(p.gbar), full(p.r), t0, (math.pi * t0 + 1.645) % (2 * math.pi), z0, v0)
    out, saved = [], numba.get_num_threads()
    try:
        for threads in sorted({1, numba.config.NUMBA_NUM_THREADS}):  # 1 and all the cores
            numba.set_num_threads(threads)
            win = empty_windows(t0.size, 65)
            ends = K.WindowEnds(*(np.zeros(t0.size, dt) for dt in (np.int8, np.int64, np.int64, np.int64)))
            K.flight_window_batch(batch, window_limits(200, 200_000, 1e-9, 64), win, ends)
            out.append([*win, *ends])
    finally:
        numba.set_num_threads(saved)
    for a, b in zip(out[0], out[-1], strict=True):  # (one run to compare where numba has one thread)
        assert np.array_equal(a, b, equal_nan=True)
    t, total, n = out[0][0], out[0][7], out[0][8]
    for k in range(t0.size):
        run = vi.simulate(p, phi=1.645, v0=v0[k], Z0=z0[k], t0=t0[k], stop_when_periodic=True, t_end=t0[k] + 400.0)
        assert run.sizes["impact"] == total[k] and np.array_equal(run.t.values[total[k] - n[k]:], t[k, :n[k]])


def test_batch_start_in_flight_needs_both_time_and_position():
    with pytest.raises(ValueError, match="t0 = .*Z0 = .*both"):
        vi.attractor_batch(0.2, 0.1, 0.5, phi=1.0, v0=0.1, Z0=0.0)
    with pytest.raises(ValueError, match=r"\|Z0\| <= d/2"):
        vi.attractor_batch(0.2, 0.1, 0.5, phi=1.0, v0=0.1, t0=0.0, Z0=0.2)


def test_the_longest_period_identified_by_default_is_64_events():
    """A motion that repeats every 65 events (and over no shorter stretch) is no period within the default
    ``max_period_events = 64``; allowed 65 events, it is one of 65 events (here: 65 bottom impacts in 26
    forcing periods, the speeds all different)."""
    n = 5 * 65
    t = np.arange(n) * (52.0 / 65)  # 65 events every 52 time units: 26 forcing periods
    ds = xr.Dataset({"t": ("impact", t), "wall": ("impact", np.full(n, -1, np.int8)),
                     "v_minus": ("impact", 0.5 + 0.01 * (np.arange(n) % 65)),
                     "phase": ("impact", (np.pi * t) % (2 * np.pi)), "kind": ("impact", np.zeros(n, np.int8))})
    assert not vi.identify_attractor(ds).periodic
    att = vi.identify_attractor(ds, max_period_events=65)
    assert att.periodic and att.events == 65 and att.period == 26
