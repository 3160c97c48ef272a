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


# a record a call returns: its fields are Attributes, not Parameters (no one constructs it)
@dataclass(frozen=True)
class PhysicalScales:  # numpydoc ignore=PR01
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

    Examples
    --------
    At the paper's device (omega = 5 pi rad/s, F = 5 N, M = 0.1245 kg) a unit of time is pi / omega = 0.2 s,
    a unit of length is a unit of velocity times a unit of time, and ``s = d * length``:

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.2, beta=math.pi / 6)
    >>> sc = p.scales
    >>> round(sc.time, 6), round(sc.velocity, 5), round(sc.length, 5)
    (0.2, 8.03213, 1.60643)
    >>> round(sc.velocity * sc.time / sc.length, 12), round(p.d * sc.length, 12)
    (1.0, 0.2)
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

    Raises
    ------
    ValueError
        A parameter out of its range, naming it and the range allowed.

    Examples
    --------
    >>> import vibroimpact as vi
    >>> p = vi.Params(d=0.14, gbar=0.0949)         # r = 0.5 by default
    >>> p.r, p.never_leaves_bottom
    (0.5, False)
    >>> vi.Params(d=0.14, gbar=0.0949, r=1.0)
    Traceback (most recent call last):
    ...
    ValueError: r = 1.0 is out of range; allowed: 0 <= r < 1
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
        """Build the non-dimensional parameters of a physical device (paper §2).

        ``d = s M omega^2 / (F pi^2)`` and ``gbar = M g sin(beta) / F``; the device's values are the
        paper's (:data:`PAPER_PHYSICS`) by default.  :meth:`vibroimpact.Device.params` builds them from
        a :class:`~vibroimpact.Device`.

        Parameters
        ----------
        s : float
            Cylinder length (m), ``s > 0``.
        beta : float
            Incline (rad), ``0 <= beta <= pi/2``.
        M : float
            Cylinder mass (kg).
        F : float
            Forcing amplitude (N).
        omega : float
            Forcing angular frequency (rad/s).
        r : float
            Coefficient of restitution, ``0 <= r < 1``.
        g : float
            Gravity (m/s^2).

        Returns
        -------
        Params
            ``d``, ``gbar`` and ``r``, with the SI ``scales`` and the ``physical`` inputs.

        Raises
        ------
        ValueError
            A physical value that is not a number or out of its range (``s``, ``M``, ``F``, ``omega`` positive,
            ``0 <= beta <= pi/2``, ``g >= 0``), or a model parameter it gives out of the model's
            (:class:`Params`), naming it and the range allowed.

        Examples
        --------
        At the paper's device ``d = 0.6225 s`` (s in m) and ``gbar = M g sin(beta) / F``:

        >>> import math, vibroimpact as vi
        >>> p = vi.Params.from_physical(s=0.2249, beta=math.pi / 6)
        >>> round(p.d, 6), round(p.gbar, 6), round(0.1245 * 9.8 * 0.5 / 5.0, 6)
        (0.14, 0.12201, 0.12201)
        >>> round(vi.Params.from_physical(s=0.2249, beta=math.pi / 6, F=10.0).d, 6)   # d falls as 1 / F
        0.07
        """
        s = _check("s", s, lambda x: x > 0, "s > 0 (metres)")
        beta = _check("beta", beta, lambda x: 0 <= x <= math.pi / 2, "0 <= beta <= pi/2 (radians)")
        M = _check("M", M, lambda x: x > 0, "M > 0 (kg)")
        F = _check("F", F, lambda x: x > 0, "F > 0 (N)")
        omega = _check("omega", omega, lambda x: x > 0, "omega > 0 (rad/s)")
        g = _check("g", g, lambda x: x >= 0, "g >= 0 (m/s^2)")
        d = s * M * omega**2 / (F * math.pi**2)  # this order: the datasets' d to the last bit
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
        """True when ``gbar >= 1``: resting on the bottom wall, ``Z'' = cos + gbar >= 0`` forever.

        Returns
        -------
        bool
            Whether the forcing can never lift the ball off the bottom wall.

        Examples
        --------
        ``gbar = M g sin(beta) / F`` reaches 1 at the paper's device (M g / F = 0.244) only for a forcing of
        at most ``M g sin(beta)``:

        >>> import math, vibroimpact as vi
        >>> vi.Params.from_physical(s=0.2, beta=math.pi / 2).never_leaves_bottom
        False
        >>> vi.Params.from_physical(s=0.2, beta=math.pi / 2, F=1.2).never_leaves_bottom   # gbar = 1.0168
        True
        """
        return self.gbar >= 1.0
