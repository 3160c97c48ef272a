"""The test suite's durations, for the testing page: what a whole run measured, kept in the repository.

    .venv/bin/python tools/test_durations.py keep [CSV]     # results/tests/durations.csv -> reference/test_durations.csv
    .venv/bin/python tools/test_durations.py table          # the page's Markdown table, from the kept record

A run of the whole suite (README's test command: no paths, no ``-m``, no ``-k``) leaves every test's seconds
(setup, call and teardown summed) and the run's wall time in ``results/tests/durations.csv`` (tests/conftest.py).
``keep`` copies that record to ``reference/test_durations.csv`` with the machine it ran on; ``table`` writes the
testing page's table from it (the docs build calls :func:`table`): the whole run, what bounds its wall time (the
tests' seconds over the processes, and the tests that share README's scratch clone, in one process), the slowest
tests, and the seconds of each test file.
"""
from __future__ import annotations

import os
import platform
import re
import sys
import time
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
RUN = ROOT / "results" / "tests" / "durations.csv"
KEPT = ROOT / "reference" / "test_durations.csv"
#: the row of the whole run's wall time
WHOLE = "(the whole run, wall)"
#: the slowest tests the table lists
SLOWEST = 15
#: the pytest-xdist group of the tests that share README's scratch clone (tests/conftest.py)
CLONE_GROUP = "readme_clone"


def keep(src: Path = RUN, dest: Path = KEPT) -> Path:
    """Copy a run's record to ``dest``, headed by the machine and the date."""
    df = pd.read_csv(src)
    if WHOLE not in set(df.test):
        raise ValueError(f"{src}: not the record of a whole run (no row {WHOLE!r})")
    head = (f"# {platform.machine()}, {os.cpu_count()} cores, {platform.system()} {platform.release()}, Python "
            f"{platform.python_version()}; `.venv/bin/python -m pytest` on a clean clone, "
            f"{time.strftime('%Y-%m-%d', time.gmtime(src.stat().st_mtime))}\n")
    dest.write_text(head + df.to_csv(index=False))
    return dest


def table(src: Path = KEPT) -> str:
    """The testing page's Markdown: the whole run's minutes, the slowest tests, and the seconds per test file."""
    head = src.read_text().splitlines()[0].lstrip("# ")
    df = pd.read_csv(src, comment="#")
    whole = float(df.loc[df.test == WHOLE, "seconds"].iloc[0])
    tests = df[df.test != WHOLE].copy()
    clone = tests.test.str.endswith(f"@{CLONE_GROUP}")
    tests["test"] = tests.test.str.replace(r"@[\w-]+$", "", regex=True)  # pytest-xdist's group suffix
    tests["file"] = tests.test.str.split("::").str[0]
    slowest = tests.nlargest(SLOWEST, "seconds")[["test", "seconds"]]
    slowest["test"] = "`" + slowest.test + "`"
    files = tests.groupby("file").seconds.agg(["count", "sum"]).sort_values("sum", ascending=False)
    files = files.rename(columns={"count": "tests", "sum": "seconds"}).reset_index()
    files["file"] = "`" + files.file + "`"
    cores = int(re.search(r"(\d+) cores", head).group(1))
    total, group = tests.seconds.sum(), tests.seconds[clone].sum()
    return (f"The whole suite: {len(tests)} tests in {whole / 60:.1f} min of wall time ({head}). "
            f"A test's seconds include its share of the fixtures it starts (a shared end-to-end run is counted "
            f"at the first test that needs it). What bounds the wall time: the tests' seconds add up to "
            f"{total / 60:.1f} min, so that the {cores} processes of `-n auto` cannot end in less than "
            f"{total / cores / 60:.1f} min however the tests are shared among them; nor in less than the "
            f"{group / 60:.1f} min of the tests that share README's scratch clone, which run in one process."
            f"\n\nThe {SLOWEST} slowest tests:\n\n"
            f"{slowest.round(1).to_markdown(index=False)}\n\nBy test file:\n\n"
            f"{files.round(1).to_markdown(index=False)}\n")


if __name__ == "__main__":
    if sys.argv[1:2] == ["keep"]:
        print(keep(Path(sys.argv[2]) if len(sys.argv) > 2 else RUN))
    elif sys.argv[1:2] == ["table"]:
        print(table())
    else:
        sys.exit(__doc__)
