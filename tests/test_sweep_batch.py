"""The batched paths of a sweep give the datasets of the one-point-at-a-time reference, to the last bit: the points'
compiled chains, the long runs side by side, the transitions located on threads, the energy's long runs and the
1:1 exit's runs without datasets."""

import math
import threading
import time
import warnings

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.analysis import energy
from vibroimpact.analysis.motions import NO_PERIOD_LABELS
from vibroimpact.analysis.settled import long_run, long_runs
from vibroimpact.analysis.transitions import _run_chains
from vibroimpact.dynamics import kernels as K
from vibroimpact.dynamics.runs import simulated_events

#: beta = pi/3 at 5 N (d = 0.6225 s): the 1:1 and 2:1 motions coexist near s = 0.199 (the up and down sweeps
#: differ), no period is found near s = 0.2525 (a transient longer than the cap: the long run settles) and the
#: motion is chaotic at s = 0.3775 (d = 0.235)
S_VALUES = [0.197, 0.1985, 0.2, 0.2015, 0.2525, 0.2535, 0.3775, 0.38, 0.43]


@pytest.fixture(scope="module")
def both():
    kw = dict(beta=math.pi / 3, phi=0.42, v0=0.87)
    return vi.sweep("s", S_VALUES, **kw), vi.sweep("s", S_VALUES, batch=False, **kw)


def test_the_test_sweep_has_hysteresis_motions_without_a_period_and_failed_long_runs(both):
    sw, _ = both
    up, down = sw.label.values
    assert np.any(up != down)
    assert np.isin(sw.label.values, NO_PERIOD_LABELS).any()
    assert (sw.long_status.values == "settles").any() and (sw.long_status.values == "aperiodic").any()
    assert (sw.settle_status.values == "newton").any()


def test_batched_sweep_is_the_reference_sweep_to_the_last_bit(both):
    sw, ref = both
    assert sw.identical(ref)


def test_a_sweep_through_a_ball_at_rest_for_good_is_the_reference_sweep():
    # at 1 N the gravity term exceeds 1 (gbar >= 1): the ball comes to rest on the bottom for good
    kw = dict(beta=math.pi / 2, phi=0.42, v0=0.87, s=0.85)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sw = vi.sweep("F", [1.0, 6.0, 14.0, 22.0], **kw)
        ref = vi.sweep("F", [1.0, 6.0, 14.0, 22.0], batch=False, **kw)
    assert (sw.status.values == K.STUCK_FOREVER).any()
    assert sw.identical(ref)


def test_long_runs_side_by_side_are_the_long_runs_one_at_a_time():
    gbar = vi.Device().gbar(math.pi / 3)
    # chaotic, settling (a 2:1 start) and at rest for good (gbar > 1)
    cases = [(0.235, gbar, 0.42, 0.87), (0.16, gbar, 1.0, 0.2), (0.2, 1.5, 0.3, 0.1)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        many = long_runs(*np.array([(d, g, 0.5, p, v) for d, g, p, v in cases]).T, impacts=2000)
        one = [long_run(d, g, 0.5, p, v, impacts=2000) for d, g, p, v in cases]
    assert [m["status"] for m in many] == ["aperiodic", "settles", "stuck"]
    for a, b in zip(many, one, strict=True):
        assert a["status"] == b["status"]
        for key in ("t", "v_minus", "kind"):
            assert a[key].dtype == b[key].dtype and np.array_equal(a[key], b[key])
        assert (a["exponents"] is None) == (b["exponents"] is None)
        if a["exponents"] is not None:
            assert a["exponents"].per_impact == b["exponents"].per_impact
            assert a["exponents"].interval == b["exponents"].interval
            assert a["exponents"].per_time == b["exponents"].per_time


def test_sweep_energy_s_long_run_averages_are_those_of_each_point_s_long_run(both):
    sw, _ = both
    en = vi.sweep_energy(sw)
    # the reference: each point's long run made again, one at a time, from the restart the sweep recorded
    expected = np.full((*sw.status.shape, 4), np.nan)
    for idx in np.ndindex(sw.status.shape):
        if str(sw.long_status.values[idx]) == "aperiodic":
            run = long_run(sw.d.values[idx[-1]], sw.gbar.values[idx[-1]], sw.attrs["r"], sw.long_phi.values[idx],
                           sw.long_v0.values[idx], impacts=int(sw.attrs["long_impacts"]), tol=float(sw.attrs["tol"]))
            if run["status"] == "aperiodic":
                expected[idx] = energy.batch_averages(run, float(sw.F.values[idx[-1]]), vi.Device(), batches=20)
    assert np.isfinite(expected).any()
    for k, v in enumerate(("U_I_long", "U_I_long_se", "U_T_long", "U_T_long_se")):
        assert np.array_equal(en[v].values, expected[..., k], equal_nan=True), v


def test_transitions_on_threads_are_the_transitions_one_after_the_other(both):
    sw, _ = both
    kw = dict(xtol=1e-6, max_periods=2000)
    tr = vi.locate_transitions(sw, workers=3, **kw)
    assert tr.sizes["transition"] >= 2
    assert tr.identical(vi.locate_transitions(sw, workers=1, **kw))


@pytest.mark.parametrize("workers", [1, 2, 4])
def test_chains_on_threads_keep_and_pass_over_the_tasks_a_plain_loop_does(workers):
    # each task ends somewhere ahead; a task is passed over where the last one kept ended beyond it
    rng = np.random.default_rng(3)
    chains = [[(c, int(i), int(i + rng.integers(0, 4))) for i in range(30)] for c in range(3)]

    def run(task):  # finishing in another order than started
        time.sleep(3e-4 * ((7 * task[1] + task[0]) % 4) if threading.current_thread() is not threading.main_thread() else 0)
        return task[2], task

    def passed(task, end):
        return end is not None and task[1] < end

    expected = []
    for chain in chains:
        end = None
        for task in chain:
            if not passed(task, end):
                end, row = run(task)
                expected.append(row)
    assert len(expected) < sum(map(len, chains))  # some are passed over
    assert _run_chains(chains, run, passed, workers) == expected


@pytest.mark.parametrize("case", [
    (0.3775, math.pi / 3, 5.0, 0.42, 0.87),  # chaotic
    (0.16 / 0.6225, math.pi / 6, 5.0, 1.015, 0.1924),  # the 2:1 orbit of Figure 7 (a): periodic
    (0.85, math.pi / 2, 1.3, 0.42, 0.87),  # gbar = 0.94: the ball chatters, sticks and is released
])
def test_the_events_without_a_dataset_are_simulate_s(case):
    s, beta, force, phi, v0 = case
    p = vi.Params.from_physical(s=s, beta=beta, F=force)
    bufs, n, status = simulated_events(p, phi, v0, 3000)
    run = vi.simulate(p, phi, v0, n_impacts=3000)
    assert n == run.sizes["impact"] and K.STATUS_NAMES[status] == run.attrs["status"]
    for v in ("t", "wall", "v_minus", "phase", "kind"):
        assert np.array_equal(getattr(bufs, v)[:n], run[v].values)


def test_the_1_1_exit_is_the_one_found_with_runs_as_datasets():
    # the values sweep_family_exit gave when every run was a simulate dataset (the same runs, to the last bit)
    sw = vi.sweep("s", np.linspace(0.33, 0.345, 4), beta=math.pi / 6, phi=0.42, v0=0.87, long_impacts=0)
    g = vi.sweep_family_exit(sw, xtol=1e-5)
    assert {k: g[k].values.item() for k in g.data_vars} == {
        "exit_status": "located", "exit_d": 0.21081412353515622, "exit_d_width": 6.079101562500577e-06,
        "exit_clearance": 4.443983294577514e-06, "exit_slowest_after": 0.0007741919675632036, "exit_kind": "grazing",
        "exit_after": "no period found (1.003 bottom impacts per top impact)", "exit_sampled": True,
        "exit_s": 0.3386572265624999, "exit_F": 5.0}


def test_cycles_newton_fails_on_are_estimated_from_long_runs_as_in_the_reference(monkeypatch):
    # a cycle Newton's method does not solve has lambda_1 from the tangent estimate of a long run: make it fail
    # on every other cycle, and the batched long runs must give the reference's estimates
    from vibroimpact.analysis import settled

    solve = settled.polish_cycle
    calls = [0]

    def failing(*a, **kw):
        calls[0] += 1
        res = solve(*a, **kw)
        return res if calls[0] % 2 or not res["settled"] else res | dict(status="not settled: Newton failed (test)",
                                                                          settled=False)

    monkeypatch.setattr(settled, "polish_cycle", failing)
    kw = dict(beta=math.pi / 3, phi=0.42, v0=0.87)
    sw = vi.sweep("s", S_VALUES, **kw)
    calls[0] = 0
    ref = vi.sweep("s", S_VALUES, batch=False, **kw)
    assert (np.char.find(sw.lyap1_source.values.astype(str), "(not settled: Newton failed (test))") > 0).sum() >= 3
    assert sw.identical(ref)


def test_the_benchmark_counts_every_event_each_kernel_call_simulates():
    from vibroimpact.analysis.settled import long_runs as runs_side_by_side
    from vibroimpact.analysis.windows import run_window
    from vibroimpact.benchmarks.bench import _event_counter

    p = vi.Params.from_physical(s=0.3775, beta=math.pi / 3)
    with _event_counter() as count:
        vi.simulate(p, 0.42, 0.87, n_impacts=1234)
        assert count[0] == 1234
    with _event_counter() as count:
        n = vi.simulate(p, 0.42, 0.87, t_end=5000.0).sizes["impact"]  # grows its buffers: several event loops
        assert n > 4096 and count[0] == n
    with _event_counter() as count:
        *_, total, _ = run_window(p.d, p.gbar, 0.5, 0.42, 0.87, 200, 200_000, 1e-9, 65, 64)
        assert count[0] == total
        runs = runs_side_by_side([p.d, 0.16], p.gbar, 0.5, [0.42, 1.0], [0.87, 0.2], impacts=2000)
        extra = sum(r["t"].size for r in runs) + 2000 * sum(r["status"] == "settles" for r in runs)
        assert count[0] == total + extra
    sw = vi.sweep("s", S_VALUES[:3], beta=math.pi / 3, phi=0.42, v0=0.87, long_impacts=0)
    with _event_counter() as count:
        ref = vi.sweep("s", S_VALUES[:3], beta=math.pi / 3, phi=0.42, v0=0.87, long_impacts=0)
    assert ref.identical(sw) and count[0] == int(sw.n_events.sum())
    assert vi.simulate is not None and K.run_window.__class__.__name__ == "CPUDispatcher"  # restored


def test_a_kernel_compiled_while_the_benchmark_counts_events_still_compiles():
    """The counter leaves every compiled function in place: a kernel first compiled inside its block (on an empty
    numba cache, the sweep's batch of long runs) calls the compiled event loop, not a counting wrapper."""
    import numba

    from vibroimpact.benchmarks.bench import _event_counter

    @numba.njit
    def first_event_time(model, start, settings, counts, out):
        return K.advance(model, start, 0, settings, counts, out)[0]

    bufs = K.EventBuffers(*(np.zeros(8, dt) for dt in (float, np.int8, float, float, float, np.int8, float)))
    with _event_counter():
        n = first_event_time(K.Model(0.3, 0.5, 0.5), K.Start(0.0, 0.3, 0.15, 0.5, K.IMPACT, 1),
                             K.Settings(math.inf, K.V_CHATTER, False, 1e-9), np.zeros(2, np.int64), bufs)
    assert n == 8 and bufs.kind[0] == K.IMPACT
