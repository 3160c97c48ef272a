"""The compiled entry points take records (numba-supported namedtuples), not long lists of positional values:
at most six parameters each, so a setting or a tolerance is named where it is given."""

import ast
import inspect
import math
from pathlib import Path

from numba import njit
from numba.core.dispatcher import Dispatcher

from vibroimpact.analysis import grazing, lyapunov, motions
from vibroimpact.benchmarks import methods
from vibroimpact.dynamics import events, kernels, runs
from vibroimpact.dynamics.events import ROOT_GAP, ROOT_VELOCITY, rtsafe

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
    assert {"advance", "batch_runs", "run_window", "window_runs", "chain_runs", "flight_window_runs", "period_update",
            "tangent_pass", "_detect",
            "_dense", "rk4_flight", "_rk4_loop"} <= {name.rsplit(".", 1)[1] for name in found}
    too_many = {name: n for name, n in found.items() if n > MAX_PARAMETERS}
    assert not too_many, f"compiled functions with more than {MAX_PARAMETERS} parameters (take records): {too_many}"


@njit
def both(c, s):
    """A search for a velocity root and one for a gap root, each named as the event finder names them (a
    global name, which numba types by its value: a Python integer there would be a literal)."""
    v = rtsafe(ROOT_VELOCITY, 0.0, 1.0, -0.5, 0.5, math.nan, math.nan, c, s, 0.0, -0.5, 0.1)
    g = rtsafe(ROOT_GAP, 0.0, 1.0, -0.5, 0.5, math.nan, math.nan, c, s, -0.5, 0.0, 0.1)
    return v[0], g[0]


def test_the_event_finder_s_root_search_is_compiled_once_for_all_its_uses():
    """Every call of ``rtsafe`` names what it solves by one of ``events.ROOT_*``, NumPy integers: numba then
    compiles one copy of the search for all of them, where a literal ``0``, ``1`` or ``2`` (or a global Python
    integer) compiles one copy per value, each about a second of the first run's compile for no measurable
    speed."""
    names = {"ROOT_VELOCITY", "ROOT_GAP", "ROOT_CHORD"}
    calls = []
    for mod in (events, grazing):
        for node in ast.walk(ast.parse(Path(mod.__file__).read_text())):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "rtsafe":
                first = node.args[0]
                name = first.id if isinstance(first, ast.Name) else ast.unparse(first)
                calls.append((mod.__name__, node.lineno, name))
    assert len(calls) >= 6, calls  # the five searches of the event finder and grazing's
    assert all(name in names for *_, name in calls), calls

    both(1.0, 0.0)
    assert [str(sig[0]) for sig in events.rtsafe.signatures] == ["int64"]
