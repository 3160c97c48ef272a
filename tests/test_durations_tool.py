"""tools/test_durations.py: the testing page's table of the suite's durations, from a whole run's record."""
import importlib.util

import pytest
from conftest import ROOT

spec = importlib.util.spec_from_file_location("test_durations_tool", ROOT / "tools" / "test_durations.py")
tool = importlib.util.module_from_spec(spec)
spec.loader.exec_module(tool)


def test_the_table_sums_each_file_and_lists_the_slowest_first(tmp_path):
    run = tmp_path / "durations.csv"
    run.write_text('test,seconds\n"tests/test_a.py::test_x",3.0\n"tests/test_b.py::test_y@readme_clone",10.0\n'
                   '"tests/test_a.py::test_z",4.5\n"(the whole run, wall)",600.0\n')
    kept = tool.keep(run, tmp_path / "kept.csv")
    assert kept.read_text().startswith("# ") and "cores" in kept.read_text().splitlines()[0]
    page = tool.table(kept)
    assert "3 tests in 10.0 min" in page
    # 17.5 s of tests on the record's processes, 10 s of them in the scratch clone's process
    cores = int(kept.read_text().split(" cores")[0].rsplit(" ", 1)[1])
    assert f"add up to 0.3 min, so that the {cores} processes" in page
    assert f"less than {17.5 / cores / 60:.1f} min however" in page and "less than the 0.2 min of the tests" in page
    slowest = page.split("slowest tests")[1].split("By test file")[0]
    assert slowest.index("test_y") < slowest.index("test_z") < slowest.index("test_x")
    by_file = page.split("By test file")[1]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in by_file.splitlines() if "`tests/" in line]
    assert rows == [["`tests/test_b.py`", "1", "10"], ["`tests/test_a.py`", "2", "7.5"]]  # summed, largest first


def test_a_partial_run_is_not_kept(tmp_path):
    run = tmp_path / "durations.csv"
    run.write_text('test,seconds\n"tests/test_a.py::test_x",3.0\n')
    with pytest.raises(ValueError, match="not the record of a whole run"):
        tool.keep(run, tmp_path / "kept.csv")


def test_the_kept_record_names_tests_that_exist():
    """The record the page shows is of this suite: its slowest tests are tests of these files."""
    import pandas as pd

    df = pd.read_csv(tool.KEPT, comment="#")
    tests = df[df.test != tool.WHOLE].nlargest(tool.SLOWEST, "seconds").test
    for t in tests:
        path, name = t.split("::")[0], t.split("::")[1].split("[")[0].split("@")[0]
        assert f"def {name}(" in (ROOT / path).read_text(), t
