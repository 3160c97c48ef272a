"""Numba's on-disk cache, keyed by the package's source.

Numba invalidates a cached function only when its own file changes, not when a function it inlines
from another module does (every kernel here inlines the flight's closed forms): after such a change
a stale compilation would run silently, and results would differ at rounding level from a fresh
one.  So the cache lives in a directory named after a hash of all the package's sources, unless the
user set ``NUMBA_CACHE_DIR``.

Within it, each function is filed by its module's place in the package (``vibroimpact/dynamics``), not
by its absolute path as numba's own locator files it, so that every copy of the same sources (another
checkout, a clone, an installed wheel) loads one compilation; each function is still checked against a
hash of its file's bytes (whatever numba's version stamps) and of its bytecode.  Numba takes the locator by name
(``NUMBA_CACHE_LOCATOR_CLASSES``, set here unless the user set it) and asks this module for
:class:`PackageCacheLocator` when it first caches a function.

Imported first by :mod:`vibroimpact`, before any decorated function; it does not import numba (which is
slow to import) but sets ``NUMBA_CACHE_DIR``, read when numba is first imported.
"""

import functools
import hashlib
import os
import sys
from pathlib import Path

from ._code_version import cache_home, source_digest

#: the package's directory (the copy imported in this process)
PACKAGE = Path(__file__).resolve().parent
#: numba's setting naming the locator it asks this module for
LOCATOR = f"{__name__}.PackageCacheLocator"


def cache_dir() -> str:
    """``$XDG_CACHE_HOME/vibroimpact/numba/<hash>`` (``~/.cache`` by default), the hash over the package's
    modules that use numba."""
    compiled = [f for f in PACKAGE.rglob("*.py")  # the modules with compiled code
                if b"numba" in f.read_bytes() and f.name not in ("_numba_cache.py", "_code_version.py")]
    return str(cache_home() / "numba" / source_digest(compiled, PACKAGE))


def _locator_class():
    """Numba's locator for a cache directory of one's own, with the module's directory relative to the
    package in place of a hash of its absolute path; for a function outside the package, the first of
    numba's own locators that takes it."""
    from numba.core import caching, config

    class PackageCacheLocator(caching.UserProvidedCacheLocator):
        __doc__ = _locator_class.__doc__

        def __init__(self, py_func, py_file):
            super().__init__(py_func, py_file)
            relative = Path(py_file).resolve().parent.relative_to(PACKAGE)
            self._cache_path = os.path.join(config.CACHE_DIR, PACKAGE.name, *relative.parts)

        def get_source_stamp(self):  # the file's bytes, as numba >= 0.68 stamps it (0.62-0.67: its time and size)
            st = os.stat(self._py_file)
            return _source_hash(self._py_file, st.st_mtime_ns, st.st_size)

        @classmethod
        def from_function(cls, py_func, py_file):
            if config.CACHE_DIR and Path(py_file).resolve().is_relative_to(PACKAGE):
                return super().from_function(py_func, py_file)
            for numba_s in caching.CacheImpl._locator_classes:  # numba's own, in its order
                locator = numba_s.from_function(py_func, py_file)
                if locator is not None:
                    return locator
            return None

    return PackageCacheLocator


@functools.lru_cache(maxsize=None)
def _source_hash(path, mtime_ns, size):  # read again when the file changes
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def __getattr__(name):  # numba asks for the locator once it is imported (PEP 562)
    if name == "PackageCacheLocator":
        globals()[name] = _locator_class()
        return globals()[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


if not os.environ.get("NUMBA_CACHE_DIR"):
    locate = not os.environ.get("NUMBA_CACHE_LOCATOR_CLASSES")  # a user's own setting is kept
    if "numba" in sys.modules:  # numba has read its environment already
        sys.modules["numba"].config.CACHE_DIR = cache_dir()
        if locate:
            sys.modules["numba"].config.CACHE_LOCATOR_CLASSES = LOCATOR
    else:  # numba reads them when first imported (and so do subprocesses: the same cache)
        os.environ["NUMBA_CACHE_DIR"] = cache_dir()
        if locate:
            os.environ["NUMBA_CACHE_LOCATOR_CLASSES"] = LOCATOR
