"""Basin stability (vibroimpact.analysis.basin_stability): the shares of the attractors from starts over the
whole state space and from switch-on, checked against the simulator run start by start, closed forms of the
Clopper-Pearson interval, the design map at the same point, and the binomial spread between seeds."""

import math
import re

import numpy as np
import pytest
from conftest import ROOT
from scipy.stats import binomtest

import vibroimpact as vi
from vibroimpact.analysis import basin_stability as bsm
from vibroimpact.analysis.design import PointAttractor

PI6 = math.pi / 6
#: between G1 and G2 at pi/6: the 2:1 and the 3:1 coexist
BISTABLE = vi.Params.from_physical(s=0.13975 / 0.6225, beta=PI6)
#: d = 0.16 at pi/6 (Figure 7 (a)): the 2:1 alone
MONOSTABLE = vi.Params.from_physical(s=0.16 / 0.6225, beta=PI6)
TWO, THREE = "2:1 period-2", "3:1 period-2"


@pytest.fixture(scope="module")
def bistable():
    return vi.basin_stability(BISTABLE, n=400, seed=0)


def shares_of(ds, label):
    """Share, interval and count of ``label`` per distribution (0 where it is not reached)."""
    k = list(ds.label.values).index(label)
    return (ds.share.values[:, k], ds.share_low.values[:, k], ds.share_high.values[:, k], ds["count"].values[:, k])


def test_starts_rerun_one_by_one_with_the_simulator_reach_the_batch_s_attractors(bistable):
    """The starts are drawn here again from the generator (not read from the dataset): 20 state-space starts
    (ten on each attractor) run by ``vi.simulate`` in flight from t = 0 and 10 switch-on starts run from rest
    on the bottom, each named by ``vi.identify_attractor``: the labels are the batch's."""
    n, seed = 400, 0
    rng = np.random.default_rng(seed)
    theta = rng.uniform(0, 2 * math.pi, n)
    z = rng.uniform(-BISTABLE.d / 2, BISTABLE.d / 2, n)
    zdot = rng.uniform(-1.0, 1.0, n)
    space = list(bistable.distribution.values).index("state space")
    batch = bistable.label.values[bistable.reached.values[space]]
    picks = [*np.flatnonzero(batch == TWO)[:10], *np.flatnonzero(batch == THREE)[:10]]
    assert len(picks) == 20
    for j in picks:
        run = vi.simulate(BISTABLE, theta[j], zdot[j], Z0=z[j], t0=0.0, stop_when_periodic=True, t_end=400.0)
        assert vi.identify_attractor(run).label == batch[j], j
    phi = np.random.default_rng(seed).uniform(0, 2 * math.pi, n)
    on = list(bistable.distribution.values).index("switch-on")
    batch_on = bistable.label.values[bistable.reached.values[on]]
    for j in [*np.flatnonzero(batch_on == TWO)[:5], *np.flatnonzero(batch_on == THREE)[:5]]:
        run = vi.simulate(BISTABLE, phi[j], 0.0, stop_when_periodic=True, t_end=400.0)
        assert vi.identify_attractor(run).label == batch_on[j], j
    # and the dataset records the starts it ran
    assert np.array_equal(bistable.start_phase.values[space], theta)
    assert np.array_equal(bistable.start_Z.values[space], z) and np.array_equal(bistable.start_Zdot.values[space], zdot)
    assert np.array_equal(bistable.start_phase.values[on], phi)


def test_shares_sum_to_one_and_each_interval_is_the_exact_binomial_one(bistable):
    n = bistable.attrs["n"]
    assert (bistable["count"].sum("attractor").values == n).all()
    assert np.allclose(bistable.share.sum("attractor").values, 1.0, rtol=0, atol=1e-12)
    # every start reaches one attractor, and the counts are those of its starts
    for i in range(2):
        assert np.array_equal(np.bincount(bistable.reached.values[i], minlength=bistable.sizes["attractor"]),
                              bistable["count"].values[i])
    assert (bistable.share_low <= bistable.share).all() and (bistable.share <= bistable.share_high).all()
    for k, lo, hi in zip(bistable["count"].values.ravel(), bistable.share_low.values.ravel(),
                         bistable.share_high.values.ravel(), strict=True):
        ci = binomtest(int(k), n).proportion_ci(0.95, method="exact")
        assert (lo, hi) == pytest.approx((ci.low, ci.high), abs=1e-12)
    assert np.allclose(bistable.E_U_T, (bistable.share * bistable.U_T).sum("attractor"), rtol=1e-12)
    for v in ("share", "share_low", "share_high", "count", "U_T"):
        assert bistable[v].dims == ("distribution", "attractor") and bistable[v].attrs["units"] in ("1", "V"), v
        assert bistable[v].attrs["long_name"], v


def test_each_attractor_has_one_output_whichever_distribution_reaches_it(bistable):
    """A periodic attractor's output is its cycle's: the runs of both distributions, from different starts, give
    the same U_T (each settled on its Newton-solved cycle)."""
    assert bistable.settled.values.all()
    u = bistable.U_T.values
    assert np.allclose(u[0], u[1], rtol=1e-9, atol=0)
    assert set(bistable.label.values) == {TWO, THREE}


def test_the_switch_on_shares_are_the_design_map_s_at_the_same_point(bistable):
    """The switch-on distribution is the design maps' starts: the design map at the same point, on the same
    400 starts at rest, counts the same starts on each attractor with the same outputs."""
    phi, v0 = vi.start_states(400, seed=0)
    dm = vi.design_map("s", [0.13975 / 0.6225], "beta", [PI6], phi=phi, v0=v0)
    for label in (TWO, THREE):
        k = list(dm.label.values[0, 0]).index(label)
        share, lo, hi, count = shares_of(bistable, label)
        assert count[0] == int(dm["count"].values[0, 0, k])
        assert (lo[0], hi[0]) == (dm.share_low.values[0, 0, k], dm.share_high.values[0, 0, k])
        kb = list(bistable.label.values).index(label)
        assert bistable.U_T.values[0, kb] == pytest.approx(dm.U_T.values[0, 0, k], rel=1e-12)


def test_at_a_monostable_point_every_start_of_both_distributions_reaches_the_2_1():
    n = 200
    ds = vi.basin_stability(MONOSTABLE, n=n, seed=4)
    assert ds.label.values.tolist() == [TWO]
    assert ds.share.values.ravel().tolist() == [1.0, 1.0]
    # the Clopper-Pearson interval of n successes out of n: [(alpha / 2)^(1/n), 1]
    assert ds.share_low.values.ravel() == pytest.approx([0.025 ** (1 / n)] * 2, rel=1e-10)
    assert ds.share_high.values.ravel().tolist() == [1.0, 1.0]


def test_a_chaotic_attractor_is_reported_with_its_long_run_output_not_dropped():
    """beta = pi/3, d = 0.235: every start of both distributions reaches the chaotic attractor; it is labelled by
    its long run (as on the design maps), counted, and carries an output with its standard error; the two
    distributions' estimates of that one output agree within four combined standard errors."""
    from vibroimpact.analysis.motions import CHAOTIC

    ds = vi.basin_stability(vi.Params.from_physical(s=0.235 / 0.6225, beta=math.pi / 3), n=40, seed=0)
    assert ds.label.values.tolist() == [CHAOTIC] and ds["count"].values.ravel().tolist() == [40, 40]
    u, se = ds.U_T.values[:, 0], ds.U_T_se.values[:, 0]
    assert np.isfinite(u).all() and (se > 0).all() and not ds.settled.values.any()
    assert abs(u[0] - u[1]) <= 4 * math.hypot(*se)


def test_in_the_bistable_band_two_seeds_agree_within_binomial_error():
    """Both motions appear among the state-space starts of each seed; the two seeds' shares of each motion
    differ by no more than their 99.9 % intervals' half-widths combined in quadrature (a 3.3-sigma statement
    about independent samples, not a bitwise one)."""
    a, b = (vi.basin_stability(BISTABLE, n=400, seed=s, confidence=0.999) for s in (1, 2))
    assert a.attrs["seed"] == 1 and b.attrs["seed"] == 2
    for ds in (a, b):
        assert set(ds.label.values) == {TWO, THREE}
    for label in (TWO, THREE):
        (pa, la, ha, ca), (pb, lb, hb, cb) = shares_of(a, label), shares_of(b, label)
        assert (ca[1] > 0) and (cb[1] > 0)
        width = np.sqrt(((ha - la) / 2) ** 2 + ((hb - lb) / 2) ** 2)
        assert (np.abs(pa - pb) <= width).all(), (label, pa, pb, width)
        for c, lo, hi in ((ca, la, ha), (cb, lb, hb)):  # the intervals are at the level asked for
            for k, l, h in zip(c, lo, hi, strict=True):
                ci = binomtest(int(k), 400).proportion_ci(0.999, method="exact")
                assert (l, h) == pytest.approx((ci.low, ci.high), abs=1e-12)


def test_the_same_seed_gives_the_same_dataset_and_another_seed_other_starts(bistable):
    again = vi.basin_stability(BISTABLE, n=400, seed=0)
    assert again.identical(bistable)
    other = vi.basin_stability(BISTABLE, n=400, seed=5)
    assert not np.array_equal(other.start_Z.values, bistable.start_Z.values)


def test_the_attributes_record_the_start_distributions(bistable):
    a = bistable.attrs
    assert (a["n"], a["seed"], a["confidence"]) == (400, 0, 0.95)
    assert list(a["Z_range"]) == [-BISTABLE.d / 2, BISTABLE.d / 2] and list(a["Zdot_range"]) == [-1.0, 1.0]
    assert list(a["phase_range"]) == [0.0, 2 * math.pi]
    assert "default_rng(0)" in a["state_space_starts"] and "start_states(400, distribution='rest', seed=0)" in a[
        "switch_on_starts"]
    on = list(bistable.distribution.values).index("switch-on")
    assert (bistable.start_Z.values[on] == BISTABLE.d / 2).all() and (bistable.start_Zdot.values[on] == 0).all()


def test_the_default_velocity_box_covers_the_paper_s_motions():
    """The largest relative speed on the paper's motions is the 1:1's at the long end of its sweeps: at s = 0.72 m
    it reaches 0.964 at pi/2 (the docstring's number) and less at the smaller inclines, and less on the force
    sweeps' long end (s = 0.85 m, F = 6 N); the default box (-1, 1) holds them all."""
    top = {}
    cases = [(0.72, b, 5.0) for b in (math.pi / 2, math.pi / 3, math.pi / 4, PI6)] + [(0.85, math.pi / 2, 6.0)]
    for s, beta, F in cases:
        run = vi.simulate(vi.Params.from_physical(s=s, beta=beta, F=F), 0.4, 0.9, stop_when_periodic=True, t_end=2000)
        t = run.t.values
        top[(s, beta, F)] = float(np.abs(vi.trajectory(run, np.linspace(t[-20], t[-1], 20_000)).Zdot).max())
    assert max(top.values()) == top[(0.72, math.pi / 2, 5.0)]
    assert f"{top[(0.72, math.pi / 2, 5.0)]:.3f}" == "0.964" and "0.964" in vi.basin_stability.__doc__
    page = " ".join((ROOT / "docs" / "guide" / "robustness.md").read_text().split())
    assert "the largest, 0.964, is the 1:1 motion's at the long end of its sweeps (s = 0.72 m, β = π/2)" in page
    assert bsm.V_RANGE[0] < -max(top.values()) and max(top.values()) < bsm.V_RANGE[1]


def _att(label, count, u_t):
    return PointAttractor(label=label, runs=np.arange(count), count=count, share=0.0, low=0.0, high=1.0, U_T=u_t,
                          U_I=0.0, u_t_runs=np.zeros(count), u_i_runs=np.zeros(count))


def test_attractors_of_the_two_distributions_are_one_only_with_one_label_and_one_output():
    """The union of the two distributions' attractors: one label and (periodic) one U_T to SAME_ORBIT make one
    attractor; otherwise two, whatever their outputs; ordered by the starts of both distributions together."""
    from vibroimpact.analysis.design import SAME_ORBIT
    from vibroimpact.analysis.motions import CHAOTIC, QUASI_PERIODIC

    u = 30_000.0
    on = [_att(THREE, 6, u), _att(TWO, 4, u + 70.0)]
    space = [_att(TWO, 9, u + 70.0 * (1 + 1e-9)), _att(CHAOTIC, 1, u), _att(THREE, 1, u * (1 + 10 * SAME_ORBIT))]
    labels, index = bsm._union([on, space])
    assert labels == [TWO, THREE, THREE, CHAOTIC]  # most starts over both first (13, 6, 1, 1), then by label
    assert index == [[1, 0], [0, 3, 2]]
    # a label alone (no period, or two periodic motions with the same output) never merges two motions
    labels, index = bsm._union([[_att(CHAOTIC, 5, u)], [_att(QUASI_PERIODIC, 5, u), _att(TWO, 4, u)]])
    assert labels == [CHAOTIC, QUASI_PERIODIC, TWO] and index == [[0], [1, 2]]
    labels, index = bsm._union([[_att(CHAOTIC, 5, u)], [_att(CHAOTIC, 3, u + 500.0)]])
    assert labels == [CHAOTIC] and index == [[0], [0]]  # one motion with no period: its windows' outputs spread


@pytest.mark.parametrize("kwargs, key", [
    (dict(n=7), "n"), (dict(n=True), "n"), (dict(n=100.0), "n"),
    (dict(v_range=(1.0, -1.0)), "v_range"), (dict(v_range=(0.5, 0.5)), "v_range"),
    (dict(v_range=(math.nan, 1.0)), "v_range"), (dict(v_range=1.0), "v_range"),
    (dict(confidence=0.0), "confidence"), (dict(confidence=1.0), "confidence"), (dict(confidence=95), "confidence"),
    (dict(seed=-1), "seed"), (dict(max_periods=0), "max_periods"),
])
def test_bad_input_is_refused_before_any_run(monkeypatch, kwargs, key):
    def no_run(*a, **k):
        raise AssertionError("a run started before the input was checked")

    monkeypatch.setattr(bsm, "attractor_batch", no_run)
    with pytest.raises(ValueError, match=rf"^{key} = .* allowed: "):
        vi.basin_stability(BISTABLE, **{"n": 50, **kwargs})
    with pytest.raises(ValueError, match=r"^params = "):
        vi.basin_stability((0.14, 0.12, 0.5), n=50)


def test_the_shares_the_robustness_page_states_are_the_call_s():
    """docs/guide/robustness.md states the 2:1 motion's share at the bistable point for both distributions (1000
    starts, seed 0) with their intervals: each stated share lies in the interval the same call gives, each
    computed share in the stated interval, and the two distributions' intervals are disjoint, as the page says."""
    text = " ".join((ROOT / "docs" / "guide" / "robustness.md").read_text().split())
    m = re.search(r"switch-on starts reach the 2:1 motion with share (0\.\d+) \(95 % interval (0\.\d+)–(0\.\d+)\), "
                  r"the state-space starts with share (0\.\d+) \((0\.\d+)–(0\.\d+)\)", text)
    assert m, "the page's sentence on the measured shares"
    stated = [float(x) for x in m.groups()]
    assert "vi.basin_stability(p, n=1000, seed=0)" in text
    ds = vi.basin_stability(BISTABLE, n=1000, seed=0)
    share, lo, hi, _ = shares_of(ds, TWO)
    for i, (s, l, h) in enumerate((stated[:3], stated[3:])):
        assert lo[i] <= s <= hi[i] and l <= share[i] <= h, (i, s, l, h, share[i], lo[i], hi[i])
    assert hi[0] < lo[1]  # "the intervals do not overlap"
    assert "all 200 starts of each distribution (seed 4) reach the 2:1 motion" in text  # the monostable test's call
