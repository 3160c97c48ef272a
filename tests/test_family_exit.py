"""Where a followed attractor leaves its impact family: the 1:1 exit and G1 (2:1)."""

import math

import numpy as np
import pytest
from conftest import CAPTIONS, gbar_of

import vibroimpact as vi
from vibroimpact.analysis.continuation import continue_orbit
from vibroimpact.analysis.family_exit import GRAZING_CLEARANCE, _clearance, family_exit, in_family
from vibroimpact.analysis.orbits import find_orbit
from vibroimpact.dynamics import kernels as K

B, T = 1, -1


@pytest.mark.parametrize("walls, n, expected", [
    ([B, T, B, T, B, T], 1, True),
    ([T, B, T, B], 1, True),
    ([B, B, T, B, B, T, B], 2, True),
    ([B, T, B, B, T], 2, True),            # the ends may cut a group short
    ([B, T, B, B, T, B, T], 1, False),     # an extra bottom impact: out of the 1:1 family
    ([B, B, T, B, B, T], 1, False),
    ([B, B, T, B, T, B, B, T], 2, False),  # a group of one bottom impact between tops
    ([B, T, T, B], 1, False),              # two top impacts in a row
    ([B, B, B], 1, False),                 # no top impact
    ([B, B, B, T, B], 2, False),           # three bottom impacts before the first top
])
def test_family_membership(walls, n, expected):
    assert in_family(walls, np.zeros(len(walls), np.int8), n) is expected


def test_a_grazing_contact_or_a_stick_is_out_of_the_family():
    walls = [B, T, B, T]
    for kind in (K.GRAZING, K.STICK):
        kinds = np.zeros(4, np.int8)
        kinds[2] = kind
        assert not in_family(walls, kinds, 1)


def _line(beta, d_hi, d_lo, n=6):
    """A line of d at fixed force and incline (gbar constant), from d_hi down to d_lo."""
    return np.linspace(d_hi, d_lo, n), gbar_of(beta)


def test_2to1_family_exit_is_the_analytic_grazing_G1():
    """Two independent methods: the 2:1 attractor followed down leaves its family where the Newton-solved
    2:1 orbit's flight touches the bottom wall (its continuation's grazing point, located to 1e-10).  The
    followed attractor is bracketed to xtol, and each run starts from an attractor up to the re-check
    distance away in d (max(1e-3 grid steps, 4 xtol)); near a grazing the basin is as thin as the
    clearance, so the exit is known to that distance: the orbit's grazing lies within it of the bracket.
    The line is Fig BiS's sweep grid (d step 4e-5)."""
    beta, xtol = math.pi / 6, 1e-8
    p = vi.Params(d=0.14, gbar=gbar_of(beta), r=0.5)
    br = continue_orbit(find_orbit(p, "BBT", 5.855, 0.4185), vary="d", d_range=(0.136, 0.142), step=5e-4)
    (g1,) = br.critical_d.values[(br.critical_kind.values == "grazing") & (br.critical_d.values > 0.137)]
    d, g = _line(beta, 0.1440, 0.1370, 176)
    ex = family_exit(d, g, 0.5, 5.855, 0.4185, n=2, xtol=xtol)
    assert ex["status"] == "located"
    assert ex["kind"] == "grazing"
    assert ex["after"] == "3:1 period-2"
    assert not ex["sampled"]  # the last 2:1 motion is periodic: its clearance is its cycle's
    assert abs(ex["d"] - g1) <= 0.5 * ex["d_width"] + max(1e-3 * (d[0] - d[1]), 4 * xtol)
    assert xtol / 100 < ex["d_width"] <= xtol  # refined to xtol, and no further
    assert ex["clearance"] < 1e-6  # the orbit's loop nearly touches the wall at the bracket's upper end


def test_pi6_1to1_motion_grazes_at_the_exit_and_the_fn2f_orbit_is_near_grazing():
    """Paper Fig FN2 (f): "grazing behaviour of 1:1 period-10 motion, d = 0.213" (beta = pi/6).  The 1:1
    attractor followed down grazes at its exit from the 1:1 family: its clearance falls linearly to 0 as d
    approaches the exit (a grazing, not a jump), the impacts born there are slow, and at the caption's d = 0.213 the caption's 1:1 period-10
    motion still clears the wall by 1.6 % of d: the paper's d is the near-grazing motion it shows."""
    beta = math.pi / 6
    g = gbar_of(beta)
    d, _ = _line(beta, 0.222, 0.205, 10)
    ex = family_exit(d, g, 0.5, 0.242, 0.676, xtol=1e-7)  # from Fig FN2 (e)'s 1:1 period-8 motion
    assert ex["status"] == "located" and ex["kind"] == "grazing"
    assert 0.2105 < ex["d"] < 0.2111
    assert ex["slowest_after"] < 1e-2
    clear = []
    for above in (2e-3, 1e-3):
        x = ex["d"] + above
        run = vi.simulate(vi.Params(d=x, gbar=g, r=0.5), phi=0.321, v0=0.674, n_impacts=5000)
        tail = run.isel(impact=slice(1000, None))
        assert in_family(tail.wall.values, tail.kind.values, 1)
        clear.append(_clearance(tail, x, g, 0.5))
    # linear in the distance to the exit: halving the distance halves the clearance (to 20 %)
    assert clear[1] / clear[0] == pytest.approx(0.5, rel=0.2)
    _, d13, v0, phi, *_ = CAPTIONS["figFN2_f"]
    run = vi.simulate(vi.Params(d=d13, gbar=g, r=0.5), phi=phi, v0=v0, n_impacts=5000)
    assert vi.identify_attractor(run).label == "1:1 period-10"
    assert 0.01 * d13 < _clearance(run.isel(impact=slice(1000, None)), d13, g, 0.5) < 0.02 * d13


def test_pi3_1to1_family_ends_without_grazing():
    """beta = pi/3, length sweep (Fig 0 (a)): the 1:1 attractor leaves its family while it still clears the
    bottom wall by several per cent of d, and the motion beyond meets the wall at finite speed: a jump of
    the chaotic attractor, not a grazing.  Independent of GRAZING_CLEARANCE: both are far from zero."""
    beta = math.pi / 3
    d, g = _line(beta, 0.245, 0.228, 12)
    ex = family_exit(d, g, 0.5, 0.42, 0.87, xtol=1e-6)
    # the start: the 1:1 motion at the line's top, reached from Fig 0's sweep start at d = 0.245
    assert ex["status"] == "located", ex["status"]
    assert ex["kind"] == "jump" and ex["sampled"]  # chaotic: its clearance is a sample's least
    assert ex["clearance"] > 3 * GRAZING_CLEARANCE * ex["d"]
    assert ex["slowest_after"] > 0.03
    assert 0.230 < ex["d"] < 0.240


def test_an_attractor_outside_the_family_at_the_start_is_reported():
    d, g = _line(math.pi / 6, 0.14, 0.138)
    ex = family_exit(d, g, 0.5, 5.855, 0.4185, n=1)  # the 2:1 motion of Fig BiS (e)
    assert ex["status"].startswith("not located: the attractor at the line's largest d")
    assert math.isnan(ex["d"])


def test_a_family_that_never_ends_on_the_line_is_reported():
    d, g = _line(math.pi / 3, 0.45, 0.40)
    ex = family_exit(d, g, 0.5, 0.42, 0.87)
    assert ex["status"].startswith("not located: the attractor stays 1:1")


def test_a_line_of_one_point_is_refused_and_the_smallest_d_is_named():
    ex = family_exit([0.3], [0.12], 0.5, 0.42, 0.87)
    assert ex["status"] == "not located: the line needs at least two points"
    d, g = _line(math.pi / 3, 0.45, 0.40)
    assert family_exit(d, g, 0.5, 0.42, 0.87)["status"].endswith(f"smallest d = {0.40:.6g}")


def test_the_motion_beyond_the_exit_is_described_by_its_bottom_impacts_per_top_impact():
    """Just past a grazing the motion adds a bottom impact now and then: more than one per top impact."""
    d, g = _line(math.pi / 6, 0.222, 0.205, 10)
    ex = family_exit(d, g, 0.5, 0.242, 0.676, xtol=1e-6)
    head, ratio = ex["after"].split("(")
    assert head == "no period found "
    assert 1.0 < float(ratio.split()[0]) < 1.1


#: d = K_F / F at s = 0.85 m (the paper's M and omega)
K_F = 0.85 * 0.1245 * 25.0


@pytest.mark.parametrize("vary, values, fixed", [("s", np.linspace(0.345, 0.33, 4), {"F": 5.0}),
                                                 ("F", K_F / np.linspace(0.25, 0.19, 8), {"s": 0.85})])
def test_sweep_family_exit_gives_the_device_at_the_exit(vary, values, fixed):
    """The swept device at the 1:1 exit is the one whose d is the exit's: s proportional to d at fixed force, the
    force inversely proportional at fixed s (d = s M omega^2 / (F pi^2))."""
    from vibroimpact.analysis.family_exit import sweep_family_exit

    beta = math.pi / 6
    sw = vi.sweep(vary, values, beta=beta, phi=0.42, v0=0.87, long_impacts=0, **fixed)
    g = sweep_family_exit(sw, xtol=1e-5)
    assert str(g.exit_status.values) == "located" and str(g.exit_kind.values) == "grazing"
    p = vi.Params.from_physical(s=float(g.exit_s), F=float(g.exit_F), beta=beta)
    assert p.d == pytest.approx(float(g.exit_d), rel=1e-12)
    assert float(g.exit_F if vary == "s" else g.exit_s) == pytest.approx(fixed["F" if vary == "s" else "s"])
    assert g.attrs["exit_xtol"] == 1e-5 and g.attrs["exit_impacts"] == 4000
    assert sweep_family_exit(sw).attrs["exit_xtol"] == 1e-7  # the default, recorded
    assert g.exit_d.attrs["units"] == "1" and g.exit_s.attrs["units"] == "m"
    assert g.exit_d.attrs["long_name"].startswith("1:1 exit")


def test_family_exit_curve_follows_d_along_the_axis_that_changes_it():
    """Lines along s (d proportional), along F (d inversely proportional) or along d; none where no axis
    changes d.  Each line's exit is the device whose d is its exit's."""
    from vibroimpact.analysis.family_exit import family_exit_curve

    beta = math.pi / 6
    kw = dict(phi=0.42, v0=0.87, xtol=1e-5)
    s_line = family_exit_curve("s", np.linspace(0.33, 0.345, 4), "beta", [beta], F=5.0, **kw)
    F_line = family_exit_curve("beta", [beta], "F", K_F / np.linspace(0.25, 0.19, 8), s=0.85, **kw)
    assert (s_line.attrs["along"], F_line.attrs["along"]) == ("s", "F")
    for c, device in ((s_line, lambda a: dict(s=a, F=5.0)), (F_line, lambda a: dict(s=0.85, F=a))):
        assert str(c.exit_kind.values[0]) == "grazing"
        p = vi.Params.from_physical(beta=beta, **device(float(c["at"][0])))
        assert p.d == pytest.approx(float(c.exit_d[0]), rel=1e-12)
    assert s_line.attrs["grid_step"] == pytest.approx(0.005)
    d_line = family_exit_curve("d", np.linspace(0.205, 0.215, 3), "gbar", [gbar_of(beta)], **kw)
    assert float(d_line["at"][0]) == pytest.approx(float(d_line.exit_d[0]))
    none = family_exit_curve("beta", [0.3, 0.5], "r", [0.5, 0.6], phi=0.42, v0=0.87)
    assert none.sizes["line"] == 0 and none.attrs["status"].startswith("no 1:1 exit curve")
    # CF style, as every dataset the workflow writes: the line's value carries its axis' units
    assert (s_line["at"].attrs["units"], F_line["at"].attrs["units"], d_line["at"].attrs["units"]) == ("m", "N", "1")
    for name in [*s_line.data_vars, *s_line.coords]:
        assert "long_name" in s_line[name].attrs, name
        assert s_line[name].dtype.kind not in "fiu" or "units" in s_line[name].attrs, name


def test_a_line_of_two_points_is_enough():
    """family_exit along a line of its two ends (the 1:1 motion of beta = pi/6 at the larger, out of the family
    at the smaller) locates the exit as the six-point line of its example does."""
    p = [vi.Params.from_physical(s=s, beta=math.pi / 6) for s in (0.345, 0.33)]
    ex = family_exit([q.d for q in p], [q.gbar for q in p], 0.5, phi=0.42, v0=0.87, xtol=1e-5)
    assert ex["status"] == "located" and round(ex["d"], 3) == 0.211


def test_the_default_xtol_brackets_the_exit_to_1e_7():
    """Called without xtol (as the sweeps' defaults do), the exit is bracketed to 1e-7 and said so."""
    d, g = _line(math.pi / 6, 0.212, 0.210, 3)
    ex = family_exit(d, g, 0.5, 0.242, 0.676)
    assert ex["status"] == "located" and 1e-9 < ex["d_width"] <= 1e-7


def test_along_a_force_line_the_exit_is_where_the_attractor_followed_at_each_point_s_own_gbar_leaves():
    """Along a line of the force at fixed s, gbar changes with d (both inversely proportional to F): between the line's
    points the runs interpolate it.  The exit located from the sweep's coarse grid (step 1.2e-3 in d) is where the
    attractor, followed down a grid 2e-6 fine around it with each point's own device (no interpolation), leaves the
    1:1 family (beta = pi/6, Figure 9 (f)'s force sweep)."""
    from vibroimpact.analysis.family_exit import _last_bottom

    beta, start = math.pi / 6, (0.010141, 0.59229)  # the 1:1 period-4 motion at F = 13.075 N

    def params(x):
        return vi.Params.from_physical(s=0.85, F=K_F / x, beta=beta)

    coarse = np.linspace(K_F / 13.075377, K_F / 13.477387, 6)
    ex = family_exit([params(x).d for x in coarse], [params(x).gbar for x in coarse], 0.5, *start, xtol=1e-7)
    assert ex["status"] == "located" and ex["kind"] == "grazing"
    state, first_out = start, None
    for x in np.concatenate([coarse[coarse > ex["d"] + 2e-5], np.arange(ex["d"] + 2e-5, ex["d"] - 2e-5, -2e-6)]):
        run = vi.simulate(params(x), phi=state[0], v0=state[1], n_impacts=5000).isel(impact=slice(1000, None))
        if not in_family(run.wall.values, run.kind.values, 1):
            first_out = x
            break
        state = _last_bottom(run) or state
    assert first_out is not None and abs(first_out - ex["d"]) <= 2e-6 + 1e-7, (ex["d"], first_out)
