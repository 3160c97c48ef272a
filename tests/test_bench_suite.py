"""benchmarks/bench_suite.py: the test command on clean clones of two commits, and its kept record."""
import importlib.util
import io
import stat
import sys

import pandas as pd
import pytest
from conftest import ROOT

spec = importlib.util.spec_from_file_location("bench_suite", ROOT / "benchmarks" / "bench_suite.py")
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)

#: a suite whose outcomes are known by construction: 3 pass, 2 fail, 1 skips, 2 error in set-up
TESTS = """\
import pytest

@pytest.fixture
def broken():
    raise RuntimeError("set-up fails")

@pytest.mark.parametrize("k", range(3))
def test_passes(k):
    assert k >= 0

@pytest.mark.parametrize("k", range(2))
def test_fails(k):
    assert k < 0

def test_skips():
    pytest.skip("on purpose")

@pytest.mark.parametrize("k", range(2))
def test_errors(broken, k):
    pass
"""


def _tree(tmp_path, ci_script):
    tree = tmp_path / "tree"
    (tree / ".ci").mkdir(parents=True)
    (tree / "test_known.py").write_text(TESTS)
    run = tree / ".ci" / "run"
    run.write_text(ci_script)
    run.chmod(run.stat().st_mode | stat.S_IXUSR)
    return tree


def test_a_suite_s_counts_and_seconds_are_pytest_s_own(tmp_path):
    """`ci_run` on a tree whose `.ci/run` runs pytest over a suite of known outcomes: the counts are those the
    suite was built to give (in one process and on two), the exit status pytest's, the seconds its own."""
    for workers in ("0", "2"):
        tree = _tree(tmp_path / workers, f"#!/bin/sh\nexec {sys.executable} -m pytest -p no:cacheprovider -n {workers} "
                                          "-o addopts= -c /dev/null --rootdir . test_known.py\n")
        row = bench.ci_run(tree, tmp_path / workers / "cache")
        assert {k: row[k] for k in bench.COUNTS} == {"passed": 3, "failed": 2, "errors": 2, "skipped": 1}
        assert row["exit status"] == 1
        assert 0 < row["seconds"] <= row["wall seconds of .ci/run"]


def test_the_caches_are_the_run_s_own(tmp_path, monkeypatch):
    """The run sees an empty cache directory of its own and none of the caller's numba cache or interpreter paths."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", "/somewhere/else")
    monkeypatch.setenv("PYTHONPATH", "/somewhere/else")
    tree = _tree(tmp_path, "#!/bin/sh\necho \"$XDG_CACHE_HOME|${NUMBA_CACHE_DIR-unset}|${PYTHONPATH-unset}\" > env.txt\n"
                           "echo '=== 1 passed in 0.01s ==='\n")
    row = bench.ci_run(tree, tmp_path / "cache")
    assert (tree / "env.txt").read_text().strip() == f"{tmp_path / 'cache'}|unset|unset"
    assert row["passed"] == 1 and row["exit status"] == 0


def test_a_log_without_pytest_s_summary_is_refused():
    with pytest.raises(ValueError, match="no pytest summary line"):
        bench.summary("ERROR: could not install packages\n")


def test_the_sides_alternate_and_each_keeps_its_fastest_run(tmp_path, monkeypatch):
    """`main` with the clone and the run stubbed: baseline first in every round, each side's fastest run kept, the
    ratio that of the kept wall seconds to two decimals (not rounded with the seconds)."""
    order, walls = [], {"7f6254a": iter([1118.34, 1200.0]), "HEAD": iter([650.0, 605.04])}
    monkeypatch.setattr(bench, "rev_of", lambda rev: rev[:7])
    monkeypatch.setattr(bench, "clone", lambda rev, dest: order.append(rev) or rev)
    monkeypatch.setattr(bench, "ci_run", lambda rev, cache: {"wall seconds of .ci/run": next(walls[rev]),
                                                             "exit status": 0, "seconds": 1.0})
    df = bench.main("7f6254a", rounds=2)
    assert order == ["7f6254a", "HEAD", "7f6254a", "HEAD"]
    assert list(df["tree"]) == ["baseline (7f6254a)", "this commit (HEAD)"]
    assert list(df["wall seconds of .ci/run"]) == [1118.3, 605.0]
    assert list(df["ratio to the baseline"]) == [1.0, 0.54]
    assert list(df["minutes of .ci/run"]) == [18.6, 10.1]


def test_the_kept_record_holds_both_sides_of_one_run():
    """The kept record: the baseline and this commit, both suites complete, the ratio that of their wall seconds,
    with the machine and the command."""
    text = (ROOT / "reference" / "bench_suite.md").read_text()
    table = text.split("\n\n")[0]
    df = pd.read_table(io.StringIO(table), sep="|", skipinitialspace=True).iloc[1:, 1:-1]
    df.columns = [c.strip() for c in df.columns]
    assert [t.split()[0] for t in df["tree"]] == ["baseline", "this"]
    wall = df["wall seconds of .ci/run"].astype(float)
    assert list(df["ratio to the baseline"].astype(float)) == pytest.approx([1.0, wall.iloc[1] / wall.iloc[0]], abs=0.006)
    assert (df["failed"].astype(int) == 0).all() and (df["errors"].astype(int) == 0).all()
    assert "Machine:" in text and "Command: `python benchmarks/bench_suite.py" in text
