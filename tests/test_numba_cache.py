"""Numba's compiled code is kept by the package's sources, wherever a copy of them lies
(vibroimpact._numba_cache): a second copy of the same sources loads what the
first compiled, a copy with one compiled module changed compiles afresh, and a function outside the package is
still cached where numba puts it."""

import os
import shutil
import subprocess
import sys
import textwrap

from vibroimpact._code_version import PACKAGE

#: one of the package's cached kernels (numba writes "[cache] data saved/loaded" for it with NUMBA_DEBUG_CACHE)
CALL = "from vibroimpact.dynamics.flight import one_minus_cos; print(one_minus_cos(0.5))"


def run(code, *, src, home, extra=None):
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env |= {"PYTHONPATH": str(src), "XDG_CACHE_HOME": str(home), "NUMBA_DEBUG_CACHE": "1", **(extra or {})}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300,
                         cwd=src)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout


def copy(where, mtime=None):
    """A copy of the package's sources under ``where`` (its files' modification time ``mtime`` where given, as a
    clone made at another time has them)."""
    shutil.copytree(PACKAGE, where / "vibroimpact", ignore=shutil.ignore_patterns("__pycache__"))
    if mtime is not None:
        for f in (where / "vibroimpact").rglob("*.py"):
            os.utime(f, (mtime, mtime))
    return where


def test_a_copy_of_the_sources_elsewhere_loads_what_another_copy_compiled(tmp_path):
    home = tmp_path / "cache"
    first, second = copy(tmp_path / "a", 1.7e9), copy(tmp_path / "elsewhere" / "b", 1.8e9)
    compiled = run(CALL, src=first, home=home)
    assert "data saved" in compiled and "data loaded" not in compiled, compiled
    loaded = run(CALL, src=second, home=home)
    assert "data loaded" in loaded and "data saved" not in loaded, loaded
    assert loaded.splitlines()[-1] == compiled.splitlines()[-1]
    # the same kernel changed in a third copy: another cache, compiled afresh
    third = copy(tmp_path / "c")
    flight = third / "vibroimpact" / "dynamics" / "flight.py"
    flight.write_text(flight.read_text() + "\n# changed\n")
    changed = run(CALL, src=third, home=home)
    assert "data saved" in changed and "data loaded" not in changed, changed


def test_a_function_outside_the_package_is_cached_by_numba_s_own_locator(tmp_path):
    home, src = tmp_path / "cache", copy(tmp_path / "a")
    (src / "mine.py").write_text(textwrap.dedent("""
        import vibroimpact
        from numba import njit

        @njit(cache=True)
        def twice(x):
            return 2 * x
    """))
    code = "import mine; print(mine.twice(21))"
    assert "data saved" in run(code, src=src, home=home)
    out = run(code, src=src, home=home)
    assert "data loaded" in out and out.splitlines()[-1] == "42"
    # a user's own locator setting is kept (numba's in-tree locator: beside the module)
    (src / "__pycache__").mkdir(exist_ok=True)
    out = run(code, src=src, home=home, extra={"NUMBA_CACHE_LOCATOR_CLASSES": "InTreeCacheLocator"})
    assert any(f.suffix == ".nbi" for f in (src / "__pycache__").iterdir()), out


def test_the_package_s_bytecode_is_written_once_and_again_only_for_a_changed_module(tmp_path):
    """vibroimpact._bytecode.write_bytecode, which the workflow calls before its first job: bytecode for every module
    under the package, Python's own (imported without compiling again), left alone while the source is unchanged,
    rewritten for a changed one; where it cannot be written, False and no error."""
    import importlib.util
    from pathlib import Path

    from vibroimpact._bytecode import write_bytecode

    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("X = 1\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "b.py").write_text("Y = 2\n")
    modules = sorted(pkg.rglob("*.py"))
    assert write_bytecode(pkg)
    pyc = {m: Path(importlib.util.cache_from_source(str(m))) for m in modules}
    assert all(p.is_file() for p in pyc.values())
    stamps = {m: p.stat().st_mtime_ns for m, p in pyc.items()}
    assert write_bytecode(pkg) and {m: p.stat().st_mtime_ns for m, p in pyc.items()} == stamps
    # imported by an interpreter that writes no bytecode: the value of the source, from the bytecode as written
    (pkg / "a.py").write_text("X = 10\n")
    os.utime(pkg / "a.py", ns=(stamps[pkg / "a.py"] + 2_000_000_000,) * 2)
    assert write_bytecode(pkg)
    assert pyc[pkg / "a.py"].stat().st_mtime_ns != stamps[pkg / "a.py"]
    assert all(pyc[m].stat().st_mtime_ns == stamps[m] for m in modules if m.name != "a.py")
    out = subprocess.run([sys.executable, "-B", "-v", "-c", "import pkg.a, pkg.sub.b; print(pkg.a.X + pkg.sub.b.Y)"],
                         cwd=tmp_path, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "12"
    assert all(f"matches {m}" in out.stderr for m in (pkg / "a.py", pkg / "sub" / "b.py")), out.stderr[-2000:]
    # nowhere to write (a file where its __pycache__ would go): False, no exception
    (pkg / "c.py").write_text("Z = 3\n")
    shutil.rmtree(pkg / "__pycache__")
    (pkg / "__pycache__").write_text("")
    assert write_bytecode(pkg) is False
