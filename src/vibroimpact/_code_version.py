"""The package sources a workflow script runs, and a short hash of them.

Snakemake reruns a job when its script or its parameters change, not when a package module the script
imports does.  Each rule with a ``script:`` therefore carries ``code_version(script)`` among its
parameters (``workflow/rules/common.smk``): a hash of every package file the script depends on, so
that editing one reruns exactly the jobs whose scripts import it, directly or not.

The dependencies are found statically, from the sources' syntax trees, without importing anything:

* the script's imports of the package (at module level or inside functions), closed over the
  package's own imports: absolute and relative, ``from . import x``; importing a module runs its
  packages' ``__init__.py`` first, so each of them is a dependency, with everything it imports
  (``from vibroimpact.outputs import plots`` depends on every plot module: ``plots/__init__.py``
  imports them all);
* the public names of the package, which its ``__init__.py`` resolves on first use through its
  ``_WHERE`` table: ``from vibroimpact import sweep`` and ``import vibroimpact as vi; vi.sweep(...)``
  depend on the module behind ``sweep``; ``vi.analysis`` (a layer) depends on all of that layer; the
  package name used other than by attribute (``getattr(vi, name)``), ``from vibroimpact import *`` or
  an import by name at run time (``importlib.import_module``, ``__import__``) in a module other than the
  package's ``__init__.py`` depend on the whole package;
* the files that are not Python modules in each package directory reached, and under its
  subdirectories that are not packages: the plots' style file, the Siconos peer's script and C source.

The precision is the module (a change anywhere in a module reruns every job that imports it, even when
the function it changed is not called); every approximation errs towards rerunning more.
:func:`source_digest` is also the numba cache's key (:mod:`vibroimpact._numba_cache`).

Every Snakemake command reads every module this way; what each source imports is kept between commands in
``$XDG_CACHE_HOME/vibroimpact/imports.json`` (``~/.cache`` by default), keyed by the source's bytes and by this
module's own (never stale: a changed source, or a changed reading of sources, is read again); a cache that cannot
be read or written is read around.
"""

from __future__ import annotations

import ast
import atexit
import hashlib
import json
import os
from functools import cache
from pathlib import Path

#: this package's directory: the sources hashed unless another copy is named
PACKAGE = Path(__file__).resolve().parent


def source_digest(files, root, length: int = 16) -> str:
    """The first ``length`` hex digits of a SHA-1 over each file's path relative to ``root`` and its
    bytes, in the order of the paths.

    >>> from pathlib import Path
    >>> len(source_digest([Path(__file__)], Path(__file__).parent, length=12))
    12
    """
    root = Path(root)
    return _digest({Path(f).relative_to(root).as_posix(): Path(f).read_bytes() for f in files}, length)


def code_version(script=None, package=PACKAGE, length: int = 12) -> str:
    """A short hash of the sources of every file of ``package`` that ``script`` depends on
    (:func:`dependencies`): it changes when one of them changes, and only then.  Without a script, of
    every file of the package (a job that imports every module, e.g. the documentation's API reference)."""
    tree = _Tree.of(package)
    rels = tree.dependencies(Path(script).read_bytes()) if script is not None else sorted(tree.files)
    return _digest({rel: tree.files[rel] for rel in rels}, length)


def dependencies(script, package=PACKAGE) -> list[Path]:
    """The files of ``package`` (its directory) that running ``script`` executes or reads: the package
    modules it imports, closed over their own imports, and the resources beside them (module docstring),
    sorted."""
    tree = _Tree.of(package)
    return [tree.root / rel for rel in tree.dependencies(Path(script).read_bytes())]


def _digest(files: dict[str, bytes], length: int) -> str:
    h = hashlib.sha1()
    for rel in sorted(files):
        h.update(f"{rel}\0{len(files[rel])}\0".encode())
        h.update(files[rel])
    return h.hexdigest()[:length]


class _Tree:
    """The package's files as read now (relative path -> bytes), its modules by name, and the package
    files each of them imports directly."""

    _last: dict[str, _Tree] = {}  # the last tree read of each package: reused while its files are the same

    @classmethod
    def of(cls, package) -> _Tree:
        root = Path(package).resolve()
        files = {}
        for d, dirs, names in os.walk(root):
            dirs[:] = sorted(x for x in dirs if x != "__pycache__" and not x.startswith("."))
            for n in names:
                if not n.startswith(".") and not n.endswith(".pyc"):
                    f = Path(d, n)
                    files[f.relative_to(root).as_posix()] = f.read_bytes()
        last = cls._last.get(str(root))
        if last is None or last.files != files:
            cls._last[str(root)] = last = cls(root, files)
        return last

    def __init__(self, root: Path, files: dict[str, bytes]):
        self.root, self.name, self.files = root, root.name, files
        packages = {rel.rpartition("/")[0] for rel in files if rel.rpartition("/")[2] == "__init__.py"}
        self.modules: dict[str, str] = {}  # module name -> relative path, for the files importable as modules
        for rel in files:
            parts = rel.split("/")
            if rel.endswith(".py") and all("/".join(parts[:i]) in packages for i in range(len(parts))):
                mod = [self.name, *parts[:-1], *([] if parts[-1] == "__init__.py" else [parts[-1][:-3]])]
                self.modules[".".join(mod)] = rel
        self.sources = set(self.modules.values())
        self.where = _public_names(files.get("__init__.py", b""))
        self._direct: dict[str, list[str] | None] = {}

    def dependencies(self, script: bytes) -> list[str]:
        """The relative paths of the files a script with this source depends on, sorted."""
        first = self._resolve(_imports(script, None, False, self.name), root_init=False)
        if first is None:
            return sorted(self.files)
        seen, todo = set(), list(first)
        while todo:
            mod = todo.pop()
            if mod in seen:
                continue
            seen.add(mod)
            direct = self._imports_of(mod)
            if direct is None:  # a dynamic import or the package used as a value: everything
                return sorted(self.files)
            todo += direct
        out = {self.modules[m] for m in seen}
        for m in seen:
            if self.modules[m].endswith("__init__.py"):
                out |= self._resources(self.modules[m].removesuffix("__init__.py"))
        return sorted(out)

    def _imports_of(self, mod: str) -> list[str] | None:
        if mod not in self._direct:
            rel = self.modules[mod]
            found = _imports(self.files[rel], mod, rel.endswith("__init__.py"), self.name)
            self._direct[mod] = self._resolve(found, root_init=mod == self.name)
        return self._direct[mod]

    def _resolve(self, found: _Found, root_init: bool) -> list[str] | None:
        """The modules ``found`` names, each with the packages it is in; None where the whole package is
        the answer."""
        if found.opaque or (found.dynamic and not root_init):
            return None
        named = []
        for module, names in found.imports:
            if module not in self.modules:
                continue  # not a module of this package (an error the script would raise)
            named.append(module)
            for n in names or ():
                if n == "*" and module == self.name:
                    return None
                if f"{module}.{n}" in self.modules:
                    named.append(f"{module}.{n}")
                elif module == self.name and n != "*":
                    named.append(self._public(n))
        for first in found.attributes:
            named.append(self._public(first))
            named += [m for m in self.modules if m == f"{self.name}.{first}" or m.startswith(f"{self.name}.{first}.")]
        if None in named:
            return None
        out = set()
        for m in filter(None, named):
            parts = m.split(".")
            out |= {p for p in (".".join(parts[: i + 1]) for i in range(len(parts))) if p in self.modules}
        return sorted(out)

    def _public(self, name: str) -> str | None:
        """The module behind a public name the package's ``__init__.py`` resolves on first use ("" for a
        name it does not list; None where it has no table: then any name may be any module)."""
        if self.where is None:
            return None
        return f"{self.name}.{self.where[name]}" if name in self.where else ""

    def _resources(self, d: str) -> set[str]:
        """The files in package directory ``d`` (relative, with its trailing slash) that are not Python
        modules, and every file under its subdirectories that are not packages."""
        out = set()
        for rel in self.files:
            if rel.startswith(d) and rel not in self.sources:
                sub = rel[len(d):].split("/")
                if not any(f"{d}{'/'.join(sub[: i + 1])}/__init__.py" in self.files for i in range(len(sub) - 1)):
                    out.add(rel)
        return out


#: this module's own digest: what a source imports is kept (:func:`_imports`) for this reading of sources only
_READER = hashlib.sha1(Path(__file__).read_bytes()).hexdigest()[:16]
#: the kept entries (loaded on first use), and whether this process added any (written at exit)
_kept: dict[str, list] | None = None
_added = False
#: at most this many entries are kept, the latest added (a source's entry is added when it is first read)
KEPT = 2000


def cache_home() -> Path:
    """This package's cache directory: ``$XDG_CACHE_HOME/vibroimpact`` (``~/.cache`` by default), where the
    imports read here and numba's compiled code (:mod:`vibroimpact._numba_cache`) are kept."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "vibroimpact"


def _cache_file() -> Path:
    return cache_home() / "imports.json"


def _kept_entries() -> dict[str, list]:
    global _kept
    if _kept is None:
        try:
            stored = json.loads(_cache_file().read_text())
            _kept = stored["entries"] if stored.get("reader") == _READER else {}
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            _kept = {}
    return _kept


@atexit.register
def _keep() -> None:
    """Write the entries (once, at exit, where this process added some): to a temporary file renamed over the
    cache, so that a command reading it at the same time reads the old one or the new one, whole."""
    if not _added:
        return
    f = _cache_file()
    tmp = f.with_name(f"{f.name}.{os.getpid()}")
    try:
        f.parent.mkdir(parents=True, exist_ok=True)
        tmp.write_text(json.dumps({"reader": _READER, "entries": dict(list(_kept.items())[-KEPT:])}))
        os.replace(tmp, f)
    except OSError:
        tmp.unlink(missing_ok=True)


class _Found:
    """What one source imports: ``(module, names)`` pairs (``names`` None for ``import module``); the
    first attribute of each chain read from a name bound to the package itself (``vi.sweep`` and
    ``vi.analysis.sweeps.sweep``: sweep, analysis); whether it imports by name at run time; whether it
    uses the package name other than by attribute."""

    def __init__(self):
        self.imports: list[tuple[str, tuple[str, ...] | None]] = []
        self.attributes: set[str] = set()
        self.dynamic = False
        self.opaque = False

    def to_list(self) -> list:
        return [[[m, list(n) if n is not None else None] for m, n in self.imports], sorted(self.attributes),
                self.dynamic, self.opaque]

    @classmethod
    def from_list(cls, kept: list) -> _Found:
        found = cls()
        found.imports = [(m, tuple(n) if n is not None else None) for m, n in kept[0]]
        found.attributes, found.dynamic, found.opaque = set(kept[1]), bool(kept[2]), bool(kept[3])
        return found


@cache
def _imports(source: bytes, name: str | None, is_package: bool, top: str) -> _Found:
    """The imports of one source (module ``name`` of package ``top``, or a script when None), cached by
    content, in this process and between processes (the module's docstring)."""
    global _added
    key = f"{hashlib.sha1(source).hexdigest()} {name} {is_package} {top}"
    kept = _kept_entries()
    if key in kept:
        try:
            return _Found.from_list(kept[key])
        except (TypeError, ValueError, IndexError):
            pass  # an entry not as written here: read the source again
    found = _read_imports(source, name, is_package, top)
    kept[key], _added = found.to_list(), True
    return found


def _read_imports(source: bytes, name: str | None, is_package: bool, top: str) -> _Found:
    """The imports of one source, from its syntax tree (:func:`_imports`)."""

    tree = ast.parse(source)
    found = _Found()
    here = (name if is_package else name.rpartition(".")[0]).split(".") if name else []
    aliases = set()  # names bound to the package itself
    # an import is a statement: only the statements are visited (most nodes are expressions, and every Snakemake
    # command reads every module this way); a call importing by name is looked for where the source names one
    dynamic = b"import_module" in source or b"__import__" in source
    for node in (ast.walk(tree) if dynamic else _statements(tree)):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name == top or a.name.startswith(top + "."):
                    found.imports.append((a.name, None))
                    if a.asname is None or a.name == top:  # binds the package (``import vibroimpact.x as m``: x)
                        aliases.add(a.asname or top)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                if not here or node.level > len(here):
                    continue  # a script's relative import is not the package's
                base = here[: len(here) - node.level + 1]
                module = ".".join(base + (node.module.split(".") if node.module else []))
            else:
                module = node.module or ""
            if module == top or module.startswith(top + "."):
                found.imports.append((module, tuple(a.name for a in node.names)))
        elif isinstance(node, ast.Call):
            f = node.func
            called = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else ""
            if called in ("import_module", "__import__"):
                found.dynamic = True
    if aliases:
        chained = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute):
                chain, v = [node.attr], node.value
                while isinstance(v, ast.Attribute):
                    chain.append(v.attr)
                    v = v.value
                if isinstance(v, ast.Name) and v.id in aliases:
                    found.attributes.add(chain[-1])
                    chained.add(id(v))
        for node in ast.walk(tree):
            if isinstance(node, ast.Name) and node.id in aliases and id(node) not in chained:
                found.opaque = True
    return found


def _statements(tree: ast.AST):
    """The statements of ``tree`` (and the clauses holding them: ``except`` handlers, ``case`` blocks), without
    descending into expressions."""
    todo = [tree]
    while todo:
        node = todo.pop()
        yield node
        todo.extend(c for c in ast.iter_child_nodes(node)
                    if isinstance(c, (ast.stmt, ast.excepthandler, ast.match_case)))


def _public_names(init: bytes) -> dict[str, str] | None:
    """The package's table of public names -> defining module (``_WHERE`` in its ``__init__.py``), None
    where it has no such literal table."""

    for node in ast.parse(init).body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "_WHERE" for t in node.targets):
            try:
                return dict(ast.literal_eval(node.value))
            except ValueError:
                return None
    return None
