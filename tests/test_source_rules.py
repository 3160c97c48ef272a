"""Rules the source keeps, read from its syntax trees: a figure module imports its helpers from the plots
package's common module only, never from another figure module; and a motion's name is written by the motions
module only (:mod:`vibroimpact.analysis.motions`), never typed by hand elsewhere in the code."""

import ast

import pytest
from conftest import ROOT

from vibroimpact.analysis.motions import is_motion_label, periodic_names_in

SRC = ROOT / "src" / "vibroimpact"
#: the one module that writes motions' names
#: where the motions' names are typed: the names themselves, and the module that classifies runs (which imports them)
MOTIONS_MODULES = (SRC / "analysis" / "motion_names.py", SRC / "analysis" / "motions.py")

PLOTS = ROOT / "src" / "vibroimpact" / "outputs" / "plots"
PLOTS_PACKAGE = "vibroimpact.outputs.plots"
#: the plots package's modules that are no figure module: the shared helpers, and the package's front
NOT_FIGURES = ("_common", "__init__")


def figure_modules() -> list[str]:
    """The names of the plots package's figure modules."""
    return sorted(p.stem for p in PLOTS.glob("*.py") if p.stem not in NOT_FIGURES)


def plots_imports(source: str) -> set[str]:
    """The modules of the plots package that a module of it, of source ``source``, imports from
    (``from ._common import x``, ``from . import energy``, ``from vibroimpact.outputs.plots.sweeps import x``)."""
    found = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            if node.level == 1:  # relative to the plots package
                found |= {node.module} if node.module else {a.name for a in node.names}
            elif node.level == 0 and (node.module or "").startswith(PLOTS_PACKAGE + "."):
                found.add(node.module.removeprefix(PLOTS_PACKAGE + ".").split(".")[0])
        elif isinstance(node, ast.Import):
            found |= {a.name.removeprefix(PLOTS_PACKAGE + ".").split(".")[0] for a in node.names
                      if a.name.startswith(PLOTS_PACKAGE + ".")}
    return found


def test_the_import_reader_finds_every_form_of_import_from_the_package():
    source = ("from ._common import wellposed\nfrom . import energy\nfrom .sweeps import last_events\n"
              "import vibroimpact.outputs.plots.chaos\nfrom vibroimpact.outputs.plots.bench import x\n"
              "from .. import layout\nfrom ...analysis.motions import no_period\nimport numpy as np\n")
    assert plots_imports(source) == {"_common", "energy", "sweeps", "chaos", "bench"}


def test_no_plot_module_imports_from_a_figure_module():
    """Shared helpers live in ``_common``: a figure module (or ``_common`` itself) that imports from another
    figure module makes that figure's module a library of the others."""
    figures = set(figure_modules())
    assert {"sweeps", "energy", "chaos", "branches", "design"} <= figures  # the reader sees the package
    offending = {}
    for name in sorted(figures) + ["_common"]:
        bad = plots_imports((PLOTS / f"{name}.py").read_text()) & figures
        if bad:
            offending[name] = sorted(bad)
    assert not offending, f"figure modules imported by other plot modules (move the helper to _common): {offending}"


# ---- motion labels ---------------------------------------------------------------------------------------------
#: code strings outside the motions module that read as a motion's name but are not one: (module, string) -> why
NOT_MOTION_LABELS = {
    ("benchmarks/workprecision.py", "chaotic"): "a benchmark scene's name (a long chaotic run), in its cases' names",
    ("benchmarks/bench.py", "chaotic"): "a kernel-speed scene's name (a long chaotic run)",
    ("benchmarks/lyapunov_precision.py", "chaotic"): "the Lyapunov chart's name for the bench's chaotic scene",
    ("outputs/speed.py", "chaotic"): "picks the benchmark's chaotic scene by its case name",
    ("outputs/figcheck.py", "unsettled"): "a field of a drawn point's well-posed record (a flag), and its count",
}
#: quotations of the paper inside code strings: they keep the paper's words
PAPER_QUOTES = {"outputs/tables.py": ('"the maximum value for 2:1 period-2 solutions"',)}


def code_strings(source: str):
    """``(line, text)`` of every string constant of ``source`` that is code, not prose: docstrings (a string
    standing alone as a statement) are left out; the literal parts of an f-string are kept."""
    tree = ast.parse(source)
    prose = {id(node.value) for node in ast.walk(tree) if isinstance(node, ast.Expr)
             and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str)}
    return [(node.lineno, node.value) for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in prose]


def typed_labels(source: str, module: str) -> list[str]:
    """The motions' names typed in the code of ``module`` (its path under the package): a string that is a motion's
    label, or that names a periodic motion inside a longer text, less :data:`NOT_MOTION_LABELS` and
    :data:`PAPER_QUOTES`."""
    found = []
    for line, text in code_strings(source):
        if is_motion_label(text) and (module, text) not in NOT_MOTION_LABELS:
            found.append(f"{module}:{line}: {text!r}")
        elif not is_motion_label(text):
            for quote in PAPER_QUOTES.get(module, ()):
                text = text.replace(quote, "")
            found += [f"{module}:{line}: {name!r} in {text[:60]!r}" for name in periodic_names_in(text)]
    return found


def test_the_label_reader_finds_typed_names_in_code_and_passes_over_prose():
    source = ('"""A module on the 2:1 period-2 motion and chaotic runs."""\n'
              'def f(lab):\n    """Picks the 1:1 period-4 points."""\n'
              '    a = lab == "2:1 period-2"\n    b = {"chaotic": 1, "quasi-periodic": 2}\n'
              '    c = f"{lab} and 3:1 T=2 here"\n    d = "a chaotic run"\n    return "2:1" + "unsettled"\n')
    found = typed_labels(source, "x.py")
    assert [f.split(": ", 1)[1] for f in found] == [
        "'2:1 period-2'", "'chaotic'", "'quasi-periodic'", "'3:1 T=2' in ' and 3:1 T=2 here'", "'unsettled'"]
    assert typed_labels('x = "chaotic"\n', "outputs/speed.py") == []  # allowed: a scene's name


@pytest.mark.parametrize("entry", sorted(NOT_MOTION_LABELS))
def test_every_allowed_string_is_still_there(entry):
    """An entry of the allow-list that the code no longer holds is dropped from it (the list stays short)."""
    module, text = entry
    assert text in [t for _, t in code_strings((SRC / module).read_text())]


def test_no_motion_label_is_typed_outside_the_motions_module():
    """Every motion's name in the package's code and the workflow's scripts comes from
    :mod:`vibroimpact.analysis.motions` (its constants, :class:`Motion`'s labels,
    :func:`~vibroimpact.analysis.motions.periodic_motion`): a name typed by hand elsewhere drifts from it."""
    modules = sorted(p for p in SRC.rglob("*.py") if p not in MOTIONS_MODULES)
    scripts = sorted((ROOT / "workflow" / "scripts").glob("*.py"))  # the workflow's jobs
    assert len(modules) > 40 and len(scripts) > 10
    found = [hit for p in modules for hit in typed_labels(p.read_text(), p.relative_to(SRC).as_posix())]
    found += [hit for p in scripts for hit in typed_labels(p.read_text(), p.relative_to(ROOT).as_posix())]
    assert not found, "motion labels typed outside analysis/motion_names.py and motions.py:\n" + "\n".join(found)
