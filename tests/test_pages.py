"""The pages a newcomer reads first: README's first screen, what the pages cite exists, the pages
describe the project rather than its history, and the catalog, changelog and contributing guide are
there and true."""

import re

import pytest
import yaml
from conftest import ROOT, readme_command

README = (ROOT / "README.md").read_text()


def pages():
    """README, CONTRIBUTING and the documentation's own pages (not what the build generates)."""
    docs = [p for p in (ROOT / "docs").rglob("*.md")
            if not {"_generated", "generated", "tutorials"} & set(p.parts) and p.name != "paper.md"]
    return [ROOT / "README.md", ROOT / "CONTRIBUTING.md", ROOT / "config" / "README.md", *sorted(docs)]


#: words that tell the project's history or the writer's situation instead of what the project is
HISTORY = re.compile(r"\btoday\b|\bnow\b|\bused to\b|\bthis machine\b|\bhere\b|\bfirst measurement\b|\brewrite\b"
                     r"|\b(?:the )?previous (?:kernel|version|run)\b|\bcommit [0-9a-f]{7,40}\b|\bbusier hour\b"
                     r"|\bother tenants\b", re.I)


def test_the_pages_describe_the_project_not_its_history():
    bad = {p.relative_to(ROOT).as_posix(): sorted({m.group(0) for m in HISTORY.finditer(p.read_text())})
           for p in pages()}
    assert not {k: v for k, v in bad.items() if v}


def test_readme_s_first_screen():
    """What and for whom, then the two commands as the first two code blocks (tests run them), one figure,
    and the links to the notation, the documentation and one's own device, before the next section."""
    first = README[:README.index("\n## ")]
    blocks = re.findall(r"```(\w+)\n(.*?)```", README, re.S)
    assert blocks[0][1].strip() == readme_command(
        "tests/test_readme.py::test_the_first_command_sets_up_and_runs_the_default_target")
    assert blocks[1][1].strip() == ".venv/bin/python -m pytest"
    assert first.count("```bash") == 2 and first.count("![") == 1
    assert "For researchers" in first
    for link in ("docs/guide/notation.md", "docs/guide/", "#rerunning-for-a-new-device", "docs/guide/troubleshooting.md"):
        assert f"]({link})" in first, link
    assert "glibc" not in first and "libm" not in first  # test internals live on the testing page
    assert re.search(r"^## Rerunning for a new device$", README, re.M)


def test_what_readme_and_the_pages_link_to_exists():
    for page in pages():
        for target in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", page.read_text()):
            if target.startswith(("http", "mailto")):
                continue
            path = (page.parent / target).resolve()
            if "_generated" in path.parts or "results" in path.relative_to(ROOT).parts[:1]:
                continue  # made by the build or the workflow
            assert path.exists(), (page.name, target)


def test_readme_cites_the_workflow_s_results_as_such():
    """What README cites under results/ is either committed (the figures) or said to be written by a
    target; the pages are said to be readable as they are only for what the repository holds."""
    import subprocess

    for cited in re.findall(r"`(results/[^`]+)`", README):
        if cited.startswith("results/figures/") and cited.endswith(".png"):
            continue
        # not committed: git ignores it (a workflow output), whether or not a run has written it here
        ignored = subprocess.run(["git", "check-ignore", "-q", "--no-index", cited], cwd=ROOT)
        if ignored.returncode == 128:
            pytest.skip("not a git repository: git cannot say what a clone holds")
        assert ignored.returncode == 0 or cited.startswith("results/figures"), cited
    assert "results are not committed, only the figures" in README
    assert "The pages are also readable in `docs/`" not in README
    ignored = (ROOT / ".gitignore").read_text()
    assert "results/*" in ignored and "!results/figures/*.png" in ignored


def test_readme_says_what_each_public_function_returns():
    """Where README names what a public function returns, the function's annotation agrees."""
    import inspect

    import vibroimpact as vi

    stated = {"find_orbit": "Orbit", "identify_attractor": "Attractor", "lyapunov": "Lyapunov",
              "orbit_energy": "dict", "family_exit": "dict", "sweep_d_graz": "dict", "polish_cycle": "dict", "long_run": "dict",
              "best_designs": "list[dict]", "simulate": "xr.Dataset", "continue_orbit": "xr.Dataset",
              "sweep": "xr.Dataset", "regime_map": "xr.Dataset", "basins": "xr.Dataset",
              "branch_energy": "xr.Dataset", "sweep_energy": "xr.Dataset", "voltage_gain": "np.ndarray"}
    for name, kind in stated.items():
        assert inspect.signature(getattr(vi, name)).return_annotation == kind, name
        assert kind == "xr.Dataset" or f"`{name}`" in README, name
    assert "Everything returns xarray datasets" not in README
    phi, v0 = vi.start_states(8)
    assert len(phi) == len(v0) == 8


def test_the_catalog_file_quotes_real_commands_and_pages():
    cat = yaml.safe_load((ROOT / ".snakemake-workflow-catalog.yml").read_text())
    desc = " ".join(cat["usage"]["mandatory-flags"]["desc"].split())
    first = readme_command("tests/test_readme.py::test_the_first_command_sets_up_and_runs_the_default_target")
    assert f"`{first}`" in desc
    for path in re.findall(r"\b((?:docs|profiles)/[\w/.-]+\w)", desc):
        assert (ROOT / path).exists(), path
    section = re.search(r'"([^"]+)"', desc).group(1)
    assert f"# {section}" in (ROOT / "docs" / "guide" / "cluster.md").read_text()


def test_changelog_contributing_and_troubleshooting_are_there_and_linked():
    changelog = (ROOT / "CHANGELOG.md").read_text()
    assert "Keep a Changelog" in changelog and "## [Unreleased]" in changelog
    contributing = (ROOT / "CONTRIBUTING.md").read_text()
    for needed in ('pytest -m "not slow"', "figure_conditioning update_figure_references", "## Add a figure",
                   "## Add a rule", "90 minutes"):
        assert needed in contributing, needed
    # the command to accept references is the one the checks page shows and a test runs
    accept = readme_command("tests/test_conditioning.py::test_references_are_accepted_with_their_measured_conditioning")
    assert accept.split("#")[0].strip() in contributing
    assert "CHANGELOG.md" in README and "CONTRIBUTING.md" in README
    index = (ROOT / "docs" / "index.md").read_text()
    assert "guide/troubleshooting" in index and "guide/notation" in index


def test_the_simulation_page_names_the_flags_the_datasets_store():
    """The simulation page lists the event kinds and run statuses as the datasets store them: each flag's
    integer and name, in the order of the datasets' ``flag_values`` and ``flag_meanings`` (a run of
    ``simulate`` and of ``simulate_batch``), and the grazing threshold the kernels use."""
    import math

    import numpy as np

    import vibroimpact as vi
    from vibroimpact.dynamics import kernels

    page = " ".join((ROOT / "docs" / "guide" / "simulation.md").read_text().split())
    flags = lambda sentence: [(int(k), name) for k, name in re.findall(r"(\d) `(\w+)`", sentence)]
    kinds = flags(re.search(r"their names, in order: (.*?); `ds.kind == 0`", page).group(1))
    statuses = flags(re.search(r"the sweeps' windows: (.*?)\.", page).group(1))
    named = lambda var: list(zip(var.attrs["flag_values"].tolist(), var.attrs["flag_meanings"].split(), strict=True))
    run = vi.simulate(vi.Params.from_physical(s=0.257, beta=math.pi / 6), phi=1.015, v0=0.1924, n_impacts=20)
    assert kinds == named(run.kind) and len(kinds) == 5
    batch = vi.simulate_batch(d=np.array([0.14, 0.16]), gbar=0.122, r=0.5, phi=1.0, v0=0.2, n_impacts=20)
    assert statuses == named(batch.status) and run.attrs["status"] in dict(statuses).values()
    assert "`ds.kind == 0` selects the impacts" in page and dict(kinds)[0] == "impact"
    threshold = float(re.search(r"an impact with \|Ż⁻\| < (\S+?)\)", page).group(1))
    assert threshold == kernels.V_GRAZING


def test_the_paper_s_authors_are_named_on_every_page_as_citation_cff_names_them():
    """Wherever a file the repository tracks writes an author of the paper with a first name or an initial
    ("L. Serdukova", "Larissa Serdukova"), it is the given name CITATION.cff states (the paper's own title
    page), or its initial."""
    import subprocess

    authors = yaml.safe_load((ROOT / "CITATION.cff").read_text())["preferred-citation"]["authors"]
    tracked = subprocess.run(["git", "ls-files", "-co", "--exclude-standard"], cwd=ROOT, capture_output=True,
                             text=True)
    if tracked.returncode:
        pytest.skip("not a git repository: git cannot say which files the repository holds")
    texts = [ROOT / f for f in tracked.stdout.split() if f.endswith((".md", ".rst", ".py", ".cff", ".yaml", ".txt"))]
    seen = 0
    for path in texts:
        text = path.read_text(errors="replace")
        for a in authors:
            for first in re.findall(rf"\b([A-Z][a-z]*\.?)\s+{a['family-names']}\b", text):
                seen += 1
                assert first in (a["given-names"], a["given-names"][0] + "."), (path.name, first, a["family-names"])
    assert seen >= 3  # the model page names all three


#: the kinds of change Keep a Changelog names, what a user reads first in each version's section
USER_KINDS = ("Added", "Changed", "Deprecated", "Removed", "Fixed", "Security")


def test_the_changelog_and_the_citation_name_the_version_and_release_date_of_the_package():
    """CHANGELOG.md's latest release is the version the package carries (_version.py) and the one CITATION.cff
    cites, with the same date; nothing says no version is tagged."""
    import datetime

    import vibroimpact

    changelog = (ROOT / "CHANGELOG.md").read_text()
    releases = re.findall(r"^## \[(\d+\.\d+\.\d+)\] - (\d{4}-\d{2}-\d{2})$", changelog, re.M)
    assert releases, "no released version in CHANGELOG.md"
    version, date = releases[0]
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert version == vibroimpact.__version__ == cff["version"]
    assert datetime.date.fromisoformat(date) == cff["date-released"]
    assert changelog.index("## [Unreleased]") < changelog.index(f"## [{version}] - {date}")
    assert "no version has been tagged" not in changelog.lower()


def test_each_version_of_the_changelog_says_first_what_changed_for_a_user():
    """Every version's section (Unreleased included) opens with Keep a Changelog's kinds (Added, Changed, Fixed...):
    internal work (refactors, the development before a release) comes after them, never first."""
    changelog = (ROOT / "CHANGELOG.md").read_text()
    sections = re.split(r"^## ", changelog, flags=re.M)[1:]
    assert sections[0].startswith("[Unreleased]") and len(sections) >= 2
    for sec in sections:
        kinds = re.findall(r"^### (.+)$", sec, re.M)
        assert kinds and kinds[0] in USER_KINDS, (sec.splitlines()[0], kinds)
        user = [k in USER_KINDS for k in kinds]
        assert user == sorted(user, reverse=True), (sec.splitlines()[0], kinds)  # the user's kinds come first
