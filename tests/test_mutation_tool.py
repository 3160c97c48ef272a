"""tools/mutation.py, as README.md runs it, at a smaller preset: a few mutants of a fast module."""

import json
import sys
from pathlib import Path

import pytest
from conftest import readme_command, run_readme, scratch_clone


@pytest.mark.slow
def test_the_mutation_tool_samples_mutants_and_reports_them(tmp_path):
    """README's command with a smaller sample (3 mutants of d_graz.py, whose tests take a few seconds, instead of
    40 of events.py): each mutant is run in the private copy and recorded killed, survived, timed out or
    invalid; the report counts them; the working tree is left as it was."""
    clone = scratch_clone(tmp_path)
    (clone / ".venv").symlink_to(Path(sys.prefix))  # the suite's environment stands for README's .venv
    cmd = readme_command("tests/test_mutation_tool.py::test_the_mutation_tool_samples_mutants_and_reports_them")
    run = cmd.split("#")[0].strip()
    assert "run events --n 40" in run
    small = run.replace("run events --n 40", "run d_graz --n 3")
    before = (clone / "src" / "vibroimpact" / "analysis" / "d_graz.py").read_bytes()
    res = run_readme(clone, small, timeout=900)
    assert res.returncode == 0, (res.stdout + res.stderr)[-3000:]
    lines = (clone / "results" / "mutation" / "results_d_graz.jsonl").read_text().split("\n")
    rows = [r for r in map(json.loads, filter(None, lines)) if "id" in r]  # the first record is the sample's header
    assert len(rows) == 3 and {r["status"] for r in rows} <= {"killed", "survived", "timeout", "invalid"}
    assert (clone / "src" / "vibroimpact" / "analysis" / "d_graz.py").read_bytes() == before
    report = run_readme(clone, ".venv/bin/python tools/mutation.py report d_graz")
    assert report.returncode == 0 and "d_graz: tried 3" in report.stdout, report.stdout + report.stderr
    # the sample kept in the repository, and the testing page's row written from it: of the current source
    keep = run_readme(clone, ".venv/bin/python tools/mutation.py keep d_graz")
    assert keep.returncode == 0, keep.stdout + keep.stderr
    kept = (clone / "tools" / "mutation_samples" / "d_graz.jsonl").read_text().split("\n")
    head = json.loads(kept[0])["sample"]
    assert (head["module"], head["n"], len(head["ids"])) == ("d_graz", 3, 3) and len(head["source_sha256"]) == 64
    scores = run_readme(clone, ".venv/bin/python tools/mutation.py scores")
    row = next(line for line in scores.stdout.splitlines() if line.startswith("| d_graz |"))
    assert "| yes |" in row and "(seed 20261123)" in row, row
