"""Codimension-one points followed in two parameters (vibroimpact.analysis.bifurcation)."""

import math

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.analysis.bifurcation import follow_point
from vibroimpact.analysis.continuation import continue_orbit
from vibroimpact.analysis.orbits import find_orbit, orbit_from_vector


def _ball_orbit(g, r):
    """The stable period-1 orbit of the vibrated bouncing ball (top wall out of reach, d = 50)."""
    theta = math.pi - math.asin(math.pi * g * (1 - r) / (1 + r))
    return find_orbit(vi.Params(d=50.0, gbar=g, r=r), "B", theta, 2 * g / (1 + r), k=1)


def _gamma_pd(r):
    return math.hypot(math.pi * (1 - r) / (1 + r), 2 * (1 + r * r) / (1 + r) ** 2)


@pytest.mark.parametrize("kind", ["B", "fold"])
def test_bouncing_ball_curves_in_gbar_and_r_are_the_closed_forms(kind):
    """Luck & Mehta (1993): the period-1 orbit is born at Gamma = pi (1 - r) / (1 + r) and doubles at
    Gamma_2(r) (gbar = 1 / Gamma).  The fold and period-doubling curves followed in (gbar, r) from one
    point must lie on them to 1e-10 over r in [0.05, 0.95]."""
    r = 0.5
    g0 = 1.02 / _gamma_pd(r) if kind == "B" else 0.98 * (1 + r) / (math.pi * (1 - r))
    curve = follow_point(_ball_orbit(g0, r), kind, params=("gbar", "r"), ranges=((0.05, 50.0), (0.05, 0.95)),
                         step=2e-2)
    rr, gg = curve.r.values, curve.gbar.values
    exact = 1 / np.array([_gamma_pd(x) for x in rr]) if kind == "B" else (1 + rr) / (np.pi * (1 - rr))
    assert np.max(np.abs(gg - exact)) < 1e-10
    assert rr.min() < 0.06 and rr.max() > 0.94  # the whole range, both ways from the start
    assert "left the box" in curve.attrs["stop_increasing"] and "left the box" in curve.attrs["stop_decreasing"]


def _z(br, j):
    """The unknowns of point ``j`` of a continued branch (as vibroimpact.analysis.bifurcation.curve_set reads them)."""
    return np.concatenate([[float(br.phase[j, 0])], np.roll(br.dt.values[j], -1), br.v_minus.values[j]])


@pytest.fixture(scope="module")
def grazing_curve():
    p = vi.Params.from_physical(s=0.1385 / vi.Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    o = find_orbit(p, "BBT", 5.855, 0.4185)
    return follow_point(o, "grazing", params=("s", "beta"), ranges=((0.19, 0.72), (0.35, 0.75)), step=5e-3)


def test_the_2to1_grazing_curve_in_s_and_beta_meets_each_one_parameter_grazing_point(grazing_curve):
    """G1 followed in (s, beta): at three inclines on the curve, the 2:1 branch continued in s alone
    (Brent's method on the clearance along a pseudo-arclength branch, another algorithm) grazes at the
    curve's s to 1e-9."""
    c = grazing_curve
    assert c.sizes["point"] > 10
    for i in np.linspace(0, c.sizes["point"] - 1, 3).astype(int):
        s, beta = float(c.s[i]), float(c.beta[i])
        ref = vi.Params.from_physical(s=1.0, beta=beta)
        # the curve's orbit, moved to s * 1.003 on its branch by one-parameter continuation (a guess
        # simulated from an orbit that grazes can go either way at the wall: find_orbit would be
        # decided at rounding level there)
        o = orbit_from_vector(vi.Params.from_physical(s=s, beta=beta), "BBT", 1, c.z.values[i])
        br = continue_orbit(o, vary="s", d_range=(s * 0.99 * ref.d, s * 1.01 * ref.d), step=1e-3, locate=False)
        j = int(np.argmin(np.abs(br.s.values - s * 1.003)))
        o = orbit_from_vector(vi.Params.from_physical(s=float(br.s[j]), beta=beta), "BBT", 1, _z(br, j))
        br = continue_orbit(o, vary="s", d_range=(s * 0.99 * ref.d, s * 1.01 * ref.d), step=1e-3)
        g = br.critical_s.values[br.critical_kind.values == "grazing"]
        assert g.size and np.min(np.abs(g - s)) < 1e-9, (s, beta, g)
    assert np.all(np.abs(c.clearance.values) < 1e-9)


def test_following_a_point_refuses_what_makes_no_sense():
    o = _ball_orbit(0.7, 0.5)
    with pytest.raises(ValueError, match="kind = 'X'"):
        follow_point(o, "X", params=("gbar", "r"), ranges=((0, 1), (0, 1)))
    with pytest.raises(ValueError, match="two different parameters"):
        follow_point(o, "B", params=("r", "r"), ranges=((0, 1), (0, 1)))
    with pytest.raises(ValueError, match="need physical parameters"):
        follow_point(o, "B", params=("s", "beta"), ranges=((0, 1), (0, 1)))
    with pytest.raises(ValueError, match="outside ranges"):
        follow_point(o, "B", params=("gbar", "r"), ranges=((0.9, 1.0), (0.4, 0.6)))


def test_curve_set_follows_each_located_point_and_records_the_ones_it_cannot(tmp_path):
    """From a continued 2:1 branch: every admissible, refined B, fold or grazing point becomes a curve
    (its first point the branch's own critical s, to 1e-9), and a point that cannot be followed is a
    curve without points whose reason is kept, never dropped."""
    from vibroimpact.analysis.bifurcation import curve_set

    p = vi.Params.from_physical(s=0.1385 / vi.Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    br = continue_orbit(find_orbit(p, "BBT", 5.855, 0.4185), vary="s", d_range=(0.13, 0.23), step=2e-3)
    br.attrs["status"] = "ok"
    ds = curve_set([br], ("s", "beta"), ((0.19, 0.72), (0.4, 0.6)), kinds=("fold", "grazing"), step=2e-2,
                   physics=dict(beta=math.pi / 6))
    want = [(k, float(s)) for k, s, a, f in zip(br.critical_kind.values, br.critical_s.values, br.critical_admissible.values,
                                                  br.critical_refined.values, strict=True) if k in ("fold", "grazing") and a and f]
    assert [(str(k), float(s)) for k, s in zip(ds.curve_kind.values, ds.curve_start_s.values, strict=True)] == want
    for c in range(ds.sizes["curve"]):
        sel = ds.curve_index.values == c
        if ds.curve_status.values[c] == "ok":
            at_start = np.abs(ds.beta.values[sel] - math.pi / 6) < 1e-12
            assert at_start.any() and np.min(np.abs(ds.s.values[sel][at_start] - ds.curve_start_s.values[c])) < 1e-9
        else:
            assert not sel.any() and ds.curve_reason.values[c]
    # a branch that failed upstream adds nothing, silently or not: it is the branch's own record
    failed = br.copy()
    failed.attrs["status"] = "failed"
    assert curve_set([failed], ("s", "beta"), ((0.19, 0.72), (0.4, 0.6)), physics=dict(beta=math.pi / 6)).sizes["curve"] == 0


def test_the_bistable_band_at_pi_6_is_g1_and_g2_of_the_branches():
    """G1 (2:1 grazing) and G2 (3:1 fold) followed in (s, beta) from the pi/6 branches: at pi/6 the band
    is exactly the branches' own located points (0.137600 and 0.141954 in d: the paper's 0.1378 and
    0.1419), to 1e-9 in s, and it stays open over a range of inclines around it."""
    from vibroimpact.analysis.bifurcation import bistable_band, curve_set

    ref = vi.Params.from_physical(s=1.0, beta=math.pi / 6)
    p = vi.Params.from_physical(s=0.1385 / ref.d, beta=math.pi / 6)
    b21 = continue_orbit(find_orbit(p, "BBT", 5.855, 0.4185), vary="s", d_range=(0.13, 0.16), step=2e-3)
    q = vi.Params.from_physical(s=0.14 / ref.d, beta=math.pi / 6)
    b31 = continue_orbit(find_orbit(q, "BBBT", 5.88, 0.3967), vary="s", d_range=(0.13, 0.16), step=2e-3)
    for b in (b21, b31):
        b.attrs["status"] = "ok"
    curves = curve_set([b21, b31], ("s", "beta"), ((0.19, 0.3), (0.4, 0.65)), kinds=("fold", "grazing"), step=1e-2,
                       physics=dict(beta=math.pi / 6))
    band = bistable_band(curves, [0.45, math.pi / 6, 0.6])
    g1 = float(b21.critical_s.values[b21.critical_kind.values == "grazing"].min())
    g2 = float(b31.critical_s.values[b31.critical_kind.values == "fold"].min())
    assert abs(float(band.s_G1[1]) - g1) < 1e-9 and abs(float(band.s_G2[1]) - g2) < 1e-9
    assert abs(g1 * ref.d - 0.137600) < 5e-7 and abs(g2 * ref.d - 0.141954) < 5e-7
    assert np.all(band.width.values > 0) and band.attrs["status"] == "ok"
    # without the 3:1 branch (another device, or its continuation failed) G2 is NaN and the band says why
    b31.attrs.update(status="failed", reason="the attractor at d=0.135 is 2:1 period-2, not 'BBBT'")
    band = bistable_band(curve_set([b21, b31], ("s", "beta"), ((0.19, 0.3), (0.4, 0.65)), kinds=("fold", "grazing"),
                                   step=1e-2, physics=dict(beta=math.pi / 6)), [math.pi / 6])
    assert abs(float(band.s_G1[0]) - g1) < 1e-9 and np.isnan(band.s_G2).all() and float(band.width[0]) == 0
    assert band.attrs["status"].startswith("no BBBT fold curve (")


def test_near_g1_the_new_impact_and_the_eigenvalue_follow_nordmarks_normal_form():
    """The 3:1 orbit born at G1 (beta = pi/6) has an impact whose speed vanishes there.  Nordmark's
    normal form for a grazing impact: that speed grows linearly with the distance mu = d - G1, and the
    impact map's large eigenvalue (its derivative carries 1 / speed) like 1 / mu.  Fitted over
    mu in [1e-6, 1e-4] on the continued branch: exponents 1 and -1 to 0.02."""
    p = vi.Params.from_physical(s=0.1385 / vi.Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    b21 = continue_orbit(find_orbit(p, "BBT", 5.855, 0.4185), vary="d", d_range=(0.135, 0.14), step=1e-3)
    g1 = float(b21.critical_d.values[b21.critical_kind.values == "grazing"].min())
    # the 3:1 orbit just above G1 whose third bottom impact is slow (the other 3:1 orbit there, Fig BiS
    # (f)'s, has no slow impact): guess from the continued 3:1 branch at d = 0.13768
    q = vi.Params(d=g1 + 5e-5, gbar=p.gbar, r=p.r)
    o = find_orbit(q, "BBBT", 5.8407, 0.41577)
    assert np.min(np.abs(o.v_minus)) < 1e-3
    br = continue_orbit(o, vary="d", d_range=(g1 + 5e-7, g1 + 2e-4), step=2e-6, locate=False)
    mu = br.d.values - g1
    vmin = np.min(np.abs(br.v_minus.values), axis=1)
    lam = np.max(br.eig_abs.values, axis=1)
    sel = (mu > 1e-6) & (mu < 1e-4)
    assert sel.sum() > 20
    slope_v = np.polyfit(np.log(mu[sel]), np.log(vmin[sel]), 1)[0]
    slope_l = np.polyfit(np.log(mu[sel]), np.log(lam[sel]), 1)[0]
    assert abs(slope_v - 1) < 0.02 and abs(slope_l + 1) < 0.02, (slope_v, slope_l)


def test_the_bouncing_balls_period_doubling_cascade_approaches_feigenbaums_constant():
    """The period-doubling cascade of the vibrated bouncing ball (r = 0.5), located word by word: the
    period-1 orbit doubles at its closed form; from the attractor just past each doubling, the orbit
    of twice as many impacts (B, BB, BBBB, ...) is continued in gbar to its own doubling.  The ratios
    of successive intervals tend to Feigenbaum's 4.6692: each nearer than the one before, the third
    within 0.5 %."""
    from vibroimpact.analysis.motions import identify_attractor
    from vibroimpact.dynamics.runs import simulate

    r, feigenbaum = 0.5, 4.669201609
    points = [1 / _gamma_pd(r)]
    theta = math.pi - math.asin(math.pi * points[0] * (1 - r) / (1 + r))
    start, k = (theta + 1e-3, 2 * points[0] / (1 + r)), 1
    for level in range(4):
        k *= 2
        g = points[-1] - 2e-3 * 0.25**level  # just past the last doubling (gbar decreasing)
        p = vi.Params(d=50.0, gbar=g, r=r)
        att = identify_attractor(simulate(p, *start, n_impacts=200_000, stop_when_periodic=True, tol=1e-11), tol=1e-11)
        cyc = att.cycle
        assert len(cyc.t) == k  # the doubled orbit: k impacts in 2k forcing half-periods
        start = (float(cyc.phase.values[0]), float(cyc.v_minus.values[0]))
        o = find_orbit(p, "B" * k, *start, k=k)
        br = continue_orbit(o, vary="gbar", value_range=(g - 0.3 * 0.22**level, g + 1e-3 * 0.22**level),
                            step=1e-3 * 0.22**level)
        b = br.critical_value.values[(br.critical_kind.values == "B") & (br.critical_value.values < g)]
        points.append(float(b.max()))
    gaps = -np.diff(points)
    delta = gaps[:-1] / gaps[1:]
    err = np.abs(delta - feigenbaum)
    assert np.all(np.diff(err) < 0) and err[-1] < 0.005 * feigenbaum, delta


def test_plane_cusps_finds_where_a_projection_turns_back():
    """The semicubical cusp (t^2, t^3) turns back once, at t = 0; a parabola and a circle arc never."""
    from vibroimpact.analysis.bifurcation import plane_cusps

    t = np.linspace(-1, 1, 41)
    assert list(plane_cusps(np.c_[t**2, t**3])) == [20]
    assert plane_cusps(np.c_[t, t**2]).size == 0
    a = np.linspace(0, 3, 50)
    assert plane_cusps(np.c_[np.cos(a), np.sin(a)]).size == 0
    # the scale of each axis does not change where it turns back
    assert list(plane_cusps(np.c_[1e3 * t**2, 1e-3 * t**3], scale=(1e3, 1e-3))) == [20]


def _synthetic_set(curves):
    """A curve_set-like dataset in (s, beta) from polylines {(word, kind): (xs, ys)}."""
    import xarray as xr

    idx, xs, ys, kinds, words = [], [], [], [], []
    for c, ((word, kind), (x, y)) in enumerate(curves.items()):
        idx += [c] * len(x)
        xs += list(x)
        ys += list(y)
        kinds.append(kind)
        words.append(word)
    ds = xr.Dataset({"curve_index": ("point", np.array(idx)), "s": ("point", np.array(xs, float)),
                     "beta": ("point", np.array(ys, float)), "curve_kind": ("curve", kinds),
                     "curve_word": ("curve", words)})
    ds.attrs["params"] = "s beta"
    return ds


def test_curve_crossings_are_the_segment_intersections():
    """Two lines crossing once at a known point, a third crossing neither."""
    from vibroimpact.analysis.bifurcation import curve_crossings

    x = np.linspace(0, 1, 11)
    ds = _synthetic_set({("BBT", "grazing"): (x, x), ("BBBT", "fold"): (x, 1 - x), ("BT", "B"): (x, x + 5)})
    cr = curve_crossings(ds)
    assert cr.sizes["crossing"] == 1
    assert (str(cr.name_a.values[0]), str(cr.name_b.values[0])) == ("BBT grazing", "BBBT fold")
    assert abs(float(cr.crossing_s[0]) - 0.5) < 1e-12 and abs(float(cr.crossing_beta[0]) - 0.5) < 1e-12
    # one set sampled twice (a wavy copy 1e-5 off the first polyline's chords "crosses" it again and
    # again): the two curves run together, no crossing; a third curve still crosses both once
    t = np.linspace(0, 1, 40)
    u = np.linspace(0, 1, 57)
    ds = _synthetic_set({("BBT", "grazing"): (t, t**2), ("BBBT", "grazing"): (u, u**2 + 1e-5 * np.sin(90 * u)),
                         ("BT", "B"): (x, 0.3 + 0 * x)})
    cr = curve_crossings(ds)
    assert "BBT grazing = BBBT grazing" in cr.attrs["coincide"]
    assert sorted(cr.name_b.values) == ["BT B", "BT B"]
    np.testing.assert_allclose(cr.crossing_s.values, np.sqrt(0.3), atol=2e-3)


def test_map_boundaries_are_on_a_curve_or_named_by_their_cause():
    """A 4 x 6 map: a vertical 1:1 | 2:1 boundary between columns 1 and 2 with a curve through it; a 2:1 |
    3:1 boundary between columns 3 and 4 on no curve (a jump); a no-period cell (aperiodic)."""
    import xarray as xr

    from vibroimpact.analysis.bifurcation import map_boundaries

    s, beta = np.arange(6.0), np.arange(4.0)
    lab = np.array([["1:1 period-2"] * 2 + ["2:1 period-2"] * 2 + ["3:1 period-2"] * 2] * 4, dtype=object)
    lab[3, 5] = "no period found"
    m = xr.Dataset({"label": (("beta", "s"), lab.astype(str))}, coords={"s": s, "beta": beta})
    b = map_boundaries(m, _synthetic_set({("BT", "B"): (np.array([1.5, 1.5]), np.array([-1.0, 4.0]))}))
    cause = dict(zip(zip(b.s.values, b.beta.values, strict=True), b.cause.values, strict=True))
    assert all(cause[(1.5, y)] == "on a curve" for y in beta)
    assert all(cause[(3.5, y)] == "jump" for y in beta)
    assert cause[(5.0, 2.5)] == "aperiodic" and cause[(4.5, 3.0)] == "aperiodic"
    assert b.sizes["boundary"] == 10
    # a curve two cells away explains nothing; in another plane it is refused
    far = map_boundaries(m, _synthetic_set({("BT", "B"): (np.array([-0.5, -0.5]), np.array([-1.0, 4.0]))}))
    assert not far.on_curve.values.any()
    other = _synthetic_set({("BT", "B"): (np.array([1.5, 1.5]), np.array([-1.0, 4.0]))})
    other.attrs["params"] = "s F"
    with pytest.raises(ValueError, match="plane"):
        map_boundaries(m, other)


def test_every_point_of_a_grazing_curve_is_admissible_contact(grazing_curve):
    """On G1 the 2:1 orbit's extremum touches the bottom wall at every point: the contact, with a
    clearance of rounding size on either side of zero, is no violation, so the whole curve (inside the
    region where the 2:1 orbit exists) is drawn admissible rather than flickering with the rounding."""
    c = grazing_curve
    assert np.all(np.abs(c.clearance.values) < 1e-9)
    assert c.admissible.values.all(), np.flatnonzero(~c.admissible.values)
