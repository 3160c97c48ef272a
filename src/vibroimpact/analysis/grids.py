"""Parameter grids: the model parameters of a sweep along one physical parameter, or of a plane of two, for a
device, with the values held where they are not an axis."""

from __future__ import annotations

import math

import numpy as np

from ..dynamics.device import PAPER, Device
from ..dynamics.params import Params

__all__ = ["HELD", "held_values", "parameter_grid", "plane_params"]

#: the values a plane, sweep or map holds where they are not its axis (a length for a force sweep, ...)
HELD = ("s", "F", "beta")


def held_values(device: Device | None, physical: dict) -> tuple[Device, dict]:
    """The device and the held values (``s``, ``F``, ``beta``; ``r`` changes the device's restitution) of a
    sweep, map or plane.  The cylinder's mass, the forcing frequency and gravity belong to the device: passing
    them alone is refused, naming the way to another device."""
    device = PAPER if device is None else device
    extra = sorted(set(physical) - {*HELD, "r"})
    if extra:
        raise ValueError(f"{', '.join(extra)} = {[physical[k] for k in extra]!r}: a property of the device; allowed: "
                         f"device=vi.Device().replace({extra[0]}=...) (held values: {', '.join(HELD)}, and r)")
    if "r" in physical:
        device = device.replace(r=float(physical["r"]))
    return device, {k: physical[k] for k in HELD if k in physical}


def parameter_grid(vary: str, values, *, beta: float, device: Device | None = None, s: float = 0.85,
                   F: float | None = None):
    """``(d, gbar, s, F)`` arrays for a sweep of the length ``s`` (``vary="s"``, at the forcing ``F``,
    default the device's) or of the force ``F`` (``vary="F"``, at the length ``s``) of a ``device``
    (default the paper's, ``Device()``); every value is validated through :class:`Params`."""
    if vary not in ("s", "F"):
        raise ValueError(f"vary = {vary!r}; allowed: 's' (length at fixed force) or 'F' (force at fixed length)")
    device = PAPER if device is None else device
    F = device.F if F is None else F
    values = np.atleast_1d(np.asarray(values, dtype=float))
    ps = [device.params(s=v if vary == "s" else s, beta=beta, F=v if vary == "F" else F) for v in values]
    d = np.array([p.d for p in ps])
    gbar = np.array([p.gbar for p in ps])
    s_arr = values if vary == "s" else np.full(values.shape, float(s))
    F_arr = values if vary == "F" else np.full(values.shape, float(F))
    return d, gbar, s_arr, F_arr


def plane_params(x_name: str, xs, y_name: str, ys, *, device: Device | None = None, **held):
    """The model parameters over a grid of two parameters (the plane of a regime or design map).

    ``x_name, y_name``: two different names, both physical (``s``, ``F``, ``beta``, with ``r``) or both
    non-dimensional (``d``, ``gbar``, with ``r``); ``device``: the harvester (default
    the paper's, ``Device()``); ``**held``: the values held where they are not an axis (``s`` 0.85 m, ``F`` the
    device's, ``beta`` pi/6 by default; ``r`` changes the device's).  Returns ``X, Y, d, gbar, r`` on
    ``(len(ys), len(xs))`` and the values held fixed (a dict).
    """
    allowed = ("s", "F", "beta", "d", "gbar", "r")
    for name in (x_name, y_name):
        if name not in allowed:
            raise ValueError(f"map axis {name!r}; allowed: {allowed}")
    if x_name == y_name:
        raise ValueError(f"map axes x_name = y_name = {x_name!r}; allowed: two different names of {allowed}")
    axes = {x_name, y_name}
    nondim = sorted(axes & {"d", "gbar"})
    if nondim and axes & {"s", "F", "beta"}:
        raise ValueError(f"map axes ({x_name!r}, {y_name!r}): {nondim[0]!r} is non-dimensional; allowed: "
                         "two of s, F, beta, r or two of d, gbar, r")
    device, held = held_values(device, held)
    X, Y = np.meshgrid(np.asarray(xs, float), np.asarray(ys, float), indexing="xy")
    base = dict(s=0.85, F=device.F, beta=math.pi / 6) | held
    p0 = device.params(**base)
    d, gbar, r = np.empty(X.shape), np.empty(X.shape), np.empty(X.shape)
    for k, (x, y) in enumerate(zip(X.ravel(), Y.ravel(), strict=True)):
        if nondim:
            v = dict(d=p0.d, gbar=p0.gbar, r=p0.r)
            v[x_name], v[y_name] = x, y
            p = Params(d=v["d"], gbar=v["gbar"], r=v["r"])
        else:
            kw = dict(base, r=device.r)
            kw[x_name], kw[y_name] = x, y
            p = device.replace(r=kw.pop("r")).params(**kw)
        d.flat[k], gbar.flat[k], r.flat[k] = p.d, p.gbar, p.r
    fixed = ({k: float(getattr(p0, k)) for k in ("d", "gbar", "r") if k not in axes} if nondim
             else {k: v for k, v in (base | {"r": device.r}).items() if k not in axes}
             | {k: getattr(device, k) for k in ("M", "omega", "g")})
    return X, Y, d, gbar, r, fixed
