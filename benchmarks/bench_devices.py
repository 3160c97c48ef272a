"""The default target's cold wall time for the paper's device and for another device, measured in one run.

    .venv/bin/python benchmarks/bench_devices.py [device file] [quality]

Each run starts from nothing: the repository as a clone has it (a scratch copy of the files git tracks, no
results), numba's cache empty (its own cache directory), the same Python environment.  The paper's device
runs `snakemake --cores 2`, the other device `snakemake --cores 2 --configfile <device file>` in a second
scratch copy, one after the other.  Prints a Markdown table of the wall times and their ratio; the default
device file is the shipped example (config/example_device.yaml), the default preset `draft`.
Its helpers serve the other benchmarks too: the scratch copy of the files, the command line of a benchmark
against a commit (:func:`baseline_args`) and the record with its machine and command (:func:`publish`).
"""
import argparse
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]


def scratch_copy(dest: Path) -> Path:
    """The files git tracks (and new ones it does not ignore) copied to ``dest``."""
    files = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, capture_output=True,
                           check=True).stdout.decode().split("\0")
    for f in filter(None, files):
        if (ROOT / f).is_file():
            (dest / f).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / f, dest / f)
    return dest


def publish(table: str, command: str, out: str | None = None) -> str:
    """A benchmark's record: its Markdown ``table`` with the machine and the ``command`` that made it (and the date)
    below it; printed, and written to ``out`` where given."""
    text = (f"{table}\n\nMachine: {platform.machine()}, {os.cpu_count()} cores, {platform.system()} "
            f"{platform.release()}, Python {platform.python_version()}. Command: `{command}` "
            f"({time.strftime('%Y-%m-%d', time.gmtime())}).\n")
    print(text)
    if out:
        Path(out).write_text(text)
    return text


def baseline_args(doc: str, rounds: int) -> argparse.Namespace:
    """The command line of a benchmark of this tree against a commit: ``BASELINE [--rounds N] [--out FILE]``
    (``rounds`` by default; fewer than one refused, naming the value and what is allowed)."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("baseline")
    ap.add_argument("--rounds", type=int, default=rounds)
    ap.add_argument("--out")
    a = ap.parse_args()
    if a.rounds < 1:
        raise SystemExit(f"--rounds {a.rounds}: allowed: an integer >= 1")
    return a


def cold_run(args: list[str], where: Path) -> float:
    """Wall seconds of ``snakemake --cores 2 <args>`` in a fresh copy under ``where``, numba's cache empty."""
    clone = scratch_copy(where / "clone")
    env = {"NUMBA_CACHE_DIR": str(where / "numba"), "PYTHONPATH": str(clone / "src"),
           "PATH": f"{Path(sys.executable).parent}:/usr/bin:/bin", "HOME": str(where)}
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *args], cwd=clone, env=env, check=True,
                   capture_output=True)
    return time.perf_counter() - t0


def main(device_file: str = "config/example_device.yaml", quality: str = "draft") -> pd.DataFrame:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in (("paper's device", []), (Path(device_file).stem, ["--configfile", device_file])):
            where = Path(tmp) / name.replace(" ", "_").replace("'", "")
            where.mkdir()
            rows.append({"device": name, "command": " ".join(["snakemake --cores 2", *args]),
                         "wall seconds (cold)": round(cold_run([*args, "--config", f"quality={quality}"], where), 1)})
    df = pd.DataFrame(rows)
    df["ratio to the paper's"] = (df["wall seconds (cold)"] / df["wall seconds (cold)"].iloc[0]).round(2)
    return df


if __name__ == "__main__":
    print(main(*sys.argv[1:]).to_markdown(index=False))
