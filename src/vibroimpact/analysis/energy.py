"""Output voltage of the dielectric-elastomer membranes, per impact and averaged (paper §5, eq. V1;
docs/guide/model.md).

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

import numpy as np
import xarray as xr

from ..datasets import annotate
from ..dynamics import kernels as K
from ..dynamics.device import PAPER, Device, Membrane, speed_si
from .settled import LONG_BATCHES, STICK_REL, long_runs

__all__ = ["Membrane", "voltage_gain", "speed_si", "averages", "window_averages", "orbit_energy", "branch_energy", "sweep_energy",
           "delivered"]


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

    Examples
    --------
    At rest the membrane is flat (``A = pi R^2``, ``U = U_in``: no gain); the gain depends on the speed's
    magnitude only and grows with it (3.36 m/s is the 2:1 orbit's fastest bottom impact at the paper's
    device):

    >>> import vibroimpact as vi
    >>> vi.voltage_gain([0.0, -1.0, 1.0, 3.36], vi.Device().membrane).round(0).tolist()   # V
    [0.0, 5740.0, 5740.0, 27198.0]
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

    Examples
    --------
    Three impacts of 1, 2 and 6 V over 4 time units (two forcing periods):

    >>> import vibroimpact as vi
    >>> [float(u) for u in vi.averages([1.0, 2.0, 6.0], 4.0)]
    [3.0, 2.25]
    """
    gain = np.asarray(gain, dtype=float)
    total = gain.sum(axis=-1)
    return total / gain.shape[-1], total / duration


def orbit_energy(orbit, device: Device = PAPER) -> dict:
    """Exact energy of a periodic orbit over one period.

    Parameters
    ----------
    orbit : Orbit
        From :func:`~vibroimpact.analysis.orbits.find_orbit`; its forcing is the one its parameters were
        built with (:meth:`vibroimpact.Device.params`), else the device's.
    device : Device
        The harvester (its mass, forcing frequency and membranes).

    Returns
    -------
    dict
        ``gain`` (V, per impact of the period), ``U_I`` and ``U_T`` (the orbit's period is
        ``2 k`` non-dimensional time units).

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params(d=0.14, gbar=0.0949, r=0.5), "BBT", 5.855, 0.4185)
    >>> e = vi.orbit_energy(o, vi.Device())  # the paper's device
    >>> round(e["U_T"]), round(e["U_I"])
    (33376, 22251)
    """
    F = orbit.params.physical.get("F", device.F)
    gain = voltage_gain(device.speed_si(orbit.v_minus, F), device.membrane)
    u_i, u_t = averages(gain, 2.0 * orbit.k)
    return {"gain": gain, "U_I": float(u_i), "U_T": float(u_t)}


def branch_energy(branch: xr.Dataset, device: Device = PAPER) -> xr.Dataset:
    """Gains and averages along an analytic branch, exact over one period at every point.

    Parameters
    ----------
    branch : xarray.Dataset
        From :func:`~vibroimpact.analysis.continuation.continue_orbit` with ``vary="s"`` or ``"F"``.
    device : Device
        The harvester (its mass, forcing frequency and membranes; the forcing of each point is the branch's).

    Returns
    -------
    xarray.Dataset
        Along ``point`` (coordinates ``d``, ``s``, ``F``): per impact ``v_minus``, ``speed`` (m/s) and
        ``gain`` (V; the impacts' walls are ``wall``), and ``U_I``, ``U_T``, ``stable``, ``admissible``;
        the device's attributes.

    Examples
    --------
    Along the 2:1 branch (3 impacts per forcing period of 2 time units) ``U_T = 3 U_I / 2``; at
    s = 0.2249 m it is :func:`~vibroimpact.orbit_energy` of the orbit there:

    >>> import math, numpy as np, vibroimpact as vi
    >>> o = vi.find_orbit(vi.Params.from_physical(s=0.2249, beta=math.pi / 6), "BBT", 5.855, 0.4185)
    >>> br = vi.continue_orbit(o, vary="s", value_range=(0.224, 0.226), step=1e-3)
    >>> en = vi.branch_energy(br)
    >>> bool(np.allclose(en.U_T, 1.5 * en.U_I, rtol=1e-12)), bool(en.stable.all())
    (True, True)
    >>> at = int(np.argmin(abs(en.s.values - 0.2249)))
    >>> round(float(en.U_T[at])), round(vi.orbit_energy(o, vi.Device())["U_T"])     # V per unit time
    (33783, 33783)
    """
    if not branch.sizes.get("point", 0):
        return xr.Dataset(attrs=dict(branch.attrs))
    F = branch["F"].values[:, None]
    speed = device.speed_si(branch["v_minus"].values, F)
    gain = voltage_gain(speed, device.membrane)
    k = float(branch.attrs.get("k", 1))
    u_i, u_t = averages(gain, 2.0 * k)
    ds = xr.Dataset(
        {"v_minus": branch["v_minus"], "speed": (("point", "impact"), speed), "gain": (("point", "impact"), gain),
         "U_I": ("point", u_i), "U_T": ("point", u_t),
         "stable": branch["stable"], "admissible": branch["admissible"], "wall": branch["wall"]},
        coords={c: branch[c] for c in ("point", "impact", "d", "s", "F") if c in branch.variables},
    )
    ds.attrs.update({k_: v for k_, v in branch.attrs.items() if k_ in ("word", "k", "beta", "r", "vary")})
    ds.attrs.update(device.attrs())
    return annotate(ds)


def window_averages(t, v_minus, kind, status, period_events, F, device: Device = PAPER, *,
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
    device, window_time
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
    speed = device.speed_si(vm, np.asarray(F, dtype=float)[..., None])
    hit = np.isfinite(t) & K.hits(kind)
    gain_all = np.where(hit, voltage_gain(np.where(hit, speed, 0.0), device.membrane), np.nan)
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


def _settled_energy(sw, F, device):
    """Gains and averages of each attractor's exact cycle (:func:`vibroimpact.analysis.settled.settle_attractors`), and the
    long-run averages (batch means, with standard errors) of each motion with no period."""

    shape = sw["status"].shape
    vm, kind = sw["cycle_v_minus"].values, sw["cycle_kind"].values
    hit = np.isfinite(vm) & K.hits(kind)
    cyc_gain = np.where(hit, voltage_gain(np.where(hit, device.speed_si(vm, F[..., None]), 0.0), device.membrane),
                        np.nan)
    per = sw["period"].values.astype(float)
    n_hit = hit.sum(axis=-1)
    total = np.nansum(cyc_gain, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cu_i = np.where(n_hit > 0, total / np.maximum(n_hit, 1), np.nan)
        cu_t = np.where(per > 0, total / (2.0 * per), np.nan)
    long = np.full((*shape, 4), np.nan)
    batches = int(sw.attrs.get("long_batches", LONG_BATCHES))
    todo = [idx for idx in np.ndindex(shape) if str(sw["long_status"].values[idx]) == "aperiodic"]
    if todo:  # the long runs again, side by side (their exponents are not needed)
        runs = long_runs(*(np.array([float(x) for x in col]) for col in zip(*(
            (sw.d.values[idx[-1]], sw.gbar.values[idx[-1]], sw.attrs["r"], sw["long_phi"].values[idx],
             sw["long_v0"].values[idx]) for idx in todo), strict=True)),
            impacts=int(sw.attrs["long_impacts"]), tol=float(sw.attrs.get("tol", 1e-9)), exponents=False)
        for idx, run in zip(todo, runs, strict=True):
            if run["status"] == "aperiodic":
                long[idx] = batch_averages(run, F[idx], device, batches=batches)
    dims, edims = ("direction", "point"), ("direction", "point", "cycle")
    return {
        "cycle_gain": (edims, cyc_gain, {"units": "V", "long_name": "gain of each impact of the attractor's cycle"}),
        "cycle_U_I": (dims, cu_i, {"units": "V", "long_name": "U_I of the attractor's cycle (exact where settled)"}),
        "cycle_U_T": (dims, cu_t, {"units": "V", "long_name": "U_T of the attractor's cycle (exact where settled)"}),
        "U_I_long": (dims, long[..., 0], {"units": "V", "long_name": "U_I over the long run of a motion with no period (batch means)"}),
        "U_I_long_se": (dims, long[..., 1], {"units": "V", "long_name": "standard error of U_I_long (batch means)"}),
        "U_T_long": (dims, long[..., 2], {"units": "V", "long_name": "U_T over the long run of a motion with no period (batch means)"}),
        "U_T_long_se": (dims, long[..., 3], {"units": "V", "long_name": "standard error of U_T_long (batch means)"}),
    }


def batch_averages(run, F, device: Device, *, batches: int) -> np.ndarray:
    """``U_I``, its standard error, ``U_T``, its standard error over the impacts of a long run
    (:func:`vibroimpact.long_run`'s dict) at forcing ``F``, from ``batches`` consecutive batches of equally
    many impacts."""
    hit = K.hits(run["kind"])
    t, gain = run["t"][hit], voltage_gain(device.speed_si(run["v_minus"][hit], F), device.membrane)
    m = gain.size // batches
    if m < 2:
        return np.full(4, np.nan)
    g = gain[:m * batches].reshape(batches, m)
    ends = t[m - 1::m][:batches]
    starts = np.concatenate([[t[0]], ends[:-1]])
    # the first batch's span starts at its first impact; the others at the previous batch's last
    first = g[0, 1:].sum() / (ends[0] - starts[0])
    u_t = np.concatenate([[first], g[1:].sum(axis=1) / (ends[1:] - starts[1:])])
    u_i = g.mean(axis=1)
    se = lambda b: float(b.std(ddof=1) / np.sqrt(b.size))
    return np.array([u_i.mean(), se(u_i), u_t.mean(), se(u_t)])


def delivered(en: xr.Dataset, q: str = "U_T"):
    """What a device delivers at each point of a sweep energy, well-posed.

    The exact cycle's average where the attractor is settled (standard error 0); a sticking cycle's, known
    to its summed chatter's accuracy (:data:`vibroimpact.analysis.settled.STICK_REL`); the long-run average
    with its batch-means standard error where no period was found and the long run stays aperiodic; NaN
    where neither is known (a transient longer than the cap, whose output is that of wherever it settles).

    Parameters
    ----------
    en : xarray.Dataset
        From :func:`~vibroimpact.sweep_energy` of a settled sweep (:func:`~vibroimpact.sweep`).
    q : {"U_T", "U_I"}
        The average (paper eq. ``V1``): per unit time or per impact.

    Returns
    -------
    value, se : numpy.ndarray
        On ``(direction, point)``, in V. A sweep energy without settled cycles gives its window averages
        and NaN standard errors.

    Examples
    --------
    Every point of this sweep is settled on a periodic orbit: its exact average, with standard error 0:

    >>> import math, vibroimpact as vi
    >>> sw = vi.sweep("s", [0.219, 0.2245, 0.23], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=0)
    >>> value, se = vi.delivered(vi.sweep_energy(sw))
    >>> value.round(-1).tolist(), se.tolist()          # up, then down (V per unit time)
    ([[33130.0, 33690.0, 34070.0], [33130.0, 33760.0, 34070.0]], [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    """
    if q not in ("U_T", "U_I"):
        raise ValueError(f"q = {q!r}; allowed: 'U_T' or 'U_I'")
    if "settled" not in en:
        return en[q].values, np.full(en[q].shape, np.nan)

    settled = en["settled"].values
    sticking = en["sticking"].values
    chaotic = en["long_status"].values.astype(str) == "aperiodic"
    value = np.where(settled | sticking, en[q].values, np.where(chaotic, en[f"{q}_long"].values, np.nan))
    se = np.where(settled, 0.0, np.where(sticking, STICK_REL * np.abs(en[q].values),
                                         np.where(chaotic, en[f"{q}_long_se"].values, np.nan)))
    return value, se


def sweep_energy(sw: xr.Dataset, device: Device = PAPER, *, window_time: float = 30.0) -> xr.Dataset:
    """Gains and averages at every point of a sweep.

    A periodic attractor is averaged over one whole period: its exact cycle's where the sweep settled it
    (:func:`vibroimpact.analysis.settled.settle_attractors`), else as the simulated events measure it (from an event to the
    same event one period earlier).  Where no period was found the average runs over the impacts of the
    last ``window_time`` time units (the paper uses 30 for the 1:1 and 20 for the 2:1 motion), and
    ``window_time`` records the span actually used; such a window is one sample of the motion, so the
    long-run averages are given beside it (``U_I_long``, ``U_T_long`` with standard errors).

    Parameters
    ----------
    sw : xarray.Dataset
        From :func:`~vibroimpact.analysis.sweeps.sweep`.
    device : Device
        The harvester (its mass, forcing frequency and membranes; each point's forcing is the sweep's).
    window_time : float
        Averaging span for aperiodic points (non-dimensional time).

    Returns
    -------
    xarray.Dataset
        On ``(direction, point)``: ``U_I``, ``U_T``, ``window_impacts`` and ``window_time`` (the
        span averaged over), the sweep's ``label``, ``sticking``, ``settled`` and ``long_status``; on
        ``(direction, point, event)`` the window's ``speed`` and ``gain``; where settled the exact cycle's
        ``cycle_gain`` (on ``cycle``), ``cycle_U_I`` and ``cycle_U_T``; the long-run averages
        ``U_I_long``, ``U_T_long`` with standard errors ``U_I_long_se``, ``U_T_long_se``.  A point resting
        on the bottom for good (``gbar >= 1``) or without impacts in its window has ``U_T = 0`` and ``U_I``
        NaN (no impact to average).

    Examples
    --------
    On the bistable interval (the middle point, d = 0.13975) the up sweep's 3:1 motion and the down sweep's
    2:1 deliver differently; ``U_T / U_I`` is the number of impacts per unit time, 4 or 3 per forcing period
    of 2 time units:

    >>> import math, vibroimpact as vi
    >>> sw = vi.sweep("s", [0.219, 0.2245, 0.23], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=0)
    >>> en = vi.sweep_energy(sw)
    >>> en.label.values[:, 1].tolist(), en.U_T.values[:, 1].round(-1).tolist()
    (['3:1 period-2', '2:1 period-2'], [33690.0, 33760.0])
    >>> (en.U_T / en.U_I).round(9).values.tolist()
    [[2.0, 2.0, 1.5], [2.0, 1.5, 1.5]]
    """
    F = sw["F"].values
    Fb = np.broadcast_to(F[None, :], sw["status"].shape)
    speed, gain_all, u_i, u_t, span, count = window_averages(
        sw["t"].values, sw["v_minus"].values, sw["kind"].values, sw["status"].values, sw["period_events"].values,
        Fb, device, window_time=window_time)
    data = {"speed": (("direction", "point", "event"), speed),
            "gain": (("direction", "point", "event"), gain_all),
            "U_I": (("direction", "point"), u_i), "U_T": (("direction", "point"), u_t),
            "window_time": (("direction", "point"), span), "window_impacts": (("direction", "point"), count),
            "label": sw["label"], "sticking": sw["sticking"]}
    if "cycle_v_minus" in sw:
        data |= _settled_energy(sw, Fb, device)
        # a settled attractor's averages are its exact cycle's (the window's are that cycle's to the
        # periodicity tolerance); resting for good keeps U_T = 0
        exact = sw["settled"].values & np.isfinite(data["cycle_U_T"][1])
        data["U_I"] = (("direction", "point"), np.where(exact, data["cycle_U_I"][1], u_i))
        data["U_T"] = (("direction", "point"), np.where(exact, data["cycle_U_T"][1], u_t))
        data["settled"] = sw["settled"]
        data["long_status"] = sw["long_status"]
    ds = xr.Dataset(data, coords={c: sw[c] for c in ("direction", "point", "d", "s", "F", "gbar") if c in sw.variables})
    ds.attrs.update({k: sw.attrs[k] for k in ("vary", "beta", "r") if k in sw.attrs}, window_time=window_time)
    ds.attrs.update(device.attrs())
    return annotate(ds)
