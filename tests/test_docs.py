"""The documentation site: built from the repository and the workflow's results with warnings as errors,
its API reference equal to the public names, every public docstring in numpydoc form, a page read in a
real browser."""

import re
import shutil
import subprocess

import pytest
from conftest import ROOT

import vibroimpact

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def api_names():
    """The names the API reference lists (its autosummary entries)."""
    text = (ROOT / "docs" / "api.rst").read_text()
    return re.findall(r"^   ([A-Za-z_]\w*)$", text, re.M)


def test_the_api_reference_lists_exactly_the_public_names():
    names = api_names()
    assert len(names) == len(set(names))
    assert set(names) == set(vibroimpact.__all__) - {"__version__"}
    # and no helper the package imports for itself shows
    assert set(dir(vibroimpact)) == {*vibroimpact.__all__, "dynamics", "analysis", "benchmarks", "outputs", "datasets"}


def test_every_public_name_has_a_numpydoc_docstring():
    """Its summary, its parameters, what it returns and an example documented (numpydoc's checks SS01, PR01,
    RT01, EX01, as the site's build applies them); the records a call returns document their fields as
    Attributes."""
    import dataclasses

    from numpydoc.validate import validate

    bad = {}
    for name in sorted(set(vibroimpact.__all__) - {"__version__"}):
        obj = getattr(vibroimpact, name)
        if dataclasses.is_dataclass(obj) and "Attributes\n" in obj.__doc__.replace(" ", ""):
            # a record a call returns: its fields documented as Attributes, every one
            documented = set(re.findall(r"^    (\w+)(?:, (\w+))? :", obj.__doc__, re.M))
            names = {n for pair in documented for n in pair if n}
            assert names >= {f.name for f in dataclasses.fields(obj)}, (name, {f.name for f in dataclasses.fields(obj)} - names)
            continue
        errors = [e for e in validate(f"vibroimpact.{name}")["errors"]
                  if e[0] in ("SS01", "PR01", "RT01", "EX01")
                  and not (isinstance(obj, type) and e[0] == "RT01")]
        if errors:
            bad[name] = errors
    assert not bad, bad


def test_the_main_functions_cite_the_paper_s_equations():
    """Where the paper has the equation, the docstring names its label."""
    cites = {"find_orbit": "zdotj_p1", "orbit_run": "zj_p1", "PhysicalScales": "nondXYt", "delivered": "V1",
             "Orbit": "Lin2"}
    for name, label in cites.items():
        doc = getattr(vibroimpact, name).__doc__ + (vibroimpact.analysis.orbits.__doc__ if name == "find_orbit" else "")
        assert label in doc, (name, label)


@pytest.mark.slow
def test_the_docs_build_with_warnings_as_errors(readme_clone, docs_build):
    """README's docs command in the scratch clone, after the default target and the check: the site
    builds (Sphinx with -W: an unresolved include, a docstring without its sections or a failing tutorial
    fails it), with the user guide, every tutorial run, the paper's figures page generated from the
    results and the API reference."""
    _, first, _ = readme_clone
    assert first.returncode == 0
    clone, res = docs_build
    warnings = clone / "logs" / "docs" / "docs.warnings.txt"
    assert res.returncode == 0, ((res.stdout + res.stderr)[-3000:] + "\nSphinx's warnings:\n"
                                 + (warnings.read_text() if warnings.exists() else "(none recorded)"))
    assert warnings.read_text().strip() == ""  # the file of warnings is written, and empty
    html = clone / "results" / "docs" / "html"
    for page in ("index", "paper", "speed", "api", "guide/model", "guide/workflow", "guide/config", "guide/studies",
                 "guide/cluster", "guide/datasets", "tutorials/index"):
        assert (html / f"{page}.html").stat().st_size > 5_000, page
    tutorials = sorted((html / "tutorials").glob("tutorial_*.html"))
    assert len(tutorials) >= 6
    for t in tutorials:  # each ran: its output and its figures are on the page
        text = t.read_text()
        assert "sphx-glr-script-out" in text or "sphx_glr" in text, t.name
    paper = (html / "paper.html").read_text()
    for fig in ("fig0b", "fig4", "figFN2", "fig2", "fig3", "figBiS", "fig0", "fig5", "work_precision"):
        assert f"{fig}.png" in paper, fig
    assert "Published values this figure shows" in paper and "Check result" in paper
    for name in vibroimpact.__all__[1:]:
        assert (html / "generated" / f"vibroimpact.{name}.html").exists(), name


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None, reason="no headless Chromium: install it with tools/install_chromium.sh (root)")
def test_a_docs_page_renders_in_a_real_browser(docs_build, tmp_path):
    """The built paper page, opened by headless Chromium as a reader's browser would: a screenshot with
    content (not blank)."""
    import numpy as np
    from PIL import Image

    clone, _ = docs_build
    page = clone / "results" / "docs" / "html" / "paper.html"
    shot = tmp_path / "paper.png"
    subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                    "--disable-background-networking", "--disable-component-update", "--disable-sync",
                    f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1300,1800", "--virtual-time-budget=5000",
                    f"--screenshot={shot}",
                    page.as_uri()], capture_output=True, timeout=120)
    img = np.asarray(Image.open(shot).convert("L"), dtype=float)
    assert img.shape[0] > 1000 and img.std() > 20  # text, a figure and tables, not an empty page
