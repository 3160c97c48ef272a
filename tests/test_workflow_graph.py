"""The rule graph and the target lists the documentation and ``python -m vibroimpact`` show, against the
Snakefile itself: no rule or target can be left out."""

import re
import subprocess
import sys

from conftest import ROOT

from vibroimpact.__main__ import TARGETS, report

sys.path.insert(0, str(ROOT / "docs" / "_ext"))
import vibroimpact_rulegraph


def _listed(flag):
    out = vibroimpact_rulegraph.snakemake(flag)
    return {line.split()[0] for line in out.splitlines() if line.strip()}


def test_the_generated_graph_and_page_hold_every_rule_and_the_targets_are_the_snakefile_s(tmp_path):
    """The graph the workflow page draws (from ``snakemake --rulegraph``) holds every rule of ``--list-rules``;
    every rule no other rule reads is a named target, and every named target is one of the Snakefile's
    target rules."""
    rules, edges = vibroimpact_rulegraph.rule_graph()
    assert set(rules) == _listed("--list-rules")
    read = {a for a, _ in edges}
    assert {r for r in rules if r not in read} <= set(TARGETS)
    assert set(TARGETS) <= _listed("--list-target-rules")
    page = vibroimpact_rulegraph.page(rules, edges)
    assert all(f"| `{r}` |" in page for r in rules) and all(f"| `{t}` |" in page for t in TARGETS)
    vibroimpact_rulegraph.draw(rules, edges, tmp_path / "graph.svg")
    svg = (tmp_path / "graph.svg").read_text()
    assert all(f">{r}</text>" in svg for r in rules)  # the SVG keeps its text as text


def test_the_workflow_page_shows_the_generated_graph_and_targets():
    page = (ROOT / "docs" / "guide" / "workflow.md").read_text()
    assert "../_generated/rulegraph.svg" in page and "{include} ../_generated/workflow_graph.md" in page
    assert "flowchart" not in page  # no hand-written graph beside the generated one
    assert "vibroimpact_rulegraph" in (ROOT / "docs" / "conf.py").read_text()


def test_readme_and_the_command_name_every_target():
    """README's table of targets and ``python -m vibroimpact`` name exactly the named targets."""
    text = (ROOT / "README.md").read_text()
    table = text[text.index("| target | what it writes |"):]
    table = table[:table.index("\n\n")]
    named = {n for row in table.splitlines()[2:] for n in re.findall(r"`(\w+)`", row.split("|")[1])}
    assert named == set(TARGETS)
    shown = report(ROOT)
    assert all(t in shown for t in TARGETS if t != "all")
    out = subprocess.run([sys.executable, "-m", "vibroimpact"], cwd=ROOT, capture_output=True, text=True, check=True)
    assert "design_maps" in out.stdout and "figure_conditioning" in out.stdout
