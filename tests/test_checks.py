"""The paper-value check: one tolerance rule for every published number."""

import math

import pandas as pd
import pytest

from vibroimpact.outputs import checks
from vibroimpact.outputs.paper import agreement_tolerance, printed_unit


@pytest.mark.parametrize("x, unit", [(0.22, 1e-2), (0.1378, 1e-4), (5.88, 1e-2), (0.4185, 1e-4), (61.0, 1.0), (0.205, 1e-3)])
def test_printed_unit(x, unit):
    assert printed_unit(x) == pytest.approx(unit)


def test_one_rule_half_a_unit_or_one_unit_for_range_ends():
    assert agreement_tolerance(0.1419) == pytest.approx(5e-5)
    assert agreement_tolerance(0.1419, range_end=True) == pytest.approx(1e-4)


@pytest.mark.parametrize("computed, status", [(0.158999, "pass"), (0.157001, "pass"), (0.1591, "fail"), (0.1569, "fail")])
def test_stable_interval_end_passes_within_one_unit_of_its_last_digit(computed, status):
    """beta = pi/3, paper: stable for 0.158 < d < 0.22 (range ends: one unit)."""
    t1 = pd.DataFrame([dict(beta=math.pi / 3, stable_from=computed, stable_to=0.22, lower_cause="B", upper_cause="fold",
                            d_B=computed)])
    (lower, upper) = checks.stability_rows(t1)
    assert lower["status"] == status and upper["status"] == "pass"
    assert lower["tolerance"] == pytest.approx(1e-3)


def test_every_row_the_check_can_produce_is_named_before_any_job():
    names = checks.item_names(["fig4_a"], [math.pi / 6, math.pi / 3])
    assert names.count("G1: 2:1 -> 3:1 grazing, d decreasing, beta=pi/6") == 1
    assert "2:1 stable interval, lower end, beta=pi/6" not in names  # that is G1, checked once
    # a caption orbit's rows name its printed figure and panel beside its config key
    assert {"Figure 7 (a) (fig4_a): motion", "Figure 7 (a) (fig4_a): Zdot(t0)", "Figure 7 (a) (fig4_a): phi"} <= set(names)
    assert "Figure 5: Zdot_k curves top to bottom, beta=pi/6" in names


def test_known_discrepancy_must_name_a_checked_item():
    df = pd.DataFrame([checks._row("a", "", 1.0, 2.0, 0.5, False)])
    with pytest.raises(ValueError, match="not checked"):
        checks.apply_known(df, {"b": "reason"})
    assert checks.apply_known(df, {"a": "reason"}).status.iloc[0] == "known discrepancy"


def _sims(status, max_dev):
    import numpy as np
    import xarray as xr

    n = len(status)
    return xr.Dataset({"status": ("sim", np.array(status)), "max_dev": ("sim", np.array(max_dev, float))},
                      coords={"d": ("sim", np.linspace(0.14, 0.2, n))}, attrs=dict(word="BBT", beta=math.pi / 6))


def test_simulated_points_row_names_every_point_not_compared():
    (row,) = checks.simulation_rows([_sims(["compared", "skipped: no analytic orbit", "compared"], [1e-14, math.nan, 2e-12])])
    assert row["status"] == "pass" and row["computed"].startswith("2 of 3 compared, max |difference| 2.0e-12")
    assert "d = 0.17: skipped: no analytic orbit" in row["note"]
    (row,) = checks.simulation_rows([_sims(["compared"], [2e-9])])
    assert row["status"] == "fail"  # beyond the identification tolerance
    (row,) = checks.simulation_rows([_sims(["not compared: the attractor is 3:1 period-2"], [math.nan])])
    assert row["status"] == "fail"  # nothing compared is no evidence


def test_another_device_with_nothing_to_compare_is_not_compared_and_a_real_failure_still_fails():
    """The rows that hold for any device fail for the paper's device where nothing was compared (no branch, no
    point simulated on it); another device may have none: its row is not compared and says why.  A comparison that
    was made and failed still fails, for any device."""
    import xarray as xr

    failed = xr.Dataset(attrs={"status": "failed", "reason": "the attractor at d=0.135 is 2:1 period-2 (BTB), not 'BBBT'"})
    rows = checks.simulation_rows([failed, _sims(["not compared: the attractor is 3:1 period-2"], [math.nan]),
                                   _sims(["compared"], [2e-9])])
    assert [r["status"] for r in rows] == ["fail"] * 3
    other = checks.for_another_device(pd.DataFrame(rows), "weak")
    assert list(other.status) == [checks.NOT_COMPARED, checks.NOT_COMPARED, "fail"]
    assert other.note[0] == ("this device (weak) has nothing to compare: nothing compared: no branch (the attractor at "
                             "d=0.135 is 2:1 period-2 (BTB), not 'BBBT')")
    assert other.note[1].startswith("this device (weak) has nothing to compare: nothing compared; not compared: d = 0.14")
    # no 1:1 period-2 attractor in any sweep: nothing to hold U_I = U_T on
    row = checks.energy_rows([], [], [], [])[0]
    assert row["item"] == "U_I = U_T for 1:1 period-2 motion" and row["status"] == "fail"
    assert checks.for_another_device(pd.DataFrame([row]), "weak").status[0] == checks.NOT_COMPARED


def test_energy_at_the_same_d_compares_the_two_coexisting_motions():
    import numpy as np
    import xarray as xr

    lab = np.array([["3:1 period-2", "3:1 period-2", "2:1 period-2"], ["2:1 period-2", "3:1 period-2", "3:1 period-2"]])
    u_t = np.array([[1.2, 1.0, 2.0], [1.0, 1.0, 1.0]])
    e = xr.Dataset({"label": (("direction", "point"), lab), "U_T": (("direction", "point"), u_t),
                    "U_I": (("direction", "point"), u_t)}, coords={"direction": ["up", "down"], "d": ("point", [0.1, 0.2, 0.3])})
    from vibroimpact.analysis.motions import Motion

    three, two = Motion(period=1, bottom=3, top=1), Motion(period=1, bottom=2, top=1)
    row = next(r for r in checks.energy_rows([], [], [e], [[two, three, three]])
               if r["item"] == "2:1 -> 3:1 at the same d: U_T rises")
    assert row["computed"].startswith("3:1 above 2:1 at 1 of 2 bistable sweep points (U_T ratio 3:1 / 2:1 in [0.5000, 1.2000])")
    assert row["status"] == "fail"


def test_zdot_order_of_the_2to1_orbit_is_its_voltage_order():
    """Evidence for the known discrepancy of the Zdot_k order (captions of Figures 2 (a) and 5: P3, P1, P2).
    The 2:1 orbit at beta = pi/3, d = 0.19 (solved by Newton from the paper's Figure 4 (b) start), has
    |Zdot| after P3 > after P2 > after P1, and the voltage rises with the impact speed on both walls
    (one membrane model): so the Zdot_k order is the U_k order, which the captions of Figure 2 (b) and
    Figure 9 give as P3, P2, P1."""
    import numpy as np

    from vibroimpact.analysis.energy import Membrane, speed_si, voltage_gain
    from vibroimpact.analysis.orbits import find_orbit
    from vibroimpact.dynamics.params import Params

    p = Params.from_physical(s=0.19 * 5.0 * math.pi**2 / (0.1245 * (5 * math.pi) ** 2), beta=math.pi / 3)
    assert p.d == pytest.approx(0.19, rel=1e-12)
    orbit = find_orbit(p, "BBT", 1.21, 0.2164)
    names = [checks.transition_name(orbit.walls, j) for j in range(3)]
    assert names == ["P3", "P1", "P2"]  # impacts B, B, T: into B from T, into B from B, into T from B
    speeds = np.abs(orbit.v_minus)
    assert [names[j] for j in np.argsort(-speeds)] == ["P3", "P2", "P1"]
    gains = voltage_gain(speed_si(speeds, 5.0, 0.1245, 5 * math.pi), Membrane(h=2.6, K=4.0847e5, R=6.3e-3, r_b=5e-3,
                                                                                U_in=2000.0, m=4.11e-3))
    assert [names[j] for j in np.argsort(-gains)] == ["P3", "P2", "P1"]
    assert np.all(np.diff(voltage_gain(np.linspace(0.05, 3.0, 50), Membrane(h=2.6, K=4.0847e5, R=6.3e-3, r_b=5e-3,
                                                                            U_in=2000.0, m=4.11e-3))) > 0)


@pytest.mark.parametrize("walls, into, names", [
    ((1, 1, -1), True, ["P3", "P1", "P2"]),
    ((1, 1, -1), False, ["P1", "P2", "P3"]),
    ((1, -1), True, ["P3", "P2"]),
    ((-1, -1, 1), True, ["P2", "P4", "P3"]),
])
def test_transition_names_follow_the_paper(walls, into, names):
    """P1 bottom -> bottom, P2 bottom -> top, P3 top -> bottom, P4 top -> top (paper section 3)."""
    assert [checks.transition_name(walls, j, into=into) for j in range(len(walls))] == names


def test_check_summaries_per_figure():
    """Each figure's caption sentence counts its own rows: data arrays (timings apart), the image row,
    and the published values shown in it (captions by prefix, sections by figure)."""
    figures = pd.DataFrame({"figure": ["fig2", "fig2", "fig2", "work_precision", "work_precision"],
                            "variable": ["a0_line0_x", "a0_line0_y", checks.IMAGE_ROW, "a0_line0_x", checks.IMAGE_ROW],
                            "max_difference": [0.0, 1e-15, 0.0, float("nan"), 12.0],
                            "status": ["pass", "fail", "pass", "excluded", "excluded"]})
    paper = pd.DataFrame({"item": ["Figure 7 (a) (fig4_a): motion", "simulated points on the BBT, beta=pi/2 branch", "x"],
                          "where": ["Figure 7 caption", "Figure 5", "section 3"],
                          "status": ["pass", "pass", "known discrepancy"]})
    s = checks.check_summaries(paper, figures)
    assert "1 of 2 arrays pass, 1 FAIL" in s["fig2"] and "image: pass (perceptual hash distance 0 bits)" in s["fig2"]
    assert "1 known discrepancy, 1 pass" in s["fig2"]
    assert "0 of 0 arrays pass (1 timing arrays excluded)" in s["work_precision"]
    assert s["fig4"].endswith("published values shown here: 1 pass.")
    assert "1 known discrepancy" in s["fig3"]


def test_the_model_document_states_the_papers_values_the_code_compares_with():
    """docs/guide/model.md carries the paper's reference values itself: every stable interval, G1, G2 and d_B
    of vibroimpact.outputs.paper and every caption orbit of the config the document lists appear in it as
    printed; and nothing in the repository's documents points outside it."""
    import re

    import yaml
    from conftest import ROOT

    from vibroimpact.outputs import paper

    doc = (ROOT / "docs" / "guide" / "model.md").read_text()
    for lo, hi in paper.STABLE_2TO1.values():
        assert f"{lo:g} < d < {hi:g}" in doc
    for x in (paper.PI6_G1, paper.PI6_G2, paper.PI6_D_B):
        assert f"{x:g}" in doc
    caps = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["captions"]
    for name in ("fig0b_a", "fig0b_b", "fig0b_c", "fig4_a", "fig4_d", "fig4_g", "figBiS_e", "figBiS_f"):
        for key in ("d", "v0", "phi"):
            assert f"{caps[name][key]:g}" in doc, (name, key)
    for f in [ROOT / "README.md", ROOT / "config" / "config.yaml", *(ROOT / "docs").rglob("*.md"),
              *(ROOT / "src").rglob("*.py"), *(ROOT / "workflow").rglob("*.smk")]:
        text = f.read_text()
        assert "MODEL.md" not in text and "shared/" not in text, f
        assert not re.search(r"\b[Ii]ssue #?\d+", text), f


def test_config_readme_names_every_key_of_the_config():
    """config/README.md describes every top-level key of config/config.yaml and every key one level
    down (a key added to the config without a word there fails)."""
    import yaml
    from conftest import ROOT

    doc = (ROOT / "config" / "README.md").read_text()
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    missing = [k for k in cfg if f"`{k}`" not in doc]
    for k, v in cfg.items():
        if isinstance(v, dict) and k not in ("captions", "scenes", "basins", "maps", "branch_scenes"):
            missing += [f"{k}.{sub}" for sub in v if f"`{sub}`" not in doc and k not in ("checks",)]
    assert not missing, missing


def _reading(beta, exit_d, fold, *, vary="s", kind="grazing", entry=None, step=1.7e-3, band=(0, 0), sweep=None):
    """A row of the d_graz table (vibroimpact.sweep_d_graz's fields) with the given exit, fold and entry into 2:1."""
    entry = fold - 1e-3 if entry is None else entry
    identity = kind == "grazing" and abs(exit_d - entry) <= step and abs(exit_d - fold) <= step
    return {"sweep": sweep or f"s_{beta:.3f}_{vary}", "beta": beta, "vary": vary, "d_graz": fold, "entry_d": entry,
            "entry_step": step, "up_end_d": fold, "exit_d": exit_d, "exit_kind": kind,
            "exit_clearance": 1e-8 if kind == "grazing" else 0.01, "band_width": exit_d - entry,
            "band_points": band[0], "band_chaotic": band[1], "band_motions": f"{band[1]} chaotic" if band[0] else "",
            "band_lyap1_max": 0.3 if band[0] else float("nan"), "tolerance": step, "identity": identity}


def _bt(beta, b_values):
    import numpy as np
    import xarray as xr

    n = len(b_values)
    return xr.Dataset({"critical_kind": ("critical", np.array(["B"] * n)), "critical_d": ("critical", np.array(b_values)),
                       "critical_admissible": ("critical", np.ones(n, bool))}, attrs={"beta": beta})


BETAS4 = [math.pi / 6, math.pi / 4, math.pi / 3, math.pi / 2]


@pytest.mark.parametrize("exits, folds, bs, status", [
    ([0.2108, 0.2255, 0.2353, 0.2659], [0.2158, 0.2188, 0.2201, 0.2205], [0.251, 0.288, 0.324, 0.361],
     ["fail", "pass", "pass", "pass"]),
    ([0.2108, 0.2255, 0.2200, 0.2659], [0.2130, 0.2188, 0.2180, 0.2205], [0.251, 0.288, 0.240, 0.361],
     ["pass", "fail", "fail", "fail"]),
])
def test_d_graz_rows_hold_the_paper_s_statements(exits, folds, bs, status):
    """Figure 3 (f): d_graz = 0.213 at pi/6 (half a unit: 0.0005), d_graz the largest d of 2:1 period-2 (the 2:1
    fold); section 5: d_graz, the 1:1 exit and the 1:1 period doubling rise with beta.  The first set is what the
    workflow computes, the second breaks each claim."""
    readings = pd.DataFrame([_reading(b, e, f) for b, e, f in zip(BETAS4, exits, folds, strict=True)])
    rows = checks.d_graz_rows(readings, [_bt(b, [0.1, d]) for b, d in zip(BETAS4, bs, strict=True)])
    assert [r["item"] for r in rows[:4]] == checks.D_GRAZ_ITEMS
    assert [r["status"] for r in rows[:4]] == status
    assert rows[0]["tolerance"] == pytest.approx(5e-4) and rows[0]["computed"] == folds[0]
    scenes = {r.sweep: {"beta": r.beta, "vary": r.vary} for r in readings.itertuples()}
    assert set(checks.D_GRAZ_ITEMS) <= set(checks.item_names([], BETAS4, scenes))
    assert {r["item"] for r in rows[4:]} <= set(checks.item_names([], BETAS4, scenes))


@pytest.mark.parametrize("exit_d, kind, entry, band, status", [
    (0.2108, "grazing", 0.2100, (0, 0), "pass"),      # the identity: the 1:1 motion grazes where 2:1 begins
    (0.2108, "jump", 0.2100, (0, 0), "fail"),         # at the right d, but no grazing
    (0.2353, "jump", 0.2194, (9, 8), "fail"),         # pi/3 by length: a chaotic band of 0.016
    (0.2108, "grazing", 0.2061, (2, 2), "fail"),      # pi/6 by length: grazing, but chaos before the 2:1
])
def test_the_identity_row_of_each_sweep_is_its_evidence(exit_d, kind, entry, band, status):
    """A row per sweep on "the 1:1 motion grazes where 2:1 begins": it passes where the exit is a grazing within
    the sweep step (the tolerance) of both the down sweep's entry into 2:1 and d_graz; its computed column gives
    the exit, the entry, d_graz and the band between, with its motions."""
    r = _reading(math.pi / 3, exit_d, 0.2105, kind=kind, entry=entry, band=band, vary="F", sweep="fig0_F")
    (row,) = checks.d_graz_rows(pd.DataFrame([r]), [], {"fig0_F": {"beta": math.pi / 3, "vary": "F"}})[3:]
    assert row["item"] == "d_graz: the 1:1 motion grazes where 2:1 begins, beta=pi/3, force sweep (fig0_F)"
    assert row["status"] == status and row["tolerance"] == pytest.approx(1.7e-3)
    assert f"1:1 exit: {kind} at {exit_d:.6f}" in row["computed"] and f"enters 2:1 at {entry:.4f}" in row["computed"]
    assert ("band" in row["computed"]) and (f"{band[0]} points of the down sweep ({band[1]} chaotic)" in row["computed"]
                                            if band[0] else "no sweep point between" in row["computed"])


def test_for_another_device_only_what_holds_for_any_device_is_compared():
    """The paper's numbers are its device's: for another device they are not compared (their computed values
    kept), while the identities and the simulator against the Newton-solved orbits still are."""
    df = pd.DataFrame([checks._row("Figure 3 (a) (figFN2_a): phi", "Figure 3 caption", 6.211, 6.3, 5e-4, False),
                       checks._row("U_I = U_T for 1:1 period-2 motion", "section 5", "equal", "1e-12", 1e-9, True),
                       checks._row("simulated points on the BBT, beta=pi/3 branch", "Figure 5", "on the branch", "x",
                                   1e-9, False),
                       checks._row("G1: 2:1 -> 3:1 grazing, d decreasing, beta=pi/6", "section 4.2", 0.1378, 0.15,
                                   1e-4, True)])
    out = checks.for_another_device(df, "heavier")
    assert list(out.status) == [checks.NOT_COMPARED, "pass", "fail", checks.NOT_COMPARED]
    assert out.computed.iloc[0] == 6.3 and "not the paper's device (heavier)" in out.note.iloc[0]
    text = checks.markdown(out, "heavier")
    assert text.startswith("Device heavier, not the paper's: the 2 rows that hold for any device were compared")
    assert "the other 2 compare numbers the paper published" in text
    figs = checks.not_compared_figures(["fig0", "fig2"], "heavier")
    assert list(figs.status) == [checks.NOT_COMPARED] * 2 and "heavier" in figs.detail.iloc[0]


def test_inclines_without_a_2to1_branch_are_rows_that_do_not_pass():
    """Another device may have no 2:1 branch at any incline (Table 1 of failed rows only): the check's rows are
    written, each computed value NaN and failing (not compared for another device), instead of stopping the job."""
    import xarray as xr

    from vibroimpact.outputs.tables import table1

    failed = [xr.Dataset(attrs={"beta": b, "status": "failed", "reason": "the attractor is 1:1 period-2"}) for b in BETAS4]
    t1 = table1(failed)
    rows = checks.stability_rows(t1) + checks.d_graz_rows(pd.DataFrame(), failed)
    assert [r["item"] for r in rows[-3:]] == checks.D_GRAZ_ITEMS[1:] and len(rows) == 8 + 3
    assert {r["status"] for r in rows} == {"fail"}
    assert all(math.isnan(r["computed"]) for r in rows if isinstance(r["computed"], float))
    assert checks.for_another_device(pd.DataFrame(rows), "weak")["status"].eq(checks.NOT_COMPARED).all()
