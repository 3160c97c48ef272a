"""Where a motion is named: the paper's names of periodic motions (``"2:1 period-2"``), the names of motions
without a period within the cap, what a run settled on, and the kind of a change from one motion to another.

A motion is a :class:`Motion` record (its impacts per cycle on each wall, its period, whether it sticks, or
which motion without a period it is); its name is :attr:`Motion.label`, written from the record and never
read back.  Motions are followed along a parameter in :mod:`~vibroimpact.analysis.sweeps` and drawn with one
colour and one name each by :mod:`vibroimpact.outputs.plots`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr
from numba import njit

from ..dynamics import kernels as K
from .motion_names import (  # noqa: F401  (the names, defined on numpy alone, are this module's too)
    APERIODIC,
    CHAOTIC,
    NO_PERIOD_LABELS,
    ONE_ONE,
    PERIODIC,
    QUASI_PERIODIC,
    THREE_ONE,
    TWO_ONE,
    UNSETTLED,
    Motion,
    is_motion_label,
    motion_without_period,
    no_period,
    no_period_label,
    orbit_motion,
    periodic_motion,
    periodic_names_in,
)

__all__ = ["Motion", "PERIODIC", "APERIODIC", "CHAOTIC", "QUASI_PERIODIC", "UNSETTLED", "NO_PERIOD_LABELS",
           "ONE_ONE", "TWO_ONE", "THREE_ONE", "is_motion_label", "periodic_motion", "periodic_names_in",
           "no_period", "no_period_label", "motion_without_period", "orbit_motion", "chatter_bounces", "cycle_class", "resolved_impacts", "transition_kind",
           "Attractor", "identify_attractor"]


def chatter_bounces(wall, kind):
    """Where the events of one cycle (repeated end to start) are the bounces of a chattering sequence
    that ends in sticking: the impacts and grazing contacts after the first of an unbroken run on the
    wall the ball then sticks to.  The model has infinitely many of them; how many the simulator
    resolves before it sums the rest (:mod:`vibroimpact.dynamics.kernels`) depends on ``v_chatter``."""
    wall, kind = np.asarray(wall), np.asarray(kind)
    n = kind.size
    is_hit = K.hits(kind)
    out = np.zeros(n, dtype=bool)
    for s in np.flatnonzero(kind == K.STICK):
        run = []
        for j in range(1, n):  # back from the stick, around the cycle
            i = (s - j) % n
            if not (is_hit[i] and wall[i] == wall[s]):
                break
            run.append(i)
        out[run[:-1]] = True  # all but the run's first impact (the landing)
    return out


def resolved_impacts(wall, kind) -> tuple[int, int]:
    """Impacts and grazing contacts the simulator resolved on the bottom and the top wall, chattering bounces
    included."""
    is_hit = K.hits(kind)
    return int(((wall == 1) & is_hit).sum()), int(((wall == -1) & is_hit).sum())


def cycle_class(wall, kind, t_span) -> Motion:
    """The :class:`Motion` of one cycle of events lasting ``t_span``.

    Its period is ``t_span`` in forcing periods (2 time units each); a chattering sequence that ends in sticking
    counts as one impact (its landing, :func:`chatter_bounces`), so that one motion has one name whatever
    the number of bounces resolved: the ball released from the bottom that lands there again, chatters to
    rest and sticks until the forcing releases it, once every two forcing periods, is
    ``"1:0 over 2 forcing periods with sticking"``.
    """
    wall, kind = np.asarray(wall), np.asarray(kind)
    counted = K.hits(kind) & ~chatter_bounces(wall, kind)
    return Motion(period=int(round(t_span / 2.0)), bottom=int(((wall == 1) & counted).sum()),
                  top=int(((wall == -1) & counted).sum()), sticking=bool((kind == K.STICK).any()))


def transition_kind(before: Motion, after: Motion) -> str:
    """Name the change of motion from ``before`` to ``after`` (in the sweep's direction)."""
    if not before.periodic and not after.periodic:
        return "none"
    if not after.periodic:
        return f"period lost ({after.label})"
    if not before.periodic:
        return "period found"
    a, b = before.per_period, after.per_period
    if a is None or b is None or before.sticking or after.sticking:
        return "other"
    if a == b:
        if after.period == 2 * before.period:
            return "period doubling"
        if before.period == 2 * after.period:
            return "period halving"
        return "period change"
    if before.period == after.period:
        if b[0] > a[0] and b[1] == a[1]:
            return "grazing: extra bottom impact"
        if b[0] < a[0] and b[1] == a[1]:
            return "bottom impact lost"
        if b[1] > a[1] and b[0] == a[0]:
            return "grazing: extra top impact"
        if b[1] < a[1] and b[0] == a[0]:
            return "top impact lost"
    return "other"


# ---------------------------------------------------------------------------------------------
# What a run settled on
# ---------------------------------------------------------------------------------------------


@njit(cache=True)
def _detect(events, tol, pmax):
    """The first event where the period test (:func:`~vibroimpact.dynamics.kernels.period_update`) finds a
    period of at most ``pmax`` events in ``events`` (:data:`~vibroimpact.dynamics.kernels.Window`), and the
    period; ``(-1, 0)`` if none."""
    counts = np.zeros(pmax + 1, dtype=np.int64)
    for i in range(events.t.shape[0]):
        if K.no_lag_matches(i, events.v_minus, counts, tol):  # the update's work where no lag can match
            continue
        lag = K.period_update(i, events, counts, tol)
        if lag > 0:
            return i, lag
    return -1, 0


# a record a call returns: its fields are Attributes, not Parameters (no one constructs it)
@dataclass(frozen=True)
class Attractor:  # numpydoc ignore=PR01
    """What a run settled on (:func:`identify_attractor`).

    Attributes
    ----------
    periodic : bool
        False when no period up to ``max_period_events`` repeated within the run.
    period : int
        Period in forcing periods (period 2 in t each).
    events : int
        Events per period.
    n_bottom, n_top : int
        Impacts (grazing contacts included) on one period, per wall.
    sticking : bool
        Whether the cycle sticks to a wall.
    label : str
        The paper's name, e.g. ``"2:1 period-2"`` or ``"1:1 period-4"``.
    t_settled : float
        Time from which the motion repeats.
    t_identified : float
        Time at which the period was identified.
    cycle : xarray.Dataset or None
        The events of one period.
    motion : Motion
        The motion the label names (its kind is :data:`APERIODIC` when not periodic).

    Examples
    --------
    The 2:1 motion of Figure 7 (a): two bottom impacts and one top impact per forcing period (2 time units):

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
    >>> a = vi.identify_attractor(vi.simulate(p, phi=1.015, v0=0.1924, n_impacts=200))
    >>> a.periodic, a.label, a.period, a.events, a.n_bottom, a.n_top, a.sticking
    (True, '2:1 period-2', 1, 3, 2, 1, False)
    >>> sorted(a.cycle.wall.values.tolist()), a.t_settled < a.t_identified     # walls: 1 bottom, -1 top
    ([-1, 1, 1], True)
    """

    periodic: bool
    period: int = 0
    events: int = 0
    n_bottom: int = 0
    n_top: int = 0
    sticking: bool = False
    label: str = "not periodic"
    t_settled: float = math.nan
    t_identified: float = math.nan
    cycle: xr.Dataset | None = None
    motion: Motion = Motion(kind=APERIODIC)


def identify_attractor(ds: xr.Dataset, tol: float = 1e-9, max_period_events: int = 64) -> Attractor:
    """Decide from a run after how long the motion is periodic, and which motion it is.

    A period is declared only after two full cycles repeat to ``tol``, so a slowly converging orbit with an
    eigenvalue near -1 is not mistaken for a period-doubled one.

    Parameters
    ----------
    ds : xarray.Dataset
        One run of :func:`~vibroimpact.simulate`.
    tol : float
        Periodicity tolerance on impact velocities and phases.
    max_period_events : int
        Longest period looked for, in events.

    Returns
    -------
    Attractor
        The motion: periodic or not, its period in forcing periods, impacts per period on each wall, its
        label (e.g. ``"2:1 period-2"``), when it settled and the events of one cycle.

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
    >>> vi.identify_attractor(vi.simulate(p, phi=1.015, v0=0.1924, n_impacts=200)).label
    '2:1 period-2'
    """
    if "run" in ds.dims:
        raise ValueError("identify_attractor takes one run; select one with ds.isel(run=k)")
    i, p = _detect(K.Window(*(ds[v].values for v in ("t", "wall", "v_minus", "phase", "kind"))), float(tol),
                   int(max_period_events))
    if p == 0:
        return Attractor(periodic=False)
    # settled from the first event of the matched stretch; the cycle is the last full period seen
    first = max(i - 3 * p + 1, 0)
    cyc = ds.isel(impact=slice(i - p + 1, i + 1))
    motion = cycle_class(cyc["wall"].values, cyc["kind"].values, float(ds["t"][i]) - float(ds["t"][i - p]))
    nb, nt = resolved_impacts(cyc["wall"].values, cyc["kind"].values)
    return Attractor(periodic=True, period=motion.period, events=p, n_bottom=nb, n_top=nt, sticking=motion.sticking,
                     label=motion.label, t_settled=float(ds["t"][first]), t_identified=float(ds["t"][i]), cycle=cyc,
                     motion=motion)
