"""Regime maps: the motion over a plane of two parameters, each run from the same bottom impact, a run without
a period split by its long run into chaotic, quasi-periodic or unsettled."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..datasets import annotate, attractor_codes
from ..dynamics.device import Device
from .grids import plane_params
from .motions import APERIODIC
from .settled import split_no_period
from .windows import EVENT_VARS, attractor_batch, last_bottom_impact

__all__ = ["regime_map"]


def _split_cells(ds, d, gbar, r, tol):
    """Labels of an :func:`attractor_batch` with every run that found no period split by its long run
    (:func:`split_no_period`, from its window's last bottom impact), and ``(lambda_1, low, high)`` of those."""
    labels = ds["label"].values.astype(object)
    lyap = np.full((labels.size, 3), np.nan)
    ev = [ds[v].values for v in EVENT_VARS]
    for i in np.flatnonzero(labels == APERIODIC):
        start = last_bottom_impact(*(e[i] for e in ev), int(np.isfinite(ev[0][i]).sum()))
        if start is None:
            continue
        split = split_no_period(d[i], gbar[i], r[i], *start, tol=tol)
        labels[i] = split.label
        lyap[i] = split.lyap1, split.lyap1_low, split.lyap1_high
    return labels.astype(str), lyap


def regime_map(x_name: str, xs, y_name: str, ys, *, phi: float = 0.0, v0: float = 0.5, max_periods: float = 200,
               tol: float = 1e-9, window: int = 65, progress: bool | None = None, device: Device | None = None,
               **held) -> xr.Dataset:
    """Attractor class over a grid of two parameters, each run from the same bottom impact.

    Parameters
    ----------
    x_name, y_name : {"s", "F", "beta", "d", "gbar", "r"}
        The two axes (different): physical (``s``, ``F``, ``beta``, with ``r``) or non-dimensional
        (``d``, ``gbar``, with ``r``), not a mix.
    xs, ys : array_like
        Their values (m, N, rad or 1).
    phi, v0 : float
        Start of every run: a bottom impact at phase ``phi`` with pre-impact velocity ``v0``.
    max_periods, tol, window, progress
        As in :func:`basins`.
    device : Device, optional
        The harvester (default the paper's, ``Device()``).
    **held
        The values held where they are not an axis (``s``, ``F``, ``beta``; ``r`` changes the device's):
        :func:`plane_params`.  On non-dimensional axes they fix the parameter that is not an axis
        (``gbar`` on a (d, r) map, ``r`` on a (d, gbar) map) through the device's scaling.

    Returns
    -------
    xarray.Dataset
        On ``(y_name, x_name)``: ``label`` (a cell with no period split into chaotic, quasi-periodic or
        unsettled by its long run, :func:`no_period_label`), ``sticking`` (whether the motion's cycle sticks
        to a wall), ``lyap1`` with ``lyap1_low``, ``lyap1_high``
        for those cells, ``period``, ``d``, ``gbar`` and ``attractor`` (an index into the labels of the
        ``legend`` attribute, JSON); attributes: the start, the settings and the values held.

    Examples
    --------
    From the same start, the shorter cylinder settles on the 3:1 motion on both inclines, the longer one on
    the 2:1 at pi/6 only; ``gbar = M g sin(beta) / F`` along beta:

    >>> import math, vibroimpact as vi
    >>> rm = vi.regime_map("s", [0.219, 0.23], "beta", [math.pi / 6, math.pi / 3], phi=5.855, v0=0.4185)
    >>> rm.label.values.tolist()
    [['3:1 period-2', '2:1 period-2'], ['3:1 period-2', '3:1 period-2']]
    >>> rm.d.values[0].round(5).tolist(), rm.gbar.values[:, 0].round(5).tolist()
    ([0.13633, 0.14318], [0.12201, 0.21133])
    """
    X, Y, d, gbar, r, fixed = plane_params(x_name, xs, y_name, ys, device=device, **held)
    axes = {x_name, y_name}
    d, gbar, r = d.ravel(), gbar.ravel(), r.ravel()
    ds = attractor_batch(d, gbar, r, phi, v0, max_periods=max_periods, tol=tol, window=window, progress=progress,
                         desc=f"regime map over ({x_name}, {y_name})")
    shape = X.shape
    labels, lyap = _split_cells(ds, d, gbar, r, tol)
    level = "its 95 % confidence interval (batch means over the long run)"
    data = {
        "label": ((y_name, x_name), labels.reshape(shape)),
        "sticking": ((y_name, x_name), ds["sticking"].values.reshape(shape)),
        "lyap1": ((y_name, x_name), lyap[:, 0].reshape(shape), {"units": "1", "long_name": "largest Lyapunov exponent per impact of a cell with no period (its long run; NaN elsewhere)"}),
        "lyap1_low": ((y_name, x_name), lyap[:, 1].reshape(shape), {"units": "1", "long_name": f"lambda_1: lower end of {level}"}),
        "lyap1_high": ((y_name, x_name), lyap[:, 2].reshape(shape), {"units": "1", "long_name": f"lambda_1: upper end of {level}"}),
        "period": ((y_name, x_name), ds["period"].values.reshape(shape), ds["period"].attrs),
        "d": ((y_name, x_name), d.reshape(shape)),
        "gbar": ((y_name, x_name), gbar.reshape(shape)),
    }
    out = xr.Dataset({k: v for k, v in data.items() if k not in axes},  # an axis is its own coordinate
                     coords={x_name: np.asarray(xs, float), y_name: np.asarray(ys, float)})
    units = {"s": ("m", "cylinder length s"), "F": ("N", "forcing amplitude ||F||"), "beta": ("rad", "incline beta"),
             "d": ("1", "non-dimensional gap d"), "gbar": ("1", "non-dimensional gravity gbar"),
             "r": ("1", "coefficient of restitution r")}
    for name in (x_name, y_name):
        out[name].attrs.update(units=units[name][0], long_name=units[name][1])
    out.attrs.update(phi=phi, v0=v0, max_periods=max_periods, tol=tol, **fixed)
    return annotate(attractor_codes(out, (y_name, x_name)))
