"""The work-precision machinery: methods against the reference, failure outcomes, cost tables.
Costs are reported, never asserted."""

import math

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.benchmarks import methods as M
from vibroimpact.benchmarks.workprecision import compiled_last, failure_map, work_precision
from vibroimpact.dynamics.reference import trajectory
from vibroimpact.outputs.tables import workflow_cost

P21 = vi.Params(d=0.16, gbar=0.1245 * 9.8 * 0.5 / 5, r=0.5)


def test_every_method_follows_a_stable_2to1_orbit():
    ref = trajectory(P21.d, P21.gbar, P21.r, 1.015, 0.1924, 10)
    rt = np.array([float(x[0]) for x in ref])
    for run, tol in ((M.run_exact(P21, 1.015, 0.1924, 10), 1e-13), (M.run_python(P21, 1.015, 0.1924, 10), 1e-13),
                     (M.run_ivp(P21, 1.015, 0.1924, 10, method="DOP853", rtol=1e-10, atol=1e-12), 1e-8),
                     (M.run_rk4(P21, 1.015, 0.1924, 10, h=1e-3), 1e-10)):
        assert run.status == M.OK
        np.testing.assert_array_equal(run.wall, [x[1] for x in ref])
        assert np.max(np.abs(run.t - rt)) < tol


def test_plain_python_run_is_the_same_algorithm():
    a = M.run_exact(P21, 1.015, 0.1924, 50)
    b = M.run_python(P21, 1.015, 0.1924, 50)
    np.testing.assert_allclose(a.t, b.t, rtol=0, atol=1e-13)


def test_work_precision_errors_fall_with_step_and_tolerance():
    wp = work_precision(n_err=8, n_cost={"exact": 200, "python": 20, "ivp": 8, "rk4": 50}, ivp_methods=("DOP853",),
                        ivp_tols=(1e-4, 1e-9), rk4_steps=(3e-2, 3e-3), scenes={"2:1": (math.pi / 6, 0.16, 1.015, 0.1924)})
    e = wp.err_t.sel(scene="2:1")
    assert float(e.sel(solver="exact (numba)")) < 1e-13
    assert float(e.sel(solver="solve_ivp DOP853 rtol=1e-09")) < float(e.sel(solver="solve_ivp DOP853 rtol=0.0001"))
    assert float(e.sel(solver="RK4 + bisection h=0.003")) < float(e.sel(solver="RK4 + bisection h=0.03"))
    assert np.all(wp.us_per_impact.values > 0)


def test_failure_map_exact_is_always_right_and_event_detection_misses_short_crossings():
    fm = failure_map(epsilons=(1e-2, 1e-10), ivp_methods=("DOP853",), ivp_tols=(1e-10,), rk4_steps=(1e-2,),
                     chaos_impacts=30, chatter_t_end=5.0, max_seconds=1.0)
    exact = fm.sel(solver="exact (numba)").outcome.values
    assert set(exact) == {"correct"}
    ivp = fm.sel(solver="solve_ivp DOP853 rtol=1e-10")
    assert str(ivp.sel(case="B hit by 1e-10").outcome.values) == "missed impact"
    assert str(ivp.sel(case="chattering into sticking").outcome.values) in ("stalled", "crashed", "wrong sequence")
    # the exact simulator is rated on its impacts against the bounce-by-bounce reference, not trusted
    assert "follows the reference's" in str(fm.sel(solver="exact (numba)", case="chattering into sticking").detail.values)


def test_each_failure_map_row_is_its_method_s_alone_whatever_the_order_the_methods_run_in():
    """The map runs the compiled families last (:func:`compiled_last`); every row must still be the outcome of
    its own method: the same as in a map of that method alone (the seconds a run took aside)."""
    kw = dict(epsilons=(1e-2, 1e-10), ivp_tols=(1e-10,), chaos_impacts=30, chatter_t_end=1.0, max_seconds=1.0,
              chatter_max_evals=2000, chaos_max_evals=5000)
    both = failure_map(ivp_methods=("DOP853",), rk4_steps=(1e-2,), **kw)
    assert list(both.family.values) == ["exact", "ivp-DOP853", "rk4"]  # the ladder's order, not the run's
    alone = [failure_map(ivp_methods=("DOP853",), rk4_steps=(), **kw),
             failure_map(ivp_methods=(), rk4_steps=(1e-2,), **kw)]
    for one in alone:
        for solver in one.solver.values:
            row, own = both.sel(solver=solver), one.sel(solver=solver)
            assert list(row.outcome.values) == list(own.outcome.values), solver
            assert list(row.sensitive.values) == list(own.sensitive.values), solver
            # the detail holds no timing (the seconds are a variable of their own, passed over as a timing)
            assert list(row.detail.values) == list(own.detail.values), solver
    runs = ["chattering into sticking", "chaotic run (30 impacts)"]
    assert np.isfinite(both.seconds.sel(case=runs)).all() and np.isnan(both.seconds.drop_sel(case=runs)).all()
    assert len(set(both.outcome.sel(case="B hit by 1e-10").values)) > 1  # rows that differ, so a swap shows


def test_compiled_last_keeps_each_group_s_order():
    ladder = [("exact", 0, "a"), ("ivp-RK45", 1, "b"), ("rk4", 2, "c"), ("ivp-Radau", 3, "d"), ("heyoka", 4, "e")]
    assert compiled_last(ladder) == [1, 3, 4, 0, 2]


def test_a_chaotic_run_cut_by_its_budget_while_right_is_stalled_not_wrong():
    """Radau at rtol 1e-10 evaluates the right-hand side ~2500 times per chaotic impact: with a budget
    of 10 000 it stops after a few impacts, all of them right; that is 'stalled', not a lost sequence
    (which needs an impact off the reference), and it stops there on any machine."""
    fm = failure_map(epsilons=(1e-2,), ivp_methods=("Radau",), ivp_tols=(1e-10,), rk4_steps=(),
                     chaos_impacts=30, chatter_t_end=1.0, max_seconds=0.3, chatter_max_evals=2000,
                     chaos_max_evals=10_000)
    detail = str(fm.sel(solver="solve_ivp Radau rtol=1e-10", case="chaotic run (30 impacts)").detail.values)
    again = failure_map(epsilons=(1e-2,), ivp_methods=("Radau",), ivp_tols=(1e-10,), rk4_steps=(),
                        chaos_impacts=30, chatter_t_end=1.0, max_seconds=0.3, chatter_max_evals=2000,
                        chaos_max_evals=10_000)
    # the same number of impacts followed however long each took
    assert detail.split(" (")[0] == str(again.sel(solver="solve_ivp Radau rtol=1e-10",
                                                   case="chaotic run (30 impacts)").detail.values).split(" (")[0]
    case = "chaotic run (30 impacts)"
    radau = fm.sel(solver="solve_ivp Radau rtol=1e-10", case=case)
    assert str(radau.outcome.values) == "stalled", str(radau.detail.values)
    assert str(fm.sel(solver="exact (numba)", case=case).outcome.values) == "correct"


def test_workflow_cost_reads_benchmark_files(tmp_path):
    (tmp_path / "maps").mkdir()
    (tmp_path / "maps" / "s_beta.tsv").write_text("s\th:m:s\tmax_rss\n1.5\t0:00:01\t100\n")
    jobs, per_fig = workflow_cost(tmp_path)
    assert float(jobs.seconds.sum()) == 1.5
    assert float(per_fig.set_index("figure").loc["regime_map", "seconds"]) == 1.5


def test_workflow_cost_counts_an_incline_s_branches_for_the_figures_that_draw_that_incline(tmp_path):
    """The job of the branches at pi/6 (benchmarks/branches/beta-0.5236_r-0.5000/batch.tsv) is rule `branches`, and
    counts for Figures 5, 6 (fig2, fig3), 8 (figBiS) and 9 (fig5), not for Figure 2 (fig0: pi/3 only)."""
    where = tmp_path / "branches" / "beta-0.5236_r-0.5000"
    where.mkdir(parents=True)
    (where / "batch.tsv").write_text("s\th:m:s\tmax_rss\n4.0\t0:00:04\t100\n")
    jobs, per_fig = workflow_cost(tmp_path)
    assert list(jobs.rule) == ["branches"]
    seconds = per_fig.set_index("figure").seconds
    assert seconds["figBiS"] == seconds["fig5"] == seconds["fig2, fig3, table1 (2:1 branches)"] == 4.0
    assert seconds["fig0"] == 0.0


def _wp(err, cost, family, setting):
    import xarray as xr

    err, cost = np.asarray(err, float), np.asarray(cost, float)
    return xr.Dataset({"err_t": (("solver", "scene"), err), "us_per_impact": (("solver", "scene"), cost),
                       "family": ("solver", family), "setting": ("solver", setting)},
                      coords={"solver": [f"m{i}" for i in range(len(family))], "scene": ["a", "b"]})


def test_matched_accuracy_takes_the_cheapest_setting_that_reaches_the_target():
    """Per family and scene the cheapest setting with error <= 1e-12; none: "cannot reach" (a finer
    setting that misses the target, or one on the wrong walls, never counts); ratios to exact."""
    from vibroimpact.benchmarks.workprecision import matched_accuracy

    wp = _wp(err=[[1e-15, 1e-15], [1e-9, 1e-9], [1e-13, np.inf], [5e-13, 2e-12], [1e-6, 1e-6]],
             cost=[[1.0, 2.0], [5.0, 5.0], [40.0, 40.0], [20.0, 10.0], [3.0, 3.0]],
             family=["exact", "heyoka", "heyoka", "heyoka", "rk4"], setting=[np.nan, 1e-9, 1e-16, 1e-12, 1e-2])
    ma = matched_accuracy(wp, 1e-12)
    h = ma.sel(family="heyoka")
    assert h.setting.sel(scene="a") == 1e-12 and h.us_per_impact.sel(scene="a") == 20.0  # cheaper of two
    assert not bool(h.reached.sel(scene="b"))  # 2e-12 misses, inf is wrong walls
    assert float(h.ratio_to_exact.sel(scene="a")) == 20.0
    assert not bool(ma.sel(family="rk4").reached.any())
    assert bool(ma.sel(family="exact").reached.all())
    # the cheapest setting is the timings' choice: a comparison of two runs (tools/same_results.py) passes over
    # what it decides, and over nothing else
    timed = {v for v in ma.data_vars if ma[v].attrs.get("provenance") == "timing"}
    assert timed == {"setting", "err_t", "ratio_to_exact"}


def test_absent_peers_are_recorded_not_dropped_silently(monkeypatch):
    from vibroimpact.benchmarks import peer_heyoka, peer_siconos
    from vibroimpact.benchmarks.workprecision import method_ladder, peer_status

    monkeypatch.setattr(peer_heyoka, "available", lambda: False)
    monkeypatch.setattr(peer_heyoka, "heyoka_version", lambda: None)
    monkeypatch.setattr(peer_siconos, "available", lambda: False)
    status = peer_status()
    assert status["heyoka"].startswith("not installed") and "not installed" in status["siconos"]
    ladder = method_ladder(["DOP853"], [1e-6], [1e-2], heyoka_tols=[1e-9], siconos_tols=[1e-9], siconos_steps=[1e-3])
    assert {f for f, _, _ in ladder} == {"exact", "python", "ivp-DOP853", "rk4"}


def test_a_siconos_peer_that_dies_is_no_impact_and_a_bug_is_raised(monkeypatch):
    """The failure map's Siconos flights: a peer process that dies or hangs is recorded as flights with no
    impact; any other exception (a bug) reaches the caller instead of being recorded as a result."""
    import subprocess

    import vibroimpact.benchmarks.peer_siconos as ps
    from vibroimpact.benchmarks import workprecision as wp

    states = [(0.3, 0.0, 0.5), (1.2, 0.0, 0.4)]

    def raising(err):
        def flights(*args, **kw):
            raise err
        return flights

    for err in (ps.SiconosPeerError("signal 6"), subprocess.TimeoutExpired("python3", 1.0)):
        monkeypatch.setattr(ps, "siconos_flights", raising(err))
        assert wp._flights("siconos-ed", 1e-10, states, 0.2, 0.1) == [(math.inf, 0)] * 2
    monkeypatch.setattr(ps, "siconos_flights", raising(KeyError("status")))
    with pytest.raises(KeyError):
        wp._flights("siconos-mj", 1e-4, states, 0.2, 0.1)


def test_a_chaotic_run_whose_outcome_a_start_one_ulp_away_changes_is_marked_sensitive(monkeypatch):
    """The failure map runs its chaotic case twice, the second time from a start one ulp away: a method that
    follows the reference from one start and parts from it from the other has an outcome the last bit decides
    (another machine's may differ), and only that cell is marked."""
    from vibroimpact.benchmarks import workprecision as W

    phi0 = W.SCENES["chaotic"][2]
    real = W._run

    def run(family, setting, p, phi, v0, n, **kw):
        out = real(family, setting, p, phi, v0, n, **kw)
        if family == "rk4" and n == 30 and phi != phi0:  # the moved start parts from the reference at once
            out = M.Run(out.t + 1.0, out.wall, out.v, out.status, out.seconds)
        return out

    monkeypatch.setattr(W, "_run", run)
    fm = failure_map(epsilons=(1e-2,), ivp_methods=(), ivp_tols=(), rk4_steps=(1e-3,), chaos_impacts=30,
                     chatter_t_end=1.0, max_seconds=0.5)
    case = "chaotic run (30 impacts)"
    assert str(fm.sel(solver="RK4 + bisection h=0.001", case=case).outcome.values) == "correct"
    assert bool(fm.sel(solver="RK4 + bisection h=0.001", case=case).sensitive)
    assert int(fm.sensitive.sum()) == 1  # the exact simulator's outcome, and every other case's, is not


def test_the_failure_table_gives_each_run_s_detail_and_the_seconds_it_took():
    import xarray as xr

    from vibroimpact.outputs.tables import failure_markdown

    cases = ["B hit by 0.01", "T miss by 0.01", "chattering into sticking", "chaotic run (30 impacts)"]
    fm = xr.Dataset(
        {"outcome": (("solver", "case"), [["correct", "missed impact", "stalled", "correct"]]),
         "detail": (("solver", "case"), [["", "", "follows 3 (stalled)", "follows 30 of 30 (ok)"]]),
         "seconds": (("solver", "case"), [[np.nan, np.nan, 0.25, 1.5e-3]])},
        coords={"solver": ["a method"], "case": cases})
    row = failure_markdown(fm).splitlines()[2]
    assert row == "| a method | 1 | 0 | 1 | 0 | 0 | 0 | 0 | stalled: follows 3 (stalled), 0.25 s | follows 30 of 30 (ok), 0.0015 s |"
