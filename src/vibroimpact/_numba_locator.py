"""Where numba keeps this package's compiled code: by the module's place in the package, not by its path.

Numba's own locator files a function's cache under a hash of its module's absolute directory, so two
copies of the same sources (a second checkout, a scratch clone, an installed wheel) compile every kernel
anew.  The package's cache directory is already named after a hash of its compiled modules' sources
(:mod:`vibroimpact._numba_cache`), and numba checks each cached function against a hash of its file's
bytes and of its bytecode; so here a function of the package is filed under its module's directory
relative to the package (``vibroimpact/dynamics``), and any copy of the same sources finds it.  Numba
imports this module by name (``NUMBA_CACHE_LOCATOR_CLASSES``, set by :mod:`vibroimpact._numba_cache`
when it chooses the cache directory); a function from anywhere else gets numba's own locator.
"""

import os
from pathlib import Path

from numba.core import caching, config

#: the package's directory (the copy imported in this process)
PACKAGE = Path(__file__).resolve().parent


class PackageCacheLocator(caching.UserProvidedCacheLocator):
    """Numba's locator for a cache directory of one's own, with the module's directory relative to the
    package in place of a hash of its absolute path; for a function outside the package, the first of
    numba's own locators that takes it."""

    def __init__(self, py_func, py_file):
        super().__init__(py_func, py_file)
        relative = Path(py_file).resolve().parent.relative_to(PACKAGE)
        self._cache_path = os.path.join(config.CACHE_DIR, PACKAGE.name, *relative.parts)

    @classmethod
    def from_function(cls, py_func, py_file):
        if config.CACHE_DIR and Path(py_file).resolve().is_relative_to(PACKAGE):
            return super().from_function(py_func, py_file)
        for numba_s in caching.CacheImpl._locator_classes:  # numba's own, in its order
            locator = numba_s.from_function(py_func, py_file)
            if locator is not None:
                return locator
        return None
