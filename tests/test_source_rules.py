"""Rules the source keeps, read from its syntax trees: a figure module imports its helpers from the plots
package's common module only, never from another figure module."""

import ast

from conftest import ROOT

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
