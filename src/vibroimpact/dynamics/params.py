"""Model parameters: non-dimensional ``(d, gbar, r)`` and their physical origin.

References: paper §2, eqs. ``nondXYt``, ``eq_relative``, ``eq_impact``; docs/guide/model.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["Params", "PhysicalScales"]


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
        M: float = 0.1245,
        F: float = 5.0,
        omega: float = 5 * math.pi,
        r: float = 0.5,
        g: float = 9.8,
    ) -> Params:
        """Build parameters from the device: length ``s`` (m), incline ``beta`` (rad), cylinder
        mass ``M`` (kg), forcing amplitude ``F`` (N), angular frequency ``omega`` (rad/s),
        restitution ``r`` and gravity ``g`` (m/s^2).

        ``d = s M omega^2 / (F pi^2)`` and ``gbar = M g sin(beta) / F`` (paper §2).
        """
        s = _check("s", s, lambda x: x > 0, "s > 0 (metres)")
        beta = _check("beta", beta, lambda x: 0 <= x <= math.pi / 2, "0 <= beta <= pi/2 (radians)")
        M = _check("M", M, lambda x: x > 0, "M > 0 (kg)")
        F = _check("F", F, lambda x: x > 0, "F > 0 (N)")
        omega = _check("omega", omega, lambda x: x > 0, "omega > 0 (rad/s)")
        g = _check("g", g, lambda x: x >= 0, "g >= 0 (m/s^2)")
        d = s * M * omega**2 / (F * math.pi**2)
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
