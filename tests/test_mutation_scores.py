"""The mutation samples the repository carries (tools/mutation_samples/) and the testing page's scores,
which ``tools/mutation.py scores`` writes from them."""

import importlib.util
import json
import re

import pytest
from conftest import ROOT

SPEC = importlib.util.spec_from_file_location("mutation_tool", ROOT / "tools" / "mutation.py")
tool = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(tool)

SAMPLES = ROOT / "tools" / "mutation_samples"


def _write(path, head, rows):
    path.write_text("".join(json.dumps(r) + "\n" for r in [head, *rows]))


def test_scores_count_a_known_sample(tmp_path):
    """A hand-made sample of seven valid mutants: 3 killed, 1 timed out, 1 invalid, 3 survivors (one
    equivalent, one blind spot that its new test kills, one not judged). Timeouts count as killed, the
    invalid one is left out, the unjudged survivor counts as a blind spot: 4 killed of 6 that change
    behaviour, 5 of 6 after the blind spot's test; a sample of another source says so."""
    rows = [{"id": i, "line": 10 + i, "kind": "const 1->2", "old": "1", "new": "2", "status": s}
            for i, s in enumerate(["killed", "killed", "killed", "timeout", "invalid", "survived", "survived",
                                   "survived"])]
    head = {"sample": {"module": "energy", "seed": 5, "n": 8, "ids": list(range(8)), "mutants": 100,
                       "source_sha256": "0" * 64, "commit": "abcdef1234", "date": "2026-01-01", "tests": []}}
    _write(tmp_path / "energy.jsonl", head, rows)
    _write(tmp_path / "energy_retest.jsonl", {"retest": {"ids": [6]}}, [{"id": 6, "status": "killed"}])
    (tmp_path / "verdicts.toml").write_text(
        '[energy.5]\nmutation = "line 15: 1 -> 2"\nverdict = "equivalent"\nreason = "a comparison at exact equality"\n'
        '[energy.6]\nmutation = "line 16: 1 -> 2"\nverdict = "blind spot"\ntest = "tests/test_energy.py::test_x"\n'
        'reason = "a wrong sign"\n'
        # written for another mutant that an earlier sample numbered 7: not this one's verdict
        '[energy.7]\nmutation = "line 99: 1 -> 2"\nverdict = "equivalent"\nreason = "another mutant entirely"\n')
    text = tool.scores(samples=str(tmp_path))
    row = next(line for line in text.splitlines() if line.startswith("| energy |"))
    assert row == "| energy | 7 of 100 (seed 5) | no (commit abcdef1) | 4 | 1 | 2 | 4 of 6 (67%) | 5 of 6 |"
    assert "| events | none kept |" in text
    assert "equivalent: a comparison at exact equality" in text
    assert "blind spot, now tested by `tests/test_energy.py::test_x`" in text
    assert "(line 17, #7): not judged yet" in text


def _kept():
    return sorted(p.stem for p in SAMPLES.glob("*.jsonl") if not p.stem.endswith("_retest"))


def test_every_module_the_tool_knows_has_a_kept_sample():
    assert _kept() == sorted(tool.TESTS)


@pytest.mark.parametrize("module", sorted(tool.TESTS))
def test_each_kept_sample_is_judged_and_kills_enough(module):
    """Every survivor has a verdict of its own mutation (equivalent with a reason, or a blind spot with a test that exists and
    kills it on the rerun); no verdict names a mutant that did not survive; on a sample of the module's
    current source the tests kill at least 80 % of the mutants that change behaviour (those the sample killed
    and the blind spots the tests they led to kill)."""
    path = SAMPLES / f"{module}.jsonl"
    head = tool.header(str(path))
    rows = tool.records(str(path))
    assert head is not None and sorted(r["id"] for r in rows) == head["ids"], "an unfinished or headless sample"
    verdicts = tool.load_verdicts(str(SAMPLES / "verdicts.toml")).get(module, {})
    by_id = {r["id"]: r for r in rows}
    stale = {i for i, v in verdicts.items() if i in by_id and v.get("mutation") != tool.mutation_of(by_id[i])}
    assert not stale, f"verdicts written for other mutants than the sample's: {stale}"
    survivors = {r["id"] for r in rows if r["status"] == "survived"}
    assert set(verdicts) <= survivors, f"verdicts on mutants that did not survive: {set(verdicts) - survivors}"
    assert survivors <= set(verdicts), f"survivors without a verdict: {survivors - set(verdicts)}"
    retest = tool.records(str(SAMPLES / f"{module}_retest.jsonl"))
    assert tool.retest_sources(str(SAMPLES / f"{module}_retest.jsonl")) <= {head["source_sha256"]}, "reruns of another source"
    for i, v in verdicts.items():
        assert v["verdict"] in ("equivalent", "blind spot") and len(v["reason"]) > 20, (i, v)
        if v["verdict"] == "blind spot":
            file, name = v["test"].split("::")
            assert re.search(rf"def {re.escape(name.split('[')[0])}\(", (ROOT / file).read_text()), v["test"]
            assert any(r["id"] == i and r["status"] in ("killed", "timeout") for r in retest), (i, "not rerun")
    s = tool.module_scores(rows, verdicts, retest)
    current = tool.sha256(open(tool.live_source(module), "rb").read()) == head["source_sha256"]
    if current:
        assert s["after"] >= 0.8 * s["changing"], s


def test_the_testing_page_includes_the_generated_scores():
    page = (ROOT / "docs" / "guide" / "testing.md").read_text()
    assert "```{include} ../_generated/mutation_scores.md" in page
    assert not re.search(r"^\| *module *\|", page, re.M), "a hand-written table of scores"
