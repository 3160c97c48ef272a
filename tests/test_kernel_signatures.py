"""The compiled entry points take records (numba-supported namedtuples), not long lists of positional values:
at most six parameters each, so a setting or a tolerance is named where it is given."""

import inspect

from numba.core.dispatcher import Dispatcher

from vibroimpact.analysis import lyapunov, motions
from vibroimpact.benchmarks import methods
from vibroimpact.dynamics import kernels, runs

#: the modules whose compiled functions the Python wrappers call: the event loop's kernels, the tangent map,
#: the period test of a recorded run, the dense output, the compared methods' compiled RK4
KERNEL_MODULES = (kernels, lyapunov, motions, runs, methods)
#: the most parameters a compiled function of these modules takes
MAX_PARAMETERS = 6


def compiled_functions():
    """``{module.name: parameter count}`` of the compiled functions defined in :data:`KERNEL_MODULES`."""
    return {f"{mod.__name__}.{name}": len(inspect.signature(obj.py_func).parameters)
            for mod in KERNEL_MODULES for name, obj in vars(mod).items()
            if isinstance(obj, Dispatcher) and obj.py_func.__module__ == mod.__name__}


def test_every_compiled_entry_point_takes_at_most_six_parameters():
    found = compiled_functions()
    # the scan sees the entry points the Python wrappers call
    assert {"advance", "run_batch", "run_window", "window_batch", "period_update", "tangent_pass", "_detect",
            "_dense", "rk4_flight", "_rk4_loop"} <= {name.rsplit(".", 1)[1] for name in found}
    too_many = {name: n for name, n in found.items() if n > MAX_PARAMETERS}
    assert not too_many, f"compiled functions with more than {MAX_PARAMETERS} parameters (take records): {too_many}"
