"""The package sources each workflow script depends on, and their hash: every rule's `code` parameter
(vibroimpact._code_version), so that a job reruns when the package code it runs changes."""

import json
import re
import shutil
import subprocess
import sys
import textwrap

import pytest
from conftest import ROOT

from vibroimpact._code_version import PACKAGE, _Tree, code_version, dependencies


def deps(tmp_path, source, package=PACKAGE):
    """The package files (relative paths) a script with this source depends on."""
    script = tmp_path / "script.py"
    script.write_text(textwrap.dedent(source))
    return {f.relative_to(package).as_posix() for f in dependencies(script, package)}


def everything(package=PACKAGE):
    return set(_Tree.of(package).files)


@pytest.fixture
def package(tmp_path):
    """A copy of the package's sources, to edit."""
    copy = tmp_path / "src" / "vibroimpact"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    return copy


def test_a_sweep_script_depends_on_the_dynamics_it_imports_and_not_on_the_plots(tmp_path):
    found = deps(tmp_path, """
        from vibroimpact.analysis.sweeps import sweep
        from vibroimpact.datasets import provenance
    """)
    # the module, its package's __init__ files, what it imports at module level and inside functions
    assert {"__init__.py", "_numba_cache.py", "_version.py", "datasets.py", "analysis/__init__.py",
            "analysis/sweeps.py", "analysis/settled.py", "analysis/lyapunov.py", "dynamics/__init__.py",
            "dynamics/kernels.py", "dynamics/params.py", "dynamics/runs.py", "dynamics/flight.py"} <= found
    assert not {f for f in found if f.startswith(("outputs/", "benchmarks/"))}, found
    assert "analysis/design.py" not in found


def test_an_import_in_any_block_is_a_dependency(tmp_path):
    """An import counts wherever a statement can hold it: a function's body, a class's, a loop's, a ``with``, a
    ``try`` and its ``except`` and ``finally`` clauses, a ``match`` case (the analysis visits the statements, not
    the expressions within them)."""
    blocks = {
        "dynamics/params.py": "def f():\n    from vibroimpact.dynamics.params import Params\n",
        "analysis/grids.py": "class C:\n    import vibroimpact.analysis.grids\n",
        "analysis/d_graz.py": "for _ in ():\n    from vibroimpact.analysis import d_graz\n",
        "analysis/energy.py": "with open(__file__):\n    from vibroimpact.analysis.energy import delivered\n",
        "analysis/motions.py": "try:\n    pass\nexcept ImportError:\n    from vibroimpact.analysis.motions import Motion\n",
        "analysis/starts.py": "try:\n    pass\nfinally:\n    from vibroimpact.analysis.starts import MIN_STARTS\n",
        "analysis/shocks.py": "match 1:\n    case 1:\n        from vibroimpact.analysis.shocks import KINDS\n",
    }
    for module, source in blocks.items():
        assert module in deps(tmp_path, source), (module, source)


def test_the_package_s_public_names_resolve_to_the_modules_behind_them(tmp_path):
    """``vibroimpact/__init__.py`` resolves its public names on first use (``_WHERE``): a script depends
    on the module behind each name it uses, on a whole layer it uses as an attribute, and on the whole
    package when it uses the package otherwise."""
    found = deps(tmp_path, "import vibroimpact as vi\n\np = vi.Params(d=0.2, gbar=0.1, r=0.5)\n")
    assert "dynamics/params.py" in found and not {f for f in found if f.startswith("analysis/")}, found
    found = deps(tmp_path, "from vibroimpact import sweep\n")
    assert "analysis/sweeps.py" in found and not {f for f in found if f.startswith("outputs/")}, found
    found = deps(tmp_path, "import vibroimpact\n\nvibroimpact.analysis.sweeps.sweep\n")
    assert {f for f in everything() if f.startswith("analysis/")} <= found
    for source in ("import vibroimpact as vi\n\ngetattr(vi, 'sweep')\n", "from vibroimpact import *\n"):
        assert deps(tmp_path, source) == everything()
    assert deps(tmp_path, "import numpy\n") == set()


def test_a_plot_script_depends_on_every_plot_module_and_the_style_file(tmp_path):
    """``plots/__init__.py`` imports every plot module, so each is a dependency; the style file beside
    them too."""
    found = deps(tmp_path, "from vibroimpact.outputs import plots\n")
    plots = {f for f in everything() if f.startswith("outputs/plots/")}
    assert "outputs/plots/vibroimpact.mplstyle" in plots and plots <= found


def test_the_hash_changes_with_a_dependency_and_not_with_another_module(tmp_path, package):
    sweep = tmp_path / "sweep.py"
    sweep.write_text("from vibroimpact.analysis.sweeps import sweep\nfrom vibroimpact.datasets import provenance\n")
    figure = tmp_path / "figure.py"
    figure.write_text("from vibroimpact.outputs import plots\n")
    before = code_version(sweep, package), code_version(figure, package)
    assert before == (code_version(sweep, package), code_version(figure, package))  # reproducible
    assert before[0] != before[1] and re.fullmatch(r"[0-9a-f]{12}", before[0])

    with open(package / "outputs" / "plots" / "energy.py", "a") as fh:
        fh.write("# an edit\n")
    (package / "analysis" / "new_module.py").write_text("X = 1\n")  # imported by neither
    after = code_version(sweep, package), code_version(figure, package)
    assert after[0] == before[0] and after[1] != before[1]

    with open(package / "outputs" / "plots" / "vibroimpact.mplstyle", "a") as fh:
        fh.write("# an edit\n")
    assert code_version(sweep, package) == before[0] and code_version(figure, package) != after[1]

    with open(package / "dynamics" / "flight.py", "a") as fh:
        fh.write("# an edit\n")
    assert code_version(sweep, package) != before[0] and code_version(figure, package) != after[1]


def test_an_import_by_name_at_run_time_depends_on_the_whole_package(tmp_path, package):
    """The modules a dynamic import may load are not known statically: the whole package, to be safe
    (the package's own ``__init__.py`` is the exception: its table of public names says)."""
    with open(package / "analysis" / "sweeps.py", "a") as fh:
        fh.write("\n\ndef _late(name):\n    import importlib\n\n    return importlib.import_module(name)\n")
    assert deps(tmp_path, "from vibroimpact.analysis.sweeps import sweep\n", package) == everything(package)
    assert deps(tmp_path, "from vibroimpact.dynamics.params import Params\n", package) != everything(package)


def test_every_module_an_import_loads_is_a_dependency_of_it(tmp_path):
    """Against Python itself: importing each module of the package loads only modules the static
    analysis names (it also names those imported inside functions, which an import does not load)."""
    code = textwrap.dedent("""
        import importlib, json, sys
        from vibroimpact._code_version import PACKAGE, _Tree
        out = {}
        for m in sorted(_Tree.of(PACKAGE).modules):
            for k in [k for k in sys.modules if k.split(".")[0] == "vibroimpact"]:
                del sys.modules[k]
            importlib.import_module(m)
            out[m] = sorted(k for k in sys.modules if k.split(".")[0] == "vibroimpact")
        print(json.dumps(out))
    """)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    tree = _Tree.of(PACKAGE)
    missed = {}
    for module, loaded in json.loads(res.stdout).items():
        found = deps(tmp_path, f"import {module}\n")
        missing = [m for m in loaded if tree.modules[m] not in found]
        if missing:
            missed[module] = missing
    assert not missed, missed


def test_every_rule_with_a_script_carries_the_hash_of_its_script_s_package_code():
    """Each rule that runs a script has ``code=code("<its script>")`` among its params (the
    documentation, whose API reference imports every module, the whole package's: ``code()``)."""
    rules = 0
    for smk in sorted((ROOT / "workflow" / "rules").glob("*.smk")):
        for m in re.finditer(r"^rule (\w+):\n(.*?)(?=^rule |\Z)", smk.read_text(), re.S | re.M):
            script = re.search(r'^    script:\n\s+"\.\./scripts/([\w.]+)"', m.group(2), re.M)
            if not script:
                continue
            rules += 1
            want = 'code=code()' if m.group(1) == "docs" else f'code=code("{script.group(1)}")'
            params = re.search(r"^    params:\n((?:        .*\n|\s*\n)+)", m.group(2), re.M)
            assert params and want in params.group(1), f"{smk.name}: rule {m.group(1)} lacks {want}"
    assert rules >= 35


def test_what_each_source_imports_is_kept_between_commands_by_content(tmp_path):
    """Every Snakemake command hashes every script's dependencies: a second process reads what each source imports
    from the kept entries (here with the syntax-tree reading made to fail: the same hash, read from the cache alone),
    a source whose bytes changed is read again, and a cache written by another reading of sources, or unreadable,
    is read around."""
    script = ROOT / "workflow" / "scripts" / "sweep.py"
    cache = tmp_path / "vibroimpact" / "imports.json"

    def run(prelude=""):
        code = (f"import vibroimpact._code_version as cv\n{prelude}\n"
                f"print(cv.code_version({str(script)!r}))\n")
        res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             env={**__import__("os").environ, "XDG_CACHE_HOME": str(tmp_path)})
        return res.stdout.strip(), res.returncode, res.stderr

    first, rc, err = run()
    assert rc == 0 and first == code_version(script), err
    kept = json.loads(cache.read_text())
    assert len(kept["entries"]) > 10  # the script and every module it reaches
    unread = "def fail(*a):\n    raise RuntimeError('read again')\ncv._read_imports = fail"
    assert run(unread)[:2] == (first, 0)  # every source found in the cache
    # an entry whose source changed is not found: the changed script is read again
    key = next(k for k in kept["entries"] if k.split()[1] == "None")
    kept["entries"] = {k: v for k, v in kept["entries"].items() if k != key}
    cache.write_text(json.dumps(kept))
    out, rc, err = run(unread)
    assert rc != 0 and "read again" in err
    assert run()[:2] == (first, 0) and run(unread)[:2] == (first, 0)  # read, kept again
    # another reader's cache (every entry there, but another reading wrote it), or a broken file: read around (and
    # written anew)
    kept = json.loads(cache.read_text())
    for broken in (json.dumps({**kept, "reader": "another"}), "{not json", "[]"):
        cache.write_text(broken)
        assert run()[:2] == (first, 0)
        assert json.loads(cache.read_text())["reader"] == kept["reader"]
