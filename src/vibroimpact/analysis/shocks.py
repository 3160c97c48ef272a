"""The critical shock of a motion: the smallest knock that drops the harvester from its motion to another
attractor.

A knock is an instantaneous jump of the ball's state relative to the cylinder at one time in flight: of its
velocity ``Zdot`` (``kind="velocity"``) or of its position ``Z`` (``kind="position"``, within the cylinder,
``|Z| < d/2``).  After the knock the run goes on exactly (:func:`~vibroimpact.simulate` from the knocked
in-flight state, with the forcing's own phase) until its motion repeats; it *returns* when it settles on
the cycle it was knocked off (same motion, every event of the cycle within ``match_tol``), it *leaves*
otherwise (another periodic motion, or no period within ``max_periods``).

The knocks are rays: a time over one period of the cycle and a direction (``+`` or ``-``).  All rays are
knocked together, one batch of runs per size (one kernel call, parallel unless numba has one thread), with
sizes growing geometrically from below and each ray at its own offset within each step of the scan
(neighbouring times together sample the sizes finely: the basins of impacting motions interleave in bands
narrower than a step), until some leave; the boundaries of those that leave are bisected to a relative
tolerance ``rtol``; the sizes over the factor :data:`FINE_SPAN` below the best are then stepped by
``scan_ratio`` for every ray, and the knock time is refined by golden-section searches around the smallest
local minima.  Whether a knocked run returns is decided for the whole batch at once (a compiled test of its
cycle's events, :func:`_same`'s to the last bit).  This is the minimal critical shock of Klinshov et al.
(2015) and Halekotte & Feudel (2020), for one component of the state at a time:
a search along rays with a bisected boundary, not a random one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..dynamics import kernels as K
from ..dynamics.device import PAPER, Device
from ..dynamics.params import Params
from ..dynamics.runs import simulate, trajectory
from .windows import empty_windows, window_limits
from .energy import voltage_gain
from .motions import APERIODIC, cycle_class
from .starts import KNOCK_KINDS

__all__ = ["Shock", "critical_shock", "KINDS", "SCAN_FLOOR", "SCAN_RATIO", "FINE_SPAN", "LOCAL_MINIMA", "AFTER_IMPACT"]

#: what a knock changes: the velocity ``Zdot`` or the position ``Z`` (defined beside the start states, which the
#: workflow's configuration check reads without loading this module)
KINDS = KNOCK_KINDS
#: the scan's smallest size, as a share of the largest admissible one
SCAN_FLOOR = 1e-4
#: the scan doubles its size up to the ceiling over this factor, then steps by ``scan_ratio``
FINE_SPAN = 4.0
#: the grid's local minima of the knock size (smallest first) around which the knock time is refined
LOCAL_MINIMA = 3
#: how long after an impact (a share of the cycle) the knock just after it comes
AFTER_IMPACT = 1e-4
#: the knocked runs' period test: tolerance, longest period (events) and cap on events (as :func:`vibroimpact.simulate`)
PERIOD_TOL, PMAX, MAX_EVENTS = 1e-9, 64, 200_000
#: the default ratio of successive sizes of the scan's fine steps
SCAN_RATIO = 1.1
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


class _Knocks:
    """The knocked runs of one motion, many at once (one kernel call per batch of knocks, parallel unless numba has
    one thread): whether each returns to the motion's cycle, counted."""

    def __init__(self, params, phi, max_periods, match_tol, cycle):
        self.params, self.phi, self.match_tol, self.cycle = params, phi, match_tol, cycle
        self.limits = window_limits(max_periods, MAX_EVENTS, PERIOD_TOL, PMAX)
        self.count = 0
        # the motion's cycle as a K.Window of its events, for _events_return
        self.events = K.Window(*(np.ascontiguousarray(cycle[v]) for v in ("t", "wall", "v_minus", "phase", "kind")))
        self.motions = {}  # cycle_class by its arguments (walls, kinds, period): a few motions, met again and again

    def runs(self, t0, z, v):
        """The windows of the runs from ``(z, v)`` in flight at ``t0``: ``(win, ends)`` (:data:`K.Window`,
        :data:`K.WindowEnds`)."""
        m = t0.size
        self.count += m
        p = self.params
        win = empty_windows(m, PMAX + 1)
        ends = K.WindowEnds(status=np.zeros(m, np.int8), lag=np.zeros(m, np.int64), total=np.zeros(m, np.int64),
                            n=np.zeros(m, np.int64))
        full = lambda x: np.full(m, float(x))
        # on numba's threads; on one, in this thread without the GIL (for callers that run shocks on threads of
        # their own)
        K.flight_window_batch(K.FlightBatch(full(p.d), full(p.gbar), full(p.r), np.ascontiguousarray(t0),
                                            (math.pi * t0 + self.phi) % (2 * math.pi), np.ascontiguousarray(z),
                                            np.ascontiguousarray(v)), self.limits, win, ends)
        return win, ends

    def classify(self, wall, kind, span):
        """:func:`cycle_class` of a cycle, looked up where its walls, kinds and period were met before."""
        key = (wall.tobytes(), kind.tobytes(), int(round(span / 2.0)))
        if key not in self.motions:
            self.motions[key] = cycle_class(wall, kind, span)
        return self.motions[key]

    def leave(self, rays, idx, size):
        """Whether each ray ``idx`` knocked by ``size`` leaves the basin, and the cycles reached by those that leave,
        in order (None: no period)."""
        z, v = rays.knocked(idx, size)
        return self.outcomes(*self.runs(rays.t[idx], z, v))

    def outcomes(self, win, ends):
        """Whether each run of a batch (:meth:`runs`) has left the motion's cycle (it does not settle on a cycle
        :func:`_same` as it), and the cycles of those that left, in order (None: no period)."""
        back = np.zeros(ends.n.size, dtype=bool)
        _events_return(win, ends, self.events, self.match_tol, back)  # _same's test of the events, at once
        for k in np.flatnonzero(back):  # and its test of the motion, where the events match
            n, lag = int(ends.n[k]), int(ends.lag[k])
            back[k] = self.classify(win.wall[k, n - lag:n], win.kind[k, n - lag:n],
                                    float(win.t[k, n - 1] - win.t[k, n - 1 - lag])) == self.cycle["motion"]
        left = ~back
        return left, [_window_cycle(win, k, int(ends.n[k]), int(ends.status[k]), int(ends.lag[k]), self.classify)
                      for k in np.flatnonzero(left)]


@njit(cache=True, error_model="numpy")
def _events_return(win, ends, ref, tol, out):
    """Where each run of a batch (``win``, ``ends``: :data:`K.Window`, :data:`K.WindowEnds`) ends on a period of as many
    events as the cycle ``ref`` (a :data:`K.Window` of one period), each within ``tol`` of one of ``ref``'s events
    (:func:`_same`'s test of the events, to the last bit; its test of the motion is left to the caller): ``out``."""
    p = ref.t.shape[0]
    for k in range(out.shape[0]):
        n, lag = ends.n[k], ends.lag[k]
        out[k] = ends.status[k] == K.PERIODIC and lag == p and 0 < lag < n and _all_within(win, k, n - lag, ref, tol)


@njit(cache=True, error_model="numpy")
def _all_within(win, k, first, ref, tol):
    """Whether every event of run ``k`` from ``first`` on (one period) is within ``tol`` of one of ``ref``'s."""
    for i in range(first, first + ref.t.shape[0]):
        if not _within(win.wall[k, i], win.kind[k, i], win.v_minus[k, i], win.phase[k, i], ref, tol):
            return False
    return True


@njit(cache=True, error_model="numpy")
def _within(wall, kind, vm, ph, ref, tol):
    """Whether an event is within ``tol`` of one of ``ref``'s events (same wall and kind), as in :func:`_same`."""
    for j in range(ref.t.shape[0]):
        if ref.wall[j] == wall and ref.kind[j] == kind:
            dph = abs((ref.phase[j] - ph + math.pi) % (2 * math.pi) - math.pi)
            both_nan = math.isnan(ref.v_minus[j]) and math.isnan(vm)
            dv = 0.0 if both_nan else abs(ref.v_minus[j] - vm)
            if dph <= tol and dv <= tol:
                return True
    return False


def _window_cycle(win, k, n, status, lag, classify=cycle_class):
    """The last period of run ``k``'s window (a dict of its events and motion, by ``classify``), or None without a
    period."""
    if status != K.PERIODIC or lag == 0 or lag >= n:
        return None
    ev = dict(zip(("t", "wall", "v_minus", "phase", "kind"), (w[k, n - lag:n] for w in win), strict=True))
    span = float(win.t[k, n - 1] - win.t[k, n - 1 - lag])
    return ev | {"span": span, "motion": classify(ev["wall"], ev["kind"], span)}


def _cycle(ds):
    """The last period of a run that stopped on a period (a dict of its events and motion), or None."""
    lag = int(ds.attrs["period_events"])
    if ds.attrs["status"] != "periodic" or lag == 0:
        return None
    n = ds.sizes["impact"]
    ev = {v: ds[v].values[n - lag:n] for v in ("t", "wall", "v_minus", "phase", "kind")}
    span = float(ds["t"].values[n - 1] - ds["t"].values[n - 1 - lag])
    return ev | {"span": span, "motion": cycle_class(ev["wall"], ev["kind"], span),
                 "start": float(ds["t"].values[n - 1 - lag])}


def _same(a, b, tol):
    """Whether cycles ``a`` and ``b`` are one: the same motion, each event of ``a`` within ``tol`` of one of ``b``
    (wall, kind, pre-impact velocity and phase).  The definition, one pair at a time; :meth:`_Knocks.outcomes`
    decides a batch of runs the same way at once."""
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


@dataclass
class _Rays:
    """Knocks along a direction at a time each: time, state before the knock, sign, largest admissible size, the
    group it belongs to (a group stops its scan where one of its rays leaves) and what is known of its boundary."""

    t: np.ndarray
    z: np.ndarray
    v: np.ndarray
    sign: np.ndarray
    limit: np.ndarray
    group: np.ndarray
    kind: str

    def __post_init__(self):
        n = self.t.size
        # where in each step of a scan the ray's size falls (a share of the step): spread over the rays in
        # time order by the golden ratio, so neighbouring times together sample each step finely
        self.offset = (np.argsort(np.argsort(self.t, kind="stable")) * _GOLD) % 1.0
        self.lo, self.hi = np.zeros(n), np.full(n, math.inf)
        self.reached = [None] * n

    def knocked(self, idx, size):
        if self.kind == "position":
            return self.z[idx] + self.sign[idx] * size, self.v[idx]
        return self.z[idx], self.v[idx] + self.sign[idx] * size


def _rays(ref, times, kind, max_size, half, group):
    """The rays at ``times`` (group ``group[j]`` for time ``j``): both directions, or away from the wall a ball
    rests on (the membrane holds a knock into it); position knocks stay inside the cylinder."""
    tr = trajectory(ref, times)
    rows = []
    for j, (t, z, v) in enumerate(zip(times, tr["Z"].values, tr["Zdot"].values, strict=True)):
        signs = (-1,) if z >= half and v == 0.0 else (1,) if z <= -half and v == 0.0 else (1, -1)
        for sign in signs:
            room = (half - sign * z) * (1.0 - 1e-9)
            lim = max_size if kind == "velocity" else room if max_size is None else min(room, max_size)
            rows.append((t, z, v, sign, lim, group[j]))
    cols = np.array(rows, dtype=float).T
    return _Rays(*cols[:3], cols[3].astype(int), cols[4], cols[5].astype(int), kind)


def _knock(knocks, rays, idx, size):
    """Knock the rays ``idx`` by ``size`` (each its own); record the size and the cycle reached where they leave
    (``hi``) and where they return (``lo``).  Returns which left."""
    left, reached = knocks.leave(rays, idx, size)
    rays.lo[idx[~left]] = size[~left]
    rays.hi[idx[left]] = size[left]
    for j, c in zip(idx[left], reached, strict=True):
        rays.reached[j] = c
    return left


def _scan(knocks, rays, idx, levels):
    """Knock the rays ``idx`` up the sizes ``levels`` (ascending) in lock-step, each ray at its ``offset`` within
    each step (staggered: together the rays sample the steps finely), each group until one of its rays leaves or
    every size was tried; a ray stops at its largest admissible size."""
    active = np.asarray(idx, dtype=int)
    levels = np.asarray(levels, dtype=float)
    steps = np.append(levels[1:] / levels[:-1], 1.0)
    for s, q in zip(levels, steps, strict=True):
        if active.size == 0:
            return
        size = np.minimum(s * q ** rays.offset[active], rays.limit[active])
        left = _knock(knocks, rays, active, size)
        stopped = np.isin(rays.group[active], rays.group[active[left]]) | (size >= rays.limit[active])
        active = active[~stopped]


def _bisect(knocks, rays, idx, rtol, floor):
    """Bisect, in lock-step, the bracket ``(lo, hi]`` of each ray ``idx`` that left until
    ``hi - lo <= rtol * hi`` (or ``floor``)."""
    active = np.asarray(idx, dtype=int)
    active = active[np.isfinite(rays.hi[active])]
    while True:
        width = rays.hi[active] - rays.lo[active]
        active = active[(width > rtol * rays.hi[active]) & (width > floor)]
        if active.size == 0:
            return
        _knock(knocks, rays, active, 0.5 * (rays.lo[active] + rays.hi[active]))


def _thin_bands(knocks, rays, idx, ratio, rtol, floor):
    """Where a group's best boundary is ``b``, knock all its rays at sizes stepping by ``ratio`` over
    ``[b /`` :data:`FINE_SPAN` ``, b)``, staggered as in :func:`_scan` (bands of leaving sizes narrower than the
    coarse scan's step: the basins of impacting motions interleave); bisect each that leaves from its size
    one step below (or from 0), and go on below the new best."""
    for g in np.unique(rays.group[idx]):
        mine = idx[rays.group[idx] == g]
        best = rays.hi[mine].min()
        if not math.isfinite(best):
            continue
        below = np.zeros(mine.size)
        for s in best / FINE_SPAN * ratio ** np.arange(int(math.log(FINE_SPAN, ratio)) + 1):
            size = s * ratio ** rays.offset[mine]
            test = (size < rays.limit[mine]) & (size < rays.hi[mine]) & (size < best)
            if not test.any():
                break
            rest = mine[test]
            left, reached = knocks.leave(rays, rest, size[test])
            if left.any():
                hit = rest[left]
                rays.lo[hit], rays.hi[hit] = below[test][left], size[test][left]
                for j, c in zip(hit, reached, strict=True):
                    rays.reached[j] = c
                _bisect(knocks, rays, hit, rtol, floor)
                best = rays.hi[mine].min()
            below[test] = np.where(np.isin(rest, rest[left]), below[test], size[test])


def _boundaries(knocks, rays, idx, levels, ratio, rtol, floor):
    """The first boundary of each group of rays ``idx`` (scanned up ``levels``, bands finer than the scan's steps
    looked for below the best by ``ratio``, bisected to ``rtol``): the smallest ``hi`` per group."""
    idx = np.asarray(idx, dtype=int)
    _scan(knocks, rays, idx, levels)
    _bisect(knocks, rays, idx, rtol, floor)
    _thin_bands(knocks, rays, idx, ratio, rtol, floor)


def critical_shock(params: Params, phi: float, v0: float, *, kind: str = "velocity", phases: int = 24,
                   rtol: float = 1e-3, max_size: float | None = None, refine: int = 6, scan_ratio: float = SCAN_RATIO,
                   max_periods: float = 200,
                   match_tol: float = 1e-6, device: Device | None = None) -> Shock:
    """The smallest knock that drops a periodic motion to another attractor.

    The motion is the one the run from the bottom impact ``(phi, v0)`` settles on.  It is knocked at
    ``phases`` times spread over one period of its cycle and just after each impact, along both directions
    (a ball resting on a wall away from it only: the membrane holds a knock into it).  The sizes are scanned
    for all these rays at once (doubling from :data:`SCAN_FLOOR` of the largest admissible size, by
    ``scan_ratio`` over the last factor :data:`FINE_SPAN`; each ray at its own offset within each step) until
    one leaves; each ray that left is bisected between the size below that returned and the size that left;
    every ray is then knocked at sizes stepping by ``scan_ratio`` over the factor :data:`FINE_SPAN` below the
    best (a band of leaving sizes the coarse steps passed over), and the knock time is refined by ``refine``
    golden-section steps between the neighbours of each of the :data:`LOCAL_MINIMA` smallest local minima of
    the grid.  A band of leaving sizes narrower than the steps at every time can still be missed.

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
    ref = simulate(params, phi=phi, v0=v0, stop_when_periodic=True, t_end=2.0 * max_periods, max_events=MAX_EVENTS)
    cycle = _cycle(ref)
    if cycle is None:
        _fail("(phi, v0)", (phi, v0), f"a start whose run repeats within max_periods = {max_periods!r}")
    knocks = _Knocks(params, phi, max_periods, match_tol, cycle)
    if max_size is None and kind == "velocity":
        max_size = 2.0 * float(np.nanmax(np.abs(cycle["v_minus"]), initial=0.0)) or 1.0
    half = 0.5 * params.d
    times = _knock_times(cycle, phases)
    rays = _rays(ref, times, kind, max_size, half, np.zeros(times.size, int))
    top = float(rays.limit.max())
    floor = rtol * SCAN_FLOOR * top
    _boundaries(knocks, rays, np.arange(rays.t.size), _scan_sizes(top, scan_ratio), scan_ratio, rtol, floor)
    found = [rays]
    grid = np.array([rays.hi[rays.t == t].min() for t in times])
    if refine and np.isfinite(grid).any():
        edges = np.concatenate([[cycle["start"]], times, [cycle["start"] + cycle["span"]]])
        brackets = [(edges[j], edges[j + 2]) for j in _local_minima(grid, LOCAL_MINIMA)]
        found += _refine(knocks, ref, brackets, rays.hi.min(), dict(kind=kind, max_size=max_size, half=half),
                         (scan_ratio, rtol, floor), refine)
    return _shock(_best(found), kind, params, phi, cycle, knocks, device)


def _scan_sizes(top, ratio):
    """The sizes scanned up to ``top``: doubling from :data:`SCAN_FLOOR` of it up to ``top /``
    :data:`FINE_SPAN` (a stable motion's basin holds a ball around its cycle), then by ``ratio`` up to ``top``."""
    fine = top / FINE_SPAN
    coarse = top * 2.0 ** -np.arange(int(math.log2(1 / SCAN_FLOOR)) + 1)[::-1]
    steps = fine * ratio ** np.arange(int(math.log(FINE_SPAN, ratio)) + 1)
    return [*coarse[coarse < fine], *steps[steps < top], top]


def _refine(knocks, ref, brackets, best, ray_args, steps_args, steps):
    """Golden-section searches of the knock time, one per bracket ``(t_lo, t_hi)``, in lock-step: at each step
    the new time of every bracket is knocked (scanned from an eighth of the best knock so far, by ``ratio``
    over ``[best/2, 2 best]``, then bisected).  Returns the rays knocked."""
    ratio, rtol, floor = steps_args
    found = []

    def f(ts):
        nonlocal best
        rays = _rays(ref, np.asarray(ts), group=np.arange(len(ts)), **ray_args)
        levels = [best / 8, best / 4, *(0.5 * best * ratio ** np.arange(int(math.log(4.0, ratio)) + 1)), 2 * best]
        idx = np.arange(rays.t.size)
        _scan(knocks, rays, idx, levels)
        _bisect(knocks, rays, idx, rtol, floor)
        found.append(rays)
        best = min(best, float(rays.hi.min()))
        return [float(rays.hi[rays.group == g].min()) for g in range(len(ts))]

    ab = np.array(brackets, dtype=float)
    c, d = ab[:, 1] - _GOLD * (ab[:, 1] - ab[:, 0]), ab[:, 0] + _GOLD * (ab[:, 1] - ab[:, 0])
    vals = f([*c, *d])
    fc, fd = np.array(vals[:len(c)]), np.array(vals[len(c):])
    for _ in range(steps):
        left = fc <= fd  # the minimum lies in [a, d]: d <- c, a new c; else in [c, b]: c <- d, a new d
        ab[left, 1], ab[~left, 0] = d[left], c[~left]
        new = np.where(left, ab[:, 1] - _GOLD * (ab[:, 1] - ab[:, 0]), ab[:, 0] + _GOLD * (ab[:, 1] - ab[:, 0]))
        fnew = np.array(f(new))
        d[left], fd[left], c[left], fc[left] = c[left], fc[left], new[left], fnew[left]
        c[~left], fc[~left], d[~left], fd[~left] = d[~left], fd[~left], new[~left], fnew[~left]
    return found


def _best(found):
    """The smallest knock that left among the rays ``found``: ``(hi, lo, sign, cycle, state, t)``, or None."""
    best = None
    for rays in found:
        j = int(np.argmin(rays.hi))
        if math.isfinite(rays.hi[j]) and (best is None or rays.hi[j] < best[0]):
            best = (float(rays.hi[j]), float(rays.lo[j]), int(rays.sign[j]), rays.reached[j],
                    (float(rays.z[j]), float(rays.v[j])), float(rays.t[j]))
    return best


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
