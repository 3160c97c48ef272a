"""The names of the motions: what a periodic motion is called by its impacts per forcing period, and the labels of
the motions without a period (:mod:`vibroimpact.analysis.motions`, which classifies runs, holds them all).

A module of its own, on numpy alone: what reads only the names (the workflow's check of its configuration, the
figure check's rules) loads neither numba nor xarray.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

__all__ = ["Motion", "PERIODIC", "APERIODIC", "CHAOTIC", "QUASI_PERIODIC", "UNSETTLED", "NO_PERIOD_LABELS",
           "ONE_ONE", "TWO_ONE", "THREE_ONE", "is_motion_label", "periodic_motion", "periodic_names_in",
           "no_period", "no_period_label", "motion_without_period", "orbit_motion"]

#: The kind of a motion with a period (the others are :data:`NO_PERIOD_LABELS`).
PERIODIC = "periodic"
#: Label of a run whose motion did not repeat within the allowed transient: chaotic, quasi-periodic,
#: of a period longer than ``pmax`` events, or converging too slowly (near a period doubling or fold).
APERIODIC = "no period found"
#: What such a motion is, by the largest Lyapunov exponent lambda_1 of its continuation over
#: ``LONG_IMPACTS`` impacts (:func:`split_no_period`); defined here once, for the sweeps, the maps, the
#: tables and the figures.  Chaotic: the interval of lambda_1 lies above 0.
CHAOTIC = "chaotic"
#: The interval of lambda_1 contains 0: neighbouring motions neither separate nor approach at a rate the
#: continuation can tell from 0 (a torus, or a period beyond the cap's reach, or the edge of chaos).
QUASI_PERIODIC = "quasi-periodic"
#: Neither: the interval lies below 0 (the motion converges, more slowly than the cap allows), or the
#: continuation finds a period, sticks (a motion that sticks again and again is eventually periodic: each
#: release starts from the same state) or comes to rest: a transient longer than the cap.
UNSETTLED = "unsettled"
#: every label of a motion without a period within the cap ("no period found" where it was not split)
NO_PERIOD_LABELS = (APERIODIC, CHAOTIC, QUASI_PERIODIC, UNSETTLED)


def no_period(labels):
    """Where a label (or array of labels) is one of a motion with no period within the cap."""
    return np.isin(np.asarray(labels).astype(str), NO_PERIOD_LABELS)


def no_period_label(long_status: str, low: float, high: float, sticks: int = 0) -> str:
    """The label of a motion with no period from its continuation (:func:`vibroimpact.long_run`): its status
    and the confidence interval ``[low, high]`` of its largest Lyapunov exponent.  Without a
    continuation (``"not run"``, ``"no restart"``) it stays :data:`APERIODIC`."""
    if long_status in ("settles", "stuck"):
        return UNSETTLED
    if long_status != "aperiodic" or not (np.isfinite(low) and np.isfinite(high)):
        return APERIODIC
    if sticks:
        return UNSETTLED
    if low > 0:
        return CHAOTIC
    if high < 0:
        return UNSETTLED
    return QUASI_PERIODIC




# a record the classification returns: its fields are Attributes, not Parameters
@dataclass(frozen=True)
class Motion:  # numpydoc ignore=PR01
    """One motion, by the parts of its name.

    Attributes
    ----------
    kind : str
        :data:`PERIODIC`, or the motion without a period it is (one of :data:`NO_PERIOD_LABELS`).
    period : int
        Forcing periods of one cycle (periodic motions; 0 otherwise).
    bottom, top : int
        Impacts and grazing contacts of one cycle on the bottom and the top wall, a chattering sequence that
        ends in sticking counted once (its landing, :func:`chatter_bounces`).
    sticking : bool
        Whether the cycle sticks to a wall.

    Examples
    --------
    >>> from vibroimpact.analysis.motions import Motion, CHAOTIC
    >>> Motion(period=1, bottom=2, top=1).label, Motion(period=2, bottom=3, top=2).label
    ('2:1 period-2', '3:2 over 2 forcing periods')
    >>> Motion(period=2, bottom=1, top=0, sticking=True).label, Motion(kind=CHAOTIC).label
    ('1:0 over 2 forcing periods with sticking', 'chaotic')
    >>> Motion(period=2, bottom=2, top=2).short_label
    '1:1 T=4'
    """

    kind: str = PERIODIC
    period: int = 0
    bottom: int = 0
    top: int = 0
    sticking: bool = False

    @property
    def periodic(self) -> bool:
        """Whether the motion has a period (within the cap)."""
        return self.kind == PERIODIC

    @property
    def per_period(self) -> tuple[int, int] | None:
        """``(n, m)`` impacts per forcing period on the bottom and top walls, where both are whole numbers."""
        k = self.period
        if not self.periodic or self.bottom % k or self.top % k:
            return None
        return self.bottom // k, self.top // k

    @property
    def label(self) -> str:
        """The paper's name, e.g. ``"2:1 period-2"``, ``"n:m over k forcing periods"`` where the counts are not
        multiples of the period, with ``" with sticking"``; or the name of a motion without a period."""
        return self._name(f"period-{2 * self.period}")

    @property
    def short_label(self) -> str:
        """The label with its period written ``T=k`` (k in t, 2 per forcing period), e.g. ``"2:1 T=2"``: the
        name written over a narrow run of points."""
        return self._name(f"T={2 * self.period}")

    def _name(self, period: str) -> str:
        if not self.periodic:
            return self.kind
        nm = self.per_period
        label = (f"{nm[0]}:{nm[1]} {period}" if nm is not None
                 else f"{self.bottom}:{self.top} over {self.period} forcing periods")
        return label + " with sticking" if self.sticking else label


def orbit_motion(word: str, k: int = 1) -> Motion:
    """The :class:`Motion` of the periodic orbit ``word`` over ``k`` forcing periods (:mod:`vibroimpact.analysis.orbits`:
    ``B`` a bottom, ``T`` a top impact).

    >>> orbit_motion("BBT").label, orbit_motion("BT", k=2).label
    ('2:1 period-2', '1:1 over 2 forcing periods')
    """
    return Motion(period=int(k), bottom=word.count("B"), top=word.count("T"))


def periodic_motion(n: int, m: int, period: int = 1) -> Motion:
    """The :class:`Motion` with ``n`` bottom and ``m`` top impacts per forcing period, repeating over ``period``
    forcing periods.

    >>> periodic_motion(2, 1).label, periodic_motion(1, 1, period=2).label
    ('2:1 period-2', '1:1 period-4')
    """
    return Motion(period=int(period), bottom=int(n) * int(period), top=int(m) * int(period))


#: the paper's motions of one forcing period: one bottom and one top impact (1:1), two bottom impacts and one top
#: (2:1), three and one (3:1); their names are their labels (``ONE_ONE.label == "1:1 period-2"``)
ONE_ONE, TWO_ONE, THREE_ONE = periodic_motion(1, 1), periodic_motion(2, 1), periodic_motion(3, 1)

#: how a periodic motion's label reads (:attr:`Motion.label`, :attr:`Motion.short_label`)
_PERIODIC_LABEL = re.compile(r"\d+:\d+ (?:period-\d+|T=\d+|over \d+ forcing periods)(?: with sticking)?")


def is_motion_label(text: str) -> bool:
    """Whether ``text`` is a motion's name: one of :data:`NO_PERIOD_LABELS`, or a periodic motion's label or short
    label as :class:`Motion` writes them.

    >>> is_motion_label("2:1 period-2"), is_motion_label("3:2 over 2 forcing periods with sticking")
    (True, True)
    >>> is_motion_label(CHAOTIC), is_motion_label("2:1"), is_motion_label("a chaotic run")
    (True, False, False)
    """
    return text in NO_PERIOD_LABELS or _PERIODIC_LABEL.fullmatch(text) is not None


def periodic_names_in(text: str) -> list[str]:
    """The periodic motions' labels written inside ``text`` (prose that names a motion)."""
    return [m.group(0) for m in _PERIODIC_LABEL.finditer(text)]


def motion_without_period(label: str) -> Motion:
    """The :class:`Motion` named by one of :data:`NO_PERIOD_LABELS`."""
    if label not in NO_PERIOD_LABELS:
        raise ValueError(f"label = {label!r}; allowed: one of {NO_PERIOD_LABELS}")
    return Motion(kind=label)
