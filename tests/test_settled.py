"""What is well-posed about a simulated attractor (vibroimpact.analysis.settled): the exact cycle of a periodic
motion, whatever run reached it, and the long-run statistics of an aperiodic one."""

import math

import numpy as np
import pytest
from conftest import gbar_of

import vibroimpact as vi
from vibroimpact.analysis.settled import (
    SETTLE_MATCH,
    batch_means,
    canonical_start,
    long_run,
    long_statistics,
    polish_cycle,
    settle_attractors,
)
from vibroimpact.analysis.sweeps import sweep
from vibroimpact.dynamics import kernels as K


def _cycle(run):
    """The last period of a run stopped when periodic: its events and its span."""
    lag = int(run.attrs["period_events"])
    n = run.sizes["impact"]
    ev = [run[v].values[n - lag:n] for v in ("t", "wall", "v_minus", "phase", "kind")]
    return ev, float(run.t.values[n - 1] - run.t.values[n - 1 - lag])


def test_the_polished_cycle_is_the_newton_orbit_from_its_canonical_first_impact():
    """Fig BiS (e): the 2:1 orbit; the run's last period, solved, equals find_orbit's orbit (another code
    path: it simulates the word from a guess) to rounding, starting at its bottom impact of least phase."""
    p = vi.Params(d=0.14, gbar=gbar_of(math.pi / 6), r=0.5)
    run = vi.simulate(p, 5.855, 0.4185, n_impacts=10_000, stop_when_periodic=True)
    ev, span = _cycle(run)
    res = polish_cycle(p.d, p.gbar, p.r, *ev, span=span)
    assert res["status"] == "newton" and res["settled"]
    bottom = np.flatnonzero(res["wall"] == 1)
    assert res["wall"][0] == 1 and res["phase"][0] == res["phase"][bottom].min()
    o = vi.find_orbit(p, "".join("B" if w == 1 else "T" for w in res["wall"]), res["phase"][0], res["v_minus"][0])
    assert np.allclose(res["v_minus"], o.v_minus, rtol=0, atol=1e-13)
    assert np.allclose(res["phase"], o.phase, rtol=0, atol=1e-13)
    assert np.allclose(res["t"], o.t, rtol=0, atol=1e-13)


def test_two_runs_stopped_at_different_places_give_the_same_cycle():
    """The recorded cycles of two runs of one orbit differ by their convergence (the periodicity
    tolerance over the orbit's contraction); the polished cycles agree to rounding.  Near the period
    doubling B of the pi/3 2:1 orbit (|lambda| near 1) convergence is slow."""
    p = vi.Params(d=0.159, gbar=gbar_of(math.pi / 3), r=0.5)  # B at d = 0.1582
    runs = [vi.simulate(p, phi, v0, n_impacts=200_000, stop_when_periodic=True) for phi, v0 in ((1.21, 0.2164),
                                                                                                (1.1, 0.25))]
    assert all(r.attrs["status"] == "periodic" for r in runs)
    cycles = [polish_cycle(p.d, p.gbar, p.r, *_cycle(r)[0], span=_cycle(r)[1]) for r in runs]
    assert all(c["settled"] for c in cycles)
    raw = [np.sort(_cycle(r)[0][2]) for r in runs]
    assert np.max(np.abs(raw[0] - raw[1])) > 1e-12  # the recorded cycles differ ...
    assert np.allclose(cycles[0]["v_minus"], cycles[1]["v_minus"], rtol=0, atol=1e-13)  # ... the exact ones do not


def test_a_cycle_too_far_from_its_orbit_or_with_a_grazing_contact_is_not_settled():
    p = vi.Params(d=0.14, gbar=gbar_of(math.pi / 6), r=0.5)
    run = vi.simulate(p, 5.855, 0.4185, n_impacts=10_000, stop_when_periodic=True)
    (t, wall, vm, phase, kind), span = _cycle(run)
    off = polish_cycle(p.d, p.gbar, p.r, t, wall, vm + 10 * SETTLE_MATCH, phase, kind, span=span)
    assert not off["settled"] and "lies" in off["status"]
    grazing = kind.copy()
    grazing[1] = K.GRAZING
    g = polish_cycle(p.d, p.gbar, p.r, t, wall, vm, phase, grazing, span=span)
    assert not g["settled"] and "grazing" in g["status"]


def test_a_sticking_cycle_is_kept_as_recorded_and_not_called_exact():
    """A cycle that sticks is its orbit (every state that sticks leaves the wall at the release phase), but
    only to its summed chatter's accuracy: recorded as sticking, not settled; its chatter's last bounces are
    grazing contacts, which do not make it unsettled for another reason."""
    sw = sweep("s", [0.3, 0.5], beta=math.pi / 2, F=1.4, max_periods=60, long_impacts=0)
    sticky = np.char.find(sw.label.values.astype(str), "sticking") >= 0
    assert sticky.any()
    assert set(sw.settle_status.values.astype(str)[sticky]) == {"sticking"}
    assert not sw.settled.values[sticky].any()
    assert np.isfinite(sw.cycle_v_minus.values[sticky]).any(axis=-1).all()


def test_canonical_start_is_the_bottom_impact_of_least_phase():
    wall = np.array([-1, 1, 1, -1, 1])
    kind = np.zeros(5, np.int8)
    phase = np.array([0.1, 5.0, 0.3, 0.2, 1.0])
    assert canonical_start(wall, kind, phase) == 2
    assert canonical_start(np.array([-1, -1]), np.zeros(2, np.int8), np.array([3.0, 2.0])) == 1


def test_batch_means_match_closed_forms():
    v = np.repeat([1.0, 2.0, 3.0, 4.0], 5)
    mean, se = batch_means(v, 4)
    assert mean == 2.5 and se == pytest.approx(np.std([1, 2, 3, 4], ddof=1) / 2, rel=1e-15)
    assert np.isnan(batch_means(np.ones(3), 4)[0])


def test_the_long_run_of_a_chaotic_motion_and_of_a_transient_that_settles():
    """pi/3 at d = 0.235 (the chaotic scene of the benchmarks): aperiodic for 4000 impacts, with batch
    means whose standard error is small; a periodic point's continuation settles and gives no statistics."""
    p = vi.Params(d=0.235, gbar=gbar_of(math.pi / 3), r=0.5)
    run = long_run(p.d, p.gbar, p.r, 0.42, 0.87, impacts=4000)
    assert run["status"] == "aperiodic"
    mean, se = long_statistics(run)
    assert 0.05 < mean < 2.0 and 0 < se < 0.05 * mean
    q = vi.Params(d=0.16, gbar=gbar_of(math.pi / 6), r=0.5)
    settled = long_run(q.d, q.gbar, q.r, 1.015, 0.1924, impacts=4000)
    assert settled["status"] == "settles" and np.isnan(long_statistics(settled)[0])
    # its exponents are those of its way into the stable orbit it settles on: below 0
    lam = settled["exponents"]
    assert lam is not None and lam.interval[0][1] < 0
    # near B the 2:1 orbit attracts slowly: the continuation settles to the periodicity tolerance within
    # its impacts, not to the last bit
    slow = vi.Params(d=0.16, gbar=gbar_of(math.pi / 3), r=0.5)  # B at 0.1582
    assert long_run(slow.d, slow.gbar, slow.r, 1.1, 0.25, impacts=4000)["status"] == "settles"


def test_a_sweep_settles_every_periodic_point_and_runs_the_aperiodic_ones_long():
    sw = sweep("s", np.linspace(0.3, 0.45, 8), beta=math.pi / 3, phi=0.42, v0=0.87, long_impacts=500)
    per = sw.period_events.values > 0
    assert sw.settled.values[per].all()
    assert set(sw.long_status.values[~per].astype(str)) <= {"aperiodic", "settles", "no restart"}
    # a settled cycle holds one period: as many events as the period, NaN after
    n = np.isfinite(sw.cycle_v_minus.values).sum(axis=-1)
    assert np.array_equal(n[per], sw.period_events.values[per])
    again = settle_attractors(sw.drop_vars([v for v in sw.data_vars if v.startswith(("cycle_", "long_", "abs_v"))]
                                           + ["settled", "settle_status"]), sw.d.values[None, :],
                             sw.gbar.values[None, :], 0.5, long_impacts=500)
    np.testing.assert_array_equal(again.cycle_v_minus.values, sw.cycle_v_minus.values)


def test_a_cycle_a_hundredth_off_its_orbit_is_another_orbit_s():
    """Newton from a cycle 0.01 off converges to the orbit, but an orbit that far from the recorded cycle
    is not the cycle's own (SETTLE_MATCH = 1e-3)."""
    p = vi.Params(d=0.14, gbar=gbar_of(math.pi / 6), r=0.5)
    run = vi.simulate(p, 5.855, 0.4185, n_impacts=10_000, stop_when_periodic=True)
    (t, wall, vm, phase, kind), span = _cycle(run)
    assert polish_cycle(p.d, p.gbar, p.r, t, wall, vm + 2e-4, phase, kind, span=span)["settled"]
    off = polish_cycle(p.d, p.gbar, p.r, t, wall, vm + 1e-2, phase, kind, span=span)
    assert not off["settled"] and "lies 1.0e-02" in off["status"]


def test_a_sticking_output_is_known_to_its_chatter_accuracy_and_no_worse():
    """delivered() gives a sticking point its value with the chatter sum's accuracy: a change of 1e-7
    (relative) is far beyond it, in units of the check's combined standard errors."""
    from test_energy import DEVICE, PAPER

    from vibroimpact.analysis.energy import Membrane, delivered, sweep_energy
    from vibroimpact.analysis.settled import STICK_REL
    from vibroimpact.outputs.figcheck import Z_CRIT

    sw = sweep("s", [0.3, 0.5], beta=math.pi / 2, F=1.4, max_periods=60, long_impacts=0)
    value, se = delivered(sweep_energy(sw, DEVICE.replace(membrane=Membrane(**PAPER))), "U_T")
    assert np.all(value > 0) and np.allclose(se, STICK_REL * value, rtol=1e-15)
    assert 1e-7 / (math.sqrt(2) * STICK_REL) > Z_CRIT


def test_the_critical_z_is_student_s_t_of_the_batches_at_one_in_a_million():
    from scipy.stats import t

    from vibroimpact.analysis.settled import LONG_BATCHES
    from vibroimpact.outputs.figcheck import Z_CRIT

    assert Z_CRIT == pytest.approx(t.ppf(1 - 0.5e-6, LONG_BATCHES - 1), abs=0.005)


def test_batch_means_of_one_value_per_batch_and_of_impacts_only():
    mean, se = batch_means(np.arange(4.0), 4)
    assert mean == 1.5 and se == pytest.approx(np.std(np.arange(4.0), ddof=1) / 2, rel=1e-15)
    events = dict(status="aperiodic", kind=np.array([0, 2, 3, 1] * 10, np.int8),
                  v_minus=np.array([1.0, 0.0, 0.0, -3.0] * 10), t=np.arange(40.0))
    mean, se = long_statistics(events, batches=4)  # |Zdot-| of the 20 impacts and grazing contacts: 1, 3, 1, ...
    assert mean == pytest.approx(2.0, rel=1e-15)
    assert se == pytest.approx(np.std([1.8, 2.2, 1.8, 2.2], ddof=1) / 2, rel=1e-12)


def test_a_sweep_runs_its_aperiodic_points_long_by_default():
    sw = sweep("s", [0.235 / 0.6225 * 1.0], beta=math.pi / 3, phi=0.42, v0=0.87)
    assert str(sw.long_status.values[0, 0]) == "aperiodic" and sw.attrs["long_impacts"] > 1000
    assert np.isfinite(sw.abs_v_mean.values).all() and (sw.abs_v_se.values > 0).all()


def test_a_sample_at_an_impact_s_instant_is_the_post_impact_state_on_either_side_of_rounding():
    """A trajectory sampled where an impact happens reads the state after it, whether rounding puts the
    impact a hair before or after the sample; a sample a microsecond before reads the state before it.
    The orbit's Newton-solved run and its simulated run agree on both."""
    from vibroimpact.analysis.orbits import orbit_run

    p = vi.Params(d=0.14, gbar=gbar_of(math.pi / 6), r=0.5)
    o = vi.find_orbit(p, "BBT", 5.855, 0.4185)
    runs = (orbit_run(o, periods=2), vi.simulate(p, o.phi, float(o.v_minus[0]), n_impacts=7))
    after, before = float(-o.params.r * o.v_minus[0]), float(o.v_minus[0])
    for run in runs:
        t2 = float(run.t.values[3])  # the return to the first impact, one period later
        for t in (t2, np.nextafter(t2, 0), np.nextafter(t2, 4), t2 - 1e-13):
            assert float(vi.trajectory(run, [t]).Zdot[0]) == pytest.approx(after, abs=1e-9), t
        assert float(vi.trajectory(run, [t2 - 1e-6]).Zdot[0]) == pytest.approx(before, abs=1e-5)


def test_a_motion_with_no_period_and_no_long_run_says_so():
    """A sweep with long_impacts = 0: its chaotic point (beta = pi/3, d = 0.235) has a restart but no long run:
    long_status "not run", no exponent, and the source says why."""
    g = gbar_of(math.pi / 3)
    sw = sweep("s", [0.235 / vi.Params.from_physical(s=1.0, beta=math.pi / 3).d], beta=math.pi / 3, phi=0.42,
               v0=0.87, long_impacts=0)
    assert np.allclose(sw.gbar.values, g) and set(sw.label.values.ravel()) == {"no period found"}
    assert set(sw.long_status.values.ravel()) == {"not run"}
    assert np.isnan(sw.lyap1.values).all()
    assert set(sw.lyap1_source.values.ravel()) == {"not estimated: no long run (long_impacts = 0)"}


def test_split_no_period_finds_by_default_that_a_periodic_start_settles():
    """split_no_period's default periodicity tolerance (1e-9, the attractors'): the 3:1 motion 1e-6 below its
    fold G2 (beta = pi/6), whose multiplier near +1 makes it converge slowly, settles within 3000 impacts;
    asked to repeat exactly (tolerance 0) it does not."""
    from vibroimpact.analysis.settled import split_no_period

    split = split_no_period(0.141953, 0.12201, 0.5, 1.645, 0.05067, impacts=3000)
    assert split.status == "settles" and split.label == "unsettled" and len(split.run["t"]) < 3000
    assert split_no_period(0.141953, 0.12201, 0.5, 1.645, 0.05067, impacts=3000, tol=0.0).status == "aperiodic"


def test_a_chaotic_point_s_long_run_statistics_are_its_batch_means():
    """A sweep's chaotic point (beta = pi/3, d = 0.235): abs_v_mean and abs_v_se are the mean and standard error
    of the 20 batch means of |Zdot-| over the long run from its recorded restart (computed here by hand)."""
    sw = sweep("s", [0.235 / vi.Params.from_physical(s=1.0, beta=math.pi / 3).d], beta=math.pi / 3, phi=0.42,
               v0=0.87, long_impacts=600)
    for k in range(2):
        assert str(sw.long_status.values[k, 0]) == "aperiodic"
        run = long_run(float(sw.d[0]), float(sw.gbar[0]), 0.5, float(sw.long_phi[k, 0]), float(sw.long_v0[k, 0]),
                       impacts=600)
        v = np.abs(run["v_minus"][np.isin(run["kind"], (K.IMPACT, K.GRAZING))])
        means = v[:v.size // 20 * 20].reshape(20, -1).mean(axis=1)
        assert float(sw.abs_v_mean[k, 0]) == pytest.approx(means.mean(), rel=1e-14)
        assert float(sw.abs_v_se[k, 0]) == pytest.approx(means.std(ddof=1) / math.sqrt(20), rel=1e-12)


def test_a_long_run_is_named_by_its_exponent_s_interval_not_its_estimate():
    """A long run without a period is chaotic only where the whole confidence interval of lambda_1 lies above 0: a
    positive estimate whose interval holds 0 is quasi-periodic (the continuation's exponents written by hand)."""
    from types import SimpleNamespace

    from vibroimpact.analysis.motions import CHAOTIC, QUASI_PERIODIC
    from vibroimpact.analysis.settled import _split

    def split(estimate, low, high):
        lam = SimpleNamespace(per_impact=[estimate, -1.0], interval=[(low, high), (-1.1, -0.9)], per_time=[estimate],
                              sticks=0)
        return _split({"status": "aperiodic", "exponents": lam})

    s = split(0.01, -0.005, 0.025)
    assert s.label == QUASI_PERIODIC and (s.lyap1, s.lyap1_low, s.lyap1_high) == (0.01, -0.005, 0.025)
    assert split(0.01, 0.004, 0.016).label == CHAOTIC
