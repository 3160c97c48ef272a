"""The event loop: impacts, chattering, sticking and release, with in-loop period detection.

All functions are numba-compiled and work on arrays, which the entry points take in records (numba
namedtuples: :data:`Model`, :data:`Settings`, :data:`Start`, :data:`EventBuffers`, :data:`Batch`,
:data:`FlightBatch`, :data:`Ends`, :data:`WindowSettings`, :data:`Window`, :data:`WindowEnds`), at most six parameters each;
:mod:`vibroimpact.dynamics.runs` and :mod:`vibroimpact.analysis.windows` wrap them.

The rebound at each impact is the impact law's (:mod:`vibroimpact.dynamics.impact`).

Chattering rule (documented in README): after an impact at wall ``w`` the relative acceleration
into the wall is ``a = w Z''``.  If ``a > 0`` and the rebound speed ``|Zdot+| = r |Zdot-|`` is below
``v_chatter``, the remaining infinite sequence of bounces is summed as under constant acceleration:
each flight lasts ``2 |Zdot+| / a`` and the speeds shrink by ``r``, so the impacts accumulate at

    t_inf = t + 2 |Zdot+| / ((1 - r) a).

The sum is used only where ``a`` changes by less than ``CHATTER_DRIFT`` (1e-9) of itself before
``t_inf``: then ``w Z''`` cannot change sign before the accumulation point (it comes before the
release), and the sum's relative error is of that order.  Near the release phase (``a`` small and
falling) the bounces are instead followed one by one, exactly, until the sum applies or the ball
leaves the wall.  The ball then sticks to the wall (event ``stick``) until ``w Z''`` changes sign, at
the phase where ``cos(pi t + phi) = -gbar``, where it is released (event ``release``) with zero
relative velocity.  With ``gbar >= 1`` a ball
stuck on the bottom is never released, and the run ends with status ``STUCK_FOREVER``.
"""

import math
import os
import threading
from collections import namedtuple
from concurrent.futures import ThreadPoolExecutor

import numba
import numpy as np
from numba import njit
from numba.cpython.unsafe.numbers import trailing_zeros  # LLVM's cttz, as numba's own math.gcd uses it

from . import impact as law
from .events import flight_impact
from .flight import PI, TWO_PI

# event kinds
IMPACT = 0
GRAZING = 1
STICK = 2
RELEASE = 3
START = 4
KIND_NAMES = ("impact", "grazing", "stick", "release", "start")
RESUME = -1  # resume after a recorded event that needs no further action
RESUME_IMPACT = -2  # resume right after a recorded impact or grazing contact

# run status
FULL = 0  # the requested number of events was recorded
T_END = 1  # t_end was reached
PERIODIC = 2  # the motion was identified as periodic (when asked to stop there)
STUCK_FOREVER = 3  # resting on the bottom with gbar >= 1: the ball never leaves again
NO_IMPACT = 4  # a flight with no impact within the search horizon (gbar = 0 only)
STATUS_NAMES = ("n_events", "t_end", "periodic", "stuck_forever", "no_impact")

#: |Zdot-| below which an impact is labelled grazing.
V_GRAZING = 1e-9
#: The chattering rule's speed ``v_chatter`` by default: a rebound slower than this may be summed to its
#: accumulation point (see ``_accumulation_time``).
V_CHATTER = 1e-9
#: Largest relative change of the acceleration over a chattering sequence that is summed to its
#: accumulation point (see ``_accumulation_time``); beyond it the bounces are followed exactly.
CHATTER_DRIFT = 1e-9
#: Longest single flight searched when no t_end is given (non-dimensional time).
TAU_HORIZON = 1.0e5


@njit(cache=True, error_model="numpy", inline="always")
def _wrap(x):
    """``x % TWO_PI`` for ``x >= 0``, bit for bit: below ``2 TWO_PI`` one subtraction, exact by
    Sterbenz's lemma (as the remainder is), without the library call."""
    if x < TWO_PI:
        return x
    if x < 2.0 * TWO_PI:
        return x - TWO_PI
    return x % TWO_PI


@njit(cache=True, error_model="numpy")
def _phase_distance(a, b):
    x = abs(a - b)
    if not x < TWO_PI:  # the remainder returns a smaller x unchanged (exactly): the call only where it matters
        x = x % TWO_PI
    return min(x, TWO_PI - x)


@njit(cache=True, error_model="numpy")
def period_update(i, events, counts, tol):
    """Update the per-lag match counters with event ``i`` of ``events`` (:data:`Window`: the event
    buffers' ``t``, ``wall``, ``v_minus``, ``phase``, ``kind``); return the smallest lag p whose last
    ``2p`` events all repeated the event ``p`` earlier (two full cycles), else 0.

    A match needs the same wall and kind, ``|Zdot-|`` and phase within ``tol``, and a time lag
    within ``tol`` of a positive even integer (a whole number of forcing periods).

    The lags are taken 64 at a time: those whose speed repeats become the bits of a word, the others' counters are
    reset, and only the lags of the set bits are compared further, in increasing order (a motion converging slowly
    repeats its speeds at a few lags for thousands of events before its period is decided; skipping the other lags
    without a branch each makes such an event about a third cheaper).  The counters and the lag returned are those
    of comparing every lag in turn.
    """
    t, wall, vm, phase, kind = events
    pmax = counts.shape[0] - 1
    top = min(pmax, i)
    v = vm[i]
    numeric = not math.isnan(v)
    found = 0
    for base in range(0, top, 64):
        repeats = np.uint64(0)  # bit b: lag base + 1 + b has the speed of event i (NaN after NaN)
        bit = np.uint64(1)
        for p in range(base + 1, min(base + 64, top) + 1):
            if abs(v - vm[i - p]) <= tol or (not numeric and math.isnan(vm[i - p])):
                repeats |= bit
            else:
                counts[p] = 0
            bit <<= np.uint64(1)
        while repeats != np.uint64(0):
            p = base + 1 + np.int64(trailing_zeros(repeats))
            repeats &= repeats - np.uint64(1)
            j = i - p
            ok = wall[i] == wall[j] and kind[i] == kind[j]
            if ok:
                ok = _phase_distance(phase[i], phase[j]) <= tol
            if ok:
                lag = t[i] - t[j]
                k = math.floor(lag / 2.0 + 0.5)
                ok = k >= 1 and abs(lag - 2.0 * k) <= tol * max(1.0, lag)
            if ok:
                counts[p] += 1
                if found == 0 and counts[p] >= 2 * p:
                    if _no_shorter_period(i, p, vm, phase, tol):
                        found = p
                    else:
                        # a shorter period is still converging: count again from here rather than
                        # re-checking at every event (the check would keep failing until it matches)
                        counts[p] = 0
            else:
                counts[p] = 0
    return found


@njit(cache=True, error_model="numpy", inline="always")
def no_lag_matches(i, vm, counts, tol):
    """Where no lag of event ``i`` can match (:func:`velocity_repeats` False), do what :func:`period_update` does
    there, reset the counters of lags 1 to ``min(pmax, i)`` (it finds no period), and return True; else False,
    counters untouched.  The event loop calls :func:`period_update`, which goes through the lags, only where this is
    False (a chaotic run's speeds almost never repeat within ``tol``)."""
    pmax = counts.shape[0] - 1
    if velocity_repeats(i, vm, pmax, tol):
        return False
    counts[1:min(pmax, i) + 1] = 0
    return True


@njit(cache=True, error_model="numpy", inline="always")
def velocity_repeats(i, vm, pmax, tol):
    """Whether one of the last ``pmax`` events before event ``i`` has its ``Zdot-`` within ``tol`` of event ``i``'s
    (or event ``i``'s is NaN, which an earlier NaN matches): the test of :func:`period_update` that no lag passes
    where this is False, taken for all lags at once in a loop the compiler vectorises."""
    v = vm[i]
    if math.isnan(v):
        return True
    earlier = vm[max(i - pmax, 0):i]
    close = 0
    for j in range(earlier.shape[0]):
        close += np.int64(abs(v - earlier[j]) <= tol)
    return close > 0


@njit(cache=True, error_model="numpy")
def _no_shorter_period(i, p, vm, phase, tol):
    """False when a divisor q of p has lag-q residuals below sqrt(tol) over the last p events.

    A period-q orbit whose eigenvalue is close to -1 converges slowly and alternately: its lag-2q
    residuals fall below ``tol`` long before its lag-q residuals do.  A genuine period-p motion keeps
    a finite lag-q splitting; a residual still below ``sqrt(tol)`` is taken as "not decided yet".
    """
    thresh = math.sqrt(tol)
    for q in range(1, p):
        if p % q != 0:
            continue
        worst = 0.0
        for k in range(i - p + 1, i + 1):
            dv = abs(vm[k] - vm[k - q]) if not math.isnan(vm[k]) else 0.0
            worst = max(worst, dv, _phase_distance(phase[k], phase[k - q]))
        if worst < thresh:
            return False
    return True


@njit(cache=True, error_model="numpy")
def _accumulation_time(c, s, u, w, model, v_chatter):
    """Time to the accumulation point of a chattering sequence after an impact on wall ``w`` with
    rebound velocity ``u`` at the phase with cosine ``c`` and sine ``s`` (constants ``model``,
    :data:`Model`), or -1 when the rule does not apply (see the module docstring).

    The sum assumes a constant acceleration ``a``; it is used only where ``a`` changes by at most
    ``CHATTER_DRIFT * a`` before the accumulation point (bounded by ``|a'| tau + |a''| tau^2 / 2``
    with ``|a'| = pi |sin theta|``, ``|a''| <= pi^2``).  So ``w Z''`` keeps its sign up to the
    accumulation point, which therefore comes before the release, and the relative error of the sum
    is of order ``CHATTER_DRIFT``.  Otherwise the next bounce is computed exactly, and so it is whenever
    the impact law's restitution is not constant (:data:`~vibroimpact.dynamics.impact.CONSTANT_RESTITUTION`):
    the bounces are then followed until the rebound speed rounds to zero.
    """
    _, gbar, r = model
    a_in = w * (c + gbar)
    if abs(u) >= v_chatter:
        return -1.0
    if a_in <= 0.0:
        # at rest exactly where the acceleration into the wall is zero and turning positive (the
        # phase where w Z'' changes sign towards the wall): the ball stays; a flight from there would
        # meet the wall again at once, forever at the same time
        return 0.0 if u == 0.0 and a_in == 0.0 and w * s < 0.0 else -1.0
    if not law.CONSTANT_RESTITUTION:
        # the geometric sum needs a constant restitution: follow the bounces one by one (a ball at rest
        # with the acceleration into the wall sticks at once, whatever the law)
        return 0.0 if u == 0.0 else -1.0
    tau = 2.0 * abs(u) / ((1.0 - r) * a_in)
    drift = PI * abs(s) * tau + 0.5 * PI * PI * tau * tau
    if drift > CHATTER_DRIFT * a_in:
        return -1.0
    return tau


#: the events a run records, one array each, indexed by event (the kernels' output buffers)
EventBuffers = namedtuple("EventBuffers", ("t", "wall", "v_minus", "v_plus", "phase", "kind", "z"))
#: where a run starts: time, forcing phase, position, velocity, kind and wall of its first event
Start = namedtuple("Start", ("t", "theta", "z", "v", "kind", "wall"))
#: the model's constants: wall distance, gravity term, restitution (floats)
Model = namedtuple("Model", ("d", "gbar", "r"))
#: how a run goes: until ``t_end``, the chattering rule's speed ``v_chatter``, whether to stop at a detected
#: period (``detect``) and the period test's tolerance ``tol``
Settings = namedtuple("Settings", ("t_end", "v_chatter", "detect", "tol"))
#: many runs from bottom impacts, one entry per run: the model's constants, the phase and pre-impact velocity
Batch = namedtuple("Batch", ("d", "gbar", "r", "theta0", "v0"))
#: many runs each from a state in flight: the constants, start time and its forcing phase, ``Z`` and ``Zdot``
FlightBatch = namedtuple("FlightBatch", ("d", "gbar", "r", "t0", "theta0", "z0", "v0"))
#: how each run of a batch ended: events recorded, status, detected period in events
Ends = namedtuple("Ends", ("n", "status", "lag"))
#: a run that keeps only its last events: at most ``max_events`` events, until ``t_end``, the chattering
#: speed, the period test's tolerance, the longest period looked for (events) and the events kept in between
WindowSettings = namedtuple("WindowSettings", ("max_events", "t_end", "v_chatter", "tol", "pmax", "cap"))
#: the events a window keeps (and the period test reads), one array each
Window = namedtuple("Window", ("t", "wall", "v_minus", "phase", "kind"))
#: how each window run of a batch ended: status, detected period in events, events simulated, events kept
WindowEnds = namedtuple("WindowEnds", ("status", "lag", "total", "n"))


@njit(cache=True, error_model="numpy")
def advance(model, start, i0, settings, counts, out):
    """Advance from an initial event ``start`` (:data:`Start`) and record events into ``out[i0:]``
    (:data:`EventBuffers`), for the constants ``model`` (:data:`Model`) and the run's ``settings``
    (:data:`Settings`); ``counts``: the period test's counters (one per lag, zeroed at the run's start).

    ``start.kind``: IMPACT (a wall impact with pre-impact velocity ``start.v``, recorded),
    START (in flight at ``start.z`` with velocity ``start.v``, recorded), or one of RESUME,
    RESUME_IMPACT, STICK to resume from the post-event state of an event already recorded at
    ``i0 - 1`` (``start.v`` is then Zdot+ and ``start.wall`` its wall).

    Returns ``(n, status, lag)``: events recorded up to index ``n``, the run status and, when
    ``detect``, the detected period in events (0 if none).
    """
    d, gbar, r = model
    t_end, v_chatter, detect, tol = settings
    t_start, theta_start, z_start, v_start, kind_start, wall_start = start
    out_t, out_wall, out_vm, out_vp, out_phase, out_kind, out_z = out
    marks = Window(out_t, out_wall, out_vm, out_phase, out_kind)
    cap = out_t.shape[0]
    half = 0.5 * d
    has_release = gbar < 1.0
    alpha = math.acos(-gbar) if has_release else 0.0
    t = t_start
    theta = theta_start % TWO_PI
    z = z_start
    u = v_start
    stuck = 0  # wall the ball rests on, 0 in flight
    i = i0
    lag = 0
    pending = -1  # kind of an event to record before moving on
    vminus = 0.0
    if kind_start == IMPACT:
        pending = IMPACT
        vminus = v_start
        z = wall_start * half
    elif kind_start == START:
        pending = START
    elif kind_start == STICK:
        stuck = wall_start
        u = 0.0
    chatter_wall = 0  # wall of an impact just recorded: the chattering rule is checked there
    if kind_start == RESUME_IMPACT:
        chatter_wall = wall_start
    c = math.cos(theta)  # cosine and sine of the current phase, recomputed only when it changes
    s = math.sin(theta)
    cs_theta = theta
    while True:
        if cs_theta != theta:
            c = math.cos(theta)
            s = math.sin(theta)
            cs_theta = theta
        if chatter_wall != 0:
            tau_inf = _accumulation_time(c, s, u, chatter_wall, model, v_chatter)
            if tau_inf >= 0.0:
                # chattering: jump to the accumulation point and stick
                if t + tau_inf > t_end:
                    return i, T_END, lag
                t += tau_inf
                theta = (theta + PI * tau_inf) % TWO_PI
                stuck = chatter_wall
                u = 0.0
                pending = STICK
            chatter_wall = 0
        if pending >= 0:
            if i >= cap:
                return i, FULL, lag
            kind = pending
            w = 0
            vp = u
            if pending == IMPACT:
                w = 1 if z > 0 else -1
                if abs(vminus) < V_GRAZING:
                    kind = GRAZING
                vp = law.rebound(vminus, r)
            elif pending == STICK or pending == RELEASE:
                w = stuck if pending == STICK else (1 if z > 0 else -1)
                vminus = 0.0
                vp = 0.0
            else:
                vminus = math.nan
            out_t[i] = t
            out_wall[i] = w
            out_vm[i] = vminus
            out_vp[i] = vp
            out_phase[i] = theta
            out_kind[i] = kind
            out_z[i] = z
            if detect and not no_lag_matches(i, out_vm, counts, tol):
                lag = period_update(i, marks, counts, tol)
            i += 1
            if detect and lag > 0:
                return i, PERIODIC, lag
            if pending == IMPACT:
                u = vp
                chatter_wall = w
                pending = -1
                continue
            if pending == RELEASE:
                stuck = 0
            pending = -1
        if stuck != 0:
            # resting on wall `stuck` while stuck*Z'' > 0; release where it changes sign
            if stuck == 1:
                if not has_release:
                    return i, STUCK_FOREVER, lag
                psi_r = alpha
            else:
                psi_r = TWO_PI - alpha
            tau_r = ((psi_r - theta) % TWO_PI) / PI
            if t + tau_r > t_end:
                return i, T_END, lag
            t += tau_r
            theta = psi_r
            z = stuck * half
            u = 0.0
            pending = RELEASE
            continue
        # flight
        tau_max = t_end - t if t_end < math.inf else TAU_HORIZON
        tau, w, vminus = flight_impact(theta, c, s, alpha, z, u, d, gbar, tau_max)
        if w == 0:
            return i, T_END if t_end < math.inf else NO_IMPACT, lag
        t += tau
        theta = _wrap(theta + PI * tau)
        z = w * half
        pending = IMPACT


def shared(kernel, m, *args):
    """``kernel(span, *args)`` over the runs ``[0, m)``, ``span = (lo, hi)`` a block of them: one block per thread
    of numba's number of threads (``numba.get_num_threads()``), the runs split evenly as numba's parallel loops
    split them; the calling thread takes the first block, a pool of threads kept for the process the others (a
    hand-over costs about 50 us more than numba's parallel loop: 2 % of a batch of 256 short runs, a quarter of
    one of 16); one block, in the calling thread, where that leaves one.  The kernels are compiled loops that release the GIL,
    each run independent of the others: the results are those of one call over all the runs, to the last bit,
    on any number of threads.  Python's threads, not numba's parallel loops, which compile the event loop into
    each loop a second time (about 2-3 s of a first run's compile per batch kernel)."""
    workers = numba.get_num_threads()
    size = max(-(-m // max(workers, 1)), 1)
    if size >= m:
        if m > 0:
            kernel((np.int64(0), np.int64(m)), *args)
        return
    spans = [(np.int64(a), np.int64(min(a + size, m))) for a in range(0, m, size)]
    pool = _pool(workers - 1)
    others = [pool.submit(kernel, span, *args) for span in spans[1:]]
    kernel(spans[0], *args)  # the calling thread takes the first block: one hand-over fewer
    for f in others:
        f.result()


#: the threads :func:`shared` runs blocks on, one pool per number of threads, kept for the process: starting
#: threads for every call would cost more than a small batch (the knocked runs of a shock go in many)
_POOLS: dict[int, ThreadPoolExecutor] = {}
_POOLS_LOCK = threading.Lock()


def _pool(workers: int) -> ThreadPoolExecutor:
    with _POOLS_LOCK:
        if workers not in _POOLS:
            _POOLS[workers] = ThreadPoolExecutor(max_workers=workers, thread_name_prefix=f"vibroimpact-{workers}")
        return _POOLS[workers]


def _forget_pools():
    """In a forked child the pools' threads do not exist (a block handed to them would never run): new pools."""
    global _POOLS_LOCK
    _POOLS_LOCK = threading.Lock()
    _POOLS.clear()


os.register_at_fork(after_in_child=_forget_pools)


def run_batch(batch, settings, pmax, out, ends):
    """Run many independent simulations on numba's threads (:func:`shared`), each from a bottom impact (paper
    convention).

    ``batch`` (:data:`Batch`): arrays of length ``m``, one entry per run; ``settings`` (:data:`Settings`)
    shared; ``pmax`` the longest period looked for (events); ``out`` (:data:`EventBuffers`) arrays of shape
    ``(m, n_events)``; ``ends`` (:data:`Ends`) arrays of length ``m``.
    """
    shared(batch_runs, batch.d.shape[0], batch, settings, np.int64(pmax), out, ends)


@njit(cache=True, error_model="numpy", nogil=True)
def batch_runs(span, batch, settings, pmax, out, ends):
    """The runs ``span[0]`` to ``span[1] - 1`` of :func:`run_batch`, one after the other."""
    for k in range(span[0], span[1]):
        counts = np.zeros(pmax + 1, dtype=np.int64)
        d = batch.d[k]
        n, status, lag = advance(Model(d, batch.gbar[k], batch.r[k]),
                                 Start(0.0, batch.theta0[k], 0.5 * d, batch.v0[k], IMPACT, 1), np.int64(0),
                                 settings, counts,
                                 EventBuffers(out.t[k], out.wall[k], out.v_minus[k], out.v_plus[k], out.phase[k],
                                              out.kind[k], out.z[k]))
        ends.n[k] = n
        ends.status[k] = status
        ends.lag[k] = lag


@njit(cache=True, error_model="numpy")
def is_hit(kind):
    """Whether an event of ``kind`` reaches a wall: an impact or a grazing contact (not a stick, a release
    or the start); the one definition every module uses."""
    return kind == IMPACT or kind == GRAZING


def hits(kind) -> np.ndarray:
    """:func:`is_hit` of an array of event kinds (NaN-padded buffers hold their kinds as integers)."""
    kind = np.asarray(kind)
    return (kind == IMPACT) | (kind == GRAZING)


@njit(cache=True, error_model="numpy")
def resume_code(kind):
    """How a run resumes after an event of ``kind``: resting (a stick), from an impact (a hit) or from a
    free state."""
    if kind == STICK:
        return STICK
    if is_hit(kind):
        return RESUME_IMPACT
    return RESUME


@njit(cache=True, error_model="numpy", nogil=True)
def run_window(model, theta0, v0, limits, win):
    """Run from a bottom impact at t = 0 (phase ``theta0``, pre-impact velocity ``v0``; constants ``model``,
    :data:`Model`) until the motion is periodic, ``limits.t_end`` or ``limits.max_events`` (:data:`WindowSettings`),
    keeping only a sliding buffer of ``limits.cap`` events; copy the last ``len(win.t)`` events out into ``win``
    (:data:`Window`).

    Returns ``(status, lag, n_total, n_window)``.
    """
    return run_window_from(model, Start(0.0, theta0, 0.5 * model.d, v0, IMPACT, 1), limits, win)


@njit(cache=True, error_model="numpy")
def run_window_from(model, start, limits, win):
    """:func:`run_window` from the first event ``start`` (:data:`Start`: a bottom impact, or in flight with kind
    START); the run lasts ``limits.t_end`` after ``start.t``."""
    max_events, duration, v_chatter, tol, pmax, cap = limits
    t_end = start.t + duration
    win_t, win_wall, win_vm, win_phase, win_kind = win
    bt = np.zeros(cap)
    bw = np.zeros(cap, dtype=np.int8)
    bvm = np.zeros(cap)
    bvp = np.zeros(cap)
    bph = np.zeros(cap)
    bk = np.zeros(cap, dtype=np.int8)
    bz = np.zeros(cap)
    counts = np.zeros(pmax + 1, dtype=np.int64)
    keep = 3 * pmax + 1
    # a run-time flag, not the literal True: `advance` is then the very specialisation `simulate` calls,
    # compiled once, so the two give the same events to the last bit
    settings = Settings(t_end, v_chatter, tol == tol, tol)
    n, status, lag = advance(model, start, np.int64(0), settings, counts,
                             EventBuffers(bt, bw, bvm, bvp, bph, bk, bz))
    total = n
    while status == FULL and total < max_events:
        # slide: keep the last `keep` events (enough for the period test), continue after them
        shift = n - keep
        for j in range(keep):
            bt[j] = bt[j + shift]
            bw[j] = bw[j + shift]
            bvm[j] = bvm[j + shift]
            bvp[j] = bvp[j + shift]
            bph[j] = bph[j + shift]
            bk[j] = bk[j + shift]
            bz[j] = bz[j + shift]
        last = keep - 1
        room = min(cap, keep + max_events - total)
        resume = Start(bt[last], bph[last], bz[last], bvp[last], resume_code(bk[last]), np.int64(bw[last]))
        n, status, lag = advance(model, resume, keep, settings, counts,
                                 EventBuffers(bt[:room], bw[:room], bvm[:room], bvp[:room], bph[:room], bk[:room],
                                              bz[:room]))
        total += n - keep
    m = min(win_t.shape[0], n)
    for j in range(m):
        src = n - m + j
        win_t[j] = bt[src]
        win_wall[j] = bw[src]
        win_vm[j] = bvm[src]
        win_phase[j] = bph[src]
        win_kind[j] = bk[src]
    return status, lag, total, m


def window_batch(batch, limits, win, ends):
    """:func:`run_window` for many runs on numba's threads (:func:`shared`): ``batch`` (:data:`Batch`) one entry per
    run, ``limits`` (:data:`WindowSettings`) shared, ``win`` (:data:`Window`) arrays of shape (m, window), ``ends``
    (:data:`WindowEnds`) arrays of length m."""
    shared(window_runs, batch.d.shape[0], batch, limits, win, ends)


@njit(cache=True, error_model="numpy", nogil=True)
def window_runs(span, batch, limits, win, ends):
    """The runs ``span[0]`` to ``span[1] - 1`` of :func:`window_batch`, one after the other (each
    :func:`run_window`'s, from :func:`run_window_from` directly: one compiled wrapper of the event loop fewer)."""
    for k in range(span[0], span[1]):
        d = batch.d[k]
        st, lag, tot, nw = run_window_from(Model(d, batch.gbar[k], batch.r[k]),
                                           Start(0.0, batch.theta0[k], 0.5 * d, batch.v0[k], IMPACT, 1), limits,
                                           Window(win.t[k], win.wall[k], win.v_minus[k], win.phase[k], win.kind[k]))
        ends.status[k] = st
        ends.lag[k] = lag
        ends.total[k] = tot
        ends.n[k] = nw


def flight_window_batch(batch, limits, win, ends):
    """:func:`window_batch` for runs each from a state in flight (``batch``, :data:`FlightBatch`): at ``t0``, forcing
    phase ``theta0``, ``Z = z0`` and ``Zdot = v0``; each lasts ``limits.t_end`` after its start.  On one numba
    thread the runs go one after the other in the calling thread, without the GIL (for callers that share their
    work among threads of their own)."""
    shared(flight_window_runs, batch.d.shape[0], batch, limits, win, ends)


@njit(cache=True, error_model="numpy", nogil=True)
def flight_window_runs(span, batch, limits, win, ends):
    """The runs ``span[0]`` to ``span[1] - 1`` of :func:`flight_window_batch`, one after the other."""
    for k in range(span[0], span[1]):
        start = Start(batch.t0[k], batch.theta0[k], batch.z0[k], batch.v0[k], START, 0)
        st, lag, tot, nw = run_window_from(Model(batch.d[k], batch.gbar[k], batch.r[k]), start, limits,
                                           Window(win.t[k], win.wall[k], win.v_minus[k], win.phase[k], win.kind[k]))
        ends.status[k] = st
        ends.lag[k] = lag
        ends.total[k] = tot
        ends.n[k] = nw


#: a sweep's points followed in chains, each point from the last bottom impact of the one before it in its
#: chain: the constants of each point (``d``, ``gbar``; ``r`` shared), the points of each chain in order
#: (``order``, ``(chains, m)`` indices), each chain's next start (``start``, ``(chains, 2)``: phase and pre-impact
#: velocity, updated as the chain goes) and the start each point used (``used``, ``(chains, m, 2)``)
Chain = namedtuple("Chain", ("d", "gbar", "r", "order", "start", "used"))


def chain_windows(chain, span, limits, win, ends):
    """:func:`run_window` along the chains of ``chain`` (:data:`Chain`), the chains on numba's threads
    (:func:`shared`): the points at positions ``span[0]`` to ``span[1] - 1`` of each chain's order, each from the
    chain's current start; a point whose window holds a bottom impact makes its last one the next start.
    ``win`` (:data:`Window`) arrays of shape ``(chains, m, window)``, ``ends`` (:data:`WindowEnds`) of shape
    ``(chains, m)``."""
    shared(chain_runs, chain.order.shape[0], chain, (np.int64(span[0]), np.int64(span[1])), limits, win, ends)


@njit(cache=True, error_model="numpy", nogil=True)
def chain_runs(chains, chain, span, limits, win, ends):
    """The chains ``chains[0]`` to ``chains[1] - 1`` of :func:`chain_windows`, one after the other."""
    for k in range(chains[0], chains[1]):
        for pos in range(span[0], span[1]):
            i = chain.order[k, pos]
            phi = chain.start[k, 0]
            v0 = chain.start[k, 1]
            chain.used[k, i, 0] = phi
            chain.used[k, i, 1] = v0
            w = Window(win.t[k, i], win.wall[k, i], win.v_minus[k, i], win.phase[k, i], win.kind[k, i])
            st, lag, tot, nw = run_window_from(Model(chain.d[i], chain.gbar[i], chain.r),
                                               Start(0.0, phi % TWO_PI, 0.5 * chain.d[i], v0, IMPACT, 1), limits, w)
            ends.status[k, i] = st
            ends.lag[k, i] = lag
            ends.total[k, i] = tot
            ends.n[k, i] = nw
            for j in range(nw - 1, -1, -1):  # the last bottom impact (windows.last_bottom_impact)
                if w.wall[j] == 1 and w.kind[j] == IMPACT and w.v_minus[j] > 0:
                    chain.start[k, 0] = w.phase[j]
                    chain.start[k, 1] = w.v_minus[j]
                    break
