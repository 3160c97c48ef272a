"""The paper's d_graz, "the maximum value for 2:1 period-2 solutions", and its identity with the 1:1 exit: "at
d = d_graz, Zdot_j = 0 and Z_j = d/2, and there is a transition to 2:1 motion for d < d_graz"
(vibroimpact.analysis.d_graz), tested at every incline by length and by force."""

import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import vibroimpact as vi
from vibroimpact.analysis.d_graz import branch_d_graz, down_entry, sweep_d_graz
from vibroimpact.analysis.family_exit import family_exit, in_family
from vibroimpact.outputs.tables import d_graz_markdown, d_graz_summary, d_graz_table


def _branch(word, d, stable, crit, **attrs):
    kinds, ds_, adm = zip(*crit, strict=True) if crit else ((), (), ())
    return xr.Dataset({"stable": ("point", np.array(stable)), "admissible": ("point", np.ones(len(d), bool)),
                       "critical_kind": ("critical", np.array(kinds, dtype=str)),
                       "critical_d": ("critical", np.array(ds_, float)),
                       "critical_admissible": ("critical", np.array(adm, bool))},
                      coords={"d": ("point", np.array(d))}, attrs={"word": word, "step": 1e-3, **attrs})


def test_d_graz_is_the_largest_admissible_fold_of_the_2to1_branch():
    d = np.linspace(0.13, 0.23, 11)
    br = _branch("BBT", d, d > 0.15, [("fold", 0.2205, True), ("fold", 0.2290, False), ("fold", 0.1401, True),
                                      ("B", 0.168, True)])
    assert branch_d_graz(br) == (0.2205, "fold of the 2:1 branch")  # the inadmissible fold is no solution
    d_none, why = branch_d_graz(_branch("BBT", d, d > 0.15, [("B", 0.168, True)]))
    assert math.isnan(d_none) and "no admissible fold" in why
    d_failed, why = branch_d_graz(xr.Dataset(attrs={"status": "failed", "reason": "the attractor is 1:1", "word": "BBT"}))
    assert math.isnan(d_failed) and why == "no 2:1 branch: the attractor is 1:1"
    assert math.isnan(branch_d_graz(_branch("BT", d, d > 0.15, [("fold", 0.2, True)]))[0])


def synthetic_sweep(down, up, d, lyap=None):
    """A sweep of points ``d`` (increasing) whose down and up directions find the motions ``down`` and ``up``."""
    lab = np.array([up, down], dtype=str)
    lam = np.full(lab.shape, -0.2) if lyap is None else np.array([np.full(len(d), -0.2), lyap])
    return xr.Dataset({"label": (("direction", "point"), lab), "lyap1": (("direction", "point"), lam)},
                      coords={"direction": ["up", "down"], "d": ("point", np.asarray(d, float))},
                      attrs={"beta": math.pi / 3, "vary": "s"})


def _transitions(exit_d, kind, up_end=0.2205):
    return xr.Dataset({"direction": ("transition", ["up", "down"]), "d": ("transition", [up_end, 0.17]),
                       "d_width": ("transition", [1e-7, 1e-7]), "before": ("transition", ["2:1 period-2", "1:1 period-2"]),
                       "exit_d": ((), exit_d), "exit_d_width": ((), 1e-7), "exit_kind": ((), kind),
                       "exit_clearance": ((), 1e-8 if kind == "grazing" else 0.02), "exit_status": ((), "located")})


D = np.round(np.arange(0.200, 0.2501, 0.005), 4)  # 0.200, 0.205, ..., 0.250


def test_the_down_sweep_enters_2to1_at_its_largest_2to1_point_within_one_step_above():
    down = ["2:1 period-2"] * 5 + ["chaotic", "2:1 period-2", "chaotic", "chaotic"] + ["1:1 period-2"] * 2
    sw = synthetic_sweep(down, ["2:1 period-2"] * 11, D)
    assert down_entry(sw) == (pytest.approx(0.230), pytest.approx(0.005))  # the first 2:1 met going down
    assert all(math.isnan(x) for x in down_entry(sw, "3:1 period-2"))
    top = synthetic_sweep(["2:1 period-2"] * 11, ["2:1 period-2"] * 11, D)
    assert down_entry(top)[0] == pytest.approx(0.25) and math.isnan(down_entry(top)[1])


def test_sweep_d_graz_reads_d_graz_every_way_and_the_band_between():
    """pi/3 by length, as the workflow finds it: the 1:1 motion leaves its family by a jump at 0.2353, the down
    sweep enters 2:1 at 0.2194 with chaos between, the 2:1 fold (and the up sweep's loss of 2:1) at 0.2201."""
    d = np.round(np.arange(0.2150, 0.2451, 0.0015), 4)
    down = np.where(d <= 0.2195, "2:1 period-2", np.where(d < 0.2353, "chaotic", "1:1 period-4")).tolist()
    down[list(d).index(0.2225)] = "5:4 over 4 forcing periods"
    lam = np.where(np.array(down) == "chaotic", 0.3, -0.1)
    sw = synthetic_sweep(down, ["2:1 period-2"] * d.size, d, lam)
    br = _branch("BBT", d, d < 0.2201, [("fold", 0.220068, True)])
    r = sweep_d_graz(sw, _transitions(0.2353, "jump", up_end=0.2200681), br)
    assert (r["d_graz"], r["d_graz_source"]) == (0.220068, "fold of the 2:1 branch")
    assert (r["entry_d"], r["entry_step"]) == pytest.approx((0.2195, 0.0015))
    assert r["up_end_d"] == pytest.approx(0.2200681) and r["d_graz_minus_entry"] == pytest.approx(0.220068 - 0.2195)
    assert (r["exit_d"], r["exit_kind"]) == (0.2353, "jump")
    assert r["exit_minus_d_graz"] == pytest.approx(0.2353 - 0.220068) and r["band_width"] == pytest.approx(0.2353 - 0.2195)
    inside = (d > 0.2195) & (d < 0.2353)
    assert r["band_points"] == inside.sum() and r["band_chaotic"] == inside.sum() - 1
    assert r["band_motions"] == f"{inside.sum() - 1} chaotic, 1 5:4 over 4 forcing periods"
    assert r["band_lyap1_max"] == pytest.approx(0.3) and r["tolerance"] == pytest.approx(0.0015)
    assert r["identity"] is False


@pytest.mark.parametrize("exit_d, kind, fold, holds", [
    (0.2200, "grazing", 0.2201, True),    # the paper's picture: the 1:1 motion grazes where the 2:1 begins
    (0.2200, "jump", 0.2201, False),      # there, but not by grazing
    (0.2200, "grazing", 0.2260, False),   # grazing where the sweep enters 2:1, but the 2:1 exists far above
    (0.2240, "grazing", 0.2201, False),   # a band of sweep points between the exit and the 2:1
])
def test_the_identity_holds_only_where_the_1to1_grazes_where_2to1_begins(exit_d, kind, fold, holds):
    d = np.round(np.arange(0.2050, 0.2351, 0.0015), 4)  # 2:1 up to 0.2195, the next point 0.2210
    down = np.where(d <= 0.2196, "2:1 period-2", np.where(d < exit_d, "chaotic", "1:1 period-4")).tolist()
    sw = synthetic_sweep(down, ["2:1 period-2"] * d.size, d)
    r = sweep_d_graz(sw, _transitions(exit_d, kind), _branch("BBT", d, d < fold, [("fold", fold, True)]))
    assert r["identity"] is holds
    assert r["band_points"] == int(((d > r["entry_d"]) & (d < exit_d)).sum())


def test_without_a_branch_or_an_exit_the_reading_says_so():
    sw = synthetic_sweep(["2:1 period-2"] * 3 + ["1:1 period-2"] * 8, ["2:1 period-2"] * 11, D)
    r = sweep_d_graz(sw, None, None)
    assert math.isnan(r["d_graz"]) and r["d_graz_source"] == "no 2:1 branch" and math.isnan(r["exit_d"])
    assert r["band_points"] == 0 and r["identity"] is False and math.isnan(r["up_end_d"])


def test_the_d_graz_table_gives_each_sweep_s_evidence_and_counts_where_the_identity_fails():
    d = np.round(np.arange(0.2150, 0.2451, 0.0015), 4)
    down = np.where(d <= 0.2195, "2:1 period-2", np.where(d < 0.2353, "chaotic", "1:1 period-4")).tolist()
    sw = synthetic_sweep(down, ["2:1 period-2"] * d.size, d, np.where(np.array(down) == "chaotic", 0.3, -0.1))
    br = _branch("BBT", d, d < 0.2201, [("fold", 0.220068, True)])
    holds = synthetic_sweep(np.where(d <= 0.2195, "2:1 period-2", "1:1 period-2").tolist(), ["2:1 period-2"] * d.size, d)
    df = d_graz_table({"fig0_s": sweep_d_graz(sw, _transitions(0.2353, "jump"), br),
                       "ok_s": sweep_d_graz(holds, _transitions(0.2200, "grazing"), br)})
    assert list(df.sweep) == ["fig0_s", "ok_s"] and list(df.identity) == [False, True]
    md = d_graz_markdown(df)
    assert ("| fig0_s | π/3 | length | 0.220068 | 0.220500 | 0.2195 (+1.5e-03) | +0.0006 | 0.235300 | jump (2.0e-02) | "
            "+0.0152 | 0.0158, 10 | 10 chaotic | 0.300 | fails |") in md
    assert d_graz_summary(df) == (
        "The paper's identity (the 1:1 motion grazes where 2:1 begins, at d_graz) holds along 1 of 2 sweeps. Along "
        "the other 1 the 1:1 motion leaves its family by jump (1), 0.0152 to 0.0152 off d_graz, and 1 down sweeps "
        "find 10 points between their entry into 2:1 and the exit (bands 0.0158 to 0.0158 wide), 10 of them chaotic "
        "(λ₁ per impact up to 0.300).")
    assert md.rstrip().endswith(d_graz_summary(df))
    assert d_graz_summary(pd.DataFrame()) == "No sweep to read d_graz along."


def test_energy_figures_mark_d_graz_at_the_2to1_fold_the_1to1_exit_by_its_kind_and_G1():
    """d_graz, the largest d of 2:1 period-2, is the 2:1 branch's admissible fold; the 1:1 exit is where the 1:1
    motion followed down leaves its family (the sweep's located transitions), named by how it leaves, never the
    grazing of the unstable 1:1 period-2 orbit; G1 where a grazing ends the stable 2:1."""
    from vibroimpact.outputs.plots._common import located_marks

    d = np.round(np.arange(0.130, 0.221, 0.001), 6)
    bt = _branch("BT", d, d > 0.16, [("grazing", 0.1579, True), ("grazing", 0.1201, True), ("grazing", 0.19, False)])
    by_grazing = _branch("BBT", d, (d >= 0.1376) & (d <= 0.2), [("grazing", 0.13762, True), ("fold", 0.2003, True)])
    by_doubling = _branch("BBT", d, (d >= 0.158) & (d <= 0.2), [("B", 0.15807, True), ("grazing", 0.13601, True),
                                                                 ("fold", 0.2003, False)])

    def exit_(d, kind):
        return xr.Dataset({"exit_d": ((), d), "exit_kind": ((), kind)})

    assert located_marks([bt, by_grazing], exit_(0.2108, "grazing")) == [
        ("d_graz", 0.2003), ("1:1 exit: grazing", 0.2108), ("G1", 0.13762)]
    assert located_marks([bt, by_doubling], exit_(0.2353, "jump")) == [("1:1 exit: jump", 0.2353)]
    assert located_marks([bt, by_doubling]) == []  # no sweep transitions, no admissible fold: nothing to mark
    assert located_marks([bt], exit_(np.nan, "")) == []  # not located


#: every incline's length and force sweep of the workflow (config energy.design), as its default target finds them:
#: a 1:1 point above the exit (its value of the swept parameter and a bottom impact of its cycle: phase, Zdot-), the
#: down sweep's first 2:1 period-2 point (the same), and the band's most chaotic point (value, a state of its long
#: run); ``fixed``: the parameter held
SWEEPS = {
    "fig5_pi2_s": dict(beta=math.pi / 2, vary="s", fixed={"F": 5.0}, top=(0.437688, 0.13778, 0.694599),
                       two=(0.352462, 1.748024, 0.191456), chaos=(0.371106, 0.018511, 0.663218)),
    "fig0_s": dict(beta=math.pi / 3, vary="s", fixed={"F": 5.0}, top=(0.405729, 0.088631, 0.660218),
                   two=(0.352462, 1.772988, 0.179729), chaos=(0.357789, 2.066331, 0.137071)),
    "fig5_pi4_s": dict(beta=math.pi / 4, vary="s", fixed={"F": 5.0}, top=(0.371106, 0.007313, 0.613215),
                       two=(0.344472, 1.650319, 0.181614), chaos=(0.347136, 0.672356, 0.69612)),
    "fig5_pi6_s": dict(beta=math.pi / 6, vary="s", fixed={"F": 5.0}, top=(0.357789, 0.014208, 0.593109),
                       two=(0.331156, 1.569097, 0.172679), chaos=(0.333819, 6.266333, 0.55693)),
    "fig5_pi2_F": dict(beta=math.pi / 2, vary="F", fixed={"s": 0.85}, top=(12.512563, 0.036627, 0.552301),
                       two=(13.075377, 1.57173, 0.162729), chaos=(12.994975, 0.161862, 0.637062)),
    "fig0_F": dict(beta=math.pi / 3, vary="F", fixed={"s": 0.85}, top=(12.673367, 0.111895, 0.631744),
                   two=(13.155779, 1.586242, 0.157068), chaos=(13.075377, 6.260337, 0.535178)),
    "design_pi4_F": dict(beta=math.pi / 4, vary="F", fixed={"s": 0.85}, top=(12.914573, 0.068805, 0.614989),
                         two=(13.316583, 1.595395, 0.150688), chaos=(13.236181, 6.190775, 0.573273)),
    "fig5_pi6_F": dict(beta=math.pi / 6, vary="F", fixed={"s": 0.85}, top=(13.075377, 0.010141, 0.59229),
                       two=(13.477387, 1.623601, 0.14118), chaos=(13.396985, 6.207142, 0.54719)),
}


def _params(case, value):
    return vi.Params.from_physical(beta=case["beta"], **{case["vary"]: value}, **case["fixed"])


@pytest.mark.parametrize("name", list(SWEEPS))
def test_the_1to1_exit_is_not_where_2to1_begins(name):
    """The paper: "at d = d_graz" the 1:1 motion grazes, "there is a transition to 2:1 motion for d < d_graz", and
    d_graz is "the maximum value for 2:1 period-2 solutions".  At every incline, by length and by force, three
    methods that share no code: the 1:1 attractor followed down (family_exit) leaves its family away from the
    2:1 orbit's fold (Newton's method and continuation) by more than the sweep's step; between the exit and the
    d where the down sweep first meets the 2:1 period-2 the attractor is in neither family and chaotic (the largest
    Lyapunov exponent of the impact map, its 95 % interval above 0)."""
    case = SWEEPS[name]
    top, two, chaos = (_params(case, v) for v in (case["top"][0], case["two"][0], case["chaos"][0]))
    # the 2:1 period-2 orbit where the down sweep meets it, continued to its fold: d_graz
    orbit = vi.find_orbit(two, "BBT", phi=case["two"][1], v0=case["two"][2])
    br = vi.continue_orbit(orbit, vary=case["vary"], d_range=(two.d - 0.005, two.d + 0.03), step=1e-3)
    d_graz, source = branch_d_graz(br.assign_attrs(word="BBT"))
    assert source == "fold of the 2:1 branch"
    # the 1:1 motion followed down, at the sweep's spacing, from above its exit to the 2:1
    step = 1.7e-3 if case["vary"] == "s" else 1.25e-3
    n = int(np.ceil((top.d - two.d) / step)) + 1
    values = (np.linspace(case["top"][0], case["two"][0], n) if case["vary"] == "s"
              else case["fixed"]["s"] * 0.1245 * 25.0 / np.linspace(top.d, two.d, n))
    line = [_params(case, v) for v in values]
    ex = family_exit([p.d for p in line], [p.gbar for p in line], 0.5, case["top"][1], case["top"][2], xtol=1e-6)
    assert ex["status"] == "located"
    assert abs(ex["d"] - d_graz) > step, (ex["d"], d_graz)  # the 1:1 motion does not leave at d_graz
    # between the 2:1 and the exit: neither family, chaotic
    assert two.d < chaos.d < ex["d"]
    run = vi.simulate(chaos, phi=case["chaos"][1], v0=case["chaos"][2], n_impacts=6000).isel(impact=slice(1000, None))
    assert not in_family(run.wall.values, run.kind.values, 1) and not in_family(run.wall.values, run.kind.values, 2)
    lam = vi.lyapunov(chaos, phi=case["chaos"][1], v0=case["chaos"][2], n_impacts=20000)
    assert lam.interval[0][0] > 0, (name, lam.interval)


def test_a_sweep_s_exit_without_located_transitions_and_a_sweep_of_one_point():
    """The transitions of a sweep that located no label change hold the 1:1 exit alone (no transition dimension):
    the exit is read, the up sweep's end of 2:1 is NaN.  A sweep of one point has no step: the tolerance is NaN; one of
    two points has its grid step."""
    d = np.round(np.arange(0.2050, 0.2351, 0.0015), 4)
    down = np.where(d <= 0.2196, "2:1 period-2", "1:1 period-4").tolist()
    sw = synthetic_sweep(down, ["2:1 period-2"] * d.size, d)
    only_exit = _transitions(0.2200, "grazing").drop_dims("transition")
    r = sweep_d_graz(sw, only_exit, _branch("BBT", d, d < 0.2201, [("fold", 0.2201, True)]))
    assert r["exit_d"] == 0.2200 and math.isnan(r["up_end_d"]) and r["identity"] is True
    one = synthetic_sweep(["2:1 period-2"], ["2:1 period-2"], [0.21])
    r = sweep_d_graz(one, None, None)
    assert r["entry_d"] == 0.21 and math.isnan(r["entry_step"]) and math.isnan(r["tolerance"])
    # two points, 2:1 at both (no step into 2:1 to read): the tolerance is the sweep's grid step
    two = synthetic_sweep(["2:1 period-2"] * 2, ["2:1 period-2"] * 2, [0.21, 0.22])
    r = sweep_d_graz(two, None, None)
    assert math.isnan(r["entry_step"]) and r["tolerance"] == pytest.approx(0.01, rel=1e-12)
