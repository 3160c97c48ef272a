"""Energy output: the membrane model and the paper's claims about energy (section 5)."""

import math

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.continuation import branch_from_simulation
from vibroimpact.energy import Membrane, branch_energy, orbit_energy, speed_si, sweep_energy, voltage_gain
from vibroimpact.orbits import find_orbit
from vibroimpact.sweeps import sweep

PAPER = dict(h=2.6, K=4.0847e5, R=6.3e-3, r_b=5.0e-3, U_in=2000.0, m=4.11e-3)
#: membrane constants the claims must survive (MODEL.md section 4: "whatever the membrane constants")
VARIANTS = [PAPER, dict(PAPER, m=1e-3), dict(PAPER, K=4.0847e4, h=2.0), dict(PAPER, R=8e-3, r_b=4e-3, m=2e-2)]
M, OMEGA = 0.1245, 5 * math.pi
K_S = M * OMEGA**2 / (5 * math.pi**2)


def test_membrane_gain_is_zero_at_rest_and_grows_with_speed():
    mb = Membrane(**PAPER)
    v = np.linspace(0, 20, 400)
    gain = voltage_gain(v, mb)
    assert gain[0] == pytest.approx(0.0, abs=1e-9)
    assert np.all(np.diff(gain) > 0)
    assert np.all(voltage_gain(-v, mb) == gain)  # the speed's sign does not matter


def test_membrane_geometry_has_a_solution_at_every_speed():
    """With R > r_b (enforced) the stretched cap always exists: cos(alpha) -> (R - r_b)/delta > 0 as
    the deflection grows, so no finite speed is outside the model; a non-finite speed gives NaN."""
    mb = Membrane(**dict(PAPER, R=5.01e-3, K=10.0))
    gain = voltage_gain(np.logspace(-6, 4, 500), mb)
    assert np.all(np.isfinite(gain)) and np.all(np.diff(gain) > 0)
    assert np.isnan(voltage_gain([np.nan], mb)[0])


@pytest.mark.parametrize("name, value", [("m", 0.0), ("K", -1.0), ("h", float("nan"))])
def test_membrane_rejects_bad_constants(name, value):
    with pytest.raises(ValueError, match=f"membrane {name} = "):
        Membrane(**dict(PAPER, **{name: value}))
    with pytest.raises(ValueError, match="must exceed the ball radius"):
        Membrane(**dict(PAPER, R=4e-3))


def test_speed_conversion_to_si():
    # ||F|| pi / (M omega) = 5 pi / (0.1245 * 5 pi) m/s per unit of Zdot
    assert speed_si(-0.5, 5.0, M, OMEGA) == pytest.approx(0.5 / 0.1245)


def test_1to1_period2_averages_per_impact_and_per_time_are_equal():
    """Paper: U_I = U_T for 1:1 period-2 motion (two impacts per two time units)."""
    p = vi.Params.from_physical(s=0.38 / K_S, beta=math.pi / 3)
    o = find_orbit(p, "BT", 0.4217, 0.8673)
    for consts in VARIANTS:
        e = orbit_energy(o, Membrane(**consts), F=5.0, M=M, omega=OMEGA)
        assert e["U_I"] == pytest.approx(e["U_T"], rel=1e-14)


@pytest.fixture(scope="module")
def pi3_sweep():
    return sweep("s", np.linspace(0.19, 0.72, 120), beta=math.pi / 3, phi=0.42, v0=0.87)


def _is_n_to_n(label):
    head = str(label).split(" ")[0]
    return "period-" in str(label) and head.split(":")[0] == head.split(":")[1]


@pytest.mark.parametrize("consts", VARIANTS)
def test_1to1_to_2to1_drops_U_I_and_raises_U_T(pi3_sweep, consts):
    """Paper: across the transition from the 1:1 family to 2:1 (an extra low-velocity impact), the
    average per impact drops and the average per unit time rises."""
    e = sweep_energy(pi3_sweep, Membrane(**consts), M=M, omega=OMEGA).sel(direction="down")
    lab, d = e.label.values, e.d.values
    top21 = max(np.flatnonzero(lab == "2:1 period-2"), key=lambda i: d[i])
    first11 = min((i for i in range(len(d)) if d[i] > d[top21] and _is_n_to_n(lab[i])), key=lambda i: d[i])
    assert e.U_I.values[top21] < e.U_I.values[first11]
    assert e.U_T.values[top21] > e.U_T.values[first11]


@pytest.fixture(scope="module")
def pi6_g1_orbits():
    """The 2:1 orbit just above G1 and the 3:1 attractor it jumps to just below (beta = pi/6)."""
    g1 = 0.1376002140
    gbar = M * 9.8 * math.sin(math.pi / 6) / 5.0
    o2 = find_orbit(vi.Params(d=g1 + 2e-5, gbar=gbar, r=0.5), "BBT", 5.855, 0.4185)
    q = vi.Params(d=g1 - 2e-5, gbar=gbar, r=0.5)
    att = vi.identify_attractor(vi.simulate(q, o2.phi, o2.v_minus[0], n_impacts=100_000, stop_when_periodic=True))
    b = att.cycle.where(att.cycle.wall == 1, drop=True)
    return o2, find_orbit(q, "BBBT", float(b.phase[0]), float(b.v_minus[0]))


@pytest.mark.parametrize("consts", VARIANTS)
def test_2to1_to_3to1_drops_U_I(pi6_g1_orbits, consts):
    o2, o3 = pi6_g1_orbits
    mb = Membrane(**consts)
    e2, e3 = (orbit_energy(o, mb, F=5.0, M=M, omega=OMEGA) for o in (o2, o3))
    assert e3["U_I"] < 0.8 * e2["U_I"]


def test_2to1_to_3to1_changes_U_T_by_under_one_percent_either_way(pi6_g1_orbits):
    """Finding, against the paper's "U_T rises" at the 2:1 -> 3:1 grazing transition: the added
    impact is slow (|Zdot| ~ 0.05) and the other impacts slow down, so U_T changes by a few percent
    at most (0.7 % with the configured constants), and whether it rises or falls depends on the
    membrane constants."""
    o2, o3 = pi6_g1_orbits
    signs = set()
    for consts in VARIANTS + [dict(PAPER, K=4.0847e3), dict(PAPER, m=5e-2)]:
        mb = Membrane(**consts)
        e2, e3 = (orbit_energy(o, mb, F=5.0, M=M, omega=OMEGA) for o in (o2, o3))
        assert abs(e3["U_T"] / e2["U_T"] - 1) < 0.03
        signs.add(e3["U_T"] > e2["U_T"])
    mb = Membrane(**PAPER)
    e2, e3 = (orbit_energy(o, mb, F=5.0, M=M, omega=OMEGA) for o in (o2, o3))
    assert -0.01 < e3["U_T"] / e2["U_T"] - 1 < 0
    assert signs == {True, False}


@pytest.fixture(scope="module")
def one_to_one_branches():
    out = {}
    for beta in (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6):
        p = vi.Params.from_physical(s=0.40 / K_S, beta=beta)
        out[beta] = branch_from_simulation(p, "BT", vary="s", d_range=(0.2, 0.46), step=2e-3, phi=0.42, v0=0.87)
    return out


def test_output_grows_with_length_at_fixed_force(one_to_one_branches):
    for br in one_to_one_branches.values():
        e = branch_energy(br, Membrane(**PAPER), M=M, omega=OMEGA)
        m = (e.stable & e.admissible).values
        order = np.argsort(e.s.values[m])
        assert np.all(np.diff(e.U_T.values[m][order]) > 0)


def test_output_grows_with_force_at_fixed_length():
    p = vi.Params.from_physical(s=0.85, beta=math.pi / 6, F=7.0)
    br = branch_from_simulation(p, "BT", vary="F", d_range=(K_S * 5 * 0.85 / 22, K_S * 5 * 0.85 / 6), step=2e-3,
                                phi=0.42, v0=0.87)
    e = branch_energy(br, Membrane(**PAPER), M=M, omega=OMEGA)
    m = (e.stable & e.admissible).values
    order = np.argsort(e.F.values[m])
    assert m.sum() > 50 and np.all(np.diff(e.U_T.values[m][order]) > 0)


def test_maximum_1to1_output_changes_less_than_one_percent_with_incline(one_to_one_branches):
    """Paper: the maximum 1:1 output over the Fig 5 range (0.19 < s < 0.72) varies by less than 1 %
    with beta."""
    maxima = []
    for br in one_to_one_branches.values():
        e = branch_energy(br, Membrane(**PAPER), M=M, omega=OMEGA)
        m = (e.stable & e.admissible & (e.s <= 0.72)).values
        maxima.append(float(e.U_T.values[m].max()))
    assert (max(maxima) - min(maxima)) / np.mean(maxima) < 0.01
