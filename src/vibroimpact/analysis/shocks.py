"""The critical shock of a motion: the smallest knock that drops the harvester from its motion to another
attractor.

A knock is an instantaneous jump of the ball's state relative to the cylinder at one time in flight: of its
velocity ``Zdot`` (``kind="velocity"``) or of its position ``Z`` (``kind="position"``, within the cylinder,
``|Z| < d/2``).  After the knock the run goes on exactly (:func:`~vibroimpact.simulate` from the knocked
in-flight state, with the forcing's own phase) until its motion repeats; it *returns* when it settles on
the cycle it was knocked off (same motion, every event of the cycle within ``match_tol``), it *leaves*
otherwise (another periodic motion, or no period within ``max_periods``).

Along each direction (``+`` and ``-``) at one knock time the boundary of the basin is bracketed by a
geometric scan of sizes from below, then located by bisection: the boundary found is the first one the
scan crosses (up to the scan's resolution, a factor ``scan_ratio``), to a relative tolerance ``rtol``.
The knock times are spread over one period of the cycle (the ball in flight), and the minimum over them is
refined by a golden-section search around the best one.  This is the minimal critical shock of
Klinshov et al. (2015) and Halekotte & Feudel (2020), for one component of the state at a time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..dynamics import kernels as K
from ..dynamics.device import PAPER, Device
from ..dynamics.params import Params
from ..dynamics.runs import simulate, trajectory
from .energy import voltage_gain
from .motions import APERIODIC, cycle_class

__all__ = ["Shock", "critical_shock", "KINDS", "SCAN_FLOOR", "FINE_SPAN", "LOCAL_MINIMA", "AFTER_IMPACT"]

#: what a knock changes: the velocity ``Zdot`` or the position ``Z``
KINDS = ("velocity", "position")
#: the scan's smallest size, as a share of the largest admissible one
SCAN_FLOOR = 1e-4
#: the scan doubles its size up to the ceiling over this factor, then steps by ``scan_ratio``
FINE_SPAN = 4.0
#: the grid's local minima of the knock size (smallest first) around which the knock time is refined
LOCAL_MINIMA = 3
#: how long after an impact (a share of the cycle) the knock just after it comes
AFTER_IMPACT = 1e-4
#: the golden ratio's conjugate, for the phase refinement
_GOLD = (math.sqrt(5.0) - 1.0) / 2.0


# a record a call returns: its fields are Attributes, not Parameters (no one constructs it)
@dataclass(frozen=True)
class Shock:  # numpydoc ignore=PR01
    """The critical shock of a motion (:func:`critical_shock`).

    Attributes
    ----------
    kind : str
        ``"velocity"`` or ``"position"``.
    size : float
        The smallest knock found that leaves the basin (non-dimensional; ``inf`` when none within the
        admissible range does), the upper end of its bisection bracket.
    size_si : float
        The same in m/s (velocity) or m (position).
    tolerance : float
        Width of the bisection bracket: the boundary lies within ``[size - tolerance, size]`` along the
        direction at that time.
    phase : float
        Forcing phase ``pi t + phi`` (mod 2 pi) at the knock.
    delay : float
        Time of the knock after the cycle's first event (non-dimensional; a forcing period is 2).
    direction : int
        +1 or -1: the sign of the jump of ``Zdot`` or ``Z`` (``Z`` points to the bottom wall).
    state : tuple of float
        ``(Z, Zdot)`` just before the knock.
    motion : str
        The motion knocked (its label).
    U_T : float
        Its output (V).
    reached : str
        The motion the knock sends the harvester to (its label; ``"no period found"`` when no period
        appeared within the run's cap).
    reached_U_T : float
        That motion's output (V; NaN without a period).
    simulations : int
        Runs used.
    reason : str
        Why ``size`` is ``inf`` (empty otherwise).

    Examples
    --------
    A knock too small to leave the 3:1 motion's basin at d = 0.13975, beta = pi/6:

    >>> import vibroimpact as vi
    >>> sh = vi.critical_shock(vi.Params(d=0.13975, gbar=0.12201), phi=1.645, v0=0.05067, max_size=1e-5,
    ...                        phases=2, refine=0)
    >>> sh.size, sh.direction, sh.reason
    (inf, 0, 'no velocity knock within the admissible range leaves the basin')
    """

    kind: str
    size: float
    size_si: float
    tolerance: float
    phase: float
    delay: float
    direction: int
    state: tuple
    motion: str
    U_T: float
    reached: str
    reached_U_T: float
    simulations: int
    reason: str = ""


def _fail(name, value, allowed):
    raise ValueError(f"{name} = {value!r}; allowed: {allowed}")


def _check(params, kind, phases, rtol, max_size, refine, scan_ratio):
    if not isinstance(params, Params):
        _fail("params", params, "a vibroimpact.Params")
    if kind not in KINDS:
        _fail("kind", kind, f"one of {KINDS}")
    if isinstance(phases, bool) or not isinstance(phases, (int, np.integer)) or phases < 2:
        _fail("phases", phases, "an integer >= 2")
    if not (isinstance(rtol, (int, float)) and 0 < rtol < 0.5):
        _fail("rtol", rtol, "0 < rtol < 0.5")
    if max_size is not None and not (isinstance(max_size, (int, float)) and 0 < max_size < math.inf):
        _fail("max_size", max_size, "None or a finite size > 0")
    if isinstance(refine, bool) or not isinstance(refine, (int, np.integer)) or refine < 0:
        _fail("refine", refine, "an integer >= 0 (golden-section steps)")
    if not (isinstance(scan_ratio, (int, float)) and 1 < scan_ratio <= 10):
        _fail("scan_ratio", scan_ratio, "1 < scan_ratio <= 10")


class _Runs:
    """The knocked runs of one motion: whether each returns to the motion's cycle, counted."""

    def __init__(self, params, phi, max_periods, match_tol):
        self.params, self.phi, self.max_periods, self.match_tol = params, phi, max_periods, match_tol
        self.count = 0
        self.cycle = None

    def run(self, t0, z, v):
        """A run from ``(z, v)`` in flight at ``t0`` until its motion repeats: its cycle (or None)."""
        self.count += 1
        ds = simulate(self.params, phi=self.phi, v0=v, Z0=z, t0=t0, stop_when_periodic=True,
                      t_end=t0 + 2.0 * self.max_periods, max_events=200_000)
        return _cycle(ds)

    def returns(self, t0, z, v):
        """Whether the run from ``(z, v)`` at ``t0`` settles on the reference cycle, and its cycle."""
        cyc = self.run(t0, z, v)
        return cyc is not None and _same(cyc, self.cycle, self.match_tol), cyc


def _cycle(ds):
    """The last period of a run that stopped on a period (a dict of its events and motion), or None."""
    lag = int(ds.attrs["period_events"])
    if ds.attrs["status"] != "periodic" or lag == 0:
        return None
    n = ds.sizes["impact"]
    ev = {v: ds[v].values[n - lag:n] for v in ("t", "wall", "v_minus", "phase", "kind")}
    span = float(ds["t"].values[n - 1] - ds["t"].values[n - 1 - lag])
    return ev | {"span": span, "motion": cycle_class(ev["wall"], ev["kind"], span), "run": ds,
                 "start": float(ds["t"].values[n - 1 - lag])}


def _same(a, b, tol):
    """Whether cycles ``a`` and ``b`` are one: the same motion, each event of ``a`` within ``tol`` of one of ``b``
    (wall, kind, pre-impact velocity and phase)."""
    if a["motion"] != b["motion"] or a["t"].size != b["t"].size:
        return False
    for w, k, vm, ph in zip(a["wall"], a["kind"], a["v_minus"], a["phase"], strict=True):
        dph = np.abs((b["phase"] - ph + math.pi) % (2 * math.pi) - math.pi)
        dv = np.where(np.isnan(b["v_minus"]) & np.isnan(vm), 0.0, np.abs(b["v_minus"] - vm))
        if not np.any((b["wall"] == w) & (b["kind"] == k) & (dph <= tol) & (dv <= tol)):
            return False
    return True


def _output(cyc, params, device):
    """``U_T`` (V) of a cycle: the membranes' gains summed over one cycle, per unit time (as the design maps)."""
    if cyc is None:
        return math.nan
    hit = K.hits(cyc["kind"])
    F = params.physical.get("F", device.F)
    gain = voltage_gain(device.speed_si(cyc["v_minus"][hit], F), device.membrane)
    return float(np.sum(gain) / (2.0 * cyc["motion"].period))


def _knocked(z, v, kind, sign, size):
    return (z + sign * size, v) if kind == "position" else (z, v + sign * size)


def _limit(z, kind, sign, half, max_size):
    """The largest admissible knock along ``sign`` from ``z``: inside the cylinder for a position knock."""
    if kind == "velocity":
        return max_size
    room = (half - sign * z) * (1.0 - 1e-9)
    return room if max_size is None else min(room, max_size)


def _scan_sizes(limit, top, ratio):
    """The sizes scanned up to ``top``: doubling from :data:`SCAN_FLOOR` of ``limit`` up to ``top /``
    :data:`FINE_SPAN` (a stable motion's basin holds a ball around its cycle), then by ``ratio`` up to ``top``."""
    fine = top / FINE_SPAN
    coarse = limit * 2.0 ** -np.arange(int(math.log2(1 / SCAN_FLOOR)) + 1)[::-1]
    steps = fine * ratio ** np.arange(int(math.log(FINE_SPAN, ratio)) + 1)
    return [*coarse[coarse < fine], *steps[steps < top], top]


def _boundary(runs, t, z, v, kind, sign, limit, ceiling, rtol, ratio):
    """The first basin boundary along ``sign`` at time ``t`` below ``min(limit, ceiling)``: ``(lo, hi, cycle at
    hi)`` with ``hi - lo <= rtol * hi``, or None where every size scanned returns."""
    top = min(limit, ceiling)
    sizes = _scan_sizes(limit, top, ratio)
    lo, hi, cyc = 0.0, None, None
    for s in sizes:
        back, c = runs.returns(t, *_knocked(z, v, kind, sign, s))
        if not back:
            hi, cyc = s, c
            break
        lo = s
    if hi is None:
        return None
    while hi - lo > rtol * hi and hi - lo > rtol * SCAN_FLOOR * limit:
        mid = 0.5 * (lo + hi)
        back, c = runs.returns(t, *_knocked(z, v, kind, sign, mid))
        if back:
            lo = mid
        else:
            hi, cyc = mid, c
    return lo, hi, cyc


def _at(runs, ref, t, kind, limit, ceiling, rtol, ratio):
    """The smallest boundary over the directions at time ``t``: ``(hi, lo, sign, cycle, (Z, Zdot))`` or None (no
    boundary below the ceiling).  A ball resting on a wall is knocked away from it only (the membrane holds a
    knock into it)."""
    tr = trajectory(ref, [t])
    z, v = float(tr["Z"][0]), float(tr["Zdot"][0])
    half = 0.5 * runs.params.d
    signs = (-1,) if z >= half and v == 0.0 else (1,) if z <= -half and v == 0.0 else (1, -1)
    best = None
    for sign in signs:
        lim = _limit(z, kind, sign, half, limit)
        top = ceiling if best is None else min(ceiling, best[0])
        found = _boundary(runs, t, z, v, kind, sign, lim, top, rtol, ratio)
        if found is not None and (best is None or found[1] < best[0]):
            best = (found[1], found[0], sign, found[2], (z, v))
    return best


def _refine(runs, ref, t_lo, t_hi, best, kind, limit, rtol, ratio, steps):
    """Golden-section search of the knock time in ``[t_lo, t_hi]`` around ``best`` (``(hi, lo, sign, cycle, state,
    t)``); the best knock seen."""
    def f(t):
        nonlocal best
        res = _at(runs, ref, t, kind, limit, 2.0 * best[0], rtol, ratio)
        if res is None:
            return math.inf
        if res[0] < best[0]:
            best = (*res, t)
        return res[0]

    a, b = t_lo, t_hi
    c, d = b - _GOLD * (b - a), a + _GOLD * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(steps):
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - _GOLD * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + _GOLD * (b - a)
            fd = f(d)
    return best


def critical_shock(params: Params, phi: float, v0: float, *, kind: str = "velocity", phases: int = 24,
                   rtol: float = 1e-3, max_size: float | None = None, refine: int = 8, scan_ratio: float = 1.1,
                   max_periods: float = 200,
                   match_tol: float = 1e-6, device: Device | None = None) -> Shock:
    """The smallest knock that drops a periodic motion to another attractor.

    The motion is the one the run from the bottom impact ``(phi, v0)`` settles on.  At ``phases`` times spread
    over one period of its cycle and just after each impact, and along both directions, the size of the
    knock is scanned geometrically from below (doubling from :data:`SCAN_FLOOR` of the largest admissible
    size, by ``scan_ratio`` over the last factor :data:`FINE_SPAN` below the ceiling: the largest admissible
    size, or twice the best knock so far) until a knocked run leaves, then bisected between the last size that returns
    and the first that leaves; the boundary found is the first one the scan crosses, up to the scan's
    resolution: a band of leaving sizes narrower than the ratio can be stepped over (basins of impacting
    motions interleave).  A ball resting on a wall is knocked away from it only.  The minimum over the times
    is then refined by ``refine`` golden-section steps between the neighbours of each of the
    :data:`LOCAL_MINIMA` smallest local minima of the grid.

    Parameters
    ----------
    params : Params
        The harvester's parameters.
    phi, v0 : float
        A bottom impact (forcing phase at t = 0, pre-impact velocity ``>= 0``) whose run settles on the motion,
        e.g. a point of a Newton orbit (:func:`vibroimpact.find_orbit`) or of a simulated attractor.
    kind : {"velocity", "position"}
        A jump of ``Zdot`` or of ``Z``.
    phases : int
        Knock times spread evenly over one period of the cycle (``>= 2``); the times just after its impacts
        are added.
    rtol : float
        Relative width of each bisection bracket (``0 < rtol < 0.5``).
    max_size : float, optional
        Largest knock looked at (non-dimensional).  By default the whole cylinder for a position knock
        (``|Z| < d/2``) and ``2 * v_max`` for a velocity knock, ``v_max`` the largest impact speed of the cycle.
    refine : int
        Golden-section steps of the phase refinement (0: the grid's best).
    scan_ratio : float
        Ratio of successive sizes of the scan near the ceiling (``1 < scan_ratio <= 10``).
    max_periods : float
        Forcing periods a knocked run may take to repeat; one that does not has left the basin.
    match_tol : float
        How close each event of a knocked run's cycle must come to the motion's (phase, ``|Zdot-|``) to be the
        same cycle.
    device : Device, optional
        The membranes and scales for ``U_T`` and the SI sizes (the paper's by default; the SI scales are the
        parameters' own when built with :meth:`Params.from_physical`).

    Returns
    -------
    Shock
        The size (non-dimensional and SI), the phase and direction of the knock, the motion reached and both
        outputs, the runs used; ``size = inf`` with a reason when no admissible knock leaves the basin.

    Raises
    ------
    ValueError
        A bad argument (naming it, its value and what is allowed), or a start whose run finds no period.

    Examples
    --------
    The 3:1 motion between G1 and G2 at the paper's incline pi/6 (d = 0.13975): a knock of its velocity
    drops it to the coexisting 2:1 motion.

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.13975 / 0.6225, beta=math.pi / 6)
    >>> sh = vi.critical_shock(p, phi=1.645, v0=0.05067, phases=4, refine=0, rtol=1e-2)
    >>> sh.motion, sh.reached, sh.direction in (1, -1)
    ('3:1 period-2', '2:1 period-2', True)
    >>> 0 < sh.size - sh.tolerance < sh.size < 0.1, round(sh.size_si / sh.size, 4)    # m/s per unit of Zdot
    (True, 8.0321)
    >>> round(sh.U_T / 1e3, 1), round(sh.reached_U_T / 1e3, 1)    # kV
    (33.7, 33.8)
    """
    _check(params, kind, phases, rtol, max_size, refine, scan_ratio)
    device = PAPER if device is None else device
    ref = simulate(params, phi=phi, v0=v0, stop_when_periodic=True, t_end=2.0 * max_periods, max_events=200_000)
    cycle = _cycle(ref)
    if cycle is None:
        _fail("(phi, v0)", (phi, v0), f"a start whose run repeats within max_periods = {max_periods!r}")
    runs = _Runs(params, phi, max_periods, match_tol)
    runs.cycle = cycle
    if max_size is None and kind == "velocity":
        max_size = 2.0 * float(np.nanmax(np.abs(cycle["v_minus"]), initial=0.0)) or 1.0
    times = _knock_times(cycle, phases)
    grid, best = [], None  # the knock size at each time of the grid (inf above the ceiling), the best knock
    for t in times:
        res = _at(runs, ref, t, kind, max_size, math.inf if best is None else 2.0 * best[0], rtol, scan_ratio)
        grid.append(math.inf if res is None else res[0])
        if res is not None and (best is None or res[0] < best[0]):
            best = (*res, t)
    edges = np.concatenate([[cycle["start"]], times, [cycle["start"] + cycle["span"]]])
    for j in _local_minima(grid, LOCAL_MINIMA) if best is not None and refine else ():
        best = _refine(runs, ref, edges[j], edges[j + 2], best, kind, max_size, rtol, scan_ratio, refine)
    return _shock(best, kind, params, phi, cycle, runs, device)


def _knock_times(cycle, phases):
    """The knock times of the grid over one cycle: ``phases`` evenly spread, and just after each impact (the
    first ``phases`` of a chattering cycle), where the ball leaves a wall."""
    t0, span = cycle["start"], cycle["span"]
    even = t0 + (np.arange(phases) + 0.5) * span / phases
    hits = np.unique(cycle["t"][K.hits(cycle["kind"])])[:phases]
    after = t0 + (hits - t0 + AFTER_IMPACT * span) % span
    return np.unique(np.concatenate([even, after]))


def _local_minima(values, n):
    """Indices of the ``n`` smallest finite local minima of ``values`` read around a circle (a cycle)."""
    v = np.asarray(values)
    m = np.isfinite(v) & (v <= np.roll(v, 1)) & (v <= np.roll(v, -1))
    idx = np.flatnonzero(m)
    return idx[np.argsort(v[idx], kind="stable")][:n].tolist()


def _shock(best, kind, params, phi, cycle, runs, device):
    scales = params.scales if params.scales is not None else device.scales(params.physical.get("F"))
    unit = scales.velocity if kind == "velocity" else scales.length
    common = dict(kind=kind, motion=cycle["motion"].label, U_T=_output(cycle, params, device),
                  simulations=runs.count + 1)
    if best is None:
        return Shock(size=math.inf, size_si=math.inf, tolerance=math.nan, phase=math.nan, delay=math.nan,
                     direction=0, state=(math.nan, math.nan), reached="", reached_U_T=math.nan,
                     reason=f"no {kind} knock within the admissible range leaves the basin", **common)
    hi, lo, sign, cyc, state, t = best
    return Shock(size=float(hi), size_si=float(hi * unit), tolerance=float(hi - lo), phase=float((math.pi * t + phi) % (2 * math.pi)),
                 delay=float(t - cycle["start"]), direction=sign, state=state,
                 reached=APERIODIC if cyc is None else cyc["motion"].label, reached_U_T=_output(cyc, params, device),
                 **common)
