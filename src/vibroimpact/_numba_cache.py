"""Numba's on-disk cache, keyed by the package's source.

Numba invalidates a cached function only when its own file changes, not when a function it inlines
from another module does (every kernel here inlines the flight's closed forms): after such a change
a stale compilation would run silently, and results would differ at rounding level from a fresh
one.  So the cache lives in a directory named after a hash of all the package's sources, unless the
user set ``NUMBA_CACHE_DIR``; within it, each function is filed by its module's place in the package
(:mod:`vibroimpact._numba_locator`), so that every copy of the same sources (another checkout, a clone,
an installed wheel) shares one compilation.  Imported first by :mod:`vibroimpact`, before any decorated function; it does not import numba
(which is slow to import) but sets ``NUMBA_CACHE_DIR``, read when numba is first imported.
"""

import os
import sys
from pathlib import Path

from ._code_version import cache_home, source_digest


def cache_dir() -> str:
    """``$XDG_CACHE_HOME/vibroimpact/numba/<hash>`` (``~/.cache`` by default), the hash over the package's
    modules that use numba."""
    package = Path(__file__).resolve().parent
    compiled = [f for f in package.rglob("*.py")  # the modules with compiled code
                if b"numba" in f.read_bytes() and f.name not in ("_numba_cache.py", "_code_version.py")]
    return str(cache_home() / "numba" / source_digest(compiled, package))


#: numba's setting naming the locator it imports (a user's own setting is kept)
LOCATOR = "vibroimpact._numba_locator.PackageCacheLocator"

if not os.environ.get("NUMBA_CACHE_DIR"):
    locate = not os.environ.get("NUMBA_CACHE_LOCATOR_CLASSES")
    if "numba" in sys.modules:  # numba has read its environment already
        sys.modules["numba"].config.CACHE_DIR = cache_dir()
        if locate:
            sys.modules["numba"].config.CACHE_LOCATOR_CLASSES = LOCATOR
    else:  # numba reads them when first imported (and so do subprocesses: the same cache)
        os.environ["NUMBA_CACHE_DIR"] = cache_dir()
        if locate:
            os.environ["NUMBA_CACHE_LOCATOR_CLASSES"] = LOCATOR
