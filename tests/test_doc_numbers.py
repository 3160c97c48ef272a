"""No number about results is pasted in the documentation: timings and cost ratios are generated from the
results at build time (the speed page cites the rows of `results/tables/speed_summary.md`), and the
computed numbers that stay in the guide's prose are found on their page and compared here with the
package's own values, computed in the test."""

import math
import re

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from conftest import ROOT

import vibroimpact as vi
from vibroimpact.outputs.speed import speed_summary, speed_summary_markdown

DOCS = ROOT / "docs"
SPEED = DOCS / "speed.md"

#: a timing or a cost ratio written out: a number followed by a unit of time, "×", "%" or "million"
TIMING = re.compile(
    r"\d\s?(?:µs|us|ms|ns|s|sec|seconds?|minutes?|min|h|hours?)\b|\d\s?(?:×|%)|×\s?\d|\d\s?million\b"
)
#: a unit of time after a number (the guide's pages quote factors and percentages that are not timings)
TIME = re.compile(r"\d\s?(?:µs|ms|ns|s|seconds?|minutes?)\b(?! =)")


def prose(text: str) -> str:
    """A page without its code blocks (commands, includes of generated tables) and HTML comments."""
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    return re.sub(r"<!--.*?-->", "", text, flags=re.S)


def test_the_speed_page_types_no_timing():
    """Every timing, ratio and rate of the speed page is in a table the workflow generates."""
    text = SPEED.read_text()
    found = sorted({m.group(0) for m in TIMING.finditer(prose(text))})
    assert not found, f"hand-typed timings on docs/speed.md: {found}"
    assert "```{include} ../results/tables/speed_summary.md\n```" in text


def test_the_guide_pages_type_no_timing():
    """The guide, README and the index quote no timing: the speed page's generated tables hold them."""
    pages = [ROOT / "README.md", DOCS / "index.md", *sorted((DOCS / "guide").glob("*.md"))]
    # d = 0.6225 s: the length s in metres, not seconds
    bad = {
        p.name: sorted({m.group(0) for m in TIME.finditer(prose(p.read_text()).replace("0.6225 s", ""))})
        for p in pages
    }
    assert not {k: v for k, v in bad.items() if v}


def test_the_docs_rule_builds_the_speed_summary():
    """The page includes the summary, so the docs target depends on the rule that writes it."""
    assert "rules.speed_summary.output" in (ROOT / "workflow" / "rules" / "docs.smk").read_text()
    bench = (ROOT / "workflow" / "rules" / "bench.smk").read_text()
    assert re.search(r'rule speed_summary:.*?md="results/tables/speed_summary.md"', bench, re.S)


def _bench_datasets():
    """Small datasets of the benchmark rules' form, with made-up values."""
    scenes = ["1:1", "2:1", "3:1", "chaotic"]
    ladder = [
        ("exact (numba)", "exact", np.nan),
        ("same algorithm, plain Python", "python", np.nan),
        ("solve_ivp DOP853 rtol=1e-06", "ivp-DOP853", 1e-6),
        ("solve_ivp DOP853 rtol=1e-10", "ivp-DOP853", 1e-10),
        ("solve_ivp RK45 rtol=1e-06", "ivp-RK45", 1e-6),
        ("solve_ivp LSODA rtol=1e-06", "ivp-LSODA", 1e-6),
        ("solve_ivp Radau rtol=1e-06", "ivp-Radau", 1e-6),
        ("RK4 + bisection h=0.01", "rk4", 1e-2),
        ("heyoka tol=1e-09", "heyoka", 1e-9),
        ("siconos-ed tol=1e-10", "siconos-ed", 1e-10),
        ("siconos-mj h=1e-4", "siconos-mj", 1e-4),
    ]
    n = len(ladder)
    err = np.full((n, 4), 1e-10)
    err[0] = err[1] = 1e-15
    cost = np.arange(1, n * 4 + 1, dtype=float).reshape(n, 4)
    wp = xr.Dataset(
        {
            "err_t": (("solver", "scene"), err),
            "us_per_impact": (("solver", "scene"), cost),
            "family": ("solver", [m[1] for m in ladder]),
            "setting": ("solver", [m[2] for m in ladder]),
        },
        coords={"solver": [m[0] for m in ladder], "scene": scenes},
    )
    fams = list(dict.fromkeys(m[1] for m in ladder))
    shape = (len(fams), 4)
    ma = xr.Dataset(
        {
            "us_per_impact": (("family", "scene"), np.ones(shape)),
            "setting": (("family", "scene"), np.ones(shape)),
            "err_t": (("family", "scene"), np.ones(shape) * 1e-13),
            "ratio_to_exact": (("family", "scene"), np.ones(shape) * 20),
            "reached": (("family", "scene"), np.ones(shape, bool)),
        },
        coords={"family": fams, "scene": scenes},
        attrs={"target": 1e-12},
    )
    cases = ["B miss by 1e-08", "B hit by 1e-08", "chattering into sticking", "chaotic run (100 impacts)"]
    fm_ladder = [m for m in ladder if m[1] not in ("python",)]
    detail = [
        [
            "",
            "",
            "follows the reference's 174 impacts faster than 1e-06 for 21, to t=1.6 in 1 s (ok)",
            "follows the reference for 60 of 100 impacts (ok, 0.5 s)",
        ]
        for _ in fm_ladder
    ]
    fm = xr.Dataset(
        {
            "outcome": (("solver", "case"), [["correct", "missed impact", "ok", "ok"] for _ in fm_ladder]),
            "detail": (("solver", "case"), detail),
            "family": ("solver", [m[1] for m in fm_ladder]),
            "setting": ("solver", [m[2] for m in fm_ladder]),
        },
        coords={"solver": [m[0] for m in fm_ladder], "case": cases},
    )
    aa = xr.Dataset(
        {
            "branch_located_err": (("step", "point_kind"), [[1e-14, 1e-14], [0.0, 0.0]]),
            "branch_grid_err": (("step", "point_kind"), [[1e-4, 1e-5], [1e-8, 1e-9]]),
            "sweep_grid_err": (("points", "grazing"), [[1e-4, 1e-4], [1e-5, 1e-5]]),
            "sweep_located_err": (("points", "grazing"), [[1e-8, 1e-10], [2e-9, 3e-10]]),
        },
        coords={
            "step": [1e-2, 1e-3],
            "point_kind": ["B", "fold"],
            "points": [25, 50],
            "grazing": ["G1", "G2"],
        },
    )
    kp = xr.Dataset(
        {
            k: ("scene", [0.2, 0.25])
            for k in (
                "us_per_impact",
                "trig_per_impact",
                "points_per_impact",
                "heyoka_stepping_us_per_impact",
            )
        }
        | {
            "impacts_per_second_1": ("scene", [5e6, 4.6e6]),
            "impacts_per_second_all": ("scene", [8e6, 7.8e6]),
        },
        coords={"scene": ["2:1", "chaotic"]},
        attrs={"cores": 2},
    )
    sim = xr.Dataset(
        {
            "speedup": ((), 2000.0),
            "lyapunov_ratio": ((), 1.5),
            "branch_points": ((), 1000),
            "branch_seconds": ((), 0.3),
            "curve_points": ((), 183),
            "curve_seconds": ((), 0.3),
            "sweep_points": ((), 1000),
            "sweep_seconds": ((), 12.0),
        }
    )
    cost = pd.DataFrame(
        {
            "file": ["a", "b", "c", "d", "e"],
            "seconds": [10.0, 5.0, 3.0, 20.0, 7.0],
            "rule": ["sweep", "regime_map", "bifurcation_set", "work_precision", "analytics_accuracy"],
        }
    )
    return dict(
        kernel=kp,
        simulator=sim,
        work_precision=wp,
        matched_accuracy=ma,
        failure_map=fm,
        analytics_accuracy=aa,
        workflow_cost=cost,
    )


def test_every_summary_row_the_speed_page_cites_is_generated():
    """The rows the speed page names (in backquotes after "summary row(s)" and in the sentences that follow
    them) are rows the generator writes from datasets of the benchmark rules' form."""
    df = speed_summary(**_bench_datasets())
    names = set(df.row)
    assert len(names) == len(df)
    text = prose(SPEED.read_text())
    cited = {
        n
        for n in re.findall(r"`([a-z][\w-]*)`", text)
        if re.match(
            r"(kernel|heyoka_stepping|impacts_per_second|exact_|work_precision_|matched_|failure_"
            r"|analytics_|cost_)",
            n,
        )
        and n != "analytics_accuracy"
    }
    assert len(cited) >= 20
    assert cited <= names, cited - names
    table = speed_summary_markdown(df)
    assert table.count("\n") == len(df) + 2 and "| `kernel_us_per_impact` |" in table
    # the values are the datasets' own
    row = df.set_index("row").value
    assert row["heyoka_stepping_ratio"] == "1×" and row["impacts_per_second_1"] == "4.6–5"
    assert row["failure_chaos_loose"] == "60" and row["cost_timed_benchmarks"] == "27 s"


# ---- computed numbers in the guide's prose, against the package -----------------------------------------


def _branch(beta, word, d0, d_range, phi=None, v0=None, step=1e-3):
    p = vi.Params.from_physical(s=d0 / vi.Params.from_physical(s=1.0, beta=beta).d, beta=beta)
    if phi is None:  # from the simulated attractor's first bottom impact
        att = vi.identify_attractor(
            vi.simulate(p, 1.0, 0.2, n_impacts=20_000, stop_when_periodic=True, tol=1e-12), tol=1e-12
        )
        bottom = att.cycle.where(att.cycle.wall == 1, drop=True)
        phi, v0 = float(bottom.phase[0]), float(bottom.v_minus[0])
    return vi.continue_orbit(vi.find_orbit(p, word, phi, v0), vary="s", d_range=d_range, step=step)


def _critical(br, kind, near):
    d = br.critical_d.values[br.critical_kind.values == kind]
    return float(d[np.argmin(np.abs(d - near))])


@pytest.fixture(scope="module")
def located():
    """The located points the guide quotes: the 2:1 branches' period doublings and folds at four inclines,
    G1 (the 2:1 grazing) and G2 (the 3:1 fold) at beta = pi/6 (located to 1e-10 whatever the step)."""
    b6 = _branch(math.pi / 6, "BBT", 0.14, (0.125, 0.23), 5.855, 0.4185)
    b6_3 = _branch(math.pi / 6, "BBBT", 0.14, (0.125, 0.15), 5.88, 0.3967)
    out = {
        "G1": _critical(b6, "grazing", 0.1376),
        "G2": _critical(b6_3, "fold", 0.142),
        "B pi/6": _critical(b6, "B", 0.133),
        "fold pi/6": _critical(b6, "fold", 0.216),
    }
    for name, beta in (("pi/2", math.pi / 2), ("pi/3", math.pi / 3), ("pi/4", math.pi / 4)):
        br = _branch(beta, "BBT", 0.18, (0.13, 0.23))
        out[f"B {name}"] = _critical(br, "B", 0.16)
        if name != "pi/2":
            out[f"fold {name}"] = _critical(br, "fold", 0.22)
    return out


def stated(page: str, pattern: str) -> list[str]:
    """The numbers a page states where ``pattern`` (a regex with a group per number) matches its text,
    line breaks read as spaces."""
    text = " ".join((ROOT / page).read_text().split())
    m = re.search(pattern, text)
    assert m, f"{page}: no match for {pattern!r}"
    return list(m.groups())


def same(text: str, value: float) -> bool:
    """A number as printed equals the value rounded to the printed decimals."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return f"{value:.{decimals}f}" == text


#: (page, pattern, the located points its numbers are, in order)
CLAIMS = [
    ("docs/guide/orbits.md", r"at \*\*G1 = (0\.\d+)\*\*", ["G1"]),
    ("docs/guide/orbits.md", r"d = (0\.\d+)\*\* — the paper's G2", ["G2"]),
    ("docs/guide/orbits.md", r"bistable for (0\.\d+) < d < (0\.\d+) \(paper", ["G1", "G2"]),
    ("docs/guide/orbits.md", r"matches both ends \((0\.\d+), (0\.\d+) against", ["B pi/3", "fold pi/3"]),
    (
        "docs/guide/orbits.md",
        r"matches B \(< 0\.133\), G1 \((0\.\d+) against 0\.1378\) and G2 \((0\.\d+) against",
        ["G1", "G2"],
    ),
    (
        "docs/guide/orbits.md",
        r"period-doubling points are (0\.\d+) and (0\.\d+) against",
        ["B pi/2", "B pi/4"],
    ),
    ("docs/guide/orbits.md", r"just below d_B = (0\.\d+) the attractor", ["B pi/2"]),
    ("docs/guide/orbits.md", r"ends \((0\.\d+), (0\.\d+)\); 0\.205", ["fold pi/6", "fold pi/4"]),
    ("docs/guide/orbits.md", r"\(λ = −1 at d = (0\.\d+), on the wall-crossing", ["B pi/6"]),
    ("docs/guide/orbits.md", r"branches' own points \(d = (0\.\d+) and (0\.\d+); the paper's", ["G1", "G2"]),
    ("docs/guide/notation.md", r"G1 = (0\.\d+), where the 2:1 orbit grazes", ["G1"]),
    ("docs/guide/notation.md", r"G2 = (0\.\d+), the 3:1 orbit's fold", ["G2"]),
    ("docs/guide/checks.md", r"located grazing point, d = (0\.\d+) = G1", ["G1"]),
]


@pytest.mark.parametrize(
    "page, pattern, names", CLAIMS, ids=[f"{c[0].split('/')[-1]}:{'+'.join(c[2])}" for c in CLAIMS]
)
def test_a_located_point_the_guide_states_is_the_package_s(located, page, pattern, names):
    numbers = stated(page, pattern)
    assert len(numbers) == len(names)
    for text, name in zip(numbers, names, strict=True):
        assert same(text, located[name]), (page, name, text, located[name])


def test_the_constants_the_checks_page_states_are_the_code_s():
    """The figure check's threshold for long-run means and the image layer's floor, as the code has them."""
    from vibroimpact.outputs import figcheck

    (z,) = stated("docs/guide/checks.md", r"within (\d+\.\d+) combined standard errors")
    assert float(z) == figcheck.Z_CRIT
    (dof,) = stated("docs/guide/checks.md", r"Student's t, (\d+) degrees of freedom, false alarm 1e-6")
    from scipy.stats import t

    assert f"{t.isf(1e-6 / 2, int(dof)):.2f}" == z


def test_the_analytic_points_the_sweeps_page_states(located):
    """The sweeps page gives the analytic points its sweeps recover (the sweep-located ones are in the
    transitions table it includes): G1 and G2 at pi/6, the 2:1 fold and period doubling at pi/3, and the
    3:1 grazing point and 4:1 fold at pi/3, in its prose and in its example's comment."""
    from test_sweeps import analytic_ends

    from vibroimpact.analysis.sweeps import sweep

    stated_at = [
        (r"analytic branches \((0\.\d+), (0\.\d+); tests", ["G1", "G2"]),
        (r"doubling \(analytic (0\.\d+) and (0\.\d+)\)", ["fold pi/3", "B pi/3"]),
    ]
    for pattern, names in stated_at:
        for text, name in zip(stated("docs/guide/sweeps.md", pattern), names, strict=True):
            assert same(text, located[name]), (name, text, located[name])
    sw = sweep("s", np.linspace(0.119, 0.127, 9) / 0.6225, beta=math.pi / 3, phi=0.42, v0=0.87)
    grazing, fold = analytic_ends(sw, math.pi / 3)
    for pattern in (
        r"fold \(analytic (0\.\d+) and (0\.\d+);",
        r"gains an impact at (0\.\d+) \(down\), 4:1 folds at (0\.\d+) \(up\)",
    ):
        lo, hi = stated("docs/guide/sweeps.md", pattern)
        assert same(lo, grazing) and same(hi, fold), (lo, hi, grazing, fold)
