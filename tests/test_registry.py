"""The registry of figures (vibroimpact.outputs.registry): one row per figure, which the workflow's target lists,
its report captions, the documentation's figures page and the printed numbers read; a figure added as one row
(with its plot function and caption) is drawn, checked and documented with no other file touched."""

import importlib
import os
import re
import subprocess
import sys

import pytest
import yaml
from conftest import ROOT, scratch_clone

from vibroimpact.outputs.paper import FIGURE_NUMBERS
from vibroimpact.outputs.registry import REGISTRY, RegistryError, figure, figures
from vibroimpact.outputs.workflow_config import ConfigError, check, figure_names

CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


def test_a_figure_is_found_by_the_number_the_paper_prints():
    assert (figure(5).stem, figure(5).rule, figure(5).caption) == ("fig2", "fig2", "fig2.rst")
    assert figure(2).stem == "fig0" and figure(9).stem == "fig5" and figure(3).stem == "figFN2"
    assert figure(2).plot == figure(9).plot == "vibroimpact.outputs.plots.energy:fig_energy"
    assert figure("fig4").number == 7 and figure("basins").number is None
    with pytest.raises(RegistryError, match=r"no figure printed as Figure 1: .*\[2, 3, 4, 5, 6, 7, 8, 9\]"):
        figure(1)
    with pytest.raises(RegistryError, match="no figure 'fig9'"):
        figure("fig9")


def test_the_printed_numbers_are_the_registry_s():
    assert FIGURE_NUMBERS == {f.stem: f.number for f in REGISTRY if f.number is not None}
    assert list(FIGURE_NUMBERS.values()) == sorted(FIGURE_NUMBERS.values())


def test_a_family_s_figure_is_found_by_its_stem_with_its_entry():
    row = figure("bifurcation_set_s_F")
    assert (row.stem, row.member, row.caption_wildcards()) == ("bifurcation_set_s_F", "s_F", {"map": "s_F"})
    assert row.heading() == "Bifurcation set over (s, ‖F̂‖)"
    assert figure("design_map_s_beta").heading() == "Design map over (s, β)"
    assert figure(9).heading() == "Figure 9 (Fig 5): output voltages for four inclines"


def test_the_config_s_figures_are_the_registry_s_in_its_order():
    assert figure_names(CONFIG) == [
        "fig0b", "fig4", "figFN2", "fig2", "fig3", "figBiS", "basins", "regime_map", "fig0", "fig5", "lyapunov",
        "design", "knocks", "knock_section", "work_precision", "failure_map", "analytics_accuracy", "lyapunov_precision",
        "bifurcation_set_s_beta",
        "bifurcation_set_s_F", "bifurcation_set_d_gbar", "bifurcation_set_d_r", "design_map_s_beta",
        "design_map_s_F"]
    tiny = {**CONFIG, "scenes": {"fig4": CONFIG["scenes"]["fig4"]}, "design": {**CONFIG["design"], "maps": []}}
    assert [f.stem for f in figures(tiny, target="design_maps")] == []
    assert "fig0b" not in figure_names(tiny) and "fig4" in figure_names(tiny)
    assert [f.stem for f in figures(CONFIG, target="all", paper_device=False) if f.rule == "bench_figure"] == []


def test_a_config_figure_the_registry_does_not_hold_is_refused():
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    cfg["scenes"]["fig7"] = cfg["scenes"]["fig4"]
    with pytest.raises(ConfigError, match=r"scenes\.fig7 = 'fig7' is not allowed; allowed: a figure of the registry"):
        check(cfg)


def test_every_row_names_a_plot_function_a_caption_and_a_rule_that_draws_it():
    """The plot function exists, the caption template is in workflow/report, and the rule is one of the workflow's,
    whose report caption and category it reads from the registry."""
    rules = {}
    for smk in (ROOT / "workflow" / "rules").glob("*.smk"):
        for m in re.finditer(r"^rule (\w+):\n(.*?)(?=^rule |\Z)", smk.read_text(), re.M | re.S):
            rules[m.group(1)] = m.group(2)
    for row in REGISTRY:
        module, _, name = row.plot.partition(":")
        assert callable(getattr(importlib.import_module(module), name)), row.plot
        assert (ROOT / "workflow" / "report" / row.caption).is_file(), row.caption
        if row.rule == "registry_figure":  # the generic rule: draws from the row's inputs, captions by the row
            generic = (ROOT / "workflow" / "rules" / "figures.smk").read_text()
            assert "rule registry_figure:" in generic and 'caption="../report/registry_figure.rst"' in generic
            assert row.inputs and all(f.startswith("results/") for f in row.inputs), row.stem
        else:
            assert f'caption=figure_caption("{row.rule}")' in rules[row.rule], row.rule
            assert f'category=figure_category("{row.rule}")' in rules[row.rule], row.rule
        assert row.check == "check_figure" and row.target in ("all", "bench", "bifurcation", "design_maps")


def test_the_target_lists_name_no_figure_but_through_the_registry():
    """The default target, `bifurcation` and `design_maps` list their figures with figure_targets (a figure
    written into a target list by hand would be drawn without its row)."""
    text = (ROOT / "Snakefile").read_text()
    all_rule = text[text.index("rule all:"):]
    assert "figure_targets(\"all\")" in all_rule and "results/figures/" not in all_rule
    for smk, target in (("bifurcation.smk", "bifurcation"), ("design.smk", "design_maps")):
        body = (ROOT / "workflow" / "rules" / smk).read_text()
        block = body[body.index(f"rule {target}:"):].split("\nrule ")[0]
        assert f'figure_targets("{target}"' in block and "results/figures/" not in block


def test_every_figure_has_a_committed_reference():
    ref = ROOT / "reference" / "figures"
    assert [f for f in figure_names(CONFIG) if not (ref / f"{f}.nc").exists()] == []


# ---- a figure added through the registry ------------------------------------------------------------------

PLOT = '''"""A figure added through the registry (the test's)."""
import matplotlib.pyplot as plt
import numpy as np


def fig_ramp():
    """A ramp and a parabola, drawn from nothing."""
    fig, ax = plt.subplots(figsize=(4, 3))
    x = np.linspace(0.0, 1.0, 11)
    ax.plot(x, x, label="ramp")
    ax.plot(x, x**2, label="parabola")
    ax.set_xlabel("d")
    ax.set_ylabel("y")
    ax.legend()
    return fig
'''
ROW = '''    Figure("ramp", None, "vibroimpact.outputs.plots.ramp:fig_ramp", "registry_figure", "ramp.rst", "A ramp"),
'''
CAPTION = '''**A ramp** (a figure added through the registry): y = d and y = d² against d.

{{ snakemake.config["_check_results"].get("ramp", "Check result: not run yet (snakemake --cores 2 check).") }}
'''
#: the documentation's figures page built from results that hold the new figure only
PAGE = '''
import sys
from pathlib import Path
import pandas as pd
import vibroimpact_pages as pages
root = Path(sys.argv[1])
(root / "results" / "checks").mkdir(parents=True, exist_ok=True)
pd.DataFrame({"item": ["x"], "where": ["section 3"], "paper": [1.0], "computed": [1.0], "tolerance": [0.1],
              "status": ["pass"], "note": [""]}).to_csv(root / "results/checks/paper_values.csv", index=False)
pd.read_csv(root / "results/checks/figures/ramp.csv").to_csv(root / "results/checks/figures.csv", index=False)
print(pages.paper_page(root))
'''


@pytest.mark.slow  # about a minute: Snakemake parses the workflow four times and runs three small jobs
def test_a_figure_added_through_the_registry_is_drawn_checked_and_documented(tmp_path):
    """In a scratch clone, a plot function (a new module), one row of the registry and its caption: the default
    target plans it, the generic rule draws it, `check` reports it as new (no committed reference) and, once its
    reference is accepted, passes it; the documentation's figures page shows it with its heading and caption."""
    clone = scratch_clone(tmp_path, git=True)
    (clone / "src/vibroimpact/outputs/plots/ramp.py").write_text(PLOT)
    reg = clone / "src/vibroimpact/outputs/registry.py"
    end = "\n)\n\n\ndef _section"  # the registry's last row, then the tuple closes
    assert end in reg.read_text()
    reg.write_text(reg.read_text().replace(end, "\n" + ROW.rstrip("\n") + end, 1))
    (clone / "workflow/report/ramp.rst").write_text(CAPTION)
    changed = subprocess.run(["git", "status", "--porcelain"], cwd=clone, capture_output=True, text=True).stdout
    assert sorted(changed.splitlines()) == [" M src/vibroimpact/outputs/registry.py",
                                            "?? src/vibroimpact/outputs/plots/ramp.py", "?? workflow/report/ramp.rst"]
    env = os.environ | {"PYTHONPATH": str(clone / "src"), "MPLBACKEND": "Agg"}

    def snakemake(*args):
        return subprocess.run([sys.executable, "-m", "snakemake", "--cores", "1", *args], cwd=clone,
                              capture_output=True, text=True, timeout=900, env=env)

    planned = snakemake("-n")
    assert planned.returncode == 0, planned.stderr[-3000:]
    assert "results/figures/ramp.png" in planned.stdout + planned.stderr
    drawn = snakemake("results/figures/ramp.png")
    assert drawn.returncode == 0, drawn.stderr[-3000:]
    assert (clone / "results/figures/ramp.png").stat().st_size > 1000
    new = snakemake("results/checks/figures/ramp.csv")
    assert new.returncode != 0 and "ramp: no committed reference reference/figures/ramp.nc" in new.stderr
    (clone / "reference/figures/ramp.nc").write_bytes((clone / "results/figures/data/ramp.nc").read_bytes())
    checked = snakemake("results/checks/figures/ramp.csv")
    assert checked.returncode == 0, checked.stderr[-3000:]
    rows = (clone / "results/checks/figures/ramp.csv").read_text()
    assert rows.count(",pass,") >= 5 and "fail" not in rows  # two lines' x and y, and the image
    page = subprocess.run([sys.executable, "-c", PAGE, str(clone)], capture_output=True, text=True, timeout=300,
                          env=env | {"PYTHONPATH": f"{clone / 'src'}{os.pathsep}{clone / 'docs' / '_ext'}"})
    assert page.returncode == 0, page.stderr[-3000:]
    assert "## A ramp\n\n![ramp](../results/figures/ramp.png)" in page.stdout
    assert "**A ramp** (a figure added through the registry)" in page.stdout
    assert "Check result: figure data vs committed reference" in page.stdout
