"""Basin stability: the share of the whole state space from which the harvester settles on each motion.

At one parameter point, ``n`` starts are drawn uniformly over a box of the state space (Menck et al. 2013,
"How basin stability complements the linear-stability paradigm", Nature Physics 9, 89): the forcing phase
``theta`` in ``[0, 2 pi)``, the ball's position ``Z`` in ``[-d/2, d/2]`` (anywhere inside the cylinder) and
its velocity relative to the cylinder ``Zdot`` in ``v_range``.  Each start is run in flight from time 0
(:func:`~vibroimpact.analysis.windows.attractor_batch`, all in one parallel call) until its motion repeats.
The runs are grouped into attractors and each attractor's output is settled as the design maps do it
(:mod:`vibroimpact.analysis.design`): a periodic attractor's outputs are those of its Newton-solved cycle, a
motion without a period keeps its long run's label (chaotic, quasi-periodic or unsettled) and averages.

Beside the state-space shares, the same point's switch-on shares: the design maps' starts (the ball at rest
on the bottom membrane, the forcing phase uniform; :func:`~vibroimpact.analysis.design.start_states`), with
the same ``n`` and ``seed``.  Each share is a binomial proportion with its Clopper-Pearson interval.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..datasets import annotate
from ..dynamics.device import PAPER, Device
from ..dynamics.params import Params
from .design import AT_REST, MIN_STARTS, SAME_ORBIT, point_attractors, share_interval, start_states
from .motions import no_period
from .windows import attractor_batch

__all__ = ["basin_stability", "DISTRIBUTIONS", "V_RANGE", "state_space_starts"]

#: the two start distributions, in the order of the dataset's ``distribution`` dimension
DISTRIBUTIONS = ("switch-on", "state space")
#: the default box of relative velocities: the paper's motions reach |Zdot| = 0.964 at most (the 1:1 at
#: the longest cylinder of its sweeps, s = 0.72 m, beta = pi/2), the bistable 2:1 and 3:1 at pi/6 about 0.46
V_RANGE = (-1.0, 1.0)
#: events kept per run, as the design maps keep (enough to span ``window_time`` without a period)
WINDOW = 96


def _fail(key, value, allowed):
    raise ValueError(f"{key} = {value!r} is not allowed; allowed: {allowed}")


def _check(params, n, seed, v_range, confidence, max_periods):
    if not isinstance(params, Params):
        _fail("params", params, "a vibroimpact.Params (vi.Params.from_physical(s=..., beta=...))")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < MIN_STARTS:
        _fail("n", n, f"an integer >= {MIN_STARTS} (fewer starts leave every share's interval spanning most of [0, 1])")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        _fail("seed", seed, "an integer >= 0")
    try:
        lo, hi = (float(v) for v in v_range)
    except (TypeError, ValueError):
        _fail("v_range", v_range, "two numbers (lo, hi) with lo < hi")
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        _fail("v_range", v_range, "(lo, hi), finite, with lo < hi (a box with some width)")
    if isinstance(confidence, bool) or not isinstance(confidence, (int, float)) or not 0 < confidence < 1:
        _fail("confidence", confidence, "a level 0 < confidence < 1")
    if isinstance(max_periods, bool) or not isinstance(max_periods, (int, float)) or not 0 < max_periods < math.inf:
        _fail("max_periods", max_periods, "a finite number of forcing periods > 0")
    return lo, hi


def state_space_starts(params: Params, n: int, seed: int = 0, v_range=V_RANGE):
    """``n`` starts uniform over the box of the state space: forcing phase ``theta`` in ``[0, 2 pi)``, ``Z`` in
    ``[-d/2, d/2]``, ``Zdot`` in ``v_range``, drawn in that order with ``numpy.random.default_rng(seed)``.
    (The phases are the first draw, so they are the switch-on starts' phases of the same seed.)"""
    rng = np.random.default_rng(seed)
    theta = rng.uniform(0.0, 2 * math.pi, n)
    z = rng.uniform(-0.5 * params.d, 0.5 * params.d, n)
    zdot = rng.uniform(v_range[0], v_range[1], n)
    return theta, z, zdot


def _runs(params, distribution, n, seed, v_range, settings):
    """The starts of one distribution (phase, Z, Zdot) and their runs."""
    d, gbar, r = params.d, params.gbar, params.r
    if distribution == "switch-on":
        phi, v0 = start_states(n, distribution="rest", seed=seed)
        runs = attractor_batch(d, gbar, r, phi, v0, progress=False, **settings)
        return (phi, np.full(n, 0.5 * d), v0), runs
    theta, z, zdot = state_space_starts(params, n, seed, v_range)
    runs = attractor_batch(d, gbar, r, theta, zdot, t0=0.0, Z0=z, progress=False, **settings)
    return (theta, z, zdot), runs


def _same(a, b) -> bool:
    """Two attractors (of two distributions' runs) are one: the same label, and for a periodic one outputs that
    agree to :data:`~vibroimpact.analysis.design.SAME_ORBIT` (as the design map groups runs)."""
    if a.label != b.label:
        return False
    if a.label == AT_REST or no_period(a.label):
        return True
    return abs(a.U_T - b.U_T) <= SAME_ORBIT * max(abs(a.U_T), abs(b.U_T), 1.0)


def _union(per_dist):
    """The attractors of all distributions, each once (most starts over all first), and for each distribution
    the index into them of each of its attractors."""
    union, index = [], []
    for atts in per_dist:
        idx = []
        for att in atts:
            k = next((j for j, u in enumerate(union) if _same(u[0], att)), None)
            if k is None:
                union.append([att, 0])
                k = len(union) - 1
            union[k][1] += att.count
            idx.append(k)
        index.append(idx)
    order = sorted(range(len(union)), key=lambda j: (-union[j][1], union[j][0].label, union[j][0].U_T))
    rank = {j: i for i, j in enumerate(order)}
    return [union[j][0].label for j in order], [[rank[k] for k in idx] for idx in index]


def basin_stability(params: Params, n: int = 400, *, seed: int = 0, v_range=V_RANGE, confidence: float = 0.95,
                    max_periods: float = 200, device: Device | None = None, tol: float = 1e-9,
                    window_time: float = 30.0) -> xr.Dataset:
    """Shares of the starts that settle on each attractor: from the whole state space and from switch-on.

    Parameters
    ----------
    params : Params
        The parameter point (its forcing ``F`` sets the outputs' scale where it was built with
        :meth:`~vibroimpact.Params.from_physical`, else the device's).
    n : int
        Starts per distribution (at least 8).
    seed : int
        Seed of ``numpy.random.default_rng`` for both distributions' starts.
    v_range : (float, float)
        The box of the relative velocity ``Zdot`` at the start (non-dimensional).  The default ``(-1, 1)``
        covers the speeds of the paper's motions (at most 0.964, the 1:1 at s = 0.72 m, beta = pi/2).
    confidence : float
        Level of the shares' Clopper-Pearson intervals.
    max_periods : float
        Longest transient in forcing periods before a run is called one with no period.
    device : Device, optional
        The harvester whose membranes give the outputs (default the paper's).
    tol : float
        Periodicity tolerance.
    window_time : float
        Averaging span of runs without a period, as in :func:`~vibroimpact.design_map`.

    Returns
    -------
    xarray.Dataset
        On ``(distribution, attractor)``, ``distribution`` = ``["switch-on", "state space"]``: ``count``,
        ``share``, ``share_low``, ``share_high``, ``U_T`` (V; NaN where no start of that distribution reaches
        the attractor), ``U_T_se``, ``settled``; ``label`` on ``attractor`` (most starts first); per
        distribution ``E_U_T``; on ``(distribution, start)`` each start (``start_phase``, ``start_Z``,
        ``start_Zdot``) and the attractor it reaches (``reached``).  Attributes: the box's bounds, ``n``,
        ``seed``, ``confidence``, the settings and the parameters.

    Examples
    --------
    Between G1 and G2 at the paper's incline (d = 0.13975) the 2:1 and the 3:1 motions coexist; the 3:1 draws
    most starts of both distributions:

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.13975 / 0.6225, beta=math.pi / 6)
    >>> bs = vi.basin_stability(p, n=100, seed=0)
    >>> bs.label.values.tolist(), bs.distribution.values.tolist()
    (['3:1 period-2', '2:1 period-2'], ['switch-on', 'state space'])
    >>> bs["count"].values.tolist()
    [[86, 14], [76, 24]]
    >>> bs.share.sum("attractor").values.tolist()
    [1.0, 1.0]
    """
    lo, hi = _check(params, n, seed, v_range, confidence, max_periods)
    device = PAPER if device is None else device
    F = float(params.physical.get("F", device.F))
    settings = dict(max_periods=float(max_periods), tol=float(tol), window=WINDOW)
    starts, per_dist, events = [], [], []
    for name in DISTRIBUTIONS:
        st, runs = _runs(params, name, n, seed, (lo, hi), settings)
        atts, nev = point_attractors(runs, params.d, params.gbar, params.r, F, device, float(window_time),
                                     float(confidence))
        starts.append(st)
        per_dist.append(atts)
        events.append(nev)
    labels, index = _union(per_dist)
    ds = _dataset(labels, index, per_dist, starts, n, confidence)
    ds["n_events"] = ("distribution", np.array(events, np.int64),
                      {"units": "1", "long_name": "events simulated over all starts of the distribution"})
    ds.attrs.update(_start_attrs(params, n, seed, lo, hi, confidence), **settings, window_time=float(window_time),
                    F=F, d=params.d, gbar=params.gbar, r=params.r,
                    **{f"physical_{k}": float(v) for k, v in params.physical.items()})
    return annotate(ds)


def _start_attrs(params, n, seed, lo, hi, confidence):
    """The start distributions, exactly: what a reader needs to draw the same starts."""
    half = 0.5 * params.d
    return {"n": int(n), "seed": int(seed), "confidence": float(confidence), "phase_range": [0.0, 2 * math.pi],
            "Z_range": [-half, half], "Zdot_range": [lo, hi],
            "switch_on_starts": f"{n} starts at rest on the bottom membrane (Z = d/2 = {half!r}, Zdot = 0), forcing "
                                f"phase uniform in [0, 2 pi): vibroimpact.start_states({n}, distribution='rest', "
                                f"seed={seed})",
            "state_space_starts": f"{n} starts at t = 0 uniform over the box: forcing phase in [0, 2 pi), Z in "
                                  f"[{-half!r}, {half!r}], Zdot in [{lo!r}, {hi!r}], drawn in that order with "
                                  f"numpy.random.default_rng({seed})"}


def _dataset(labels, index, per_dist, starts, n, confidence):
    """The shares, intervals and outputs per (distribution, attractor), and each start's attractor."""
    shape = (len(DISTRIBUTIONS), len(labels))
    count = np.zeros(shape, np.int64)
    u_t, u_t_se = np.full(shape, np.nan), np.full(shape, np.nan)
    settled = np.zeros(shape, bool)
    reached = np.full((len(DISTRIBUTIONS), n), -1, np.int64)
    for i, (atts, idx) in enumerate(zip(per_dist, index, strict=True)):
        for att, k in zip(atts, idx, strict=True):
            count[i, k], u_t[i, k], u_t_se[i, k], settled[i, k] = att.count, att.U_T, att.U_T_se, att.settled
            reached[i, att.runs] = k
    ci = np.array([[share_interval(int(c), n, confidence) for c in row] for row in count]).reshape(*shape, 2)
    share = count / n
    level = f"{confidence:g} Clopper-Pearson interval"
    da, ds_ = ("distribution", "attractor"), ("distribution", "start")
    out = xr.Dataset(
        {"label": ("attractor", np.array(labels, dtype=str),
                   {"units": "1", "long_name": "attractor: n:m impacts per period and period, or with no period chaotic, "
                    "quasi-periodic or unsettled by its long run (most starts over both distributions first)"}),
         "count": (da, count, {"units": "1", "long_name": "starts of the distribution reaching the attractor"}),
         "share": (da, share, {"units": "1", "long_name": "share of the distribution's starts reaching the attractor "
                               "(basin stability for the state-space distribution)"}),
         "share_low": (da, ci[..., 0], {"units": "1", "long_name": f"lower end of the share's {level}"}),
         "share_high": (da, ci[..., 1], {"units": "1", "long_name": f"upper end of the share's {level}"}),
         "U_T": (da, u_t, {"units": "V", "long_name": "average voltage gain per unit time U_T of the attractor, from the "
                           "distribution's runs on it (NaN where none reaches it)"}),
         "U_T_se": (da, u_t_se, {"units": "V", "long_name": "standard error of U_T (a long run's, with no period; NaN "
                                 "where settled or unknown)"}),
         "settled": (da, settled, {"units": "1", "long_name": "U_T is exact: the attractor's Newton-solved or sticking "
                                   "cycle, or resting"}),
         "E_U_T": ("distribution", (share * np.nan_to_num(u_t)).sum(axis=1),
                   {"units": "V", "long_name": "expected U_T from a random start of the distribution: sum of share x U_T"}),
         "reached": (ds_, reached, {"units": "1", "long_name": "index of the attractor the start reaches"}),
         "start_phase": (ds_, np.stack([s[0] for s in starts]), {"units": "rad", "long_name": "forcing phase at the "
                                                                 "start (t = 0)"}),
         "start_Z": (ds_, np.stack([s[1] for s in starts]), {"units": "1", "long_name": "relative position Z at the "
                                                             "start (non-dimensional; the bottom wall at d/2)"}),
         "start_Zdot": (ds_, np.stack([s[2] for s in starts]), {"units": "1", "long_name": "relative velocity Zdot at "
                                                                "the start (non-dimensional)"})},
        coords={"distribution": list(DISTRIBUTIONS), "attractor": np.arange(len(labels)), "start": np.arange(n)})
    out["distribution"].attrs.update(long_name="start distribution: switch-on (at rest on the bottom membrane, "
                                     "uniform phase) or state space (uniform over the box of phase, Z and Zdot)")
    return out
