"""Every public name has an example that runs: an Examples section with doctest lines, run by pytest's
``--doctest-modules`` over the package (pyproject.toml), and the numpydoc checks the site's build applies
(docs/conf.py) pass on every public name and documented member."""

import dataclasses
import inspect
import re
import runpy

import pytest
from conftest import ROOT

import vibroimpact

PUBLIC = sorted(set(vibroimpact.__all__) - {"__version__"})  # __version__ is a string: no docstring


def examples_section(doc: str) -> str:
    """The text of a numpydoc docstring's Examples section ('' where it has none)."""
    parts = re.split(r"^Examples\n-{8,}\n", doc, flags=re.M)
    if len(parts) < 2:
        return ""
    # up to the next section header (a line underlined with dashes), if any
    return re.split(r"^\S[^\n]*\n-{3,}\n", parts[1], flags=re.M)[0]


def members(cls):
    """The public methods and properties a class defines itself (the API pages list them)."""
    fields = {f.name for f in dataclasses.fields(cls)} if dataclasses.is_dataclass(cls) else set()
    return [name for name, value in vars(cls).items()
            if not name.startswith("_") and name not in fields
            and (inspect.isfunction(value) or isinstance(value, (classmethod, staticmethod, property)))]


def numpydoc_config():
    """The checks and exclusions of docs/conf.py (the site's build fails on any check they select)."""
    conf = runpy.run_path(str(ROOT / "docs" / "conf.py"))
    exclude = re.compile("|".join(conf["numpydoc_validation_exclude"]))
    return set(conf["numpydoc_validation_checks"]), exclude


@pytest.mark.parametrize("name", PUBLIC)
def test_every_public_name_has_an_example(name):
    doc = inspect.getdoc(getattr(vibroimpact, name)) or ""
    assert doc, f"{name}: no docstring"
    section = examples_section(doc)
    assert section, f"{name}: no Examples section"
    assert re.search(r"^>>> \S", section, re.M), f"{name}: its Examples section has no doctest line (>>>)"


def test_the_examples_section_is_found_only_where_it_is():
    assert examples_section("Sum.\n\nExamples\n--------\n>>> 1 + 1\n2\n") == ">>> 1 + 1\n2\n"
    assert examples_section("Sum.\n\nReturns\n-------\nint\n    The sum.\n") == ""
    prose = "Sum.\n\nExamples\n--------\nNone here.\n\nNotes\n-----\n>>> 1\n"
    assert not re.search(r"^>>> \S", examples_section(prose), re.M)


def test_every_public_name_and_member_passes_the_site_s_numpydoc_checks():
    """SS01, PR01, RT01 and EX01 (docs/conf.py): the build of the API reference fails on any of them."""
    validate = pytest.importorskip("numpydoc.validate").validate
    checks, exclude = numpydoc_config()
    assert {"SS01", "PR01", "RT01", "EX01"} <= checks
    names = [f"vibroimpact.{n}" for n in PUBLIC]
    names += [f"vibroimpact.{n}.{m}" for n in PUBLIC if inspect.isclass(getattr(vibroimpact, n))
              for m in members(getattr(vibroimpact, n))]
    bad = {}
    for full in names:
        if exclude.search(full):
            continue
        errors = [e for e in validate(full)["errors"] if e[0] in checks]
        if errors:
            bad[full] = errors
    assert not bad, bad
    # the exclusions are the record classes' attribute lists (and the dataclass constructors), not more
    assert not [n for n in names[:len(PUBLIC)] if exclude.search(n)]
