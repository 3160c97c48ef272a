"""vibroimpact: exact dynamics of the inclined vibro-impact energy harvester.

Serdukova, Kuske, Yurchenko, "Post-grazing dynamics of a vibro-impacting energy generator".
"""

from . import portraits
from ._version import __version__
from .params import Params, PhysicalScales
from .simulate import Attractor, identify_attractor, simulate, simulate_batch, trajectory

__all__ = [
    "__version__", "Params", "PhysicalScales", "simulate", "simulate_batch", "trajectory",
    "identify_attractor", "Attractor", "portraits",
]
