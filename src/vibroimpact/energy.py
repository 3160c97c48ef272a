"""Output voltage of the dielectric-elastomer membranes, per impact and averaged (paper §5, eq. V1;
docs/model.md).

A ball of radius ``r_b`` and mass ``m`` hits a membrane of active radius ``R`` at speed ``v``
(m/s).  Its largest deflection follows from an energy balance against a power-law membrane force
``K delta^h``; the stretched area is a spherical cap on the ball plus a conical skirt to the
clamp; constant charge and an incompressible membrane give ``U ∝ A^2``:

    delta = [(h + 1) m v^2 / (2 K)]^(1 / (h + 1))
    b = 2 r_b (delta - r_b),  c = R^2 + (delta - r_b)^2,  e = 2 R sqrt(R^2 + delta^2 - 2 delta r_b)
    cos(alpha) = (e - b) / (2 c)
    A = 2 pi r_b^2 (1 - cos alpha) + pi (R^2 - r_b^2 sin^2 alpha) / cos alpha
    U = U_in (A / (pi R^2))^2

Averages over a window of N impacts lasting ``t_f - t_0`` (non-dimensional time):
``U_I = sum(U_k - U_in) / N`` and ``U_T = sum(U_k - U_in) / (t_f - t_0)``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
import xarray as xr

from . import kernels as K
from .datasets import annotate

__all__ = ["Membrane", "voltage_gain", "speed_si", "averages", "window_averages", "orbit_energy", "branch_energy", "sweep_energy"]


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


def deflection(speed, membrane: Membrane) -> np.ndarray:
    """Largest membrane deflection (m) of an impact at ``speed`` (m/s): the ball's kinetic energy
    ``m v^2 / 2`` is taken up by the restoring force ``K x^h``, ``K delta^(h+1) / (h+1)``."""
    v = np.abs(np.asarray(speed, dtype=float))
    mb = membrane
    return ((mb.h + 1.0) * mb.m * v**2 / (2.0 * mb.K)) ** (1.0 / (mb.h + 1.0))


def voltage_gain(speed, membrane: Membrane) -> np.ndarray:
    """Voltage gain ``U_k - U_in`` of one impact (module docstring).

    Parameters
    ----------
    speed : array_like
        Impact speeds (m/s, any sign: the magnitude is used).
    membrane : Membrane
        Membrane and ball constants.

    Returns
    -------
    numpy.ndarray
        Gains (V), shaped like ``speed``.  Where the stretched geometry has no real solution
        (``cos(alpha)`` outside ``(0, 1]``, a deflection too large for the model) the result is
        NaN: flagged, never a silent number.
    """
    mb = membrane
    delta = deflection(speed, mb)
    b = 2.0 * mb.r_b * (delta - mb.r_b)
    c = mb.R**2 + (delta - mb.r_b) ** 2
    e = 2.0 * mb.R * np.sqrt(mb.R**2 + delta**2 - 2.0 * delta * mb.r_b)
    cos_a = (e - b) / (2.0 * c)
    valid = (cos_a > 0.0) & (cos_a <= 1.0 + 1e-12)
    cos_a = np.where(valid, np.minimum(cos_a, 1.0), np.nan)
    sin2 = 1.0 - cos_a**2
    area = 2.0 * math.pi * mb.r_b**2 * (1.0 - cos_a) + math.pi * (mb.R**2 - mb.r_b**2 * sin2) / cos_a
    return mb.U_in * (area / (math.pi * mb.R**2)) ** 2 - mb.U_in


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
    """
    return np.abs(np.asarray(v_nondim, dtype=float)) * np.asarray(F, dtype=float) * math.pi / (M * omega)


def averages(gain, duration):
    """Averages of the gains of ``N`` impacts: per impact and per unit time.

    Parameters
    ----------
    gain : array_like
        Gains (V) of the impacts, along the last axis.
    duration : float or array_like
        Time spanned by those impacts (non-dimensional).

    Returns
    -------
    U_I, U_T : numpy.ndarray
        ``sum(gain) / N`` (V per impact) and ``sum(gain) / duration`` (V per unit time).
    """
    gain = np.asarray(gain, dtype=float)
    total = gain.sum(axis=-1)
    return total / gain.shape[-1], total / duration


def orbit_energy(orbit, membrane: Membrane, *, F: float, M: float, omega: float) -> dict:
    """Exact energy of a periodic orbit over one period.

    Parameters
    ----------
    orbit : Orbit
        From :func:`~vibroimpact.orbits.find_orbit`.
    membrane : Membrane
        Membrane and ball constants.
    F, M, omega : float
        Forcing amplitude (N), cylinder mass (kg), forcing frequency (rad/s).

    Returns
    -------
    dict
        ``gain`` (V, per impact of the period), ``U_I`` and ``U_T`` (the orbit's period is
        ``2 k`` non-dimensional time units).
    """
    gain = voltage_gain(speed_si(orbit.v_minus, F, M, omega), membrane)
    u_i, u_t = averages(gain, 2.0 * orbit.k)
    return {"gain": gain, "U_I": float(u_i), "U_T": float(u_t)}


def branch_energy(branch: xr.Dataset, membrane: Membrane, *, M: float, omega: float) -> xr.Dataset:
    """Gains and averages along an analytic branch, exact over one period at every point.

    Parameters
    ----------
    branch : xarray.Dataset
        From :func:`~vibroimpact.continuation.continue_orbit` with ``vary="s"`` or ``"F"``.
    membrane : Membrane
        Membrane and ball constants.
    M, omega : float
        Cylinder mass (kg) and forcing frequency (rad/s).

    Returns
    -------
    xarray.Dataset
        Along ``point``: ``speed``, ``gain`` (per impact), ``U_I``, ``U_T``, ``stable``, ``admissible``.
    """
    if not branch.sizes.get("point", 0):
        return xr.Dataset(attrs=dict(branch.attrs))
    F = branch["F"].values[:, None]
    speed = speed_si(branch["v_minus"].values, F, M, omega)
    gain = voltage_gain(speed, membrane)
    k = float(branch.attrs.get("k", 1))
    u_i, u_t = averages(gain, 2.0 * k)
    ds = xr.Dataset(
        {"v_minus": branch["v_minus"], "speed": (("point", "impact"), speed), "gain": (("point", "impact"), gain),
         "U_I": ("point", u_i), "U_T": ("point", u_t),
         "stable": branch["stable"], "admissible": branch["admissible"], "wall": branch["wall"]},
        coords={c: branch[c] for c in ("point", "impact", "d", "s", "F") if c in branch.variables},
    )
    ds.attrs.update({k_: v for k_, v in branch.attrs.items() if k_ in ("word", "k", "beta", "r", "vary")})
    ds.attrs.update({f"membrane_{k_}": v for k_, v in asdict(membrane).items()})
    return annotate(ds)


def window_averages(t, v_minus, kind, status, period_events, F, membrane: Membrane, *, M: float, omega: float,
                    window_time: float = 30.0):
    """Gains and averages of runs from their saved windows of events (the last events of each run).

    A periodic run (``period_events > 0``) is averaged over one whole period, as the simulation
    measured it: from an event to the same event one period earlier (exact to rounding).  Any other
    run is averaged over the impacts of its last ``window_time`` time units.  A run resting on the
    bottom for good (status ``stuck_forever``) or without impacts in its window has ``U_T = 0`` and
    ``U_I`` NaN (no impact to average).

    Parameters
    ----------
    t, v_minus, kind : numpy.ndarray
        Events on ``(..., event)``, NaN-padded after the last real event.
    status, period_events, F : numpy.ndarray
        Per run (shape ``...``): the run status, events per period (0: none found) and the force (N).
    membrane, M, omega, window_time
        As in :func:`sweep_energy`.

    Returns
    -------
    speed, gain : numpy.ndarray
        Per event (m/s and V; NaN where not an impact).
    U_I, U_T, span, count : numpy.ndarray
        Per run: the averages, the time span averaged over and the impacts in it.
    """
    t, vm, kind = (np.asarray(a) for a in (t, v_minus, kind))
    shape = t.shape[:-1]
    speed = speed_si(vm, np.asarray(F, dtype=float)[..., None], M, omega)
    hit = np.isfinite(t) & ((kind == 0) | (kind == 1))
    gain_all = np.where(hit, voltage_gain(np.where(hit, speed, 0.0), membrane), np.nan)
    u_i, u_t, span = np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan)
    count = np.zeros(shape, np.int64)
    status, lags = np.asarray(status), np.asarray(period_events)
    for idx in np.ndindex(shape):
        ti = t[idx]
        if status[idx] == K.STUCK_FOREVER:
            # resting on the bottom for good: no impact in the long run
            u_t[idx], span[idx] = 0.0, math.inf
            continue
        m = int(np.isfinite(ti).sum())
        lag = int(lags[idx])
        if lag:
            # one whole period, as the simulation measured it: from an event to the same event one
            # period earlier (a period is identified after two cycles, so the window holds lag + 1)
            sl = slice(m - lag, m)
            duration = ti[m - 1] - ti[m - 1 - lag]
        else:
            # the last window_time time units: the impacts after t_end - window_time, over the time
            # from the event before the first of them (the window's span is at least window_time,
            # unless the saved events do not reach that far back)
            t_end = ti[m - 1]
            first = max(int(np.searchsorted(ti[:m], t_end - window_time, side="right")), 1)
            sl = slice(first, m)
            duration = t_end - ti[first - 1]
        h = hit[idx][sl]
        n = int(h.sum())
        span[idx], count[idx] = duration, n
        if n:
            u_i[idx], u_t[idx] = averages(gain_all[idx][sl][h], duration)
        else:
            u_t[idx] = 0.0  # stuck or resting over the whole window: no impact, no output
    return np.where(hit, speed, np.nan), gain_all, u_i, u_t, span, count


def sweep_energy(sw: xr.Dataset, membrane: Membrane, *, M: float, omega: float, window_time: float = 30.0) -> xr.Dataset:
    """Gains and averages at every point of a sweep.

    A periodic attractor is averaged over one whole period, as long as the simulated events measure it
    (from an event to the same event one period earlier; exact to rounding).  Where no period was found the
    average runs over the impacts of the last ``window_time`` time units (the paper uses 30 for the
    1:1 and 20 for the 2:1 motion), and ``window_time`` records the span actually used.

    Parameters
    ----------
    sw : xarray.Dataset
        From :func:`~vibroimpact.sweeps.sweep`.
    membrane : Membrane
        Membrane and ball constants.
    M, omega : float
        Cylinder mass (kg) and forcing frequency (rad/s).
    window_time : float
        Averaging span for aperiodic points (non-dimensional time).

    Returns
    -------
    xarray.Dataset
        On ``(direction, point)``: ``U_I``, ``U_T``, ``window_impacts`` and ``window_time`` (the
        span averaged over).  A point resting on the bottom for good (``gbar >= 1``) or without
        impacts in its window has ``U_T = 0`` and ``U_I`` NaN (no impact to average).
    """
    F = sw["F"].values
    speed, gain_all, u_i, u_t, span, count = window_averages(
        sw["t"].values, sw["v_minus"].values, sw["kind"].values, sw["status"].values, sw["period_events"].values,
        np.broadcast_to(F[None, :], sw["status"].shape), membrane, M=M, omega=omega, window_time=window_time)
    ds = xr.Dataset(
        {"speed": (("direction", "point", "event"), speed),
         "gain": (("direction", "point", "event"), gain_all),
         "U_I": (("direction", "point"), u_i), "U_T": (("direction", "point"), u_t),
         "window_time": (("direction", "point"), span), "window_impacts": (("direction", "point"), count),
         "label": sw["label"]},
        coords={c: sw[c] for c in ("direction", "point", "d", "s", "F", "gbar") if c in sw.variables},
    )
    ds.attrs.update({k: sw.attrs[k] for k in ("vary", "beta", "r") if k in sw.attrs}, window_time=window_time)
    ds.attrs.update({f"membrane_{k}": v for k, v in asdict(membrane).items()})
    return annotate(ds)
