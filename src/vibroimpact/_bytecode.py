"""The package's bytecode, written once before the workflow's jobs import it.

Every job of the workflow is a fresh interpreter that imports the package.  Where Python does not write
bytecode itself (``PYTHONDONTWRITEBYTECODE`` set, as container images often have it, or a source tree
it cannot write to), each of them compiled every module it imports from source again (a figure job's imports:
1.33 s with the compiling, 1.18 s without).  The workflow calls :func:`write_bytecode` once before its first job
(``onstart`` in the Snakefile): :mod:`compileall` writes what is missing or older than its source and
leaves the rest, so a second run costs a look at each file.  The bytecode is what Python itself would
write (checked against the source's modification time and size when imported): the results cannot
depend on it.
"""

import compileall
from pathlib import Path

#: the package's directory (the copy imported in this process)
PACKAGE = Path(__file__).resolve().parent


def write_bytecode(package: Path = PACKAGE) -> bool:
    """Write the bytecode (``__pycache__``) of each module under ``package`` that has none up to date.
    Returns whether every module has it now; False where one could not be written (a read-only install,
    whose modules are then compiled at import as before) or compiled, which is never an error here: the
    import that needs the module reports that."""
    return bool(compileall.compile_dir(str(package), quiet=2, workers=1))
