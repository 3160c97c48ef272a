"""The browsable report: built by Snakemake from the default run, read as a reader would."""

import shutil
import subprocess

import numpy as np
import pytest
import yaml
from conftest import ROOT, readme_command, run_readme

from vibroimpact.outputs.workflow_config import figure_names

#: every figure `check` compares, from the registry of figures (vibroimpact.outputs.registry): `check` draws them
FIGURES = figure_names(yaml.safe_load((ROOT / "config" / "config.yaml").read_text()))
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.fixture(scope="module")
def report(default_run):
    """README's report command, as written, in the scratch clone README's first command set up."""
    tmp_path, res = default_run
    assert res.returncode == 0, res.stderr[-3000:]
    out = run_readme(tmp_path, readme_command(
        "tests/test_report.py::test_report_holds_every_figure_with_its_caption_and_the_checks"))
    assert out.returncode == 0, out.stderr[-3000:]
    return tmp_path / "results" / "report.html"


@pytest.mark.slow
def test_report_holds_every_figure_with_its_caption_and_the_checks(report):
    html = report.read_text()
    assert report.stat().st_size > 1_000_000  # self-contained: the figures are embedded
    for fig in FIGURES:
        assert f"{fig}.png" in html, fig
    for text in ("Paper figures", "Beyond the paper", "Checks", "paper_values.csv", "figures.csv",
                 "located critical points A1"):
        assert text in html, text
    # every figure's caption carries its check result (data arrays and image), none says "not run yet"
    assert html.count("Check result: figure data vs committed reference") == len(FIGURES)
    assert "not run yet" not in html


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None, reason="no headless Chromium: install it with tools/install_chromium.sh (root)")
def test_report_renders_in_a_real_browser(report, tmp_path):
    """Headless Chromium runs the report's scripts: the rendered page lists the categories and every
    figure, and a screenshot of it is not blank."""
    base = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--virtual-time-budget=15000"]
    dom = subprocess.run([*base, "--dump-dom", report.as_uri()], capture_output=True, text=True, timeout=180).stdout
    assert "Paper figures" in dom and "Checks" in dom
    shot = tmp_path / "report.png"
    subprocess.run([*base, f"--screenshot={shot}", "--window-size=1280,1600", report.as_uri()],
                   capture_output=True, timeout=180, check=True)
    import matplotlib.image as mpimg

    img = mpimg.imread(shot)
    assert img.shape[0] >= 1000 and float(np.std(img[..., :3])) > 0.02  # something is drawn
