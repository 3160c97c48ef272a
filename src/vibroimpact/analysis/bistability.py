"""Bistability: the intervals of d where the up and the down sweep follow two coexisting motions, bounded by
the located transitions (:func:`vibroimpact.analysis.transitions.locate_transitions`)."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

__all__ = ["bistable_intervals"]


def bistable_intervals(sw: xr.Dataset, transitions: xr.Dataset) -> xr.Dataset:
    """Intervals of d where two motions coexist, bounded by the located transitions.

    An interval is bistable where the up sweep (d increasing) follows one motion ``A`` and the down
    sweep another, ``B``: ``A`` exists up to where the up sweep loses it, and ``B`` down to where
    the down sweep loses it.  So the **lower end** is the located transition of the *down* sweep
    that ends ``B`` (the nearest one below the interval with ``before == B``) and the **upper end**
    the located transition of the *up* sweep that ends ``A``.  Two sources of intervals:

    * ``"sweeps differ"``: a run of grid points where the two sweeps end on different motions;
      ``B`` is the down sweep's motion at the run's lowest point and ``A`` the up sweep's at its
      highest.  An end whose motion is aperiodic has no located transition: it is then the middle
      of the grid step outside the run, with the grid step as its width (``*_source = "grid"``).
      A run that reaches the end of the swept range ends there (``*_source = "range end"``, width
      NaN): the interval may extend beyond it.
    * ``"transitions only"``: a located up transition where the up sweep goes from ``A`` to ``B``
      above a located down transition where the down sweep goes from ``B`` to ``A``, bounding no
      such run (both sweeps jump between the same two grid points).

    Parameters
    ----------
    sw : xarray.Dataset
        A sweep from :func:`sweep`.
    transitions : xarray.Dataset
        Its located transitions, from :func:`locate_transitions`.

    Returns
    -------
    xarray.Dataset
        Along ``interval``: ``d_lo``, ``d_hi``, their bracket widths ``d_lo_width``,
        ``d_hi_width``, ``lo_source``/``hi_source`` (``"located"``, ``"grid"`` or ``"range end"``), ``label_up``
        (``A``), ``label_down`` (``B``) and ``found_by``.

        An interval that would have zero or negative width (located ends in the wrong order) is left out and
        named in the attribute ``inconsistent_intervals``.

    Examples
    --------
    The bistable interval [G1, G2] of the paper's incline pi/6, bounded by the located transitions:

    >>> import math, vibroimpact as vi
    >>> sw = vi.sweep("s", [0.219, 0.2245, 0.23], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=0)
    >>> iv = vi.bistable_intervals(sw, vi.locate_transitions(sw, xtol=1e-6))
    >>> iv.d_lo.values.round(5).tolist(), iv.d_hi.values.round(5).tolist(), iv.lo_source.values.tolist()
    ([0.1376], [0.14195], ['located'])
    >>> iv.label_up.values.tolist(), iv.label_down.values.tolist(), iv.found_by.values.tolist()
    (['3:1 period-2'], ['2:1 period-2'], ['sweeps differ'])
    """
    d = sw["d"].values
    t_dir = transitions["direction"].values.astype(str)
    t_d = transitions["d"].values
    t_w = transitions["d_width"].values
    t_before = transitions["before"].values.astype(str)

    def located(direction, label, side, bound):
        """The located transition of ``direction`` ending ``label`` nearest beyond ``bound``."""
        sel = (t_dir == direction) & (t_before == label)
        sel &= (t_d <= bound) if side < 0 else (t_d >= bound)
        if not sel.any():
            return None
        k = np.flatnonzero(sel)
        k = k[np.argmax(t_d[k])] if side < 0 else k[np.argmin(t_d[k])]
        return float(t_d[k]), float(t_w[k])

    rows = _where_sweeps_differ(sw["label"].values, d, located)
    # hysteresis loops the grid did not see: the up sweep goes from A to B across a located up
    # transition above a located down transition where the down sweep goes from B to A (the
    # transitions' own "after" may be aperiodic: a slow transient just past a fold)
    def sweep_label(k_dir, x, side):
        beyond = np.flatnonzero(d > x) if side > 0 else np.flatnonzero(d < x)
        return str(sw["label"].values[k_dir][beyond[0] if side > 0 else beyond[-1]]) if beyond.size else None

    for k in np.flatnonzero(t_dir == "up"):
        lab_b = sweep_label(0, t_d[k], +1)
        for m in np.flatnonzero((t_dir == "down") & (t_before == lab_b)):
            lo_d, hi_d = float(t_d[m]), float(t_d[k])
            if sweep_label(1, lo_d, -1) != t_before[k] or lab_b == t_before[k]:
                continue
            if lo_d < hi_d and not any(r_[0] <= hi_d and lo_d <= r_[1] for r_ in rows):
                rows.append((lo_d, hi_d, float(t_w[m]), float(t_w[k]), "located", "located",
                             str(t_before[k]), str(t_before[m]), "transitions only"))
    rows.sort(key=lambda r_: r_[0])
    bad = [f"d_lo = {r_[0]!r} >= d_hi = {r_[1]!r} (up sweep {r_[6]!r}, down sweep {r_[7]!r})"
           for r_ in rows if not r_[1] > r_[0]]
    return _intervals_dataset([r_ for r_ in rows if r_[1] > r_[0]], bad)


def _where_sweeps_differ(labels, d, located):
    """The intervals of :func:`bistable_intervals` found where the sweeps differ on the grid: one per run of
    grid points, each end the located transition (``located(direction, label, side, bound)``), a grid step or
    the range's end."""
    up, down = labels
    step = float(np.median(np.diff(d))) if len(d) > 1 else 0.0
    rows = []
    differ = up != down
    i = 0
    while i < len(d):
        if not differ[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(d) and differ[j + 1]:
            j += 1
        lab_a, lab_b = str(up[j]), str(down[i])
        lo = located("down", lab_b, -1, d[i])
        hi = located("up", lab_a, +1, d[j])
        lo_src, hi_src = "located", "located"
        if lo is None and i == 0:  # the motions still differ at the range's end: it bounds the
            lo, lo_src = (float(d[0]), math.nan), "range end"  # interval, which may go on beyond
        elif lo is None:  # the down motion ends aperiodic: not located
            lo, lo_src = (0.5 * (d[i - 1] + d[i]), step), "grid"
        if hi is None and j == len(d) - 1:
            hi, hi_src = (float(d[-1]), math.nan), "range end"
        elif hi is None:
            hi, hi_src = (0.5 * (d[j] + d[j + 1]), step), "grid"
        rows.append((lo[0], hi[0], lo[1], hi[1], lo_src, hi_src, lab_a, lab_b, "sweeps differ"))
        i = j + 1
    return rows


def _intervals_dataset(rows, bad):
    """The bistable intervals' dataset (:func:`bistable_intervals`'s Returns); ``bad``: those left out."""
    col = list(zip(*rows, strict=True)) if rows else [()] * 9
    ds = xr.Dataset(
        {
            "d_lo": ("interval", np.array(col[0], dtype=float),
                     {"units": "1", "long_name": "lower end: the down sweep loses label_down"}),
            "d_hi": ("interval", np.array(col[1], dtype=float),
                     {"units": "1", "long_name": "upper end: the up sweep loses label_up"}),
            "d_lo_width": ("interval", np.array(col[2], dtype=float),
                           {"units": "1", "long_name": "the lower end lies within d_lo +- d_lo_width/2"}),
            "d_hi_width": ("interval", np.array(col[3], dtype=float),
                           {"units": "1", "long_name": "the upper end lies within d_hi +- d_hi_width/2"}),
            "lo_source": ("interval", np.array(col[4], dtype=object).astype(str),
                          {"long_name": "located transition, grid step (aperiodic motion, not located) or range end"}),
            "hi_source": ("interval", np.array(col[5], dtype=object).astype(str),
                          {"long_name": "located transition, grid step (aperiodic motion, not located) or range end"}),
            "label_up": ("interval", np.array(col[6], dtype=object).astype(str),
                         {"long_name": "motion followed by the up sweep (d increasing)"}),
            "label_down": ("interval", np.array(col[7], dtype=object).astype(str),
                           {"long_name": "motion followed by the down sweep (d decreasing)"}),
            "found_by": ("interval", np.array(col[8], dtype=object).astype(str),
                         {"long_name": "sweeps differ on the grid, or transitions only"}),
        },
        coords={"interval": np.arange(len(rows))},
    )
    if bad:
        ds.attrs["inconsistent_intervals"] = ("intervals of non-positive width, left out (the located transitions "
                                              "are inconsistent): " + "; ".join(bad))
    return ds
