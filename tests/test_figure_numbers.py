"""The paper's figures by the numbers the published paper prints (Figure 2 ... Figure 9), from one
definition (vibroimpact.outputs.paper.FIGURE_NUMBERS): every figure of the default config is numbered."""

import yaml
from conftest import ROOT

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
