"""Speed against accuracy for the largest Lyapunov exponent ``lambda_1``.

On a few motions, each method's estimate of ``lambda_1`` per unit of non-dimensional time t (forcing period 2)
is compared with a long run of the exact tangent map (:func:`~vibroimpact.lyapunov`, whose batch-means interval
is the reference's uncertainty), against its wall-clock cost, measured in one process, one run after another:

* ``tangent``: :func:`~vibroimpact.lyapunov` itself (the Jacobians of the impact map along a run of the exact
  simulator) at several run lengths;
* ``benettin-exact`` and ``benettin-DOP853``: Benettin's two-trajectory method on the impact map.  A second
  trajectory starts ``delta`` away from the first in the impact state ``(t_k, Zdot-_k)``, both fly to their
  next impact, and the separation is measured between the two states of the **same impact count** ``k + 1``
  (``Delta t = t'_{k+1} - t_{k+1}``, ``Delta Zdot- = Zdot-'_{k+1} - Zdot-_{k+1}``, Euclidean norm), never at a
  common time: at a common time one ball may have rebounded and the other not, and the velocities differ by
  ``O(1)``.  The second trajectory is then put back ``delta`` away along the separation (renormalised at every
  impact), so that it starts each flight from the first one's wall.  Where it meets the other wall (a flight
  that grazes for one and not the other) the step is not counted and the second trajectory restarts
  ``delta`` away along its last direction (``resyncs``).  The flights are solved by the exact simulator's flight
  solver (the one :func:`~vibroimpact.simulate` chains) or by ``solve_ivp`` DOP853 with terminal events
  (:func:`vibroimpact.benchmarks.methods.ivp_flight`) at a tolerance ladder; ``delta`` is the square root of
  the flights' error level (machine epsilon, or the tolerance), the usual choice for a finite difference;
* ``nolds-lyap_r`` and ``nolds-lyap_e``: Rosenstein's and Eckmann's time-series estimators of the nolds
  package on the sequence of signed pre-impact velocities, which give an exponent per impact, converted to
  per unit time by the run's mean time between impacts.

Repeats start from different impacts of the motion (bottom impacts of a run from its start, after a
transient).  Every cell of the dataset has a value or says why not (``reason``).
"""

from __future__ import annotations

import importlib
import importlib.util
import math
import time
import warnings
from importlib.metadata import version

import numpy as np
import xarray as xr

from ..analysis.lyapunov import MIN_PER_BATCH, lyapunov
from ..analysis.motions import identify_attractor
from ..analysis.orbits import find_orbit
from ..dynamics import impact as law
from ..dynamics import kernels as K
from ..dynamics.device import PAPER
from ..dynamics.events import flight_impact
from ..dynamics.params import Params
from ..dynamics.runs import simulate
from .methods import ivp_flight

__all__ = ["MOTIONS", "FAMILIES", "lyapunov_precision", "benettin", "exact_flight", "series_exponent",
           "load_nolds", "summarise"]

#: the motions compared: (beta, d, phi, v0, word of the periodic orbit or None); the chaotic one is the
#: speed benchmarks' chaotic scene, the 2:1 the bistable 2:1 of Figure 8 (e), the 3:1 one just below its fold
#: G2 (its largest multiplier about 0.89: :func:`vibroimpact.find_orbit`)
MOTIONS = {
    "chaotic": (math.pi / 3, 0.235, 0.4, 0.6, None),
    "2:1": (math.pi / 6, 0.14, 5.855, 0.4185, "BBT"),
    "3:1 near fold": (math.pi / 6, 0.14195, 5.864, 0.4069, "BBBT"),
}

#: the method families, in the order of the dataset's solvers
FAMILIES = ("tangent", "benettin-exact", "benettin-DOP853", "nolds-lyap_r", "nolds-lyap_e")

#: embedding of the time-series estimators: ``2 m + 1`` for the impact map's ``m = 2`` dimensions
#: (Takens), and Eckmann's local maps of the map's own dimension
NOLDS_SETTINGS = {"emb_dim": 5, "matrix_dim": 2}

#: impacts between the reference run's end and the first repeat's start, and after each repeat's longest run
START_GAP = 1000


def _params(beta, d):
    return Params(d=d, gbar=PAPER.gbar(beta), r=PAPER.r)


def exact_flight(theta, z0, u, d, gbar):
    """The next impact of a flight by the exact simulator's flight solver.

    Parameters
    ----------
    theta : float
        Forcing phase at the flight's start.
    z0, u : float
        Position and velocity at the start.
    d, gbar : float
        Model parameters (``gbar < 1``).

    Returns
    -------
    tuple
        ``(tau, wall, Zdot-)``; ``(inf, 0, nan)`` where no impact comes.

    Examples
    --------
    The first flight of Figure 7 (a)'s orbit, as the simulator chains it:

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
    >>> tau, wall, v = exact_flight(1.015, p.d / 2, -p.r * 0.1924, p.d, p.gbar)
    >>> run = vi.simulate(p, 1.015, 0.1924, n_impacts=2)
    >>> bool(wall == run.wall.values[1]), bool(tau == run.t.values[1]), bool(v == run.v_minus.values[1])
    (True, True, True)
    """
    theta = theta % (2 * math.pi)
    alpha = math.acos(-gbar)
    return flight_impact(theta, math.cos(theta), math.sin(theta), alpha, z0, u, d, gbar, math.inf)


def benettin(flight, p: Params, phi: float, v0: float, n_impacts: int, *, delta: float = 1.5e-8,
             transient: int | None = None) -> dict:
    """Benettin's two-trajectory estimate of ``lambda_1`` on the impact map, separation measured at the
    same impact count and renormalised at every impact (see the module's notes).

    Parameters
    ----------
    flight : callable
        ``flight(theta, z0, u)`` -> ``(tau, wall, Zdot-)``: the next impact of a flight.
    p : Params
        The parameters.
    phi, v0 : float
        The start: a bottom impact at phase ``phi`` with pre-impact velocity ``v0``.
    n_impacts : int
        Impacts followed, the transient included.
    delta : float
        The separation the second trajectory is put back to.
    transient : int, optional
        Impacts before the stretching is counted (default a tenth).

    Returns
    -------
    dict
        ``per_impact``, ``per_time`` (``lambda_1``), ``resyncs`` and ``status`` (``"ok"`` or why not).

    Raises
    ------
    ValueError
        A bad ``n_impacts`` or ``delta``.

    Examples
    --------
    >>> import math
    >>> p = _params(math.pi / 6, 0.14)
    >>> out = benettin(lambda th, z, u: exact_flight(th, z, u, p.d, p.gbar), p, 5.855, 0.4185, 300)
    >>> out["status"], round(out["per_time"], 2)
    ('ok', -0.24)
    """
    if isinstance(n_impacts, bool) or not isinstance(n_impacts, (int, np.integer)) or n_impacts < 2:
        raise ValueError(f"n_impacts = {n_impacts!r}; allowed: an integer >= 2")
    if not (isinstance(delta, (int, float)) and 0 < delta < 1e-2):
        raise ValueError(f"delta = {delta!r}; allowed: a separation in (0, 1e-2)")
    transient = int(n_impacts) // 10 if transient is None else int(transient)
    half, r = p.d / 2, p.r
    theta, wall, vm = phi % (2 * math.pi), 1, v0
    ddt, ddv = delta / math.sqrt(2), delta / math.sqrt(2)  # the second trajectory's offsets in (t, Zdot-)
    total, span, counted, resyncs = 0.0, 0.0, 0, 0
    for k in range(int(n_impacts)):
        z0 = wall * half
        tau, w1, v1 = flight(theta, z0, law.rebound(vm, r))
        tau2, w2, v2 = flight(theta + math.pi * ddt, z0, law.rebound(vm + ddv, r))
        if w1 == 0:
            return dict(per_impact=math.nan, per_time=math.nan, resyncs=resyncs,
                        status=f"no impact after impact {k}: the flight solver found none")
        gap_t, gap_v = ddt + tau2 - tau, v2 - v1
        g = math.hypot(gap_t, gap_v)
        if w2 != w1 or not math.isfinite(g) or g == 0.0:
            resyncs += 1  # the pair parted walls: restart delta away along the last direction
        else:
            if k >= transient:
                total += math.log(g / delta)
                span += tau
                counted += 1
            ddt, ddv = delta * gap_t / g, delta * gap_v / g
        theta, wall, vm = (theta + math.pi * tau) % (2 * math.pi), w1, v1
    if counted == 0:
        return dict(per_impact=math.nan, per_time=math.nan, resyncs=resyncs,
                    status="no step counted: the pair parted walls at every impact")
    status = "ok" if resyncs <= counted // 10 else f"the pair parted walls at {resyncs} of {n_impacts} impacts"
    return dict(per_impact=total / counted, per_time=total / span, resyncs=resyncs, status=status)


def load_nolds():
    """nolds' estimators module and how it was loaded, or ``(None, reason)``.

    nolds 0.6.3 fails at import on Python 3.11 (its ``datasets`` module calls ``importlib.resources.files``
    on a module, which Python accepts from 3.12 on); its estimators live in ``nolds.measures``, which imports
    nothing of the package, so where the package's import fails that module is loaded on its own.

    Returns
    -------
    tuple
        ``(module, note)``, or ``(None, reason)`` where nolds is not installed.

    Examples
    --------
    >>> mod, note = load_nolds()
    >>> mod is None or callable(mod.lyap_r)
    True
    """
    try:
        import nolds

        return nolds, f"nolds {_nolds_version()}"
    except ModuleNotFoundError:
        return None, "not installed (pip install nolds: the 'peers' extra)"
    except TypeError as err:  # nolds 0.6.3 on Python < 3.12
        spec = importlib.util.find_spec("nolds")
        path = f"{spec.submodule_search_locations[0]}/measures.py"
        mspec = importlib.util.spec_from_file_location("_nolds_measures", path)
        mod = importlib.util.module_from_spec(mspec)
        mspec.loader.exec_module(mod)
        return mod, f"nolds {_nolds_version()} (nolds.measures loaded on its own: the package's import fails: {err})"


def _nolds_version():
    return version("nolds")


def series_exponent(measures, method: str, series) -> tuple[float, str]:
    """``lambda_1`` per step of a time series by a nolds estimator, with ``"ok"`` or why it is not finite.

    Parameters
    ----------
    measures : module
        nolds' estimators (:func:`load_nolds`).
    method : str
        ``"lyap_r"`` (Rosenstein) or ``"lyap_e"`` (Eckmann, its largest exponent).
    series : array_like
        The series (one value per impact).

    Returns
    -------
    tuple
        ``(exponent per step, status)``.

    Raises
    ------
    ValueError
        An unknown ``method``.

    Examples
    --------
    >>> import numpy as np
    >>> mod, _ = load_nolds()
    >>> x = np.empty(600); x[0] = 0.3
    >>> for k in range(599): x[k + 1] = 4 * x[k] * (1 - x[k])     # the logistic map: ln 2 per step
    >>> lam, status = series_exponent(mod, "lyap_r", x) if mod else (0.69, "ok")
    >>> status, bool(lam > 0)
    ('ok', True)
    """
    if method not in ("lyap_r", "lyap_e"):
        raise ValueError(f"method = {method!r}; allowed: 'lyap_r' or 'lyap_e'")
    x = np.asarray(series, dtype=float)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            if method == "lyap_r":
                lam = float(measures.lyap_r(x, emb_dim=NOLDS_SETTINGS["emb_dim"], fit="poly"))
            else:
                lam = float(measures.lyap_e(x, **NOLDS_SETTINGS)[0])
    except Exception as err:  # a failing estimator is a result, recorded with its reason
        return math.nan, f"{method} raised {type(err).__name__}: {err}"
    if not math.isfinite(lam):
        return lam, (f"{method} gives {lam}: the series repeats (a periodic motion), so neighbours lie at "
                     "distance 0 and the logarithms are infinite" if math.isinf(lam) else f"{method} gives {lam}")
    return lam, "ok"


def _ladder(tangent_n, benettin_n, ivp_n, ivp_tols, series_n):
    """(label, family, impacts, tolerance, delta) of every solver."""
    eps = np.finfo(float).eps
    out = [(f"tangent n={n}", "tangent", n, math.nan, math.nan) for n in tangent_n]
    out += [(f"Benettin exact n={n}", "benettin-exact", n, math.nan, math.sqrt(eps)) for n in benettin_n]
    out += [(f"Benettin DOP853 rtol={tol:.0e} n={n}", "benettin-DOP853", n, tol, math.sqrt(tol))
            for tol in ivp_tols for n in ivp_n]
    out += [(f"nolds {m} n={n}", f"nolds-{m}", n, math.nan, math.nan) for m in ("lyap_r", "lyap_e")
            for n in series_n]
    return out


def _starts(p, phi, v0, repeats, skip, longest):
    """Bottom-impact starts ``(phase, Zdot-)`` on the motion for each repeat: on a run from the motion's start,
    after its first ``skip`` impacts (the reference's) and ``longest`` + :data:`START_GAP` impacts apart, so that
    on a chaotic motion the repeats' runs and the reference's share no stretch of trajectory."""
    stride = int(longest) + START_GAP
    run = simulate(p, phi, v0, n_impacts=int(skip) + START_GAP + stride * repeats + 20)
    idx = np.flatnonzero(K.hits(run.kind.values) & (run.wall.values == 1))
    out = []
    for j in range(repeats):
        k = idx[np.searchsorted(idx, int(skip) + START_GAP + stride * j)]
        out.append((float(run.phase.values[k]), float(run.v_minus.values[k])))
    return out


def _tangent(p, phi, v0, n):
    batches = max(2, min(20, (n - n // 10 - 1) // MIN_PER_BATCH))
    ly = lyapunov(p, phi, v0, n, batches=batches)
    return dict(per_impact=ly.per_impact[0], per_time=ly.per_time[0], resyncs=0, status=ly.status)


def _series(measures, method, p, phi, v0, n):
    run = simulate(p, phi, v0, n_impacts=n)
    hit = K.hits(run.kind.values)
    t, v = run.t.values[hit], run.v_minus.values[hit]
    lam, status = series_exponent(measures, method, v)
    mean_dt = (t[-1] - t[0]) / (t.size - 1)
    return dict(per_impact=lam, per_time=lam / mean_dt, resyncs=0, status=status)


def _one(family, setting, p, start, measures):
    """One estimate: ``dict(per_impact, per_time, resyncs, status)``."""
    (phi, v0), (_, _, n, tol, delta) = start, setting
    if family == "tangent":
        return _tangent(p, phi, v0, n)
    if family == "benettin-exact":
        return benettin(lambda th, z, u: exact_flight(th, z, u, p.d, p.gbar), p, phi, v0, n, delta=delta)
    if family == "benettin-DOP853":
        return benettin(lambda th, z, u: ivp_flight(th, z, u, p.d, p.gbar, tol, tol * 1e-2, "DOP853"), p, phi,
                        v0, n, delta=delta)
    return _series(measures, family.split("-", 1)[1], p, phi, v0, n)


def _reference(p, phi, v0, word, n_ref):
    start = time.perf_counter()
    ly = lyapunov(p, phi, v0, int(n_ref))
    seconds = time.perf_counter() - start
    floquet = math.nan
    if word is not None:
        run = simulate(p, phi, v0, n_impacts=START_GAP + 20)
        k = START_GAP + int(np.flatnonzero(run.wall.values[START_GAP:] == 1)[0])
        orbit = find_orbit(p, word, float(run.phase.values[k]), float(run.v_minus.values[k]))
        floquet = math.log(float(np.max(np.abs(orbit.eigenvalues)))) / 2.0  # period 2 in t
    label = identify_attractor(simulate(p, phi, v0, n_impacts=4000)).label
    return ly, seconds, floquet, label


def _check(name, values, low):
    """Integers at least ``low``, else a ValueError naming ``name``."""
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not v >= low:
            shown = values[0] if len(values) == 1 and name in ("n_ref", "repeats") else list(values)
            raise ValueError(f"{name} = {shown!r}; allowed: integers >= {low}")


def lyapunov_precision(*, n_ref=200_000, tangent_n=(100, 1000, 10_000, 100_000), benettin_n=(100, 1000, 10_000),
                       ivp_n=(100, 300), ivp_tols=(1e-6, 1e-9, 1e-12), series_n=(250, 500, 1000, 2000),
                       repeats=3, motions=None) -> xr.Dataset:
    """Error of every method's ``lambda_1`` against a long run of the tangent map, and its cost.

    Parameters
    ----------
    n_ref : int
        Impacts of the reference run (:func:`~vibroimpact.lyapunov`).
    tangent_n, benettin_n, ivp_n, series_n : sequence of int
        Run lengths (impacts) of the tangent map, Benettin on the exact flights, Benettin on DOP853 and
        the nolds estimators.
    ivp_tols : sequence of float
        DOP853's rtol (atol a hundredth of it).
    repeats : int
        Starts per motion (each method's interval is their spread).
    motions : dict, optional
        ``{name: (beta, d, phi, v0, word or None)}`` (default :data:`MOTIONS`).

    Returns
    -------
    xarray.Dataset
        Dimensions ``motion``, ``solver``, ``repeat``: ``lambda1`` (per unit time), ``lambda1_per_impact``,
        ``error``, ``seconds``, ``resyncs``, ``reason`` (``"ok"`` or why the estimate is not finite); per solver its ``family``, ``n_impacts``,
        ``tolerance`` and ``delta``; per motion the reference, its interval and Floquet value.

    Raises
    ------
    ValueError
        A bad size, tolerance or motion, naming it.

    Examples
    --------
    >>> ds = lyapunov_precision(n_ref=5000, tangent_n=(300,), benettin_n=(300,), ivp_n=(20,), ivp_tols=(1e-9,),
    ...                         series_n=(300,), repeats=2, motions={"2:1": MOTIONS["2:1"]})
    >>> ds.sizes["solver"], bool((ds.reason != "").all())
    (5, True)
    >>> float(abs(ds.lambda1.sel(solver="tangent n=300") - ds.lambda_floquet).max()) < 0.01
    True
    """
    motions = MOTIONS if motions is None else motions
    if not isinstance(motions, dict) or not motions:
        raise ValueError(f"motions = {motions!r}; allowed: a non-empty dict name -> (beta, d, phi, v0, word)")
    for name, vals, low in (("n_ref", [n_ref], 1000), ("tangent_n", tangent_n, 100), ("series_n", series_n, 250),
                            ("benettin_n", benettin_n, 20), ("ivp_n", ivp_n, 20), ("repeats", [repeats], 1)):
        _check(name, list(vals), low)
    if not all(isinstance(t, float) and 0 < t < 1e-3 for t in ivp_tols):
        raise ValueError(f"ivp_tols = {list(ivp_tols)!r}; allowed: floats in (0, 1e-3)")
    ladder = _ladder(tangent_n, benettin_n, ivp_n, ivp_tols, series_n)
    measures, nolds_note = load_nolds()
    shape = (len(motions), len(ladder), int(repeats))
    lam, lam_i, sec = (np.full(shape, np.nan) for _ in range(3))
    resyncs = np.zeros(shape, dtype=np.int64)
    status = np.full(shape, "", dtype=object)
    ref = {k: np.full(len(motions), np.nan) for k in ("ref", "low", "high", "ref_s", "dt", "floquet")}
    labels, starts = [], np.full((len(motions), int(repeats), 2), np.nan)
    _warm_up()
    for i, (beta, d, phi, v0, word) in enumerate(motions.values()):
        p = _params(beta, d)
        ly, ref["ref_s"][i], ref["floquet"][i], label = _reference(p, phi, v0, word, n_ref)
        labels.append(label)
        ref["ref"][i], (ref["low"][i], ref["high"][i]) = ly.per_time[0], ly.interval_time[0]
        ref["dt"][i] = ly.mean_time
        for j, start in enumerate(_starts(p, phi, v0, int(repeats), n_ref, max(s[2] for s in ladder))):
            starts[i, j] = start
            for s, setting in enumerate(ladder):
                family = setting[1]
                if family.startswith("nolds") and measures is None:
                    status[i, s, j] = f"nolds {nolds_note}"
                    continue
                t0 = time.perf_counter()
                out = _one(family, setting, p, start, measures)
                sec[i, s, j] = time.perf_counter() - t0
                lam[i, s, j], lam_i[i, s, j] = out["per_time"], out["per_impact"]
                resyncs[i, s, j], status[i, s, j] = out["resyncs"], out["status"]
    return _dataset(motions, ladder, (lam, lam_i, sec, resyncs, status, starts), ref, labels,
                    dict(n_ref=int(n_ref), repeats=int(repeats), nolds=nolds_note, **NOLDS_SETTINGS))


def _warm_up():
    """Compile the numba kernels before the timings."""
    p = _params(math.pi / 6, 0.14)
    lyapunov(p, 5.855, 0.4185, 300, batches=2)
    exact_flight(1.0, p.d / 2, -0.2, p.d, p.gbar)


def _dataset(motions, ladder, arrays, ref, labels, attrs):
    lam, lam_i, sec, resyncs, status, starts = arrays
    err = np.abs(lam - ref["ref"][:, None, None])
    cube = ("motion", "solver", "repeat")
    per_t = "1/t (per unit of non-dimensional time t, forcing period 2)"
    ds = xr.Dataset(
        {
            "lambda1": (cube, lam, {"units": per_t, "long_name": "largest Lyapunov exponent lambda_1 per unit time"}),
            "lambda1_per_impact": (cube, lam_i, {"units": "1/impact", "long_name": "lambda_1 per impact"}),
            "error": (cube, err, {"units": per_t, "long_name": "|lambda_1 - lambda_1 of the reference run|"}),
            "seconds": (cube, sec, {"units": "s", "long_name": "wall-clock time of the estimate (its run included)"}),
            "resyncs": (cube, resyncs, {"units": "1", "long_name": "Benettin: impacts where the pair parted walls "
                                                                  "(not counted; restarted delta away)"}),
            "reason": (cube, status.astype(str), {"long_name": "ok, or why the estimate is not finite or what it passed through"}),
            "start_phase": (("motion", "repeat"), starts[..., 0], {"units": "rad", "long_name": "the repeat's start: "
                                                                           "phase of a bottom impact"}),
            "start_v": (("motion", "repeat"), starts[..., 1], {"units": "1", "long_name": "the repeat's start: "
                                                                     "its pre-impact velocity"}),
            "family": ("solver", [s[1] for s in ladder], {"long_name": "method family"}),
            "n_impacts": ("solver", np.array([s[2] for s in ladder], dtype=np.int64),
                          {"units": "1", "long_name": "impacts of the run (the series' length for nolds)"}),
            "tolerance": ("solver", [s[3] for s in ladder], {"units": "1", "long_name": "DOP853 rtol (atol rtol/100)"}),
            "delta": ("solver", [s[4] for s in ladder],
                      {"units": "1", "long_name": "Benettin: separation renormalised to, in (t, Zdot-)"}),
            "lambda_ref": ("motion", ref["ref"], {"units": per_t, "long_name": "lambda_1 of the reference run "
                                                                               "(tangent map)"}),
            "lambda_ref_low": ("motion", ref["low"], {"units": per_t, "long_name": "reference: lower end of its "
                                                                                   "95 % batch-means interval"}),
            "lambda_ref_high": ("motion", ref["high"], {"units": per_t, "long_name": "reference: upper end"}),
            "ref_seconds": ("motion", ref["ref_s"], {"units": "s", "long_name": "wall-clock time of the reference"}),
            "mean_time": ("motion", ref["dt"], {"units": "1", "long_name": "mean time between impacts (reference)"}),
            "lambda_floquet": ("motion", ref["floquet"],
                               {"units": per_t, "long_name": "ln max|mu| / 2 of the periodic orbit (find_orbit; "
                                                             "NaN: no period)"}),
            "motion_label": ("motion", labels, {"long_name": "the attractor the start settles on (exact simulator)"}),
            "start": ("motion", [f"beta={m[0]:.6g}, d={m[1]:g}, phi={m[2]:g}, v0={m[3]:g}" for m in motions.values()],
                      {"long_name": "parameters and start (a bottom impact)"}),
        },
        coords={"motion": ("motion", list(motions), {"long_name": "motion compared"}),
                "solver": ("solver", [s[0] for s in ladder], {"long_name": "method and its setting"}),
                "repeat": ("repeat", np.arange(sec.shape[2]), {"units": "1", "long_name": "start on the motion"})},
    )
    ds.attrs.update(attrs, reference="vibroimpact.lyapunov (exact tangent map), n_ref impacts",
                    separation="Benettin: states compared at the same impact count, renormalised every impact")
    return ds


def summarise(ds: xr.Dataset) -> xr.Dataset:
    """Per motion and solver, over the repeats: the mean estimate, the median, smallest and largest error,
    the median relative error, the median cost (one slow run on a shared machine does not move it), the repeats
    with a finite estimate and those whose sign is the reference's.

    Parameters
    ----------
    ds : xarray.Dataset
        A :func:`lyapunov_precision` dataset.

    Returns
    -------
    xarray.Dataset
        Dimensions ``motion``, ``solver``.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> ds = xr.Dataset({"lambda1": (("motion", "solver", "repeat"), [[[0.2, 0.3], [np.nan, -0.1]]]),
    ...                  "seconds": (("motion", "solver", "repeat"), [[[1.0, 3.0], [1.0, 1.0]]]),
    ...                  "lambda_ref": ("motion", [0.25])})
    >>> ds["error"] = abs(ds.lambda1 - ds.lambda_ref)
    >>> s = summarise(ds)
    >>> s.finite.values.tolist(), s.sign_agrees.values.tolist(), s.seconds.values.tolist()
    ([[2, 1]], [[2, 0]], [[2.0, 1.0]])
    """
    finite = np.isfinite(ds.lambda1)
    rel = ds.error / abs(ds.lambda_ref)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN cells: NaN
        out = xr.Dataset({
            "lambda1": ds.lambda1.mean("repeat"),
            "error_median": ds.error.median("repeat"),
            "error_min": ds.error.min("repeat"),
            "error_max": ds.error.max("repeat"),
            "relative_error": rel.median("repeat"),
            "seconds": ds.seconds.median("repeat"),
            "finite": finite.sum("repeat"),
            "sign_agrees": (finite & (np.sign(ds.lambda1) == np.sign(ds.lambda_ref))).sum("repeat"),
        })
    return out
