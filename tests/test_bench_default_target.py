"""benchmarks/bench_default_target.py: what bounds the default target's cold wall time, and its kept record."""
import importlib.util
import re
import sys

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "benchmarks"))  # the script imports its neighbour bench_devices
spec = importlib.util.spec_from_file_location("bench_default_target", ROOT / "benchmarks" / "bench_default_target.py")
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)

#: Snakemake's account of three jobs as a run prints it: one claiming both cores, one a single core, one claiming
#: both cores with no benchmark file
LOG = """\
[Sat Nov 28 14:27:02 2026]
localrule work_precision:
    output: results/bench/work_precision.nc
    jobid: 37
    benchmark: benchmarks/bench/work_precision.tsv
    threads: 2
    resources: tmpdir=/tmp

[Sat Nov 28 14:27:02 2026]
rule sweep:
    output: results/sweeps/a.nc
    benchmark: benchmarks/sweeps/a.tsv
    resources: tmpdir=/tmp

[Sat Nov 28 14:27:16 2026]
localrule all:
    jobid: 0
    threads: 2
"""


def _benchmark(path, seconds):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f"s\th:m:s\tcpu_time\n{seconds}\t0:00:{int(seconds):02d}\t{seconds / 2}\n")


def test_the_jobs_that_run_alone_are_those_claiming_every_core(tmp_path):
    _benchmark(tmp_path / "benchmarks/bench/work_precision.tsv", 14.25)
    _benchmark(tmp_path / "benchmarks/sweeps/a.tsv", 9.0)
    assert bench.run_alone_seconds(LOG, tmp_path, cores=2) == 14.25
    assert bench.run_alone_seconds(LOG, tmp_path, cores=3) == 0.0  # two threads of three: not alone
    assert bench.run_alone_seconds(LOG.replace("localrule", "rule"), tmp_path, cores=2) == 14.25


ROW = {"wall seconds (cold)": 159.1, "CPU seconds (cold)": 288.4, "CPU seconds (warm cache)": 184.4,
       "benchmarked jobs": 45, "start-up CPU seconds per job": 0.8, "run-alone jobs' wall seconds": 22.0,
       "Snakemake's own CPU seconds": 30.0, "benchmarked jobs (warm cache)": 45}


def test_the_floor_is_the_cpu_over_the_cores_and_its_parts_add_up_to_it():
    parts = dict(zip(*bench.bounds(ROW, cores=2, goal=60.0).iloc[:, :2].T.values))
    floor = parts["floor: the CPU seconds of all processes / 2 cores"]
    assert floor == pytest.approx(144.2, abs=0.05)
    assert parts["of it, compiling the kernels"] == pytest.approx(52.0, abs=0.05)
    assert parts["of it, starting the jobs"] == pytest.approx(18.0, abs=0.05)  # 45 x 0.8 / 2
    assert parts["of it, Snakemake's own process"] == pytest.approx(15.0, abs=0.05)
    assert parts["of it, the jobs' computing"] == pytest.approx(144.2 - 52.0 - 18.0 - 15.0, abs=0.1)
    assert parts["cores idle beside the jobs that run alone (timed)"] == pytest.approx(11.0, abs=0.05)
    assert parts["the goal: CPU seconds of at most 120 / cores"] == 60.0
    on_three = dict(zip(*bench.bounds(ROW, cores=3).iloc[:, :2].T.values))  # two of three cores wait
    assert on_three["cores idle beside the jobs that run alone (timed)"] == pytest.approx(22.0 * 2 / 3, abs=0.05)


def test_a_warm_run_of_other_jobs_is_refused():
    with pytest.raises(ValueError, match="the warm run ran 39 benchmarked jobs, the cold run 45"):
        bench.bounds(ROW | {"benchmarked jobs (warm cache)": 39})


def test_a_keep_directory_holding_a_side_s_results_is_refused_before_any_run(tmp_path, monkeypatch):
    (tmp_path / "this").mkdir()
    monkeypatch.setattr(bench, "cold_default_target", lambda *a: pytest.fail("ran before refusing"))
    with pytest.raises(SystemExit, match=f"--keep {tmp_path}: {tmp_path / 'this'} exists"):
        bench.main("HEAD", 1, str(tmp_path))


def _table(text, first_header):
    """The header and the rows of the Markdown table of ``text`` whose header starts with ``first_header``."""
    lines = text[text.index(first_header):].splitlines()
    block = lines[:next((i for i, line in enumerate(lines) if not line.startswith("|")), len(lines))]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in block]
    return rows[0], rows[2:]


def test_the_kept_record_bounds_its_own_cold_run():
    """The record the speed page includes: the bounds table is the one its first table's runs give."""
    text = (ROOT / "reference" / "bench_default_target.md").read_text()
    header, rows = _table(text, "| tree")
    this = dict(zip(header, rows[-1]))
    cores = int(re.search(r"(\d+) cores", text).group(1))
    bounds = {r[0]: float(r[1]) for r in _table(text, "| part")[1] if r[1]}
    cold, warm = float(this["CPU seconds (cold)"]), float(this["CPU seconds (warm cache)"])
    assert bounds["the cold wall time"] == pytest.approx(float(this["wall seconds (cold)"]), abs=0.06)
    assert bounds[f"floor: the CPU seconds of all processes / {cores} cores"] == pytest.approx(cold / cores, abs=0.06)
    assert bounds["of it, compiling the kernels"] == pytest.approx((cold - warm) / cores, abs=0.06)
    assert bounds["of it, Snakemake's own process"] == pytest.approx(
        float(this["Snakemake's own CPU seconds"]) / cores, abs=0.06)
    parts = [bounds[k] for k in bounds if k.startswith("of it")]
    assert len(parts) == 4
    assert sum(parts) == pytest.approx(cold / cores, abs=0.2)
    assert bounds["the cold wall time"] >= bounds[f"floor: the CPU seconds of all processes / {cores} cores"]


def test_a_job_s_start_up_is_measured_as_the_tree_s_jobs_start(tmp_path):
    """A tree whose scripts import the collector's settings first is probed with them first; an older tree
    (a baseline commit without the module) without them."""
    assert bench.startup_code(tmp_path) == "import " + ", ".join(bench.STARTUP)
    assert bench.startup_code(ROOT) == f"import {bench.JOB_FIRST}, " + ", ".join(bench.STARTUP)
    first = (ROOT / "workflow" / "scripts" / "sweep.py").read_text().split('"""')[2].strip().splitlines()[0]
    assert first.split("#")[0].strip() == f"import {bench.JOB_FIRST}"  # as the workflow's scripts start
