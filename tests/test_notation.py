"""docs/guide/notation.md against the code: every code name it gives exists, every dataset variable it
gives is one the package writes, the time convention is the code's, and every page links to it."""

import dataclasses
import inspect
import math
import re

import pytest
from conftest import ROOT

import vibroimpact as vi
from vibroimpact.datasets import VARIABLES

PAGE = ROOT / "docs" / "guide" / "notation.md"
SOURCE = "\n".join(p.read_text() for p in (ROOT / "src" / "vibroimpact").rglob("*.py"))


def rows():
    """``(symbol, unit, code cell, dataset cell)`` of every row of the symbols table."""
    text = PAGE.read_text()
    table = text[text.index("| symbol | meaning |"):].split("\n\n")[0].splitlines()[2:]
    out = []
    for line in table:
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        assert len(cells) == 5, line
        out.append((cells[0], cells[2], cells[3], cells[4]))
    return out


def resolves(name):
    """``vi.A.b`` (an attribute or a dataclass field) or ``vi.f(kw=)`` (a function taking ``kw``)."""
    call = re.fullmatch(r"vi\.([\w.]+)\((\w+)=\)", name)
    path = call.group(1) if call else name.removeprefix("vi.")
    obj = vi
    for part in path.split("."):
        fields = {f.name for f in dataclasses.fields(obj)} if dataclasses.is_dataclass(obj) else set()
        if part in fields and not hasattr(obj, part):
            return not call
        obj = getattr(obj, part)
    return call is None or call.group(2) in inspect.signature(obj).parameters


def written(var):
    """A dataset variable the package writes: in VARIABLES, or named as a string where a module builds it."""
    return var in VARIABLES or re.search(rf"[\"']{re.escape(var)}[\"']|\b{re.escape(var)}=", SOURCE) is not None


def test_the_table_has_the_symbols_the_pages_use():
    symbols = " ".join(r[0] for r in rows())
    for s in ("d", "s", "ḡ", "‖F̂‖", "ω", "M", "r", "φ", "v0", "Ż⁻", "t", "τ", "n:m", "period-k", "BBT", "P1",
              "G1", "d_graz", "λ₁", "U_k", "Ū_I", "Ū_T", "w", "NS", "0.6225"):
        assert s in symbols, s


def test_every_code_name_and_dataset_variable_exists():
    bad = []
    for symbol, _, code, data in rows():
        for name in re.findall(r"`([^`]+)`", code):
            if name.startswith("vi.") and not resolves(name):
                bad.append((symbol, name))
        if not data.startswith("—"):
            bad += [(symbol, v) for v in re.findall(r"`(\w+)`", data) if not written(v)]
    assert not bad, bad


def test_the_units_are_the_datasets_units():
    """Where a row names a dataset variable VARIABLES describes, its unit is the one the datasets carry."""
    for symbol, unit, _, data in rows():
        first = re.findall(r"`(\w+)`", data)
        if first and first[0] in VARIABLES and VARIABLES[first[0]][0]:
            assert VARIABLES[first[0]][0] == unit, (symbol, unit, VARIABLES[first[0]][0])


def test_the_time_convention_and_the_paper_s_factor_are_the_code_s():
    p = vi.Params.from_physical(s=1.0, beta=math.pi / 2)
    dev = vi.Device()
    assert p.d == pytest.approx(0.6225, rel=1e-12) and p.gbar == pytest.approx(0.24402, rel=1e-12)
    assert p.scales.time == pytest.approx(math.pi / dev.omega)  # tau = (pi / omega) t
    text = PAGE.read_text()
    assert "τ = (π / ω) t, that is t = ω τ / π" in text
    model = (ROOT / "docs" / "guide" / "model.md").read_text()
    assert "t*" not in model and "τ = π t / ω" in model
    assert "t = omega tau / pi" in VARIABLES["t"][2]


#: symbols whose use on a page calls for the link
SYMBOLS = re.compile(r"ḡ|‖F̂‖|Ż|λ|d_graz|β|Ū|\bn:m\b")


def test_readme_and_every_page_using_a_symbol_link_to_the_notation_before_or_at_its_first_use():
    readme = (ROOT / "README.md").read_text()
    assert readme.index("docs/guide/notation.md") < SYMBOLS.search(readme).start() + 200
    for page in [*sorted((ROOT / "docs" / "guide").glob("*.md")), ROOT / "docs" / "speed.md"]:
        text = page.read_text()
        if page.name == "notation.md" or not SYMBOLS.search(text):
            continue
        assert "notation.md" in text, page.name
        # the link sits in the paragraph of the first symbol or before it
        first = SYMBOLS.search(text).start()
        assert text.index("notation.md") < text.find("\n\n", first) if "\n\n" in text[first:] else True, page.name
    assert "guide/notation" in (ROOT / "docs" / "index.md").read_text()
