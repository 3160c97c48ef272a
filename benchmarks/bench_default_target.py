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
filled: the wall and CPU seconds left when nothing is compiled (the difference is what compiling costs).
"""
from __future__ import annotations

import argparse
import csv
import io
import os
import platform
import resource
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_devices import ROOT, scratch_copy  # noqa: E402


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


def job_seconds(bench_dir: Path) -> tuple[int, float, float]:
    """Jobs, and the sums of their wall and CPU seconds, from a run's Snakemake benchmark files."""
    n, wall, cpu = 0, 0.0, 0.0
    for f in bench_dir.rglob("*.tsv"):
        rows = list(csv.DictReader(f.open(), delimiter="\t"))
        if rows:
            n, wall, cpu = n + 1, wall + float(rows[-1]["s"]), cpu + float(rows[-1]["cpu_time"])
    return n, wall, cpu


def children_cpu() -> float:
    """User and system CPU seconds of every process this one started and waited for (and of theirs, down the tree
    whose parents waited for them), as the operating system counts them."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def default_target(tree: Path, env: dict) -> tuple[float, float, int, float, float]:
    """``snakemake --cores 2`` in ``tree``: its wall seconds, the CPU seconds of all its processes (Snakemake and
    every job), and the jobs, their wall and CPU seconds."""
    cpu0, t0 = children_cpu(), time.perf_counter()
    subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2"], cwd=tree, env=env, check=True,
                   capture_output=True)
    return time.perf_counter() - t0, children_cpu() - cpu0, *job_seconds(tree / "benchmarks")


def cold_default_target(tree: Path, where: Path, warm: bool = False) -> dict:
    """The default target in ``tree`` with an empty numba cache under ``where``; with ``warm``, then again from no
    results with the cache that run filled (what compiling cost: the difference)."""
    env = os.environ | {"NUMBA_CACHE_DIR": str(where / "numba"), "PYTHONPATH": str(tree / "src")}
    env.pop("VIRTUAL_ENV", None)
    if warm:
        shutil.copytree(tree / "results", where / "results-as-cloned")
    wall, cpu, n, job_wall, job_cpu = default_target(tree, env)
    row = {"wall seconds (cold)": wall, "CPU seconds (cold)": cpu, "benchmarked jobs": n,
           "jobs' wall seconds": job_wall, "jobs' CPU seconds": job_cpu}
    if warm:  # the same paths (numba's cache is keyed by the source files' paths), the results as cloned
        shutil.move(tree / "results", where / "results-cold")
        shutil.copytree(where / "results-as-cloned", tree / "results")
        fresh_mtimes(tree / "results")
        shutil.rmtree(tree / ".snakemake")
        for f in (tree / "benchmarks").rglob("*.tsv"):
            f.unlink()
        wall, cpu, _, _, job_cpu = default_target(tree, env)
        row |= {"wall seconds (warm cache)": wall, "CPU seconds (warm cache)": cpu,
                "jobs' CPU seconds (warm cache)": job_cpu}
        shutil.rmtree(tree / "results")
        shutil.move(where / "results-cold", tree / "results")
    return row


def main(baseline: str = "HEAD", rounds: int = 1, keep: str | None = None, warm: bool = False) -> pd.DataFrame:
    sides = {f"baseline ({baseline})": lambda d: baseline_copy(baseline, d), "this tree": scratch_copy}
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
    df = pd.DataFrame(rows).round(1)
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
    table = main(a.baseline, a.rounds, a.keep, a.warm).to_markdown(index=False)
    cpu = os.cpu_count()
    text = (f"{table}\n\nMachine: {platform.machine()}, {cpu} cores, {platform.system()} {platform.release()}, "
            f"Python {platform.python_version()}. Command: `python benchmarks/bench_default_target.py "
            f"{a.baseline} --rounds {a.rounds}{' --warm' * a.warm}` ({time.strftime('%Y-%m-%d', time.gmtime())}).\n")
    print(text)
    if a.out:
        Path(a.out).write_text(text)
