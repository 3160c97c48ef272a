"""The workflow's rule graph and its named targets, generated from the Snakefile when the site is built.

* ``_generated/rulegraph.svg``: the graph of ``snakemake --rulegraph`` over every named target (with one
  study configured, so that the study's rule is in it too), drawn in layers from the rules that read no
  other rule's output to the targets.
* ``_generated/workflow_graph.md``: the named targets (:data:`vibroimpact.__main__.TARGETS`) and, for every
  rule of the graph, the rules whose output it reads and the rules that read its output.

Graphviz is not needed: the graph is parsed from Snakemake's dot text and laid out here, so the page holds
exactly the rules Snakemake reports (tests/test_workflow_graph.py compares it with ``--list-rules``).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: one study configured, so that the graph holds the rule only a study runs
STUDY = "studies=[{beta: 0.4, r: 0.6}]"


def snakemake(*args: str, root: Path = ROOT) -> str:
    """Standard output of ``snakemake ARGS`` in ``root`` (no lock taken: it only reads the workflow)."""
    res = subprocess.run([sys.executable, "-m", "snakemake", "--nolock", *args], cwd=root, capture_output=True,
                         text=True)
    if res.returncode:
        raise RuntimeError(f"snakemake {' '.join(args)} failed:\n{res.stderr[-3000:]}")
    return res.stdout


def parse_dot(dot: str) -> tuple[list[str], list[tuple[str, str]]]:
    """Rule names and edges ``(reads-from, read-by)`` of Snakemake's ``--rulegraph dot`` text."""
    nodes = dict(re.findall(r'^\s*(\d+)\[label = "(\w+)"', dot, re.M))
    edges = [(nodes[a], nodes[b]) for a, b in re.findall(r"^\s*(\d+) -> (\d+)", dot, re.M)]
    return sorted(nodes.values()), sorted(set(edges))


def rule_graph(root: Path = ROOT) -> tuple[list[str], list[tuple[str, str]]]:
    """The workflow's rules and edges over every named target, with one study configured."""
    from vibroimpact.__main__ import TARGETS

    return parse_dot(snakemake("--config", STUDY, "--rulegraph", "dot", "--", *TARGETS, root=root))


def layers(rules: list[str], edges: list[tuple[str, str]]) -> dict[str, int]:
    """Each rule's layer: the length of the longest chain of rules whose outputs lead to it."""
    before = {r: [a for a, b in edges if b == r] for r in rules}
    layer: dict[str, int] = {}

    def depth(r):
        if r not in layer:
            layer[r] = 1 + max((depth(a) for a in before[r]), default=-1)
        return layer[r]

    for r in rules:
        depth(r)
    return layer


def draw(rules: list[str], edges: list[tuple[str, str]], path: Path) -> None:
    """The graph as an SVG, one column per layer, each column ordered by the mean row of what it reads."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with plt.rc_context({"svg.fonttype": "none", "svg.hashsalt": "rulegraph"}):  # text as text, stable ids
        _draw(plt, rules, edges, path)


def _draw(plt, rules, edges, path):
    layer = layers(rules, edges)
    n = max(layer.values()) + 1
    columns = [sorted(r for r in rules if layer[r] == i) for i in range(n)]
    row: dict[str, float] = {}
    for col in columns:
        def key(r):
            ins = [row[a] for a, b in edges if b == r and a in row]
            return (sum(ins) / len(ins) if ins else -1.0, r)
        for i, r in enumerate(sorted(col, key=key)):
            row[r] = i - (len(col) - 1) / 2
    height = max(len(c) for c in columns)
    fig, ax = plt.subplots(figsize=(2.3 * n, 0.42 * height + 0.6))
    pos = {r: (2.3 * layer[r], -row[r]) for r in rules}
    boxes = {r: ax.text(x, y, r, ha="center", va="center", fontsize=8, zorder=3,
                        bbox=dict(boxstyle="round,pad=0.25", fc="#dce8f7" if r in _targets() else "white", ec="0.3",
                                  lw=0.8))
             for r, (x, y) in pos.items()}
    for a, b in edges:  # from the right side of what is read to the left side of its reader
        ax.annotate("", xy=(0, 0.5), xycoords=boxes[b], xytext=(1, 0.5), textcoords=boxes[a], zorder=2,
                    arrowprops=dict(arrowstyle="-|>", color="0.55", lw=0.6, alpha=0.8, shrinkA=2, shrinkB=2,
                                    connectionstyle="arc3,rad=0.0"))
    ax.set_xlim(-1.2, 2.3 * (n - 1) + 1.2)
    ax.set_ylim(-(height + 1) / 2, (height + 1) / 2)
    ax.axis("off")
    fig.savefig(path, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)


def _targets():
    from vibroimpact.__main__ import TARGETS

    return TARGETS


def page(rules: list[str], edges: list[tuple[str, str]]) -> str:
    """The Markdown of the named targets and of every rule's inputs and readers."""
    lines = ["| target | what it writes |", "|---|---|"]
    lines += [f"| `{t}` | {what} |" for t, what in _targets().items()]
    lines += ["", "| rule | reads the output of | its output is read by |", "|---|---|---|"]
    for r in rules:
        ins = ", ".join(f"`{a}`" for a, b in edges if b == r) or "(the config only)"
        outs = ", ".join(f"`{b}`" for a, b in edges if a == r) or "(a target)"
        lines.append(f"| `{r}` | {ins} | {outs} |")
    return "\n".join(lines) + "\n"


def generate(app=None, root: Path = ROOT) -> list[str]:
    """Write ``_generated/rulegraph.svg`` and ``_generated/workflow_graph.md`` in the site's source (``docs/``);
    return the rules."""
    rules, edges = rule_graph(root)
    out = (Path(app.srcdir) if app is not None else root / "docs") / "_generated"
    out.mkdir(parents=True, exist_ok=True)
    draw(rules, edges, out / "rulegraph.svg")
    (out / "workflow_graph.md").write_text(page(rules, edges))
    return rules


def setup(app):
    app.connect("builder-inited", generate)
    return {"version": "1", "parallel_read_safe": True}
