"""The package as users get it: a wheel that works outside the repository, its version, and the
command that says where the workflow is and what it needs."""

import ast
import os
import re
import shutil
import subprocess
import sys
import zipfile

import pytest
from conftest import ROOT

import vibroimpact


def test_python_m_vibroimpact_names_the_version_the_workflow_and_the_optional_parts():
    out = subprocess.run([sys.executable, "-m", "vibroimpact"], cwd=ROOT, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert f"vibroimpact {vibroimpact.__version__}" in out.stdout
    assert str(ROOT / "Snakefile") in out.stdout
    for part in ("heyoka", "Siconos", "SLURM executor plugin"):
        assert part in out.stdout


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    """``pip wheel .`` (as ``pip install .`` builds it: setuptools from the package index in an isolated
    build environment), then unpacked into a directory of its own."""
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src-tree"  # a copy: setuptools leaves a build/ directory where it builds
    src.mkdir()
    for item in ("pyproject.toml", "README.md", "LICENSE", "src"):
        if (ROOT / item).is_dir():
            shutil.copytree(ROOT / item, src / item, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
        else:
            shutil.copy(ROOT / item, src / item)
    res = subprocess.run([sys.executable, "-m", "pip", "wheel", str(src), "--no-deps",
                          "-w", str(tmp / "dist"), "-q"], capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr[-2000:]
    (whl,) = (tmp / "dist").glob("vibroimpact-*.whl")
    site = tmp / "site"
    zipfile.ZipFile(whl).extractall(site)
    return whl, site


def test_the_wheel_holds_the_package_and_its_data_not_the_workflow(wheel):
    whl, _ = wheel
    names = zipfile.ZipFile(whl).namelist()
    assert "vibroimpact/__init__.py" in names and "vibroimpact/outputs/plots/vibroimpact.mplstyle" in names
    assert any(n.startswith("vibroimpact/benchmarks/_siconos/") for n in names)
    assert not any(n.startswith(("workflow/", "config/", "tests/")) or n == "Snakefile" for n in names)
    assert f"vibroimpact-{vibroimpact.__version__}.dist-info/entry_points.txt" in names


def test_the_wheel_runs_the_api_outside_the_repository(wheel, tmp_path):
    """From a directory outside the repository with the wheel's copy first on the path: the package
    imported is the wheel's, it simulates the 2:1 orbit of Fig 4 (a), draws a figure with its style
    file, and its command says there is no workflow here."""
    _, site = wheel
    code = (
        "import math, vibroimpact as vi\n"
        "from vibroimpact.outputs import plots\n"
        "import matplotlib.pyplot as plt\n"
        "print(vi.__file__)\n"
        "p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)\n"
        "a = vi.identify_attractor(vi.simulate(p, 1.015, 0.1924, n_impacts=3000))\n"
        "print(a.label)\n"
        "plots.use_style(); fig = plt.figure(); plt.plot([0, 1]); plots.save(fig, 'f', formats=('png',))\n"
    )
    env = dict(os.environ, PYTHONPATH=str(site))  # numba's cache: the package's (the wheel holds the same sources)
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    lines = out.stdout.split("\n")
    assert lines[0].startswith(str(site)) and lines[1] == "2:1 period-2"
    assert (tmp_path / "f.png").stat().st_size > 1000
    cmd = subprocess.run([sys.executable, "-m", "vibroimpact"], cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=120)
    assert cmd.returncode == 0 and "workflow: none here" in cmd.stdout, cmd.stdout + cmd.stderr


def test_each_layer_imports_only_the_layers_below_it():
    """dynamics < analysis < benchmarks < outputs: no module imports a layer above its own (the base
    modules datasets, _progress, _version and _numba_cache serve every layer), and the public names stay
    importable from the package itself."""
    import ast

    order = ["dynamics", "analysis", "benchmarks", "outputs"]
    pkg = ROOT / "src" / "vibroimpact"
    bad = []
    for layer in order:
        for f in (pkg / layer).rglob("*.py"):
            here = f.relative_to(pkg).with_suffix("").parts[:-1]
            for node in ast.walk(ast.parse(f.read_text())):
                if isinstance(node, ast.ImportFrom):
                    if node.level:
                        base = list(here[:len(here) - node.level + 1])
                        target = [*base, *(node.module.split(".") if node.module else [])]
                    elif node.module and node.module.startswith("vibroimpact."):
                        target = node.module.split(".")[1:]
                    else:
                        continue
                    names = [a.name for a in node.names] if not node.module and node.level else []
                    top = target[0] if target else (names[0] if names else "")
                    if top in order and order.index(top) > order.index(layer):
                        bad.append(f"{f.relative_to(pkg)}: {ast.unparse(node)}")
    assert not bad, bad
    assert {"simulate", "find_orbit", "continue_orbit", "sweep", "design_map", "curve_set"} <= set(vibroimpact.__all__)


def test_no_module_imports_another_module_s_private_name():
    """What one module needs of another is a documented public function of it: no ``from .x import _name``
    across files (a private module, such as ``_progress`` or ``_version``, may be imported: it is the
    package's own)."""
    import ast

    pkg = ROOT / "src" / "vibroimpact"
    bad = []
    for f in pkg.rglob("*.py"):
        for node in ast.walk(ast.parse(f.read_text())):
            if not isinstance(node, ast.ImportFrom) or (not node.level and not (node.module or "").startswith("vibroimpact")):
                continue
            base = f.parent if node.level else pkg.parent
            for _ in range(max(node.level - 1, 0)):
                base = base.parent
            where = base.joinpath(*node.module.split(".")) if node.module else base
            for a in node.names:
                private = a.name.startswith("_") and not a.name.startswith("__")
                if private and not ((where / f"{a.name}.py").is_file() or (where / a.name).is_dir()):
                    bad.append(f"{f.relative_to(pkg)}:{node.lineno}: {ast.unparse(node)}")
    assert not bad, bad


#: the only imports a function may hold: optional parts and what only one rarely used path needs
LAZY_IMPORTS = {
    "heyoka": "the optional peer (tools/probe_heyoka.py)",
    "nolds": "the optional time-series estimators (its import fails on Python 3.11: loaded apart then)",
    "imagehash": "the image check only", "PIL": "the image check only",
    "yaml": "the perturbed regeneration only (a Snakemake config)",
    "tqdm": "a progress bar, only when one is shown",
    "scipy": "its solvers and statistics where they are called (test_a_figure_job_s_imports_load_no_scipy)",
}
#: the functions that import a required package late, and why
LATE_IMPORTERS = {("_numba_cache.py", "_locator_class"): "numba's cache locator, built when numba asks for it: the "
                                                          "module sets numba's environment before numba is imported",
                  ("figdata.py", "figure_data"): "matplotlib where a figure's data are taken: a figure's check job (24 "
                                                 "in `check`) compares saved arrays and loads no matplotlib (0.13 s each; "
                                                 "test_reading_the_workflow_loads_neither_numba_nor_xarray)"}


def test_no_import_hides_in_a_function():
    """Imports sit at the top of each module, so that an import cycle fails at import (as
    test_every_module_imports_alone_in_a_fresh_interpreter checks) rather than hiding in a late import: a
    function imports only the optional parts of :data:`LAZY_IMPORTS`."""
    import ast

    pkg = ROOT / "src" / "vibroimpact"
    bad = []
    for f in pkg.rglob("*.py"):
        for fn in ast.walk(ast.parse(f.read_text())):
            if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(fn):
                if isinstance(node, ast.Import):
                    tops = [a.name.split(".")[0] for a in node.names]
                elif isinstance(node, ast.ImportFrom):
                    tops = ["." * node.level + (node.module or "")] if node.level else [node.module.split(".")[0]]
                else:
                    continue
                if any(t not in LAZY_IMPORTS for t in tops) and (f.name, fn.name) not in LATE_IMPORTERS:
                    bad.append(f"{f.relative_to(pkg)}:{node.lineno} ({fn.name}): {ast.unparse(node)}")
    assert not bad, bad


def fresh_python(code: str) -> subprocess.CompletedProcess:
    """``code`` run in a fresh interpreter (matplotlib on Agg), which must succeed: its result."""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "MPLBACKEND": "Agg"})
    assert out.returncode == 0, out.stderr[-2000:]
    return out


def test_a_figure_job_s_imports_load_no_scipy():
    """What a job that reads datasets and draws imports (the plots, the tables, the design and knock analyses, the
    simulator's benchmarks) loads none of scipy's solvers and statistics: scipy.integrate, .optimize, .special and
    .stats cost 0.3-0.6 s a process, paid by every such job of the workflow; the functions that call them import
    them."""
    code = ("import sys\n"
            "import vibroimpact.outputs.plots, vibroimpact.outputs.tables, vibroimpact.analysis.design\n"
            "import vibroimpact.analysis.continuation, vibroimpact.benchmarks.workprecision, vibroimpact.analysis.robust\n"
            "heavy = ('integrate', 'optimize', 'special', 'stats', 'linalg', 'sparse')\n"
            "print(sorted(m for m in sys.modules if m.split('.')[:2] in [['scipy', h] for h in heavy]))\n")
    out = fresh_python(code)
    assert out.stdout.strip() == "[]", out.stdout


def test_reading_the_workflow_loads_neither_numba_nor_xarray():
    """What every Snakemake command runs before any job (the package modules the Snakefile and the rule files import
    at their top: the configuration's check, the code hash, the registry) loads neither numba nor xarray, scipy or
    matplotlib (0.4-0.6 s a command); nor does the figure check's job (one per figure) load numba or
    matplotlib (it compares saved arrays and draws nothing)."""
    files = [ROOT / "Snakefile", *sorted((ROOT / "workflow" / "rules").glob("*.smk"))]
    mods = sorted({m for f in files for m in re.findall(r"^from (vibroimpact[\w.]*) import", f.read_text(), re.M)})
    assert "vibroimpact.outputs.workflow_config" in mods, mods
    script = ast.parse((ROOT / "workflow" / "scripts" / "check_figure.py").read_text())
    job = sorted({n.module for n in script.body if isinstance(n, ast.ImportFrom) and n.module.startswith("vibroimpact")})
    code = ("import importlib, sys\n"
            f"for m in {mods!r}: importlib.import_module(m)\n"
            "print(sorted(m for m in ('numba', 'xarray', 'scipy', 'matplotlib') if m in sys.modules))\n"
            f"for m in {job!r}: importlib.import_module(m)\n"
            "print(sorted(m for m in ('numba', 'matplotlib') if m in sys.modules))\n")
    reading, figure_check = fresh_python(code).stdout.split("\n")[:2]
    assert reading == "[]" and figure_check == "[]", (reading, figure_check)


def test_drawing_and_tabulating_load_none_of_the_benchmarked_methods():
    """A figure or table job (the plots and tables modules) reads the benchmarks' datasets and their names only: it
    loads neither the module that makes them (work-precision, the failure map) nor the high-precision reference
    (mpmath): 0.1 s a job."""
    code = ("import sys, vibroimpact.outputs.plots, vibroimpact.outputs.tables\n"
            "print(sorted(m for m in ('mpmath', 'vibroimpact.benchmarks.workprecision', 'vibroimpact.dynamics.reference')"
            " if m in sys.modules))\n")
    assert fresh_python(code).stdout.strip() == "[]"


def test_every_module_imports_alone_in_a_fresh_interpreter():
    """No import cycle: each module of the package imports first, alone, with nothing of the package loaded."""
    code = ("import importlib, pkgutil, sys, vibroimpact\n"
            "mods = sorted(m.name for m in pkgutil.walk_packages(vibroimpact.__path__, 'vibroimpact.'))\n"
            "bad = []\n"
            "for m in mods:\n"
            "    for k in [k for k in sys.modules if k.startswith('vibroimpact')]:\n"
            "        del sys.modules[k]\n"
            "    try:\n"
            "        importlib.import_module(m)\n"
            "    except ImportError as e:\n"
            "        bad.append(f'{m}: {e}')\n"
            "print(len(mods)); print(bad)\n")
    out = fresh_python(code)
    n, bad = out.stdout.split("\n")[:2]
    assert int(n) > 50 and bad == "[]", out.stdout


def test_importing_the_plots_leaves_the_user_s_backend():
    """The package draws with whatever matplotlib backend its user chose (the workflow chooses Agg for its
    jobs): importing every plotting module changes none."""
    code = ("import matplotlib; matplotlib.use('svg'); import vibroimpact.outputs.plots as p, pkgutil, importlib;"
            " [importlib.import_module(f'{p.__name__}.{m.name}') for m in pkgutil.iter_modules(p.__path__)];"
            " print(matplotlib.get_backend())")
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "svg", out.stdout + out.stderr
    assert 'os.environ.setdefault("MPLBACKEND", "Agg")' in (ROOT / "Snakefile").read_text()


def test_license_and_citation_name_one_version_and_the_paper():
    """A BSD-3-Clause license the wheel carries; CITATION.cff cites this version of the software and the
    paper it reproduces; the version is written once (_version.py) and the citation agrees with it."""
    import yaml

    assert (ROOT / "LICENSE").read_text().startswith("BSD 3-Clause License")
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    import datetime

    assert cff["cff-version"] == "1.2.0" and cff["type"] == "software" and cff["authors"]
    assert cff["version"] == vibroimpact.__version__ and cff["license"] == "BSD-3-Clause"
    assert isinstance(cff["date-released"], datetime.date)  # YAML reads an ISO date as a date
    paper = cff["preferred-citation"]
    assert paper["type"] == "article"
    assert paper["title"] == "Post-grazing dynamics of a vibro-impacting energy generator"
    assert [a["family-names"] for a in paper["authors"]] == ["Serdukova", "Kuske", "Yurchenko"]
    assert all(a["given-names"] and a["affiliation"] for a in paper["authors"])
    # only what the paper states: it names no journal, year or DOI
    assert not {"journal", "year", "doi", "volume"} & set(paper)
    assert 'dynamic = ["version"]' in (ROOT / "pyproject.toml").read_text()  # read from _version.py


def test_the_wheel_carries_the_license(wheel):
    whl, _ = wheel
    names = zipfile.ZipFile(whl).namelist()
    assert any(n.endswith("licenses/LICENSE") for n in names), [n for n in names if "dist-info" in n]


def test_the_package_page_names_every_module_of_each_layer():
    """docs/guide/package.md says where each job lives: every module of a layer is named in its layer's entry
    (a module added, split or renamed without the page is caught)."""
    page = (ROOT / "docs" / "guide" / "package.md").read_text()
    for layer in ("dynamics", "analysis", "benchmarks", "outputs"):
        entry = re.search(rf"^- `{layer}/`:(.*?)(?=^- |\Z)", page, re.M | re.S).group(1)
        named = set(re.findall(r"`(\w+)/?`", entry))
        files = {p.stem for p in (ROOT / "src" / "vibroimpact" / layer).glob("*.py") if not p.stem.startswith("_")}
        files |= {p.name for p in (ROOT / "src" / "vibroimpact" / layer).iterdir()
                  if p.is_dir() and not p.name.startswith("_")}
        assert files <= named, f"{layer}/ modules the page does not name: {sorted(files - named)}"


def test_no_function_outside_the_numba_kernels_exceeds_100_lines():
    """A function longer than a screenful does several jobs: outside the compiled kernels (one loop each, which
    numba compiles as a whole) every function, its docstring included, fits in 100 lines."""
    import ast

    long = []
    for f in (ROOT / "src" / "vibroimpact").rglob("*.py"):
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                compiled = any("njit" in ast.unparse(d) for d in node.decorator_list)
                if node.end_lineno - node.lineno + 1 > 100 and not compiled:
                    long.append(f"{f.relative_to(ROOT)}:{node.lineno} {node.name} "
                                f"({node.end_lineno - node.lineno + 1} lines)")
    assert not long, long


def _line_shapes(path):
    """``(line, shape)`` of each line of code of a module: its tokens with every name (not keyword), number and
    string replaced by one symbol; a doctest line as written.  Left out: imports and decorators, comments, prose
    and rows of literals only (a table's data, not code)."""
    import io
    import keyword
    import tokenize
    from collections import defaultdict

    literal = {"S", "0", ",", ":", "(", ")", "[", "]", "{", "}", "-", "+"}
    out, toks = {}, defaultdict(list)
    for tok in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        if tok.type in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT,
                        tokenize.ENDMARKER):
            continue
        if tok.type == tokenize.STRING and tok.start[0] != tok.end[0]:  # a docstring: its doctest lines
            for k, line in enumerate(tok.string.split("\n")):
                if line.strip().startswith((">>> ", "... ")):
                    out[tok.start[0] + k] = line.strip()
            continue
        if tok.type == tokenize.NAME:
            toks[tok.start[0]].append(tok.string if keyword.iskeyword(tok.string) else "N")
        else:
            toks[tok.start[0]].append({tokenize.NUMBER: "0", tokenize.STRING: "S"}.get(tok.type, tok.string))
    for line, t in toks.items():
        if not set(t) <= literal and t[0] not in ("import", "from", "@"):
            out[line] = " ".join(t)
    return sorted(out.items())


def repeated_shapes(files, n=6):
    """Pairs of places sharing ``n`` consecutive lines of code of the same shape (:func:`_line_shapes`), leaving
    out idioms (a run in more than 8 places) and thin runs (fewer than 3 lines of 6 tokens or more)."""
    from collections import defaultdict

    places = defaultdict(list)
    for f in files:
        rows = _line_shapes(f)
        for i in range(len(rows) - n + 1):
            places[tuple(s for _, s in rows[i:i + n])].append((f, rows[i][0], rows[i + n - 1][0]))
    pairs = []
    for run, where in places.items():
        if len(where) > 8 or sum(len(s.split()) >= 6 for s in run) < 3:
            continue
        pairs += [(a, b) for i, a in enumerate(where) for b in where[i + 1:]
                  if a[0] != b[0] or a[2] < b[1] or b[2] < a[1]]
    return pairs


def test_no_two_places_in_the_package_share_six_lines_of_the_same_shape(tmp_path):
    """One home for each piece of logic: no run of six lines of code stands twice in src/ (with other names,
    numbers or strings); the checker itself finds a copied block with renamed variables."""
    pairs = repeated_shapes(sorted((ROOT / "src" / "vibroimpact").rglob("*.py")))
    assert not pairs, [f"{a[0].relative_to(ROOT)}:{a[1]}-{a[2]} ~ {b[0].relative_to(ROOT)}:{b[1]}-{b[2]}"
                       for a, b in pairs]
    block = ("def f(a, b):\n    x = a + 2 * b\n    if x > 3:\n        y = g(x, a)\n    else:\n"
             "        y = h(x, b)\n    return y + x * a\n\n\n")
    (tmp_path / "one.py").write_text(block)
    (tmp_path / "two.py").write_text(block.replace("a", "p").replace("b", "q").replace("3", "7"))
    (tmp_path / "three.py").write_text(block.replace("    else:\n", "    elif x < 0:\n"))
    assert repeated_shapes([tmp_path / "one.py", tmp_path / "two.py"])  # renamed: the same shape
    assert not repeated_shapes([tmp_path / "one.py", tmp_path / "three.py"])  # another branch: another shape


def test_every_public_name_is_what_it_names_after_every_module_is_imported():
    """Importing a submodule never replaces a public name (a module named like a function would): after every
    module of the package is imported, each name of ``__all__`` is still its function, class or value."""
    code = ("import importlib, inspect, pkgutil, vibroimpact as vi\n"
            "for m in pkgutil.walk_packages(vi.__path__, 'vibroimpact.'):\n"
            "    importlib.import_module(m.name)\n"
            "print([n for n in vi.__all__ if inspect.ismodule(getattr(vi, n))])\n"
            "print(vi.simulate.__module__, vi.identify_attractor.__module__)\n")
    out = fresh_python(code)
    assert out.stdout.split("\n")[:2] == ["[]", "vibroimpact.dynamics.runs vibroimpact.analysis.motions"], out.stdout
