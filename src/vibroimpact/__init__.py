"""vibroimpact: exact dynamics of the inclined vibro-impact energy harvester.

Serdukova, Kuske, Yurchenko, "Post-grazing dynamics of a vibro-impacting energy generator".

The main entry points are importable from here: simulation (:func:`simulate`, :func:`trajectory`,
:func:`identify_attractor`), periodic orbits and their branches (:func:`find_orbit`,
:func:`continue_orbit`), sweeps (:func:`sweep`, :func:`locate_transitions`,
:func:`bistable_intervals`, :func:`basins`, :func:`regime_map`) and the voltage per impact
(:class:`Membrane`, :func:`voltage_gain`, :func:`speed_si`, :func:`averages`,
:func:`orbit_energy`, :func:`branch_energy`, :func:`sweep_energy`).
"""

from . import (
    _numba_cache,  # noqa: F401  (first: the numba cache is keyed by the source)
    portraits,
)
from ._version import __version__
from .continuation import branch_from_simulation, continue_orbit, simulate_along
from .energy import Membrane, averages, branch_energy, orbit_energy, speed_si, sweep_energy, voltage_gain
from .orbits import Orbit, OrbitError, find_orbit
from .params import Params, PhysicalScales
from .simulate import Attractor, identify_attractor, simulate, simulate_batch, trajectory
from .sweeps import basins, bistable_intervals, locate_transitions, regime_map, sweep

__all__ = [
    "__version__", "Params", "PhysicalScales", "simulate", "simulate_batch", "trajectory",
    "identify_attractor", "Attractor", "portraits",
    "find_orbit", "Orbit", "OrbitError", "continue_orbit", "branch_from_simulation", "simulate_along",
    "sweep", "locate_transitions", "bistable_intervals", "basins", "regime_map",
    "Membrane", "voltage_gain", "speed_si", "averages", "orbit_energy", "branch_energy", "sweep_energy",
]
