"""The default target's cold wall time, this tree against a baseline commit, measured in one run.

    .venv/bin/python benchmarks/bench_default_target.py [BASELINE] [--rounds N] [--warm] [--out FILE]

Each run starts from nothing, as a fresh clone does: a scratch copy of the files (the baseline commit's, from
`git archive`, or this working tree's: the files git tracks and new ones it does not ignore), no results,
numba's cache empty (a directory of its own), the same Python environment; then `snakemake --cores 2` (the
default target at the configured preset).  Per run: the wall seconds, the CPU seconds of all its processes as the
operating system counts them (Snakemake's and every job's, user and system), the jobs run, and from the jobs' own
benchmark files (sampled) the sum of their wall and CPU seconds.  With ``--rounds N`` the two alternate N times (baseline first) and
each side's fastest run is reported, so that a noisy stretch of a shared machine slows one round of each.  The
baseline defaults to ``HEAD`` (the last commit, against the uncommitted tree).  Prints a Markdown table
with the machine and the command; ``--out`` also writes it to a file; ``--keep DIR`` keeps both sides' results of
the last round (``DIR/baseline``, ``DIR/this``), for ``tools/same_results.py DIR/baseline DIR/this``.  With
``--warm`` each side runs again in the same place from the results as cloned, with the numba cache its cold run
filled: the wall and CPU seconds left when nothing is compiled (the difference is what compiling costs), and a second
table of what bounds this tree's cold wall time, measured in the same run (:func:`bounds`).
"""
from __future__ import annotations

import argparse
import contextlib
import csv
import io
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import pandas as pd
import psutil

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_devices import ROOT, publish, scratch_copy  # noqa: E402


def baseline_copy(rev: str, dest: Path) -> Path:
    """The files of commit ``rev`` in ``dest``."""
    data = subprocess.run(["git", "archive", "--format=tar", rev], cwd=ROOT, capture_output=True, check=True).stdout
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        tar.extractall(dest, filter="data")
    return dest


def fresh_mtimes(tree: Path) -> Path:
    """Every file of ``tree`` given one modification time, as a fresh clone has them (a copy that kept the working
    tree's times would leave a figure newer than the code that draws it, and Snakemake would not redraw it)."""
    now = time.time()
    for f in tree.rglob("*"):
        if f.is_file():
            os.utime(f, (now, now))
    return tree


def last_measure(bench_file: Path) -> dict | None:
    """The last row of a Snakemake benchmark file (``s``: wall seconds, ``cpu_time``), None where it has none."""
    with bench_file.open() as fh:
        rows = list(csv.DictReader(fh, delimiter="\t"))
    return rows[-1] if rows else None


def job_seconds(bench_dir: Path) -> tuple[int, float, float]:
    """Jobs, and the sums of their wall and CPU seconds, from a run's Snakemake benchmark files."""
    n, wall, cpu = 0, 0.0, 0.0
    for f in bench_dir.rglob("*.tsv"):
        if row := last_measure(f):
            n, wall, cpu = n + 1, wall + float(row["s"]), cpu + float(row["cpu_time"])
    return n, wall, cpu


def children_cpu() -> float:
    """User and system CPU seconds of every process this one started and waited for (and of theirs, down the tree
    whose parents waited for them), as the operating system counts them."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


#: the cores the default target runs on (``snakemake --cores CORES``)
CORES = 2
#: what a job loads before it computes anything: Snakemake's script preamble, the arrays, the datasets and their
#: files, the compiler and the package's dataset writer (a job loads these at least; most load more)
STARTUP = ("snakemake.script", "numpy", "xarray", "netCDF4", "numba", "vibroimpact.datasets")
#: what every job of a tree that has it imports before anything else: its garbage collector's settings
JOB_FIRST = "vibroimpact.outputs.job"


def startup_code(tree: Path) -> str:
    """A job's start-up in ``tree`` (:data:`STARTUP`, after :data:`JOB_FIRST` where the tree has that module), as
    Python code."""
    first = [JOB_FIRST] if (tree / "src" / Path(*JOB_FIRST.split("."))).with_suffix(".py").is_file() else []
    return "import " + ", ".join(first + list(STARTUP))


def run_alone_seconds(log: str, tree: Path, cores: int = CORES) -> float:
    """The wall seconds, from their benchmark files, of the jobs a run's Snakemake output ``log`` shows claiming all
    ``cores`` (``threads: N``; the timed ones, which run alone while the other cores wait)."""
    total = 0.0
    for block in re.split(r"\n(?=(?:local)?rule \S+:\n)", log):
        bench = re.search(r"^\s+benchmark: (\S+)$", block, re.M)
        threads = re.search(r"^\s+threads: (\d+)$", block, re.M)
        if bench and threads and int(threads.group(1)) >= cores and (tree / bench.group(1)).is_file():
            row = last_measure(tree / bench.group(1))
            total += float(row["s"]) if row else 0.0
    return total


def startup_cpu(env: dict, tree: Path, repeats: int = 3) -> float:
    """The CPU seconds of starting one job of ``tree`` (:func:`startup_code` in a fresh interpreter), the least of
    ``repeats``."""
    best = math.inf
    for _ in range(repeats):
        cpu0 = children_cpu()
        subprocess.run([sys.executable, "-c", startup_code(tree)], env=env, check=True)
        best = min(best, children_cpu() - cpu0)
    return best


def bounds(row: dict, cores: int = CORES, goal: float = 60.0) -> pd.DataFrame:
    """What bounds a tree's cold wall time (``row``: :func:`cold_default_target`'s with ``warm``), each part as wall
    seconds on ``cores``: the floor every schedule meets (the CPU seconds of all processes over the cores) and the
    parts of it the run measured (compiling: the cold run's CPU less the warm one's, which must have run the same
    jobs; starting the jobs: the jobs times one job's start-up, :func:`startup_cpu`; Snakemake's own process; the
    rest: the jobs' computing), the cores left idle beside the jobs that run alone, and the goal (its CPU seconds:
    ``goal`` times the cores)."""
    if row["benchmarked jobs (warm cache)"] != row["benchmarked jobs"]:
        raise ValueError(f"the warm run ran {row['benchmarked jobs (warm cache)']} benchmarked jobs, the cold run "
                         f"{row['benchmarked jobs']}: their CPU seconds differ by more than compiling")
    floor = row["CPU seconds (cold)"] / cores
    compiling = (row["CPU seconds (cold)"] - row["CPU seconds (warm cache)"]) / cores
    starting = row["benchmarked jobs"] * row["start-up CPU seconds per job"] / cores
    snakemake = row["Snakemake's own CPU seconds"] / cores
    alone = row["run-alone jobs' wall seconds"]
    parts = [
        ("the cold wall time", row["wall seconds (cold)"], "measured"),
        (f"floor: the CPU seconds of all processes / {cores} cores", floor, "no schedule finishes sooner"),
        ("of it, compiling the kernels", compiling, "(cold CPU - warm CPU, the same jobs) / cores"),
        ("of it, starting the jobs", starting,
         f"{row['benchmarked jobs']} jobs x {row['start-up CPU seconds per job']:.2f} CPU s each / cores"),
        ("of it, Snakemake's own process", snakemake, "its CPU seconds / cores"),
        ("of it, the jobs' computing", floor - compiling - starting - snakemake, "the rest of the floor"),
        ("cores idle beside the jobs that run alone (timed)", alone * (cores - 1) / cores,
         f"their wall seconds ({alone:.1f}) x {cores - 1}/{cores}"),
        (f"the goal: CPU seconds of at most {goal * cores:.0f} / cores", goal, ""),
    ]
    return pd.DataFrame(parts, columns=["part", "wall seconds on the cores", "how"]).round(1)


def default_target(tree: Path, env: dict, *args: str) -> dict:
    """``snakemake --cores 2 ARGS`` in ``tree``: its wall seconds, the CPU seconds of all its processes (Snakemake and
    every job) and of Snakemake's own process alone (its last reading, every 0.2 s, before it ended), the jobs, their
    wall and CPU seconds, and the wall seconds of the jobs that ran alone."""
    cpu0, t0 = children_cpu(), time.perf_counter()
    with tempfile.TemporaryFile("w+") as out:
        run = subprocess.Popen([sys.executable, "-m", "snakemake", "--cores", str(CORES), *args], cwd=tree, env=env,
                               stdout=out, stderr=subprocess.STDOUT, text=True)
        own = 0.0
        with contextlib.suppress(psutil.Error):
            proc = psutil.Process(run.pid)
            while run.poll() is None:
                times = proc.cpu_times()
                own = times.user + times.system
                time.sleep(0.2)
        if run.wait():
            out.seek(0)
            raise subprocess.CalledProcessError(run.returncode, run.args, out.read()[-3000:])
        wall, cpu = time.perf_counter() - t0, children_cpu() - cpu0
        out.seek(0)
        log = out.read()
    n, job_wall, job_cpu = job_seconds(tree / "benchmarks")
    return {"wall": wall, "cpu": cpu, "snakemake": own, "jobs": n, "job_wall": job_wall, "job_cpu": job_cpu,
            "alone": run_alone_seconds(log, tree)}


def cold_default_target(tree: Path, where: Path, warm: bool = False) -> dict:
    """The default target in ``tree`` with an empty numba cache under ``where``; with ``warm``, then again from no
    results with the cache that run filled (what compiling cost: the difference)."""
    env = os.environ | {"NUMBA_CACHE_DIR": str(where / "numba"), "PYTHONPATH": str(tree / "src")}
    env.pop("VIRTUAL_ENV", None)
    if warm:
        shutil.copytree(tree / "results", where / "results-as-cloned")
    cold = default_target(tree, env)
    row = {"wall seconds (cold)": cold["wall"], "CPU seconds (cold)": cold["cpu"], "benchmarked jobs": cold["jobs"],
           "jobs' wall seconds": cold["job_wall"], "jobs' CPU seconds": cold["job_cpu"],
           "Snakemake's own CPU seconds": cold["snakemake"], "run-alone jobs' wall seconds": cold["alone"]}
    if warm:  # the same paths (numba's cache is keyed by the source files' paths), the results as cloned
        shutil.move(tree / "results", where / "results-cold")
        shutil.copytree(where / "results-as-cloned", tree / "results")
        fresh_mtimes(tree / "results")
        shutil.rmtree(tree / ".snakemake")
        for f in (tree / "benchmarks").rglob("*.tsv"):
            f.unlink()
        # every job of the cold run again: the cloned figures left newer than the sources would let Snakemake skip
        # the jobs that draw them from results it no longer has
        again = default_target(tree, env, "--forceall")
        row |= {"benchmarked jobs (warm cache)": again["jobs"],
                "wall seconds (warm cache)": again["wall"], "CPU seconds (warm cache)": again["cpu"],
                "jobs' CPU seconds (warm cache)": again["job_cpu"], "start-up CPU seconds per job": startup_cpu(env, tree)}
        shutil.rmtree(tree / "results")
        shutil.move(where / "results-cold", tree / "results")
    return row


def main(baseline: str = "HEAD", rounds: int = 1, keep: str | None = None, warm: bool = False) -> pd.DataFrame:
    sides = {f"baseline ({baseline})": lambda d: baseline_copy(baseline, d), "this tree": scratch_copy}
    taken = [str(Path(keep) / name.split()[0]) for name in sides if keep and (Path(keep) / name.split()[0]).exists()]
    if taken:  # refused before the runs, not after the first one's minutes
        raise SystemExit(f"--keep {keep}: {', '.join(taken)} exists; allowed: a directory without baseline/ and this/")
    runs = {name: [] for name in sides}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(rounds):
            for name, copy in sides.items():
                where = Path(tmp) / f"{k}-{len(runs[name])}-{name.split()[0]}"
                (where / "tree").mkdir(parents=True)
                runs[name].append(cold_default_target(fresh_mtimes(copy(where / "tree")), where, warm))
                if keep and k == rounds - 1:  # the last round's results, to compare (tools/same_results.py)
                    shutil.copytree(where / "tree" / "results", Path(keep) / name.split()[0])
                shutil.rmtree(where)
    rows = [{"tree": name, **min(r, key=lambda x: x["wall seconds (cold)"])} for name, r in runs.items()]
    df = pd.DataFrame(rows)
    df["ratio to the baseline"] = (df["wall seconds (cold)"] / df["wall seconds (cold)"].iloc[0]).round(2)
    return df


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("baseline", nargs="?", default="HEAD")
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--out")
    ap.add_argument("--keep", help="copy each side's results of the last round to KEEP/baseline and KEEP/this")
    ap.add_argument("--warm", action="store_true", help="also run each side again with the numba cache it filled")
    a = ap.parse_args()
    df = main(a.baseline, a.rounds, a.keep, a.warm)
    table = df.round(2).to_markdown(index=False)
    if a.warm:  # what bounds this tree's cold wall time, from its cold and warm runs above
        table += ("\n\nWhat bounds this tree's cold wall time, from its runs above:\n\n"
                  + bounds(df.iloc[-1].to_dict()).to_markdown(index=False))
    publish(table, f"python benchmarks/bench_default_target.py {a.baseline} --rounds {a.rounds}{' --warm' * a.warm}",
            a.out)
