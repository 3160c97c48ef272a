"""The garbage collector of a workflow process: it collects less often, and not at all when the process ends.

Every job of the workflow is a fresh interpreter that imports numpy, xarray, matplotlib, numba and the package
(more than 100 000 objects the cyclic garbage collector tracks) and then computes for a few seconds.  With CPython's
thresholds (700, 10, 10) the collector goes over all of those objects three or four times while the job imports
and computes, and once more while the interpreter shuts down: counted per process (:data:`gc.callbacks`) over
the default target, 0.16 to 0.33 CPU s per job while it runs, and about 0.25 s more at its end, of jobs that take
1 to 15 s.  Importing this module (the first statement of every script of the workflow, of the Snakefile, so of
Snakemake's own process and of each ``run:`` job's, and of the tests' ``conftest.py``) calls :func:`collect_less`.

The collector collects only garbage in reference cycles; what it frees and when never changes a result.
"""

import atexit
import gc

#: the youngest generation's threshold: a collection per this many new tracked objects (CPython's default: 700),
#: so that each generation is collected ten times less often; the older generations keep their thresholds
YOUNG = 7000

_done = False


def collect_less() -> None:
    """Set the youngest generation's threshold to :data:`YOUNG` and, at exit, freeze what the process holds
    (:func:`gc.freeze`): the interpreter then frees it at shutdown by reference counts alone, without going over
    it once more for cycles (the exit handlers registered before this call, which run after it, still run).
    Garbage in cycles is still collected while the process runs.  A second call changes nothing."""
    global _done
    if _done:
        return
    gc.set_threshold(YOUNG, *gc.get_threshold()[1:])
    atexit.register(gc.freeze)
    _done = True


collect_less()
