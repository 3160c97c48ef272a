"""Fig BiS (g): the paper calls G2 a grazing point; the 3:1 orbit ends there at a fold, and the caption says so
with the number the continued branch gives."""

import math
import re

import pytest
from conftest import ROOT

import vibroimpact as vi
from vibroimpact.analysis.continuation import continue_orbit
from vibroimpact.analysis.orbits import find_orbit
from vibroimpact.outputs.plots.sweeps import fold_evidence


@pytest.fixture(scope="module")
def g2():
    """The 3:1 orbit of Fig BiS (f) (beta = pi/6, d = 0.14) continued in s through G2."""
    p = vi.Params.from_physical(s=0.14 / vi.Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    branch = continue_orbit(find_orbit(p, "BBBT", 5.88, 0.3967), vary="s", d_range=(0.125, 0.15), step=5e-4)
    return fold_evidence(branch, 0.1419)


def test_g2_is_a_fold_of_the_3_to_1_orbit_not_a_grazing_point(g2):
    """At G2 the largest multiplier crosses +1 where d turns back (a fold), and the slowest impact keeps a
    speed far from 0 (at a grazing point it would be 0)."""
    assert g2["d"] == pytest.approx(0.1419, abs=1e-4)
    assert g2["lam_before"] < 1 < g2["lam_after"] and g2["lam_after"] - g2["lam_before"] < 0.1
    assert g2["d_turns"]
    assert 0.025 < g2["v_min"] < 0.035


def test_the_caption_states_the_slowest_impact_speed_at_g2_from_the_branch(g2):
    caption = (ROOT / "workflow" / "report" / "figBiS.rst").read_text()
    stated = re.findall(r"slowest impact keeps a speed of (0\.\d+)", caption)
    assert stated == [f"{g2['v_min']:.3f}"]
    assert "fold" in caption and "G2" in caption


def test_the_caption_states_how_many_points_a_panel_draws_per_direction():
    from vibroimpact.outputs.plots.sweeps import BIS_POINTS

    caption = (ROOT / "workflow" / "report" / "figBiS.rst").read_text()
    assert re.findall(r"at most (\d+) per panel", caption) == [str(BIS_POINTS)]
