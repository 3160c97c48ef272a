"""The test command on a clean clone, this commit against a baseline commit, measured in one run.

    .venv/bin/python benchmarks/bench_suite.py BASELINE [--rounds N] [--out FILE]

Each side is what CI runs: a fresh ``git clone`` of the repository at the commit (the baseline, ``HEAD`` for this
one: commit a change before measuring it), then ``.ci/run`` in it (the virtual environment from the commit's
``requirements.lock``, the package, a one-node SLURM where the machine allows, and README's test command), with
every cache of the package empty (``XDG_CACHE_HOME`` a directory of its own: numba's compiled kernels and the
import cache start from nothing, as on CI; pip's cache of downloaded wheels is kept, so that the set-up's seconds
are the install's, not a download's).  Per run: the wall seconds of ``.ci/run`` (set-up and suite), the
seconds pytest reports for the suite alone, its counts (passed, failed, errors, skipped) and ``.ci/run``'s exit
status.  With ``--rounds N`` the two alternate N times (baseline first) and each side's fastest run is reported.
Prints a Markdown table with the machine and the command; ``--out`` also writes it to a file.  A side whose suite
fails is reported with its counts, not dropped; one whose ``.ci/run`` ends before pytest's summary (its set-up
failed) stops the benchmark with the end of its output.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_devices import ROOT, baseline_args, publish  # noqa: E402

#: the counts pytest's last line reports (``=== 1372 passed, 10 skipped in 611.23s (0:10:11) ===``)
COUNTS = ("passed", "failed", "errors", "skipped")


def summary(log: str) -> dict:
    """pytest's counts and seconds from the last summary line of ``log`` (a count it does not name: 0; no summary
    line: ValueError, naming the end of the log)."""
    lines = [ln for ln in log.splitlines() if re.search(r"\bin [0-9.]+s\b", ln) and "=" in ln]
    if not lines:
        raise ValueError(f"no pytest summary line in the log; its end: {log[-500:]!r}")
    last = lines[-1]
    counts = {k: 0 for k in COUNTS}
    for n, word in re.findall(r"(\d+) (passed|failed|errors?|skipped)\b", last):
        counts["errors" if word.startswith("error") else word] = int(n)
    return counts | {"seconds": float(re.search(r"\bin ([0-9.]+)s\b", last).group(1))}


def clone(rev: str, dest: Path) -> Path:
    """A fresh clone of this repository at commit ``rev`` in ``dest``."""
    subprocess.run(["git", "clone", "-q", str(ROOT), str(dest)], check=True)
    subprocess.run(["git", "checkout", "-q", rev], cwd=dest, check=True)
    return dest


def ci_run(tree: Path, cache: Path) -> dict:
    """``.ci/run`` in ``tree`` with the package's caches under ``cache``: its wall seconds, exit status and pytest's
    :func:`summary`."""
    pip_cache = os.environ.get("PIP_CACHE_DIR") or str(Path.home() / ".cache" / "pip")
    env = os.environ | {"XDG_CACHE_HOME": str(cache), "PIP_CACHE_DIR": pip_cache}
    for var in ("VIRTUAL_ENV", "NUMBA_CACHE_DIR", "PYTHONPATH"):  # nothing of the caller's environment leaks in
        env.pop(var, None)
    t0 = time.perf_counter()
    run = subprocess.run([str(tree / ".ci" / "run")], cwd=tree, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    return {"wall seconds of .ci/run": wall, "exit status": run.returncode, **summary(run.stdout + run.stderr)}


def rev_of(rev: str) -> str:
    """The short hash of ``rev``."""
    return subprocess.run(["git", "rev-parse", "--short", rev], cwd=ROOT, capture_output=True, text=True,
                          check=True).stdout.strip()


def main(baseline: str, rounds: int = 1) -> pd.DataFrame:
    sides = {f"baseline ({rev_of(baseline)})": baseline, f"this commit ({rev_of('HEAD')})": "HEAD"}
    runs = {name: [] for name in sides}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(rounds):
            for name, rev in sides.items():
                where = Path(tmp) / f"{k}-{name.split()[0]}"
                runs[name].append(ci_run(clone(rev, where / "tree"), where / "cache"))
    rows = [{"tree": name, **min(r, key=lambda x: x["wall seconds of .ci/run"])} for name, r in runs.items()]
    df = pd.DataFrame(rows)
    df["minutes of .ci/run"] = df["wall seconds of .ci/run"] / 60
    df["ratio to the baseline"] = (df["wall seconds of .ci/run"] / df["wall seconds of .ci/run"].iloc[0]).round(2)
    return df.round({"wall seconds of .ci/run": 1, "seconds": 1, "minutes of .ci/run": 1})


if __name__ == "__main__":
    a = baseline_args(__doc__, rounds=1)
    publish(main(a.baseline, a.rounds).to_markdown(index=False),
            f"python benchmarks/bench_suite.py {a.baseline} --rounds {a.rounds}", a.out)
