"""vibroimpact: exact dynamics of the inclined vibro-impact energy harvester.

Serdukova, Kuske, Yurchenko, "Post-grazing dynamics of a vibro-impacting energy generator".

The package is in layers, each importing only the layers below it (and the base modules
:mod:`~vibroimpact.datasets`, ``_progress``, ``_version``, ``_numba_cache``, ``_code_version``):

* :mod:`vibroimpact.dynamics`: parameters, the closed-form flight, impact location, the jitted
  event loop and :func:`simulate`;
* :mod:`vibroimpact.analysis`: periodic orbits, continuation in one and two parameters, grazing,
  settled attractors, sweeps and maps, energy, design under multistability;
* :mod:`vibroimpact.benchmarks`: the methods compared (ours and the peers), work-precision, failure
  map;
* :mod:`vibroimpact.outputs`: datasets for figures, tables, the checks against the paper and the
  figure references, and the plots.

The public names (:data:`__all__`) are importable from here, each on first use (PEP 562), so
``import vibroimpact`` is fast and a script pays only for the modules it touches (scipy's
optimizers, numba's compiled kernels, ...).
"""

import importlib

from . import _numba_cache  # noqa: F401  (first: the numba cache is keyed by the source)
from ._version import __version__

#: public name -> the module that defines it (the API reference lists them in this order)
_WHERE = {
    # dynamics
    "Params": "dynamics.params", "PhysicalScales": "dynamics.params",
    "Device": "dynamics.device", "Membrane": "dynamics.device",
    "simulate": "dynamics.runs", "simulate_batch": "dynamics.runs", "trajectory": "dynamics.runs",
    # analysis: periodic orbits and their branches
    "Orbit": "analysis.orbits", "OrbitError": "analysis.orbits", "find_orbit": "analysis.orbits",
    "orbit_run": "analysis.orbits",
    "continue_orbit": "analysis.continuation", "branch_from_simulation": "analysis.continuation",
    "simulate_along": "analysis.continuation",
    "follow_point": "analysis.bifurcation", "curve_set": "analysis.bifurcation",
    # analysis: attractors, sweeps and maps
    "polish_cycle": "analysis.settled", "long_run": "analysis.settled",
    "lyapunov": "analysis.lyapunov", "Lyapunov": "analysis.lyapunov",
    "identify_attractor": "analysis.motions", "Attractor": "analysis.motions",
    "sweep": "analysis.sweeps", "attractor_batch": "analysis.windows", "locate_transitions": "analysis.transitions",
    "period_doublings": "analysis.transitions",
    "bistable_intervals": "analysis.bistability", "basins": "analysis.basins", "regime_map": "analysis.regime_maps",
    "family_exit": "analysis.family_exit", "sweep_family_exit": "analysis.family_exit",
    "family_exit_curve": "analysis.family_exit",
    "branch_d_graz": "analysis.d_graz", "down_entry": "analysis.d_graz", "sweep_d_graz": "analysis.d_graz",
    # analysis: energy and design
    "voltage_gain": "analysis.energy", "speed_si": "analysis.energy",
    "averages": "analysis.energy", "orbit_energy": "analysis.energy", "branch_energy": "analysis.energy",
    "sweep_energy": "analysis.energy", "delivered": "analysis.energy",
    "design_map": "analysis.design", "start_states": "analysis.starts", "tolerance_analysis": "analysis.design",
    "best_designs": "analysis.design",
    "critical_shock": "analysis.shocks", "Shock": "analysis.shocks",
    "knock_map": "analysis.robust", "knock_section": "analysis.robust", "robust_choice": "analysis.robust",
    "basin_stability": "analysis.basin_stability",
}

__all__ = ["__version__", *_WHERE]


def __getattr__(name):
    if name in _WHERE:
        value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    elif name in _LAYERS:
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module 'vibroimpact' has no attribute {name!r}")
    globals()[name] = value
    return value


#: the layers, importable as attributes (``vibroimpact.analysis``)
_LAYERS = ("dynamics", "analysis", "benchmarks", "outputs", "datasets")


def __dir__():
    """The public names and the layers: no helper the package imports itself."""
    return sorted({*__all__, *_LAYERS})
