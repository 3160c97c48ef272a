"""Model parameters: non-dimensional ``(d, gbar, r)`` and their physical origin.

References: paper §2, eqs. ``nondXYt``, ``eq_relative``, ``eq_impact``; docs/guide/model.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["PAPER_PHYSICS", "Params", "PhysicalScales", "length_factor"]

#: the paper's device (section 2): cylinder mass M (kg), forcing amplitude F (N), angular frequency omega
#: (rad/s; the paper writes "5 pi Hz"), gravity g (m/s^2), restitution r.  The one place these numbers are
#: written in the package: ``vibroimpact.Device()``, the paper's device, is built from them.
PAPER_PHYSICS = {"M": 0.1245, "F": 5.0, "omega": 5 * math.pi, "g": 9.8, "r": 0.5}


def length_factor(M: float, omega: float) -> float:
    """``k = M omega^2 / pi^2`` (N/m), the factor of the non-dimensional length: ``d = k s / F`` (paper §2)."""
    return M * omega**2 / math.pi**2


def _check(name: str, value: float, ok: bool, allowed: str) -> float:
    """Return ``float(value)`` or raise a ValueError naming the parameter and the allowed range."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r} is not a number; allowed: {allowed}") from None
    if not math.isfinite(x) or not ok(x):
        raise ValueError(f"{name} = {value!r} is out of range; allowed: {allowed}")
    return x


@dataclass(frozen=True)
class PhysicalScales:
    """Factors converting non-dimensional quantities to SI units (paper eq. ``nondXYt``).

    ``tau = time * t``, ``dX/dtau = velocity * Xdot``, ``X = length * X*``.

    Attributes
    ----------
    time : float
        Seconds per unit of t (pi / omega).
    velocity : float
        m/s per unit of Zdot (F pi / (M omega)).
    length : float
        Metres per unit of Z (F pi^2 / (M omega^2)).
    """

    time: float  #: seconds per unit of t (pi / omega)
    velocity: float  #: m/s per unit of Zdot (F pi / (M omega))
    length: float  #: metres per unit of Z (F pi^2 / (M omega^2))


@dataclass(frozen=True)
class Params:
    """Non-dimensional parameters of the relative motion ``Z'' = cos(pi t + phi) + gbar``.

    Parameters
    ----------
    d : float
        Non-dimensional cylinder length, ``d > 0``. Walls at ``Z = +d/2`` (bottom) and ``-d/2`` (top).
    gbar : float
        Gravity along the incline relative to the forcing, ``gbar >= 0``. With ``gbar >= 1`` the
        forcing can never lift the ball off the bottom wall once it rests there.
    r : float
        Coefficient of restitution, ``0 <= r < 1``; impact law ``Zdot+ = -r Zdot-``.
    scales : PhysicalScales or None
        Set by :meth:`from_physical`; ``None`` for purely non-dimensional parameters.
    physical : dict
        The physical inputs (s, beta, M, F, omega, g) when built by :meth:`from_physical`.
    """

    d: float
    gbar: float
    r: float = 0.5
    scales: PhysicalScales | None = field(default=None, compare=False)
    physical: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "d", _check("d", self.d, lambda x: x > 0, "d > 0"))
        object.__setattr__(self, "gbar", _check("gbar", self.gbar, lambda x: x >= 0, "gbar >= 0"))
        object.__setattr__(self, "r", _check("r", self.r, lambda x: 0 <= x < 1, "0 <= r < 1"))

    @classmethod
    def from_physical(
        cls,
        s: float,
        beta: float,
        M: float = PAPER_PHYSICS["M"],
        F: float = PAPER_PHYSICS["F"],
        omega: float = PAPER_PHYSICS["omega"],
        r: float = PAPER_PHYSICS["r"],
        g: float = PAPER_PHYSICS["g"],
    ) -> Params:
        """Build parameters from the device: length ``s`` (m), incline ``beta`` (rad), cylinder
        mass ``M`` (kg), forcing amplitude ``F`` (N), angular frequency ``omega`` (rad/s),
        restitution ``r`` and gravity ``g`` (m/s^2); the paper's device (:data:`PAPER_PHYSICS`) by default.
        :meth:`vibroimpact.Device.params` builds them from a device.

        ``d = s M omega^2 / (F pi^2)`` and ``gbar = M g sin(beta) / F`` (paper §2).
        """
        s = _check("s", s, lambda x: x > 0, "s > 0 (metres)")
        beta = _check("beta", beta, lambda x: 0 <= x <= math.pi / 2, "0 <= beta <= pi/2 (radians)")
        M = _check("M", M, lambda x: x > 0, "M > 0 (kg)")
        F = _check("F", F, lambda x: x > 0, "F > 0 (N)")
        omega = _check("omega", omega, lambda x: x > 0, "omega > 0 (rad/s)")
        g = _check("g", g, lambda x: x >= 0, "g >= 0 (m/s^2)")
        d = length_factor(M, omega) * s / F
        gbar = M * g * math.sin(beta) / F
        scales = PhysicalScales(
            time=math.pi / omega,
            velocity=F * math.pi / (M * omega),
            length=F * math.pi**2 / (M * omega**2),
        )
        phys = dict(s=s, beta=beta, M=M, F=F, omega=omega, g=g)
        return cls(d=d, gbar=gbar, r=r, scales=scales, physical=phys)

    @property
    def never_leaves_bottom(self) -> bool:
        """True when ``gbar >= 1``: resting on the bottom wall, ``Z'' = cos + gbar >= 0`` forever."""
        return self.gbar >= 1.0
