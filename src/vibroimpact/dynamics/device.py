"""A device: the cylinder and its forcing, gravity, the restitution of the impacts and the membranes.

One value carries everything physical about a harvester (paper §2 and the energy model of
docs/guide/model.md), with the conversions between its SI quantities and the non-dimensional model:

    d = s M omega^2 / (F pi^2) = k s / F,   k = M omega^2 / pi^2
    gbar = M g sin(beta) / F
    speed (m/s) = |Zdot| F pi / (M omega)

The paper's device is :data:`PAPER`; a workflow config gives another with its ``physics`` and
``membrane`` (:meth:`Device.from_config`).
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from .params import PAPER_PHYSICS, Params, PhysicalScales, length_factor

__all__ = ["Device", "Membrane", "PAPER", "PAPER_MEMBRANE", "speed_si"]


#: relative difference below which two devices' values are the same (rounding of a value written out)
SAME_RTOL = 1e-12


@dataclass(frozen=True)
class Membrane:
    """Membrane and ball constants (SI); ``config/config.yaml`` gives each value's provenance.

    Parameters
    ----------
    h : float
        Exponent of the membrane force ``K delta^h``.
    K : float
        Its stiffness coefficient (N / m^h).
    R : float
        Active membrane radius (m); must exceed ``r_b``.
    r_b : float
        Ball radius (m).
    U_in : float
        Input voltage (V).
    m : float
        Ball mass (kg).

    Examples
    --------
    The paper's membrane is the default device's; the ball must fit inside the active radius:

    >>> import vibroimpact as vi
    >>> mb = vi.Membrane(h=2.6, K=4.0847e5, R=6.3e-3, r_b=5.0e-3, U_in=2000.0, m=4.11e-3)
    >>> mb == vi.Device().membrane
    True
    >>> vi.Membrane(h=2.6, K=4.0847e5, R=5.0e-3, r_b=5.0e-3, U_in=2000.0, m=4.11e-3)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: membrane R = 0.005 must exceed the ball radius r_b = 0.005 (the stretched-cap geometry ...)
    """

    h: float  #: exponent of the membrane force K delta^h
    K: float  #: stiffness coefficient of the membrane force (N / m^h)
    R: float  #: active membrane radius (m)
    r_b: float  #: ball radius (m)
    U_in: float  #: input voltage (V)
    m: float  #: ball mass (kg)

    def __post_init__(self):
        for name, value in asdict(self).items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"membrane {name} = {value!r}; allowed: a finite number > 0")
        if self.R <= self.r_b:
            raise ValueError(f"membrane R = {self.R!r} must exceed the ball radius r_b = {self.r_b!r} "
                             "(the stretched-cap geometry has no real solution otherwise)")


#: the membrane of the energy model's public re-implementations (docs/guide/model.md); the ball mass is an
#: assumption (a steel ball of radius r_b)
PAPER_MEMBRANE = Membrane(h=2.6, K=4.0847e5, R=6.3e-3, r_b=5.0e-3, U_in=2000.0, m=4.11e-3)


def _out(x):
    """A Python float for a scalar, the array otherwise."""
    return float(x) if np.ndim(x) == 0 else x


def _positive(name, value, allowed, ok=lambda x: x > 0):
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r} is not a number; allowed: {allowed}") from None
    if not (math.isfinite(x) and ok(x)):
        raise ValueError(f"{name} = {value!r} is out of range; allowed: {allowed}")
    return x


def speed_si(v_nondim, F, M, omega):
    """Dimensional impact speed of a non-dimensional ``Zdot-``: ``|v| F pi / (M omega)``.

    Parameters
    ----------
    v_nondim : array_like
        Non-dimensional pre-impact velocities.
    F, M, omega : float or array_like
        Forcing amplitude (N), cylinder mass (kg), forcing frequency (rad/s).

    Returns
    -------
    numpy.ndarray
        Speeds (m/s).

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> round(float(vi.speed_si(-0.4185, 5.0, 0.1245, 5 * math.pi)), 6)   # m/s: |v| F / (M omega / pi)
    3.361446
    >>> round(0.4185 * 5.0 / (0.1245 * 5.0), 6)
    3.361446
    """
    return np.abs(np.asarray(v_nondim, dtype=float)) * np.asarray(F, dtype=float) * math.pi / (M * omega)


@dataclass(frozen=True)
class Device:
    """A vibro-impact harvester: cylinder mass, forcing, gravity, restitution and membranes.

    Parameters
    ----------
    M : float
        Cylinder mass (kg).
    F : float
        Forcing amplitude ``||F||`` (N); the nominal one: a force sweep varies it.
    omega : float
        Forcing angular frequency (rad/s).
    g : float
        Gravity (m/s^2).
    r : float
        Coefficient of restitution, ``0 <= r < 1``.
    membrane : Membrane
        Membrane and ball constants.
    name : str
        What the device is called (its results' folder in the workflow).

    Notes
    -----
    The defaults are the paper's device (section 2; the membrane of docs/guide/model.md):
    ``Device()`` is it.

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> dev = vi.Device()                    # by default the paper's: M = 124.5 g, F = 5 N, omega = 5 pi
    >>> round(dev.d(0.2249), 4), round(dev.s(0.14), 4)     # d = 0.6225 s (s in m)
    (0.14, 0.2249)
    >>> p = dev.params(s=0.2249, beta=math.pi / 6)
    >>> round(p.d, 4), round(p.gbar, 4)
    (0.14, 0.122)
    >>> heavier = dev.replace(M=0.2, name="heavier")
    >>> round(heavier.d(0.2249), 4)
    0.2249
    """

    M: float = PAPER_PHYSICS["M"]
    F: float = PAPER_PHYSICS["F"]
    omega: float = PAPER_PHYSICS["omega"]
    g: float = PAPER_PHYSICS["g"]
    r: float = PAPER_PHYSICS["r"]
    membrane: Membrane = field(default=PAPER_MEMBRANE)
    name: str = "paper"

    def __post_init__(self):
        for key, allowed, ok in (("M", "M > 0 (kg)", None), ("F", "F > 0 (N)", None),
                                 ("omega", "omega > 0 (rad/s)", None),
                                 ("g", "g >= 0 (m/s^2)", lambda x: x >= 0),
                                 ("r", "0 <= r < 1", lambda x: 0 <= x < 1)):
            object.__setattr__(self, key, _positive(key, getattr(self, key), allowed, *(() if ok is None else (ok,))))
        if not isinstance(self.membrane, Membrane):
            raise ValueError(f"membrane = {self.membrane!r}; allowed: a vibroimpact.Membrane")

    @classmethod
    def from_config(cls, physics: dict, membrane: dict, name: str | None = None) -> Device:
        """The device of a workflow config's ``physics`` and ``membrane`` blocks.

        Parameters
        ----------
        physics : dict
            ``M``, ``F``, ``omega``, ``g`` and ``r`` (other keys are ignored).
        membrane : dict
            The fields of a :class:`Membrane`.
        name : str, optional
            The device's name; by default ``"paper"`` where it is the paper's device and
            :meth:`default_name` otherwise.

        Returns
        -------
        Device
            The device.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> paper = vi.Device()
        >>> membrane = {"h": 2.6, "K": 4.0847e5, "R": 6.3e-3, "r_b": 5.0e-3, "U_in": 2000.0, "m": 4.11e-3}
        >>> vi.Device.from_config(paper.physics(), membrane).name
        'paper'
        >>> heavy = vi.Device.from_config({**paper.physics(), "M": 0.2}, membrane)
        >>> heavy.name == heavy.default_name() != "paper"
        True
        """
        dev = cls(**{k: physics[k] for k in ("M", "F", "omega", "g", "r")}, membrane=Membrane(**membrane))
        if name:
            return dev.replace(name=name)
        return dev if dev.same_physics(PAPER) else dev.replace(name=dev.default_name())

    def replace(self, **changes) -> Device:
        """A copy with some fields changed.

        Parameters
        ----------
        **changes
            New values of any fields (``membrane`` included), checked as in the constructor.

        Returns
        -------
        Device
            The copy.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> dev = vi.Device().replace(F=10.0, name="stronger")
        >>> dev.F, dev.M, dev.name
        (10.0, 0.1245, 'stronger')
        """
        return replace(self, **changes)

    def same_physics(self, other: Device) -> bool:
        """Whether two devices are the same harvester (their names aside).

        Parameters
        ----------
        other : Device
            The device compared.

        Returns
        -------
        bool
            True where every physical and membrane value agrees to rounding (:data:`SAME_RTOL`, relative):
            a value written with a few more digits, or moved by a few units in the last place (the
            figure check's perturbed regenerations), is the same device.

        Examples
        --------
        >>> import math, vibroimpact as vi
        >>> heavier = vi.Device(M=math.nextafter(vi.Device().M, 1.0))         # one ulp: the same harvester
        >>> vi.Device().same_physics(heavier), vi.Device().same_physics(vi.Device(r=0.6))
        (True, False)
        """
        mine, theirs = self.physics() | asdict(self.membrane), other.physics() | asdict(other.membrane)
        return all(math.isclose(v, theirs[k], rel_tol=SAME_RTOL, abs_tol=0.0) for k, v in mine.items())

    def physics(self) -> dict:
        """``M, F, omega, g, r`` as a dict (the workflow config's ``physics`` block).

        Returns
        -------
        dict
            The five values by name.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> {k: round(v, 4) for k, v in vi.Device().physics().items()}   # the paper's device (omega = 5 pi)
        {'M': 0.1245, 'F': 5.0, 'omega': 15.708, 'g': 9.8, 'r': 0.5}
        """
        return {k: getattr(self, k) for k in ("M", "F", "omega", "g", "r")}

    def attrs(self) -> dict:
        """A dataset's attributes naming the device that made it: its name, physics and membrane constants.

        Returns
        -------
        dict
            ``device`` (the name), ``device_M``, ... ``device_r`` and ``membrane_h``, ... ``membrane_m``.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> a = vi.Device().attrs()
        >>> len(a), a["device"], a["device_F"], a["membrane_U_in"]
        (12, 'paper', 5.0, 2000.0)
        """
        return {"device": self.name, **{f"device_{k}": v for k, v in self.physics().items()},
                **{f"membrane_{k}": v for k, v in asdict(self.membrane).items()}}

    def default_name(self) -> str:
        """A name for the device from its values: ``device-`` and 8 hex digits of their hash.

        Returns
        -------
        str
            The name: the same for the same values, whatever the device is called.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> a, b = vi.Device(M=0.2).default_name(), vi.Device(M=0.2, name="x").default_name()
        >>> a == b, a.startswith("device-"), len(a), a == vi.Device().default_name()
        (True, True, 15, False)
        """
        text = json.dumps({**self.physics(), "membrane": asdict(self.membrane)}, sort_keys=True)
        return "device-" + hashlib.sha1(text.encode()).hexdigest()[:8]

    @property
    def k(self) -> float:
        """``M omega^2 / pi^2`` (N/m): ``d = k s / F``.

        Returns
        -------
        float
            The factor (N/m).

        Examples
        --------
        >>> import vibroimpact as vi
        >>> round(vi.Device().k, 6)          # 0.1245 kg * 25: d = 0.6225 s at F = 5 N
        3.1125
        """
        return length_factor(self.M, self.omega)

    def d(self, s, F=None):
        """Non-dimensional length of a cylinder of length ``s`` (m) at forcing ``F`` (N).

        Parameters
        ----------
        s : float or array_like
            Cylinder lengths (m).
        F : float or array_like, optional
            Forcing amplitudes (N); the device's by default.

        Returns
        -------
        float or numpy.ndarray
            ``d = k s / F``.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> dev = vi.Device()
        >>> round(dev.d(1.0), 6), dev.d([0.2, 0.4], F=10.0).round(6).tolist()
        (0.6225, [0.06225, 0.1245])
        """
        F = self.F if F is None else np.asarray(F, dtype=float)
        return _out(np.asarray(s, dtype=float) * self.M * self.omega**2 / (F * math.pi**2))  # as Params rounds it

    def s(self, d, F=None):
        """Cylinder length (m) whose non-dimensional length is ``d`` at forcing ``F`` (N).

        Parameters
        ----------
        d : float or array_like
            Non-dimensional lengths.
        F : float or array_like, optional
            Forcing amplitudes (N); the device's by default.

        Returns
        -------
        float or numpy.ndarray
            ``s = d F / k`` (m), the inverse of :meth:`d`.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> dev = vi.Device()
        >>> round(dev.s(0.6225), 6), round(dev.s(dev.d(0.3, F=7.0), F=7.0), 12)
        (1.0, 0.3)
        """
        return _out(np.asarray(d, dtype=float) * (self.F if F is None else np.asarray(F, dtype=float)) / self.k)

    def F_for(self, d, s):
        """The forcing (N) at which a cylinder of length ``s`` (m) has non-dimensional length ``d``.

        Parameters
        ----------
        d : float or array_like
            Non-dimensional lengths.
        s : float or array_like
            Cylinder lengths (m).

        Returns
        -------
        float or numpy.ndarray
            ``F = k s / d`` (N).

        Examples
        --------
        >>> import vibroimpact as vi
        >>> dev = vi.Device()        # d = 0.14 at s = 0.2249 m and F = 5 N; F doubles as d halves
        >>> round(dev.F_for(0.14, 0.2249), 4), round(dev.F_for(0.07, 0.2249), 4)
        (5.0, 10.0)
        """
        return _out(self.k * np.asarray(s, dtype=float) / np.asarray(d, dtype=float))

    def gbar(self, beta, F=None):
        """Non-dimensional gravity ``M g sin(beta) / F`` at incline ``beta`` (rad).

        Parameters
        ----------
        beta : float or array_like
            Inclines (rad).
        F : float or array_like, optional
            Forcing amplitudes (N); the device's by default.

        Returns
        -------
        float or numpy.ndarray
            ``gbar``.

        Examples
        --------
        >>> import math, vibroimpact as vi
        >>> dev = vi.Device()
        >>> round(dev.gbar(math.pi / 6), 6), round(dev.gbar(math.pi / 2, F=1.2), 6)   # 0.1245 * 9.8 / 1.2
        (0.12201, 1.01675)
        """
        return _out(self.M * self.g * np.sin(np.asarray(beta, dtype=float))
                    / (self.F if F is None else np.asarray(F, dtype=float)))

    def params(self, s: float, beta: float, F: float | None = None) -> Params:
        """The model parameters of a cylinder of length ``s`` (m) at incline ``beta`` (rad) and forcing ``F``.

        Parameters
        ----------
        s : float
            Cylinder length (m).
        beta : float
            Incline (rad).
        F : float, optional
            Forcing amplitude (N); the device's by default.

        Returns
        -------
        Params
            From :meth:`Params.from_physical` with the device's mass, frequency, restitution and gravity.

        Examples
        --------
        >>> import math, vibroimpact as vi
        >>> p = vi.Device(r=0.6).params(s=0.2249, beta=math.pi / 6, F=10.0)
        >>> round(p.d, 6), round(p.gbar, 6), p.r
        (0.07, 0.061005, 0.6)
        """
        return Params.from_physical(s=s, beta=beta, M=self.M, F=self.F if F is None else F, omega=self.omega,
                                    r=self.r, g=self.g)

    def scales(self, F: float | None = None) -> PhysicalScales:
        """Seconds, m/s and metres per non-dimensional unit of time, velocity and length.

        Parameters
        ----------
        F : float, optional
            Forcing amplitude (N); the device's by default.

        Returns
        -------
        PhysicalScales
            The three factors.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> sc = vi.Device().scales()
        >>> round(sc.time, 6), round(sc.velocity, 5), round(sc.length, 5)   # pi / omega, ...
        (0.2, 8.03213, 1.60643)
        >>> round(vi.Device().scales(F=10.0).length / sc.length, 12)        # proportional to F
        2.0
        """
        F = self.F if F is None else float(F)
        return PhysicalScales(time=math.pi / self.omega, velocity=F * math.pi / (self.M * self.omega),
                              length=F * math.pi**2 / (self.M * self.omega**2))

    def speed_si(self, v, F=None):
        """Dimensional speed (m/s) of non-dimensional velocities ``v`` at forcing ``F`` (:func:`speed_si`).

        Parameters
        ----------
        v : float or array_like
            Non-dimensional velocities (any sign).
        F : float or array_like, optional
            Forcing amplitudes (N); the device's by default.

        Returns
        -------
        float or numpy.ndarray
            Speeds (m/s), the velocity unit of :meth:`scales` times ``|v|``.

        Examples
        --------
        >>> import vibroimpact as vi
        >>> dev = vi.Device()
        >>> round(dev.speed_si(-0.4185), 5), round(0.4185 * dev.scales().velocity, 5)
        (3.36145, 3.36145)
        """
        return _out(speed_si(v, self.F if F is None else F, self.M, self.omega))


#: the paper's device (section 2; the membrane of docs/guide/model.md)
PAPER = Device()
