"""Speed against accuracy for the largest Lyapunov exponent: Benettin's two-trajectory method against the tangent map
and the orbits' Floquet multipliers, the dataset's completeness, its table, figure and summary rows, and bad input."""

import math

import numpy as np
import pytest

import vibroimpact as vi
from vibroimpact.benchmarks import lyapunov_precision as LP
from vibroimpact.benchmarks.lyapunov_precision import (
    FAMILIES,
    MOTIONS,
    benettin,
    exact_flight,
    lyapunov_precision,
    series_exponent,
)
from vibroimpact.outputs.speed import speed_summary
from vibroimpact.outputs.tables import lyapunov_precision_markdown

SMOKE = dict(n_ref=5000, tangent_n=(300,), benettin_n=(100,), ivp_n=(20,), ivp_tols=(1e-9,), series_n=(250,),
             repeats=2)


def _motion(name):
    beta, d, phi, v0, word = MOTIONS[name]
    return LP._params(beta, d), phi, v0, word


def _flight(p):
    return lambda th, z, u: exact_flight(th, z, u, p.d, p.gbar)


def _orbit(name):
    """The motion's periodic orbit (Newton on a bottom impact of the settled run) and ln max|mu| / 2."""
    p, phi, v0, word = _motion(name)
    run = vi.simulate(p, phi, v0, n_impacts=1020)
    k = 1000 + int(np.flatnonzero(run.wall.values[1000:] == 1)[0])
    orbit = vi.find_orbit(p, word, float(run.phase.values[k]), float(run.v_minus.values[k]))
    return p, orbit, math.log(float(np.max(np.abs(orbit.eigenvalues)))) / 2


@pytest.fixture(scope="module")
def smoke():
    return lyapunov_precision(**SMOKE)


def test_benettin_on_exact_flights_agrees_with_the_tangent_map_on_the_chaotic_motion():
    """Two independent linearisations of the same run (a finite difference of two trajectories compared at equal
    impact counts, and the Jacobians of the impact map) give the same lambda_1 per unit time, within the tangent
    map's batch-means interval; both are positive."""
    p, phi, v0, _ = _motion("chaotic")
    b = benettin(_flight(p), p, phi, v0, 20_000)
    ly = vi.lyapunov(p, phi, v0, 20_000)
    low, high = ly.interval_time[0]
    assert b["status"] == "ok" and b["resyncs"] == 0
    assert b["per_time"] > 0 and low > 0
    assert abs(b["per_time"] - ly.per_time[0]) < (high - low) / 2
    # per impact and per unit time differ by the mean time between impacts
    assert b["per_time"] / b["per_impact"] == pytest.approx(ly.per_time[0] / ly.per_impact[0], rel=1e-3)
    assert ly.per_time[0] / ly.per_impact[0] != pytest.approx(1.0, rel=5e-3)  # so the check above can fail


def test_on_the_stable_2to1_both_are_negative_and_give_its_floquet_exponent():
    """On the stable 2:1 orbit (3 impacts a forcing period of 2) lambda_1 per unit time is ln max|mu| / 2 of its
    Floquet multipliers (find_orbit's monodromy): Benettin over whole periods to 1e-6, the tangent map (whose
    batches need not be whole periods) to 1e-3, both negative."""
    p, orbit, floquet = _orbit("2:1")
    assert orbit.stable and floquet < 0
    b = benettin(_flight(p), p, orbit.phi, float(orbit.v_minus[0]), 330, transient=30)  # 100 periods counted
    ly = vi.lyapunov(p, orbit.phi, float(orbit.v_minus[0]), 4000)
    assert b["per_time"] < 0 and ly.per_time[0] < 0
    assert abs(b["per_time"] - floquet) < 1e-6
    assert abs(ly.per_time[0] - floquet) < 1e-3


def test_a_run_that_stops_part_way_through_a_period_is_off_by_its_ends():
    """On the 3:1 near its fold (4 impacts a period, one of them slow) the stretching is spread unevenly over a
    period's impacts: counted over whole periods Benettin gives the Floquet exponent to 1e-5, two impacts more
    and it is off by more than 1e-3, by less at twice the length (an O(1/n) end term)."""
    p, orbit, floquet = _orbit("3:1 near fold")
    start = (orbit.phi, float(orbit.v_minus[0]))
    whole = benettin(_flight(p), p, *start, 440, transient=40)
    part = benettin(_flight(p), p, *start, 442, transient=40)
    longer = benettin(_flight(p), p, *start, 882, transient=80)
    assert abs(whole["per_time"] - floquet) < 1e-5
    assert abs(part["per_time"] - floquet) > 1e-3
    assert abs(part["per_time"] - floquet) / 3 < abs(longer["per_time"] - floquet) < abs(part["per_time"] - floquet)


def test_the_near_fold_motion_is_a_3to1_just_below_its_fold():
    """The 3:1 motion the chart calls near fold: the start settles on the 3:1 period-2 orbit, stable with its
    largest multiplier between 0.85 and 0.95 (1 at the fold), and 1e-4 above it the orbit no longer exists
    (Newton from the same guess fails)."""
    p, orbit, _ = _orbit("3:1 near fold")
    mu = float(np.max(np.abs(orbit.eigenvalues)))
    assert orbit.stable and 0.85 < mu < 0.95
    beta, d, phi, v0, word = MOTIONS["3:1 near fold"]
    assert vi.identify_attractor(vi.simulate(p, phi, v0, n_impacts=4000)).label == "3:1 period-2"
    with pytest.raises(vi.OrbitError):
        vi.find_orbit(LP._params(beta, d + 1e-4), word, orbit.phi, float(orbit.v_minus[0]))


def test_every_method_and_motion_has_a_value_or_a_reason(smoke):
    ds = smoke
    assert list(ds.motion.values) == list(MOTIONS)
    assert set(ds.family.values) == set(FAMILIES)
    finite = np.isfinite(ds.lambda1.values)
    reason = ds.reason.values.astype(str)
    assert (reason != "").all()
    assert (finite | (reason != "ok")).all()  # no silent NaN
    assert np.isfinite(ds.seconds.values).all() and (ds.seconds.values > 0).all()
    for name in ("lambda1", "error", "seconds", "lambda_ref", "lambda_floquet"):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
    # the periodic motions' impact velocities repeat: nolds' estimators give no finite value, and say why
    periodic = ds.sel(motion=["2:1", "3:1 near fold"], solver=ds.family.str.startswith("nolds"))
    assert not np.isfinite(periodic.lambda1.values).any()
    assert all("repeats" in r for r in periodic.reason.values.ravel())
    # the Floquet exponents of the periodic motions lie in the reference runs' intervals; NaN for the chaotic one
    assert np.isnan(float(ds.lambda_floquet.sel(motion="chaotic")))
    per = ds.sel(motion=["2:1", "3:1 near fold"])
    assert ((per.lambda_ref_low < per.lambda_floquet) & (per.lambda_floquet < per.lambda_ref_high)).all()


def test_the_units_are_converted_consistently(smoke):
    """An estimate per impact and per unit time differ by the mean time between impacts: on the periodic motions
    2 / 3 (2:1, three impacts a forcing period of 2) and 1 / 2 (3:1), for the tangent map and Benettin; nolds'
    per-impact estimates on the chaotic motion are converted by the mean time between the impacts of their
    series, recomputed here from each repeat's start."""
    per = smoke.sel(solver=~smoke.family.str.startswith("nolds"))
    for motion, dt in (("2:1", 2 / 3), ("3:1 near fold", 1 / 2)):
        ratio = (per.lambda1_per_impact / per.lambda1).sel(motion=motion)
        assert np.allclose(ratio.values, dt, rtol=0.05), motion  # runs of part periods: a little off
    ch = smoke.sel(motion="chaotic")
    p, _, _, _ = _motion("chaotic")
    for so in ch.solver.values[ch.family.str.startswith("nolds").values]:
        for j in ch.repeat.values:
            run = vi.simulate(p, float(ch.start_phase[j]), float(ch.start_v[j]), n_impacts=int(ch.n_impacts.sel(solver=so)))
            t = run.t.values
            r = ch.sel(solver=so, repeat=j)
            assert float(r.lambda1_per_impact / r.lambda1) == pytest.approx((t[-1] - t[0]) / (t.size - 1), rel=1e-9)


def test_benettin_counts_the_impacts_where_the_pair_parts_walls():
    """Where the second trajectory meets the other wall (here forced at every fifth impact) the step is not
    counted (resyncs), and when that is more than a tenth of the steps the status says so."""
    p, orbit, floquet = _orbit("2:1")
    flight, calls = _flight(p), [0]

    def parting(th, z, u):
        calls[0] += 1
        tau, wall, v = flight(th, z, u)
        return (tau, -wall, v) if calls[0] % 10 == 0 else (tau, wall, v)  # every fifth perturbed flight

    out = benettin(parting, p, orbit.phi, float(orbit.v_minus[0]), 300)
    assert out["resyncs"] == 60 and "parted walls at 60 of 300" in out["status"]
    assert out["per_time"] < 0


def test_nolds_absent_is_recorded_not_dropped(monkeypatch):
    monkeypatch.setattr(LP, "load_nolds", lambda: (None, "not installed (pip install nolds: the 'peers' extra)"))
    ds = lyapunov_precision(**SMOKE | {"motions": {"2:1": MOTIONS["2:1"]}})
    nolds = ds.sel(solver=ds.family.str.startswith("nolds"))
    assert nolds.sizes["solver"] == 2
    assert all("not installed" in r for r in nolds.reason.values.ravel())
    assert np.isnan(nolds.lambda1.values).all()


def test_the_table_and_the_summary_rows_come_from_the_dataset(smoke):
    md = lyapunov_precision_markdown(smoke)
    assert md.count("\n") == 2 + smoke.sizes["motion"] * (smoke.sizes["solver"] + 1)
    assert "none: lyap_r gives -inf" in md
    rows = speed_summary(lyapunov_precision=smoke).set_index("row").value
    assert {"lyap_reference", "lyap_floquet", "lyap_tangent_error", "lyap_benettin_exact_error",
            "lyap_benettin_ivp_error", "lyap_nolds_r_chaotic", "lyap_nolds_e_periodic"} <= set(rows.index)
    assert rows["lyap_nolds_r_periodic"] == "0 (2:1); 0 (3:1 near fold)"


def test_the_figure_draws_a_panel_per_motion_and_a_line_per_method(smoke):
    import matplotlib.pyplot as plt

    from vibroimpact.outputs.plots import fig_lyapunov_precision

    fig = fig_lyapunov_precision(smoke)
    try:
        axes = fig.get_axes()
        assert len(axes) == smoke.sizes["motion"]
        labels = [t.get_text() for t in fig.legends[0].get_texts()]
        assert sum(lab.startswith(("tangent", "Benettin", "nolds")) for lab in labels) == len(FAMILIES)
        # the periodic motions' nolds estimates: crosses at the top, none on the chaotic panel
        crosses = [[ln for ln in ax.get_lines() if ln.get_marker() == "x"] for ax in axes]
        assert len(crosses[0]) == 0 and len(crosses[1]) == len(crosses[2]) == 2
    finally:
        plt.close(fig)


def test_the_logistic_map_gives_nolds_a_positive_exponent():
    """nolds, as loaded here, gives the logistic map at 4 (ln 2 per step) a positive exponent: its sign only,
    as nolds' own tests check (with the chart's embedding, 5, its size is far off: the divergence saturates
    within the fitted stretch)."""
    mod, note = LP.load_nolds()
    if mod is None:
        pytest.skip(note)
    x = np.empty(1000)
    x[0] = 0.3
    for k in range(999):
        x[k + 1] = 4 * x[k] * (1 - x[k])
    lam, status = series_exponent(mod, "lyap_r", x)
    assert status == "ok" and 0 < lam < math.log(2)


@pytest.mark.parametrize(("kwargs", "key"), [
    ({"repeats": 0}, "repeats"),
    ({"tangent_n": (50,)}, "tangent_n"),
    ({"series_n": (100,)}, "series_n"),
    ({"ivp_tols": (0.1,)}, "ivp_tols"),
    ({"n_ref": 10}, "n_ref"),
    ({"motions": {}}, "motions"),
])
def test_bad_arguments_name_the_key(kwargs, key):
    with pytest.raises(ValueError, match=rf"^{key} = "):
        lyapunov_precision(**SMOKE | kwargs)


def test_bad_benettin_and_estimator_arguments_name_the_key():
    p, phi, v0, _ = _motion("2:1")
    with pytest.raises(ValueError, match=r"^n_impacts = 1;"):
        benettin(_flight(p), p, phi, v0, 1)
    with pytest.raises(ValueError, match=r"^delta = 0;"):
        benettin(_flight(p), p, phi, v0, 100, delta=0)
    with pytest.raises(ValueError, match=r"^method = 'lyap_x';"):
        series_exponent(None, "lyap_x", [1.0, 2.0])
