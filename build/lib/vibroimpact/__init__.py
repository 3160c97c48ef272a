"""vibroimpact: exact dynamics of the inclined vibro-impact energy harvester.

Serdukova, Kuske, Yurchenko, "Post-grazing dynamics of a vibro-impacting energy generator".

The main entry points are importable from here: simulation (:func:`simulate`, :func:`trajectory`,
:func:`identify_attractor`), periodic orbits and their branches (:func:`find_orbit`,
:func:`continue_orbit`), sweeps (:func:`sweep`, :func:`locate_transitions`,
:func:`bistable_intervals`, :func:`basins`, :func:`regime_map`) and the voltage per impact
(:class:`Membrane`, :func:`voltage_gain`, :func:`speed_si`, :func:`averages`,
:func:`orbit_energy`, :func:`branch_energy`, :func:`sweep_energy`).

Each is imported on first use (PEP 562), so ``import vibroimpact`` is fast and a script pays only
for the modules it touches (scipy's optimizers, numba's compiled kernels, ...).
"""

import importlib
import sys
import types

from . import _numba_cache  # noqa: F401  (first: the numba cache is keyed by the source)
from ._version import __version__

#: public name -> the submodule that defines it
_WHERE = {
    "branch_from_simulation": "continuation", "continue_orbit": "continuation", "simulate_along": "continuation",
    "Membrane": "energy", "averages": "energy", "branch_energy": "energy", "orbit_energy": "energy",
    "speed_si": "energy", "sweep_energy": "energy", "voltage_gain": "energy",
    "Orbit": "orbits", "OrbitError": "orbits", "find_orbit": "orbits",
    "Params": "params", "PhysicalScales": "params",
    "Attractor": "simulate", "identify_attractor": "simulate", "simulate": "simulate", "simulate_batch": "simulate",
    "trajectory": "simulate",
    "basins": "sweeps", "bistable_intervals": "sweeps", "locate_transitions": "sweeps", "regime_map": "sweeps",
    "sweep": "sweeps",
}
_SUBMODULES = ("portraits",)

__all__ = ["__version__", *_WHERE, *_SUBMODULES]


def __getattr__(name):
    if name in _WHERE:
        value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module 'vibroimpact' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))


class _Package(types.ModuleType):
    """The package, with one rule: the submodule :mod:`vibroimpact.simulate` does not shadow the
    function :func:`simulate` (importing a submodule sets it as the package's attribute; the eager
    ``from .simulate import simulate`` used to rebind the name, which a lazy import never does)."""

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and _WHERE.get(name) == name:
            return  # the submodule stays in sys.modules; the name resolves to the function on use
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
