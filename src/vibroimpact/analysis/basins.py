"""Basins of attraction: the motion reached from each bottom impact of a grid of starts, at one parameter
point."""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..datasets import annotate, attractor_codes
from ..dynamics.params import Params
from .windows import attractor_batch

__all__ = ["basins"]


def basins(params: Params, phis, v0s, *, max_periods: float = 400, tol: float = 1e-9, window: int = 65,
           progress: bool | None = None) -> xr.Dataset:
    """Attractor reached from each bottom impact ``(phase, v0)`` of a grid, at one parameter point.

    Parameters
    ----------
    params : Params
        The parameter point.
    phis, v0s : array_like
        Grid axes: phase (rad) and pre-impact velocity of the first bottom impact.
    max_periods : float
        Longest transient, in forcing periods, before a start is called aperiodic.
    tol : float
        Tolerance of the periodicity test.
    window : int
        Events kept per run.
    progress : bool, optional
        A progress bar (default: only when run interactively).

    Returns
    -------
    xarray.Dataset
        On ``(phi, v0)``: ``label`` (e.g. ``"2:1 period-2"``), ``sticking`` (whether the motion's cycle
        sticks to a wall), ``period``, ``n_events`` and the integer
        ``attractor``, an index into the labels listed (as JSON) in the ``legend`` attribute.

    Examples
    --------
    Between G1 and G2 (d = 0.13975, pi/6) the starts of a small grid split between the two coexisting motions:

    >>> import json, numpy as np, vibroimpact as vi
    >>> b = vi.basins(vi.Params(d=0.13975, gbar=0.12201), np.linspace(0, 2 * np.pi, 4, endpoint=False),
    ...               [0.1, 0.4])
    >>> legend = json.loads(b.attrs["legend"])
    >>> sorted(legend)
    ['2:1 period-2', '3:1 period-2']
    >>> bool((np.array(legend)[b.attractor.values] == b.label.values).all())
    True
    """
    P, V = np.meshgrid(np.asarray(phis, float), np.asarray(v0s, float), indexing="ij")
    ds = attractor_batch(params.d, params.gbar, params.r, P.ravel(), V.ravel(), max_periods=max_periods,
                         tol=tol, window=window, progress=progress, desc="basins")
    shape = P.shape
    out = xr.Dataset(
        {
            "label": (("phi", "v0"), ds["label"].values.reshape(shape)),
            "sticking": (("phi", "v0"), ds["sticking"].values.reshape(shape)),
            "period": (("phi", "v0"), ds["period"].values.reshape(shape), ds["period"].attrs),
            "n_events": (("phi", "v0"), ds["n_events"].values.reshape(shape), ds["n_events"].attrs),
        },
        coords={"phi": np.asarray(phis, float), "v0": np.asarray(v0s, float)},
    )
    out.attrs.update(d=params.d, gbar=params.gbar, r=params.r, max_periods=max_periods, tol=tol,
                     **{k: v for k, v in params.physical.items()})
    return annotate(attractor_codes(out, ("phi", "v0")))
