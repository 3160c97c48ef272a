"""Pages of the documentation generated from the workflow's results when the site is built.

* ``paper.md``: every figure the workflow regenerates, the paper's first, by the numbers it prints
  (Figure 2 ... Figure 9), then the project's own; each with its heading and its caption from its row of the
  registry of figures (:mod:`vibroimpact.outputs.registry`: the same templates the Snakemake report renders,
  ``workflow/report/*.rst``), its check
  result (arrays and image against the committed reference) and the published values it shows, each with
  the value computed now and its status; then the whole table of the paper's values.
* ``_generated/variables.md``: every variable the datasets carry, with its units and meaning
  (:data:`vibroimpact.datasets.VARIABLES`).
* ``_generated/conditioning.md``: how far each figure array moved when the figures were recomputed under
  another libm, other OpenBLAS kernels and inputs moved by ulps, and whether its declared rule passed it
  (the committed ``reference/figures/conditioning*.csv``).
* ``_generated/mutation_scores.md``: the mutation samples the repository carries
  (``tools/mutation_samples/``) and the verdicts on their survivors, counted by ``tools/mutation.py scores``.
* ``_generated/test_durations.md``: the test suite's durations as a whole run on a clean clone measured them
  (the committed ``reference/test_durations.csv``, ``tools/test_durations.py table``).

Nothing is typed: a site built before the workflow ran stops with the target to run.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pandas as pd
from sphinx.errors import ExtensionError

from vibroimpact.outputs.paper import FIGURE_NUMBERS
from vibroimpact.outputs.registry import RegistryError, figure, render_caption


def title(fig: str) -> str:
    """A figure's heading: its row of the registry of figures (:func:`vibroimpact.outputs.registry.figure`)."""
    try:
        return figure(fig).heading()
    except RegistryError:
        return fig.replace("_", " ")


def _caption(report: Path, fig: str, checks: dict) -> str:
    """A figure's caption, its registry row's template rendered as the Snakemake report renders it."""
    try:
        row = figure(fig)
    except RegistryError as err:
        raise ExtensionError(f"no caption template for figure {fig!r}: {err}") from None
    return render_caption(report, row, checks)


def _number(x):
    try:
        return float(x)
    except ValueError:
        return x


def _markdown_table(df: pd.DataFrame) -> str:
    return df.to_markdown(index=False).replace("|:-", "|--").replace("-:|", "--|")


def page_order(figures) -> list[str]:
    """The paper's figures in its order (Figure 2, 3, ...), then the project's own in the workflow's."""
    figures = list(dict.fromkeys(figures))
    return sorted((f for f in figures if f in FIGURE_NUMBERS), key=FIGURE_NUMBERS.get) + [
        f for f in figures if f not in FIGURE_NUMBERS]


def paper_page(root: Path) -> str:
    """The paper reproduction page, from results/ (figures, checks) and workflow/report (captions)."""
    from vibroimpact.outputs.checks import IMAGE_ROW, check_summaries, figures_of_item, markdown

    results = root / "results"
    need = [results / "checks" / "paper_values.csv", results / "checks" / "figures.csv"]
    missing = [str(p.relative_to(root)) for p in need if not p.exists()]
    if missing:
        raise ExtensionError(f"the documentation is built from the workflow's results, and {', '.join(missing)} "
                             "is missing: run `snakemake --cores 2 docs` (it runs `all` and `check` first)")
    paper = pd.read_csv(need[0], keep_default_na=False)
    figures = pd.read_csv(need[1])
    checks = check_summaries(paper, figures)
    summary = paper["status"].value_counts()
    out = ["# The paper's figures, regenerated", "",
           "Every figure below is drawn by the workflow from its saved datasets and compared, array by array, "
           "with its committed reference (see [the checks](guide/checks.md)); the published numbers each shows "
           f"are compared with the values computed now. Paper values: {summary.get('pass', 0)} pass, "
           f"{summary.get('known discrepancy', 0)} known discrepancies (each with the evidence a test reproduces), "
           f"{summary.get('fail', 0)} fail. Figure arrays: {int((figures.status == 'pass').sum())} pass, "
           f"{int((figures.status == 'excluded').sum())} excluded (timings), "
           f"{int((~figures.status.isin(['pass', 'excluded'])).sum())} fail.", "",
           "The paper's figures come first, in its order and by the numbers the published paper prints, each "
           "with its LaTeX label beside it (Figure 1, the device, is a sketch and is not regenerated); the "
           "project's own figures follow.", ""]
    rows_of = {}
    for i, (item, where) in enumerate(zip(paper["item"], paper["where"], strict=True)):
        for fig in figures_of_item(str(item), str(where)):
            rows_of.setdefault(fig, []).append(i)
    for fig in page_order(figures.figure):
        png = results / "figures" / f"{fig}.png"
        if not png.exists():
            raise ExtensionError(f"{png.relative_to(root)} is missing: run `snakemake --cores 2 docs`")
        out += [f"## {title(fig)}", "", f"![{fig}](../results/figures/{fig}.png)", "",
                "```{eval-rst}", _caption(root / "workflow" / "report", fig, checks), "```", ""]
        image = figures[(figures.figure == fig) & (figures.variable == IMAGE_ROW)]
        arrays = figures[(figures.figure == fig) & (figures.variable != IMAGE_ROW)]
        rules = arrays.rule.value_counts()
        out.append("Arrays compared: " + ", ".join(f"{n} by {rule}" for rule, n in rules.items())
                   + (f"; image {image.status.iloc[0]} ({image.max_difference.iloc[0]:g} bits)" if len(image) else "")
                   + ".")
        out.append("")
        if fig in rows_of:
            sel = paper.iloc[rows_of[fig]].copy()
            for col in ("paper", "computed", "tolerance"):  # mixed columns come back as text
                sel[col] = sel[col].map(_number)
            out += ["Published values this figure shows:", "", markdown(sel), ""]
    out += ["## Every published value", "", "```{include} ../results/checks/paper_values.md", "```", ""]
    return "\n".join(out)


def variables_page() -> str:
    from vibroimpact.datasets import VARIABLES

    rows = [{"variable": f"`{k}`", "units": units, "long name": long_name, "description": description}
            for k, (units, long_name, description) in sorted(VARIABLES.items())]
    return _markdown_table(pd.DataFrame(rows)) + "\n"


def _tool(root: Path, name: str):
    """A script of ``tools/``, loaded as a module."""
    spec = importlib.util.spec_from_file_location(f"{name}_tool", root / "tools" / f"{name}.py")
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    return tool


def mutation_scores(root: Path) -> str:
    """The testing page's table of mutation scores (``tools/mutation.py scores``)."""
    return _tool(root, "mutation").scores()


def test_durations(root: Path) -> str:
    """The testing page's table of the suite's durations (``tools/test_durations.py table``)."""
    return _tool(root, "test_durations").table()


def conditioning_page(root: Path) -> str:
    """The testing page's table of the figures' measured conditioning (the committed
    ``reference/figures/conditioning*.csv``, :func:`vibroimpact.outputs.conditioning.conditioning_markdown`)."""
    from vibroimpact.outputs.conditioning import conditioning_markdown

    ref = root / "reference" / "figures"
    return conditioning_markdown(pd.read_csv(ref / "conditioning.csv", keep_default_na=False, na_values=[""]),
                                 pd.read_csv(ref / "conditioning_summary.csv"))


def generate(app):
    src = Path(app.srcdir)
    root = src.parent
    (src / "_generated").mkdir(exist_ok=True)
    (src / "_generated" / "conditioning.md").write_text(conditioning_page(root))
    (src / "paper.md").write_text(paper_page(root))
    (src / "_generated" / "variables.md").write_text(variables_page())
    (src / "_generated" / "mutation_scores.md").write_text(mutation_scores(root))
    (src / "_generated" / "test_durations.md").write_text(test_durations(root))


def setup(app):
    app.connect("builder-inited", generate)
    return {"version": "1", "parallel_read_safe": True}
