"""README.md's commands, run as a user runs them: in a scratch clone, as written, on an emulated other machine.

Every shell block of the documentation carries a marker naming the test that runs it (or `.ci/run`);
the tests here read the command from README.md itself, so what is tested is what a user is told.
"""

import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml
from conftest import DOCUMENTS, ROOT, _copy_workflow, readme_command, run_readme, shell_blocks

DOCS = DOCUMENTS


def test_every_shell_command_in_the_docs_is_run_by_a_test():
    """Each shell block of README.md and the docs names the test that executes it (as written, or its
    code path at a smaller preset) or `.ci/run`, and that test exists."""
    blocks = [(doc, *b) for doc in DOCS if doc.exists() for b in shell_blocks(doc)]
    assert len(blocks) >= 6
    for doc, kind, target, cmd in blocks:
        assert kind, f"{doc.name}: a shell block with no 'tested by' or 'run by' marker:\n{cmd}"
        if kind == "run by":
            assert target == ".ci/run", target
            assert cmd in (ROOT / ".ci" / "run").read_text().splitlines(), f".ci/run does not run `{cmd}`"
            continue
        path, _, name = target.partition("::")
        assert (ROOT / path).is_file(), target
        assert re.search(rf"^def {re.escape(name)}\(", (ROOT / path).read_text(), re.M), f"{target}: no such test"


def test_ci_runs_readme_s_set_up_and_test_command():
    """`.ci/run` sets up as the first command does (its install steps, the same words) and then runs
    exactly README's test command."""
    first = readme_command("tests/test_readme.py::test_the_first_command_sets_up_and_runs_the_default_target")
    ci = (ROOT / ".ci" / "run").read_text()
    for step in first.split(" && ")[:-1]:  # everything but the workflow run
        assert step.replace(".venv/bin/pip install", ".venv/bin/pip install -q") in ci, step


@pytest.mark.slow
def test_the_first_command_sets_up_and_runs_the_default_target(readme_clone):
    """From a fresh clone, under the other libm: a venv with the locked versions, the package, and the
    default target's figures, tables and datasets."""
    clone, first, _ = readme_clone
    assert first.returncode == 0, (first.stdout + first.stderr)[-3000:]
    for f in ("results/figures/fig0.png", "results/figures/fig5.png", "results/figures/figBiS.png",
              "results/tables/table1.md", "results/checks/paper_values.csv", "results/tables/workflow_cost.md"):
        assert (clone / f).stat().st_size > 500, f
    # the locked versions, not whatever a resolver picks today
    pins = dict(re.findall(r"^([A-Za-z0-9_.-]+)==(\S+)", (ROOT / "requirements.lock").read_text(), re.M))
    got = subprocess.run([clone / ".venv" / "bin" / "python", "-m", "pip", "list", "--format=freeze"],
                         capture_output=True, text=True, check=True).stdout
    have = dict(line.split("==") for line in got.split() if "==" in line)
    norm = lambda n: re.sub(r"[-_.]+", "-", n).lower()
    have = {norm(k): v for k, v in have.items()}
    for name in ("numpy", "scipy", "numba", "llvmlite", "matplotlib", "xarray", "snakemake", "netcdf4", "pandas"):
        assert have[name] == pins[name], (name, have[name], pins[name])
    # the package's bytecode written before the first job (Snakefile's onstart), for every module, those no job
    # imports too, whether or not Python writes bytecode itself
    missing = [p for p in (clone / "src" / "vibroimpact").rglob("*.py")
               if not Path(importlib.util.cache_from_source(str(p))).is_file()]
    assert not missing, missing
    # a figure that did not change is not rewritten: every figure whose drawn arrays are the committed
    # reference's to rounding (the check's strict tolerance, every array) keeps its committed PNG, which git sees
    # unchanged; under the other libm those whose arrays ride on chaotic runs, statistics or timings move, and
    # are drawn anew
    checks = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["figure_checks"]

    def to_rounding(a, b):
        if a.dtype.kind not in "fiub" or b.dtype.kind not in "fiub":
            return a.equals(b)
        return a.shape == b.shape and np.allclose(a.values.astype(float), b.values.astype(float), equal_nan=True,
                                                  rtol=checks["rtol"], atol=checks["atol"])

    changed = subprocess.run(["git", "-C", str(clone), "status", "--porcelain", "--", "results/figures"],
                             capture_output=True, text=True, check=True).stdout.split("\n")
    changed = {Path(line[3:]).stem for line in changed if line.strip()}
    same = set()
    for ref in (clone / "reference" / "figures").glob("*.nc"):
        new, old = (xr.load_dataset(p) for p in (clone / "results" / "figures" / "data" / ref.name, ref))
        if set(new.data_vars) == set(old.data_vars) and all(to_rounding(new[v], old[v]) for v in old.data_vars):
            same.add(ref.stem)
    assert len(same) >= 5 and not same & changed, same & changed


@pytest.mark.slow
def test_the_check_passes_under_another_libm(readme_clone):
    """README's check command, run after the first under glibc's other libm code path, passes: every
    published value reproduced or a listed discrepancy, every figure's arrays by the rule its figure declared
    from what produced them: pointwise for exact values, never for what rides on a chaotic run, a statistic,
    a method's error or a timing."""
    from vibroimpact.outputs.conditioning import libm_switch_works
    from vibroimpact.outputs.figcheck import NOT_POINTWISE

    if not libm_switch_works():
        pytest.skip("glibc does not dispatch sin on FMA/AVX2 here: the libm switch emulates nothing on this CPU")
    clone, _, check = readme_clone
    assert check.returncode == 0, (check.stdout + check.stderr)[-4000:]
    df = pd.read_csv(clone / "results" / "checks" / "paper_values.csv")
    assert len(df) > 50 and set(df["status"]) <= {"pass", "known discrepancy"}
    assert (df["status"] == "pass").sum() > 50
    assert df.loc[df["status"] == "known discrepancy", "note"].str.len().min() > 20
    figs = pd.read_csv(clone / "results" / "checks" / "figures.csv")
    assert set(figs["status"]) <= {"pass", "excluded"} and figs["figure"].nunique() >= 14
    assert (figs["rule"] == "strict").sum() > 500
    # the sweeps' clouds, the maps, the continuation curves, the methods' errors and the chaotic run's outcomes
    # were compared by what is well-posed; nothing whose provenance forbids it pointwise
    assert {"motions", "curve", "magnitude", "outcome", "timing"} <= set(figs["rule"])
    assert not (figs["provenance"].isin(NOT_POINTWISE) & (figs["rule"] == "strict")).any()
    md = (clone / "results" / "checks" / "figures.md").read_text()
    assert "chaotic run: computed along a chaotic trajectory" in md and "spread " in md


@pytest.mark.slow
def test_the_study_command_builds_its_figure(readme_clone):
    """README's rerun for a new incline and restitution, after the default target: the study's branches,
    sweep, energies, figure and figure data; its branches are the API's orbits."""
    import vibroimpact as vi

    clone, first, _ = readme_clone
    assert first.returncode == 0
    res = run_readme(clone, readme_command("tests/test_readme.py::test_the_study_command_builds_its_figure"))
    assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
    key = "beta-0.4000_r-0.6000"
    study = clone / "results" / "studies" / key
    assert (study / "study.png").stat().st_size > 10_000
    data = xr.load_dataset(study / "study-figure-data.nc")
    assert len(data.data_vars) > 10
    sw = xr.load_dataset(clone / "results" / "sweeps" / key / "study_s.nc")
    assert sw.attrs["r"] == 0.6 and abs(sw.attrs["beta"] - 0.4) < 1e-15
    assert (clone / "results" / "energy" / key / "study_s.nc").exists()
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    ph = cfg["physics"]
    for word in ("BT", "BBT"):
        br = xr.load_dataset(clone / "results" / "branches" / key / f"orbit-{word}_vary-s.nc")
        assert br.attrs["status"] != "failed", br.attrs.get("reason")
        good = np.flatnonzero(br.admissible.values & br.stable.values)  # where the simulator follows the word
        assert good.size > 10
        for i in good[[0, good.size // 2, -1]]:
            p = vi.Params.from_physical(s=float(br.s[i]), beta=0.4, M=ph["M"], F=ph["F"], omega=ph["omega"],
                                        r=0.6, g=ph["g"])
            o = vi.find_orbit(p, word, float(br.phase[i, 0]), float(br.v_minus[i, 0]), k=int(br.attrs.get("k", 1)))
            assert np.allclose(o.v_minus, br.v_minus[i].values, rtol=0, atol=1e-9), (word, i)
    # the study adds its jobs only: a second run has nothing to do
    again = run_readme(clone, readme_command("tests/test_readme.py::test_the_study_command_builds_its_figure")
                       + " -n")
    assert "Nothing to be done" in again.stdout + again.stderr


@pytest.mark.slow
def test_the_device_command_runs_the_example_device(readme_clone):
    """README's line for a device of one's own, after the default target, at the smoke preset (its path at a
    smaller preset: the device's scenes, sweeps and maps at fewer points; the draft preset's path is the first
    command's): the example device's whole default target runs into its own folder; the paper's results are not
    written over; its datasets name the device; its paper-value check compares only what holds for any device."""
    clone, first, _ = readme_clone
    assert first.returncode == 0
    paper = sorted((clone / "results" / "figures").glob("*.png")) + [clone / "results" / "checks" / "paper_values.csv"]
    before = {p: p.read_bytes() for p in paper}
    device = yaml.safe_load((ROOT / "config" / "example_device.yaml").read_text())
    res = run_readme(clone, readme_command("tests/test_readme.py::test_the_device_command_runs_the_example_device")
                     + " --config quality=smoke")
    assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
    assert all(p.read_bytes() == b for p, b in before.items())  # the paper's results untouched
    root = clone / "results" / "devices" / device["device"]
    drawn = {p.name for p in (root / "results" / "figures").glob("*.png")}
    # every figure of the paper's default target, but the check's own maps and the speed-and-accuracy
    # figures (they measure the simulator on the paper's device whatever the config)
    bench = {"work_precision.png", "failure_map.png", "analytics_accuracy.png", "lyapunov_precision.png"}
    default = {p.name for p in paper if p.suffix == ".png" and not p.name.startswith(("bifurcation_set", "design_map"))}
    assert bench <= default and default - bench <= drawn, (default - bench) - drawn
    assert not drawn & bench
    sw = xr.load_dataset(root / "results" / "sweeps" / "beta-1.0472_r-0.5000" / "fig0_s.nc")
    assert sw.attrs["device"] == device["device"] and sw.attrs["device_M"] == device["physics"]["M"]
    assert (root / "results" / "checks" / "paper_values.md").read_text().startswith(
        f"Device {device['device']}, not the paper's")
    check = (root / "results" / "checks" / "paper_values.csv").read_text()
    assert "not compared" in check and ",fail," not in check  # what holds for any device passes


@pytest.mark.slow
def test_a_changed_impact_law_fails_the_figure_check(tmp_path):
    """The check catches a change of the science that the other machine's libm does not make: the package's
    restitution moved in its fifth digit (every device's r -> 1.00002 r where Params are made from physical
    values, in a private copy of the package the workflow imports) moves Fig 2's branches beyond the strict
    tolerance, and checking that figure fails, naming its arrays.  (The same change made in the config is
    another device, whose figures the reference check does not compare.)"""
    _copy_workflow(tmp_path)
    shutil.copytree(ROOT / "src", tmp_path / "pkg", ignore=shutil.ignore_patterns("__pycache__"))
    params = tmp_path / "pkg" / "vibroimpact" / "dynamics" / "params.py"
    law = "        return cls(d=d, gbar=gbar, r=r, scales=scales, physical=phys)\n"
    assert law in params.read_text()
    params.write_text(params.read_text().replace(law, law.replace("r=r,", "r=r * 1.00002,")))
    # numba's cache is the package's (its compiled modules are unchanged: the restitution is a kernel's argument)
    env = os.environ | {"PYTHONPATH": str(tmp_path / "pkg")}
    res = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", "results/checks/figures/fig2.csv"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=900, env=env)
    out = res.stdout + res.stderr
    assert res.returncode != 0
    assert "fig2 differs from its reference" in out, out[-3000:]
    assert re.search(r"\|\s*fig2\s*\|\s*a\d+_line\d+_[xy]\s*\|.*\|\s*strict\s*\|.*\|\s*fail\s*\|", out), out[-3000:]


def _slice(tmp_path, targets):
    _copy_workflow(tmp_path)
    res = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *targets], cwd=tmp_path,
                         capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stderr[-3000:]
    return [xr.load_dataset(tmp_path / t) for t in targets]


@pytest.mark.slow
def test_the_same_config_gives_identical_datasets(tmp_path):
    """Two runs of the same config on one machine write the same datasets bit for bit (a sweep with its
    chaotic points' long runs, a branch with its located critical points), all but their creation time."""
    targets = ["results/sweeps/beta-0.5236_r-0.5000/figBiS.nc",
               "results/branches/beta-1.0472_r-0.5000/orbit-BBT_vary-s.nc"]
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    for x, y in zip(_slice(tmp_path / "a", targets), _slice(tmp_path / "b", targets), strict=True):
        assert x.attrs.pop("created") and y.attrs.pop("created")
        xr.testing.assert_identical(x, y)


def test_the_lock_pins_every_package_with_hashes_and_the_conda_env_alike():
    """requirements.lock: exact versions with hashes, one version per package for every Python and
    platform; workflow/envs/pins.txt the same versions; pyproject.toml keeps ranges."""
    lock = (ROOT / "requirements.lock").read_text()
    pins = re.findall(r"^([A-Za-z0-9_.-]+)==(\S+?)(?: ;.*)? \\$", lock, re.M)
    names = [n for n, _ in pins]
    assert len(pins) > 50 and len(set(names)) == len(names)
    for name in ("numpy", "scipy", "numba", "matplotlib", "snakemake", "heyoka", "snakemake-executor-plugin-slurm"):
        assert name in names, name
    lines = lock.splitlines()
    for i, line in enumerate(lines):
        if re.match(r"^[A-Za-z0-9]", line):
            assert lines[i + 1].strip().startswith("--hash=sha256:"), f"{line}: no hashes"
    env = (ROOT / "workflow" / "envs" / "pins.txt").read_text()
    assert sorted(re.findall(r"^([A-Za-z0-9_.-]+==\S+)", env, re.M)) == sorted(f"{n}=={v}" for n, v in pins)
    assert "-r pins.txt" in (ROOT / "workflow" / "envs" / "vibroimpact.yaml").read_text()
    deps = (ROOT / "pyproject.toml").read_text()
    assert '"numpy>=' in deps and "numpy==" not in deps


def test_the_libm_switch_changes_sin_where_glibc_dispatches_it():
    """The emulated other machine is another machine: with the switch, numpy's and numba's sin differ in
    the last bit for some arguments (skipped on a CPU whose glibc takes one path anyway)."""
    from vibroimpact.outputs.conditioning import LIBM_SWITCH, libm_switch_works

    code = ("import math, numpy as np, numba, hashlib\n"
            "x = np.random.default_rng(2).uniform(-50, 50, 100000)\n"
            "f = numba.njit(lambda a: np.array([math.sin(v) for v in a]))\n"
            "print(hashlib.sha1(f(x).tobytes()).hexdigest(), hashlib.sha1(np.sin(x).tobytes()).hexdigest())")
    out = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          env=os.environ | env).stdout.split() for env in ({}, LIBM_SWITCH)]
    numba_differs, numpy_differs = out[0][0] != out[1][0], out[0][1] != out[1][1]
    assert libm_switch_works() == numpy_differs == numba_differs
    if not numpy_differs:
        pytest.skip("glibc does not dispatch sin on FMA/AVX2 here: the switch changes nothing on this CPU")


@pytest.mark.slow
def test_a_study_whose_branches_cannot_start_records_why_and_still_draws(readme_clone):
    """README's study command for a restitution where no 1:1 or 2:1 impact orbit is the attractor at the
    branches' start (r = 0.05: the ball chatters into sticking): the branches' datasets record the failure
    and its reason, not a traceback, and the study's sweep, energy and figure are still made."""
    clone, first, _ = readme_clone
    assert first.returncode == 0
    cmd = readme_command("tests/test_readme.py::test_the_study_command_builds_its_figure")
    res = run_readme(clone, cmd.replace("r: 0.6", "r: 0.05"))
    assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
    key = "beta-0.4000_r-0.0500"
    for word in ("BT", "BBT"):
        br = xr.load_dataset(clone / "results" / "branches" / key / f"orbit-{word}_vary-s.nc")
        assert br.attrs["status"] == "failed" and "with sticking" in br.attrs["reason"], br.attrs
    assert (clone / "results" / "studies" / key / "study.png").stat().st_size > 10_000
    assert "Traceback" not in res.stderr


@pytest.mark.slow
def test_the_bench_target_times_the_simulator(readme_clone):
    """README's benchmark command after the default target: the simulator's timings and accuracy against
    the 40-digit reference, as a dataset and the table README quotes."""
    clone, first, _ = readme_clone
    assert first.returncode == 0
    res = run_readme(clone, readme_command("tests/test_readme.py::test_the_bench_target_times_the_simulator"))
    assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
    ds = xr.load_dataset(clone / "results" / "bench" / "simulator.nc")
    assert len(ds.data_vars) >= 3
    table = (clone / "results" / "tables" / "bench_simulator.md").read_text()
    assert "exact simulator" in table and "solve_ivp" in table


@pytest.mark.slow
def test_the_lock_refresh_resolves_the_project_s_ranges(tmp_path):
    """README's command to refresh the lock, in a scratch clone: it resolves pyproject.toml's ranges with
    the extras into a hashed lock and the conda environment's pins, the same versions in both, every
    dependency of pyproject.toml pinned (the versions themselves move with new releases)."""
    from conftest import scratch_clone

    clone = scratch_clone(tmp_path)
    res = run_readme(clone, readme_command("tests/test_readme.py::test_the_lock_refresh_resolves_the_project_s_ranges"),
                     timeout=900)
    assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
    lock = (clone / "requirements.lock").read_text()
    pins = dict(re.findall(r"^([A-Za-z0-9_.-]+)==(\S+?)(?: ;.*)? \\$", lock, re.M))
    env = dict(re.findall(r"^([A-Za-z0-9_.-]+)==(\S+?)(?: ;.*)?$", (clone / "workflow" / "envs" / "pins.txt").read_text(), re.M))
    assert pins and pins == env
    wanted = re.findall(r'"([A-Za-z0-9_.-]+)(?:\[[^]]*\])?[<>=!~]', (ROOT / "pyproject.toml").read_text())
    norm = lambda n: re.sub(r"[-_.]+", "-", n).lower()
    missing = {norm(w) for w in wanted if w not in ("setuptools",)} - {norm(n) for n in pins}
    assert not missing, missing


def test_the_api_example_runs():
    """README's ten lines, run as written, print what README shows under them (every line, to the digits
    printed: the critical points are refined to 1e-10 and the interval's ends located to 1e-7, and none of the
    printed values lies within 1e-8 of a rounding boundary of its last digit), and what README says of the
    output holds: B is where the orbit crosses the wall, the second grazing is on the saddle past the fold, and
    the bistable interval holds the 2:1 one way and the 3:1 the other."""
    import contextlib
    import io

    text = (ROOT / "README.md").read_text()
    found = re.search(r"<!-- tested by tests/test_readme.py::test_the_api_example_runs -->\n```python\n(.*?)```\n"
                      r"\nIt prints \(the test runs the lines above and compares what they print with this\):\n\n"
                      r"```text\n(.*?)```", text, re.S)
    assert found, "README's example and the output block under it"
    code, shown = found.groups()
    assert len(code.strip().splitlines()) <= 12
    out = io.StringIO()
    scope = {}
    with contextlib.redirect_stdout(out):
        exec(compile(code, "README.md", "exec"), scope)
    printed = [line.rstrip() for line in out.getvalue().splitlines()]
    assert printed == shown.rstrip("\n").splitlines()
    br, sw = scope["br"], scope["sw"]
    kinds = list(br.critical_kind.values)
    assert kinds[0] == "B" and not br.critical_admissible.values[0]
    assert br.critical_d.values[0] < br.critical_d.values[kinds.index("grazing")]  # B below G1
    fold = int(np.argmax(br.d.values))
    last = int(np.argmin(abs(br.d.values[fold:] - br.critical_d.values[-1]))) + fold
    assert kinds[-1] == "grazing" and br.stability.values[last] == "saddle"
    assert not br.stable.values[fold + 1:].any() and br.stable.values[fold - 5:fold].all()
    vi = scope["vi"]
    iv = vi.bistable_intervals(sw, vi.locate_transitions(sw))
    assert {str(iv.label_up.values[0]).split()[0], str(iv.label_down.values[0]).split()[0]} == {"2:1", "3:1"}


@pytest.mark.slow
def test_the_readme_states_what_the_check_finds(readme_clone):
    """What README.md says of the check holds in its results: no published value fails (README types no
    count: the check's report gives them)."""
    clone, _, check = readme_clone
    assert check.returncode == 0
    df = pd.read_csv(clone / "results" / "checks" / "paper_values.csv")
    counts = df["status"].value_counts()
    assert counts["pass"] > 0 and counts.get("fail", 0) == 0
    text = " ".join((ROOT / "README.md").read_text().split())
    assert "to the digits printed or explains the difference with evidence a test reproduces" in text
    assert not re.search(r"reproduces \d+|explains \d+", text)
