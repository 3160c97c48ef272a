"""One physical motion, one name: a chattering sequence that ends in sticking counts as one impact, so the
label of a sticking motion does not depend on how many of its bounces the simulator resolves."""

import math

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.analysis.motions import chatter_bounces, cycle_class
from vibroimpact.dynamics import kernels as K

IM, G, S, R = K.IMPACT, K.GRAZING, K.STICK, K.RELEASE


def test_the_bottom_stick_release_cycle_has_one_name_across_beta():
    """s = 0.72 m, F = 5 N, from rest on the bottom (the design maps' starts): released by the forcing, the
    ball flies without reaching the top, lands on the bottom, chatters to rest and sticks until the next
    release, once every two forcing periods.  The simulator resolves 31 bounces at beta = 1.0464 and pi/3
    and 30 at beta = 1.0988 before it sums the rest (design map rows labelled "31:0 over 2 forcing periods"
    and "15:0 period-4" by the resolved counts)."""
    atts = [vi.identify_attractor(vi.simulate(vi.Params.from_physical(s=0.72, beta=b), 0.65, 0.0, n_impacts=3000))
            for b in (1.0464, math.pi / 3, 1.0988)]
    assert [a.n_bottom for a in atts] == [31, 31, 30]  # resolved impacts: they differ
    for a in atts:
        kinds = a.cycle.kind.values
        assert a.period == 2 and a.n_top == 0
        assert (kinds == S).sum() == 1 and (kinds == R).sum() == 1
        assert (a.cycle.wall.values[kinds == S] == 1).all()  # it sticks on the bottom
    assert {a.label for a in atts} == {"1:0 over 2 forcing periods with sticking"}


def test_a_top_then_bottom_sticking_cycle_keeps_its_top_impacts_and_one_bottom_landing():
    """(s, F) plane at beta = pi/6: released from the bottom, the ball hits the top four times (a run the
    kernel follows bounce by bounce: the ball leaves the top, no sticking there), lands on the bottom,
    chatters to rest and sticks, every forcing period.  35 and 36 bottom bounces are resolved at F = 17.13 N
    and 18.10 N: one name."""
    atts = [vi.identify_attractor(vi.simulate(vi.Params.from_physical(s=0.19, beta=math.pi / 6, F=F), 0.42, 0.87,
                                              n_impacts=20_000)) for F in (17.13, 18.10)]
    assert [(a.n_bottom, a.n_top) for a in atts] == [(35, 4), (36, 4)]
    assert {a.label for a in atts} == {"1:4 period-2 with sticking"}


@pytest.mark.parametrize("wall, kind, bounces", [
    # release, a landing, three bounces and a grazing contact, stick: the landing counts
    ([1, 1, 1, 1, 1, 1, 1], [R, IM, IM, IM, IM, G, S], [0, 0, 1, 1, 1, 1, 0]),
    # the cycle starts inside the run (it repeats end to start): the landing is the last event
    ([1, 1, 1, 1, 1], [IM, IM, S, R, IM], [1, 1, 0, 0, 0]),
    # two bottom impacts in a row with no sticking (2:1): both count
    ([1, 1, -1], [IM, IM, IM], [0, 0, 0]),
    # a run on the top, then a landing on the bottom that chatters and sticks: the top run counts
    ([1, -1, -1, 1, 1, 1], [R, IM, IM, IM, IM, S], [0, 0, 0, 0, 1, 0]),
])
def test_chatter_bounces_are_the_impacts_after_the_landing_of_a_run_that_sticks(wall, kind, bounces):
    assert chatter_bounces(np.array(wall), np.array(kind)).astype(int).tolist() == bounces


def test_labels_of_motions_without_sticking_keep_every_impact():
    assert cycle_class(np.array([1, 1, -1]), np.array([IM, IM, IM]), 2.0).label == "2:1 period-2"
    assert cycle_class(np.array([1, -1, 1, 1, -1]), np.array([IM, IM, IM, G, IM]), 4.0).label == "3:2 over 2 forcing periods"


def test_a_run_with_no_period_is_an_attractor_with_nothing_counted():
    """identify_attractor of a chaotic run (beta = pi/3, d = 0.235): not periodic, with no period, events,
    impacts or sticking counted, and the label saying so."""
    g = 0.1245 * 9.8 * math.sin(math.pi / 3) / 5.0
    a = vi.identify_attractor(vi.simulate(vi.Params(d=0.235, gbar=g, r=0.5), phi=0.42, v0=0.87, n_impacts=400))
    assert (a.periodic, a.period, a.events, a.n_bottom, a.n_top, a.sticking, a.label) == (
        False, 0, 0, 0, 0, False, "not periodic")
    assert a.cycle is None and not a.motion.periodic and math.isnan(a.t_settled)


def test_a_window_dataset_records_which_motions_stick_beside_their_labels():
    """attractor_batch (the windows of sweeps, maps and basins) carries each run's ``sticking`` flag from its
    motion: the bottom stick-release cycle sticks; the 2:1 motion between G1 and G2 does not."""
    p = vi.Params.from_physical(s=0.72, beta=math.pi / 3)
    ab = vi.attractor_batch([p.d, 0.13975], [p.gbar, 0.12201], 0.5, phi=[0.65, 5.855], v0=[0.0, 0.4185],
                            max_periods=1500, max_events=400_000)
    assert ab.label.values.tolist() == ["1:0 over 2 forcing periods with sticking", "2:1 period-2"]
    assert ab.sticking.values.tolist() == [True, False]


def test_a_ball_bouncing_once_per_forcing_period_is_a_motion_of_one_event():
    """d = 10 (the top out of reach), gbar = 0.8, r = 0.5: the bouncing ball's period-one orbit, one bottom
    impact per forcing period, is found from a start near it as a motion of one event per period, its
    pre-impact speed 2 gbar / (1 + r) (over a flight of 2 time units gravity turns the rebound r v into v).
    The cycle is identified to the periodicity tolerance 1e-9; its multipliers have modulus 0.5, so it lies
    within 1e-9 / (1 - 0.5) of the orbit."""
    a = vi.identify_attractor(vi.simulate(vi.Params(d=10.0, gbar=0.8, r=0.5), 2.5, 1.3, n_impacts=400))
    assert (a.label, a.events, a.period) == ("1:0 period-2", 1, 1)
    assert a.cycle.v_minus.values[0] == pytest.approx(2 * 0.8 / 1.5, abs=2e-9)


def test_the_paper_s_motions_and_an_orbit_s_word_are_named_as_the_paper_names_them():
    """The paper's names: 1:1, 2:1 and 3:1 impacts per forcing period, each of period 2 in t (one forcing period);
    an orbit's word counts its bottom (B) and top (T) impacts over one forcing period unless told more; prose
    names are found where they are written; a motion with no period named without its count of stickings is named
    by its exponent's interval alone."""
    from vibroimpact.analysis.motion_names import (
        ONE_ONE,
        THREE_ONE,
        TWO_ONE,
        no_period_label,
        orbit_motion,
        periodic_names_in,
    )

    assert [m.label for m in (ONE_ONE, TWO_ONE, THREE_ONE)] == ["1:1 period-2", "2:1 period-2", "3:1 period-2"]
    assert orbit_motion("BBT") == TWO_ONE and orbit_motion("BT", k=2).label == "1:1 over 2 forcing periods"
    assert periodic_names_in("from 2:1 period-2 to 3:1 T=2 and 1:0 over 2 forcing periods with sticking") == [
        "2:1 period-2", "3:1 T=2", "1:0 over 2 forcing periods with sticking"]
    assert no_period_label("aperiodic", 0.01, 0.3) == "chaotic"
