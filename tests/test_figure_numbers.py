"""The paper's figures by the numbers the published paper prints (Figure 2 ... Figure 9), from one
definition (the registry of figures, vibroimpact.outputs.registry, from which
vibroimpact.outputs.paper.FIGURE_NUMBERS is derived): every figure of the default config is numbered, and
no page, caption, table or plot docstring names one by its LaTeX label alone."""

import re
import sys
from types import SimpleNamespace

import pytest
import yaml
from conftest import ROOT

from vibroimpact.outputs.checks import item_names
from vibroimpact.outputs.paper import FIGURE_NUMBERS, caption_figure, figure_name, latex_label


def paper_figures(cfg):
    """The figures the workflow files under "Paper figures": scenes, branch figures, Fig BiS, voltages."""
    return [*cfg["scenes"], *cfg["branch_scenes"], "figBiS", *cfg["energy"]["figures"]]


def test_the_numbers_follow_the_paper_s_order_each_once():
    """In the paper's order (Figure 1, the device, is not regenerated): 2, 3, ..., 9."""
    assert list(FIGURE_NUMBERS.values()) == list(range(2, 2 + len(FIGURE_NUMBERS)))
    assert list(FIGURE_NUMBERS) == ["fig0", "figFN2", "fig0b", "fig2", "fig3", "fig4", "figBiS", "fig5"]


def test_every_paper_figure_and_caption_of_the_default_config_is_numbered():
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    assert sorted(paper_figures(cfg)) == sorted(FIGURE_NUMBERS)
    assert all(caption_figure(name) for name in cfg["captions"]), cfg["captions"]


def test_a_figure_is_named_by_its_printed_number_with_its_label_beside_it():
    assert figure_name("fig0") == "Figure 2 (Fig 0)"
    assert figure_name("fig5", label=False) == "Figure 9"
    assert figure_name("figFN2", "f", label=False) == "Figure 3 (f)"
    assert latex_label("fig0b") == "Fig 0b"
    assert caption_figure("figBiS_e") == "Figure 8 (e)"
    assert caption_figure("mine") is None and caption_figure("fig7_a") is None


def test_the_caption_table_names_each_orbit_by_its_printed_figure_and_panel():
    import xarray as xr

    from vibroimpact.outputs.portraits import summary_markdown

    one = dict(d=0.197, motion_stated="1:1", motion_found="1:1 period-2", v0=0.5474, v_attractor=0.5474, dv=0.0,
               phi=6.211, phase_attractor=6.211, dphase=0.0)
    table = xr.Dataset({k: ("caption", [v]) for k, v in one.items()}, coords={"caption": ["figFN2_a"]})
    assert "| Figure 3 (a) | figFN2_a | 0.197 |" in summary_markdown(table)


#: a LaTeX label in text: "Fig 0", "Fig FN2", "Figs 0 and 5", "Fig. 2" (the project's file stems, fig0, do not match)
LABEL = re.compile(r"\bFig(s?)\.?[ ~]?(0b|FN2|BiS|0|2|3|4|5)\b")


def bare_labels(text: str) -> list[str]:
    """Where ``text`` names a paper figure by its LaTeX label without its printed number just before it
    ("Figure 2 (Fig 0)" and "**Figure 2** (LaTeX label Fig 0)" pass; "Fig 0" and "Figs 0 and 5" do not)."""
    bad = []
    for m in LABEL.finditer(text):
        number = FIGURE_NUMBERS["fig" + m.group(2)]
        if m.group(1) or f"Figure {number}" not in text[max(0, m.start() - 40):m.start()]:
            bad.append(" ".join(text[max(0, m.start() - 40):m.end() + 20].split()))
    return bad


class _Wildcards:
    """Every wildcard a caption reads has one value."""

    def __init__(self, value):
        self.value = value

    def __getattr__(self, name):
        return self.value


def rendered_captions():
    """Each report caption (workflow/report/*.rst), rendered as the report and the docs render it, once
    per figure it switches on and once for the rest."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.FileSystemLoader(ROOT / "workflow" / "report"))
    config = {"_check_results": {}, "_figure_numbers": FIGURE_NUMBERS, "_registry_captions": {}}
    for path in sorted((ROOT / "workflow" / "report").glob("*.rst")):
        values = re.findall(r'snakemake\.wildcards\.\w+ == "(\w+)"', path.read_text())
        for value in [*values, "other"]:
            snakemake = SimpleNamespace(wildcards=_Wildcards(value), config=config)
            yield f"{path.name} ({value})", env.get_template(path.name).render(snakemake=snakemake)


def pages():
    """Every page a reader sees: README, the docs' pages, the tutorials, the config's README, the citation
    and the rendered captions."""
    files = [ROOT / "README.md", ROOT / "CITATION.cff", ROOT / "config" / "README.md", *ROOT.glob("docs/*.md"),
             *ROOT.glob("docs/guide/*.md"), *ROOT.glob("examples/*.py")]
    yield from ((str(f.relative_to(ROOT)), f.read_text()) for f in files if f.name != "paper.md")
    yield from rendered_captions()


def test_the_label_check_finds_a_bare_label():
    assert bare_labels("as in Fig 0 (a)") and bare_labels("Figs 0 and 5") and bare_labels("Figure 5 (Fig 0)")
    assert bare_labels("fig0.png, Figure 2 (Fig 0), **Figure 3** (LaTeX label Fig FN2), Figure 9 (c)") == []


def test_no_page_or_caption_names_a_paper_figure_by_its_label_alone():
    """Figures are named by the numbers the published paper prints; a LaTeX label appears only beside its number."""
    bad = {name: found for name, text in pages() if (found := bare_labels(text))}
    assert not bad, bad


def docstrings(path):
    """Every docstring of a Python file (module, classes, functions)."""
    import ast

    tree = ast.parse(path.read_text())
    return [d for n in ast.walk(tree) if isinstance(n, (ast.Module, ast.ClassDef, ast.FunctionDef))
            and (d := ast.get_docstring(n))]


def test_no_plot_or_workflow_script_docstring_names_a_paper_figure_by_its_label_alone():
    """The plot functions keep the LaTeX labels as names (``fig2`` draws Figure 5, the registry of figures says
    which draws which); their docstrings and the workflow scripts' name the printed figures."""
    files = [*ROOT.glob("src/vibroimpact/outputs/plots/*.py"), *ROOT.glob("workflow/scripts/*.py")]
    bad = {f.name: found for f in files for d in docstrings(f) if (found := bare_labels(d))}
    assert not bad, bad


def test_the_check_table_and_the_figures_page_name_figures_by_their_printed_numbers():
    """The check's items (the keys of checks.known), the reasons the config gives, and the figures page's titles."""
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    betas = sorted({b for sc in cfg["branch_scenes"].values() for b in sc["betas"]})
    texts = [*item_names(list(cfg["captions"]), betas), *cfg["checks"]["known"].values()]
    assert not [t for t in texts if bare_labels(t)]
    pytest.importorskip("sphinx")
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import vibroimpact_pages

    from vibroimpact.outputs.registry import figures

    titles = [vibroimpact_pages.title(f.stem) for f in figures(cfg)]
    assert not [t for t in titles if bare_labels(t)] and len(titles) >= 20
    assert all(vibroimpact_pages.title(f).startswith(figure_name(f) + ": ") for f in FIGURE_NUMBERS)
    assert vibroimpact_pages.page_order(["basins", "fig5", "fig0b", "fig0"]) == ["fig0", "fig0b", "fig5", "basins"]


#: where a page shows one of the paper's figures: its image (by the file stem) or its bold heading
SHOWN = re.compile(r"!\[[^\]]*\]\([^)]*?/(\w+)\.png\)|\*\*Figure (\d+)\*\*")


def shown_order(text: str) -> list[int]:
    """The printed numbers of the paper's figures a page shows, each at its first image or bold heading, in the
    page's order."""
    order = []
    for m in SHOWN.finditer(text):
        number = FIGURE_NUMBERS.get(m.group(1)) if m.group(1) else int(m.group(2))
        if number is not None and number not in order:
            order.append(number)
    return order


def test_the_order_check_finds_a_figure_out_of_order():
    assert shown_order("**Figure 4** ![a](x/fig0b.png) **Figure 7** ![b](../figFN2.png) ![c](y/basins.png)") == [4, 7, 3]
    assert shown_order("![Figure 2](results/figures/fig0.png) ... ![Figure 8](results/figures/figBiS.png)") == [2, 8]


def test_every_page_shows_the_paper_s_figures_in_the_paper_s_order():
    """README, the guide and the site's own pages show the paper's figures by increasing printed number."""
    files = [ROOT / "README.md", *sorted(ROOT.glob("docs/*.md")), *sorted(ROOT.glob("docs/guide/*.md"))]
    shown = {str(f.relative_to(ROOT)): shown_order(f.read_text()) for f in files if f.name != "paper.md"}
    assert {k: v for k, v in shown.items() if v != sorted(v)} == {}
    assert sum(len(v) for v in shown.values()) >= 8  # the check sees them: every figure is shown somewhere


def test_the_generated_figures_page_shows_them_in_the_paper_s_order(tmp_path):
    """The site's figures page (docs/_ext, built from the results), from results listing the figures in another
    order: the paper's first, by printed number, then the project's own."""
    pytest.importorskip("sphinx")
    import pandas as pd

    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    import vibroimpact_pages

    figures = ["basins", "fig5", "fig4", "fig0b", "figBiS", "fig3", "fig2", "figFN2", "fig0", "lyapunov"]
    (tmp_path / "results" / "checks").mkdir(parents=True)
    (tmp_path / "results" / "figures").mkdir()
    (tmp_path / "workflow").mkdir()
    (tmp_path / "workflow" / "report").symlink_to(ROOT / "workflow" / "report")
    pd.DataFrame({"item": ["x"], "where": ["section 3"], "paper": [1.0], "computed": [1.0], "tolerance": [0.1],
                  "status": ["pass"], "note": [""]}).to_csv(tmp_path / "results" / "checks" / "paper_values.csv",
                                                            index=False)
    pd.DataFrame({"figure": figures, "variable": "a", "rule": "strict", "max_difference": 0.0, "status": "pass",
                  "detail": ""}).to_csv(tmp_path / "results" / "checks" / "figures.csv", index=False)
    for f in figures:
        (tmp_path / "results" / "figures" / f"{f}.png").write_bytes(b"")
    page = vibroimpact_pages.paper_page(tmp_path)
    assert shown_order(page) == sorted(FIGURE_NUMBERS.values())
    assert page.index("(../results/figures/fig5.png)") < page.index("(../results/figures/basins.png)")
