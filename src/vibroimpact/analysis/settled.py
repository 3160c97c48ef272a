"""What is well-posed about a simulated attractor: the exact cycle of a periodic motion, and long-run
statistics of an aperiodic one.

A run is declared periodic once two consecutive cycles agree to the periodicity tolerance, so the
impacts it records are the orbit's only to within that tolerance divided by the distance of the
orbit's largest eigenvalue from the unit circle: near a period doubling or a fold (1e-6 and worse
measured along the paper's sweeps) they depend on where the transient happened to stop, and a
last-bit change of one ``sin`` moves them.  :func:`polish_cycle` solves the periodic orbit through
the recorded cycle by Newton's method (:func:`vibroimpact.analysis.orbits.solve_orbit`) and returns it from a
canonical first impact, so the values are the orbit's to rounding, wherever the run stopped.  A cycle
that sticks is the orbit already (every state that sticks leaves the wall at the release phase), to the
accuracy of its summed chatter.

Where no period is found (chaos, a quasi-periodic motion, a period longer than the cap, or a transient
longer than the allowed time), single impacts and short-window averages are samples of the motion and
part company between two machines after a few impacts; what is reproducible is their long-run
statistics.  :func:`long_run` continues the motion for a fixed number of impacts and returns the
batch means of what the figures draw, with their standard errors.
"""

from __future__ import annotations

import numpy as np

from ..dynamics import kernels as K
from ..dynamics.flight import TWO_PI

__all__ = ["polish_cycle", "long_run", "batch_means", "canonical_start",
           "SETTLE_MATCH", "STICK_REL", "LONG_IMPACTS", "LONG_BATCHES"]

#: a Newton orbit is the recorded cycle's own when every impact's velocity and phase lie within this of
#: the recorded ones (the recorded cycle converged to the periodicity tolerance divided by the orbit's
#: distance from a bifurcation: up to 2e-4 was measured; distinct orbits of one word lie further apart)
SETTLE_MATCH = 1e-3
#: relative accuracy of a sticking cycle's values: its chatter is summed where the acceleration changes
#: by less than 1e-9 of itself before the bounces accumulate (vibroimpact.dynamics.kernels), and two machines'
#: sticking cycles were measured 1.06e-9 apart (relative) in the design maps' outputs
STICK_REL = 1e-9
#: impacts of an aperiodic motion's long run, and the batches its means are taken over
LONG_IMPACTS = 4000
LONG_BATCHES = 20


def canonical_start(wall, kind, phase) -> int:
    """Index of the cycle's canonical first event: the bottom impact with the smallest phase (any
    event with the smallest phase where the cycle has no bottom impact).  Phases are well-conditioned,
    so two runs of the same orbit start its cycle at the same impact."""
    wall, kind, phase = (np.asarray(a) for a in (wall, kind, phase))
    ph = np.mod(phase, TWO_PI)
    cand = np.flatnonzero((wall == 1) & (kind == K.IMPACT))
    if not cand.size:
        cand = np.arange(ph.size)
    return int(cand[np.argmin(ph[cand])])


def polish_cycle(d, gbar, r, t, wall, v_minus, phase, kind, span) -> dict:
    """The exact periodic orbit through one recorded cycle of a run.

    Parameters
    ----------
    d, gbar, r : float
        Parameters.
    t, wall, v_minus, phase, kind : array_like
        The cycle's events in order (one period: from an event up to, not including, its return).
    span : float
        The cycle's duration (a whole number of forcing periods, 2 time units each), e.g. from an
        event to the same event one period earlier.

    Returns
    -------
    dict
        ``status``: ``"newton"`` (solved; the orbit matches the cycle to :data:`SETTLE_MATCH`),
        ``"sticking"`` (the recorded cycle: it sticks, so it is the orbit to :data:`STICK_REL`; not
        settled), or why it is not settled (a grazing
        contact, Newton failed, another orbit, not admissible); ``settled`` (bool); and the cycle from
        its canonical first event (:func:`canonical_start`): ``t`` (from 0), ``wall``, ``v_minus``,
        ``phase``, ``kind``; where settled, the orbit's ``jacobian`` (its map's over one period, eq.
        ``Lin2``), its factors ``step_jacobians`` (one per flight) and ``multipliers`` (its eigenvalues).

    Examples
    --------
    The 2:1 cycle of a run at the point of Figure 7 (a), solved exactly: its multipliers are a complex pair
    of modulus ``r^N = 0.125`` for ``N = 3`` impacts (the map's determinant is ``r^(2N)``):

    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
    >>> a = vi.identify_attractor(vi.simulate(p, phi=1.015, v0=0.1924, n_impacts=200))
    >>> c = a.cycle
    >>> orbit = vi.polish_cycle(p.d, p.gbar, p.r, c.t.values, c.wall.values, c.v_minus.values, c.phase.values,
    ...                         c.kind.values, span=2.0 * a.period)
    >>> orbit["status"], orbit["settled"], orbit["wall"].tolist()
    ('newton', True, [1, -1, 1])
    >>> [round(float(abs(m)), 9) for m in orbit["multipliers"]]
    [0.125, 0.125]
    """
    from ..dynamics.params import Params
    from .orbits import OrbitError, orbit_from_vector, parse_word, solve_orbit, step_jacobians

    t, v_minus, phase = (np.asarray(a, dtype=float) for a in (t, v_minus, phase))
    wall, kind = np.asarray(wall, dtype=np.int8), np.asarray(kind, dtype=np.int8)
    n = t.size
    j0 = canonical_start(wall, kind, phase)
    k = max(int(round(float(span) / 2.0)), 1)
    span = 2.0 * k
    order = np.roll(np.arange(n), -j0)
    tt = np.mod(t[order] - t[j0], span)
    out = dict(t=tt, wall=wall[order], v_minus=v_minus[order], phase=np.mod(phase[order], TWO_PI),
               kind=kind[order], status="", settled=False)
    if np.any((kind == K.STICK) | (kind == K.RELEASE)):  # its chatter's last bounces are grazing contacts
        # every state that sticks leaves the wall at the release phase, so the recorded cycle is the orbit,
        # to the accuracy of its summed chatter (STICK_REL), not to rounding
        return out | dict(status="sticking")
    if np.any(kind == K.GRAZING):
        return out | dict(status="not settled: a grazing contact in the cycle")
    tau = np.diff(np.append(tt, span))
    z0 = np.concatenate([[out["phase"][0]], tau, out["v_minus"]])
    word = "".join("B" if w == 1 else "T" for w in out["wall"])
    try:
        z = solve_orbit(z0, out["wall"].astype(np.int64), d, gbar, r, k)
        o = orbit_from_vector(Params(d=d, gbar=gbar, r=r), word, k, z)
    except (OrbitError, ValueError, np.linalg.LinAlgError) as err:
        return out | dict(status=f"not settled: Newton failed ({err})")
    dphase = (o.phase - out["phase"] + np.pi) % TWO_PI - np.pi
    dev = max(float(np.max(np.abs(o.v_minus - out["v_minus"]))), float(np.max(np.abs(dphase))))
    if not dev <= SETTLE_MATCH:
        return out | dict(status=f"not settled: the Newton orbit lies {dev:.1e} from the cycle")
    if not o.admissible:
        return out | dict(status=f"not settled: the Newton orbit is not admissible ({o.reason})")
    return out | dict(t=o.t, v_minus=np.array(o.v_minus), phase=np.array(o.phase), status="newton", settled=True,
                      multipliers=np.asarray(o.eigenvalues), jacobian=np.asarray(o.jacobian),
                      step_jacobians=step_jacobians(o.z, parse_word(o.word), float(gbar), float(r)))


def batch_means(values, batches: int = LONG_BATCHES):
    """Mean and its standard error from ``batches`` consecutive batches of equal length."""
    v = np.asarray(values, dtype=float)
    m = v.size // batches
    if m < 1:
        return np.nan, np.nan
    b = v[:m * batches].reshape(batches, m).mean(axis=1)
    return float(b.mean()), float(b.std(ddof=1) / np.sqrt(batches))


def long_run(d, gbar, r, phi, v0, *, impacts: int = LONG_IMPACTS, tol: float = 1e-9) -> dict:
    """An aperiodic motion continued for ``impacts`` events from a bottom impact ``(phi, v0)``.

    The start is typically the last bottom impact of a run that found no period.

    Parameters
    ----------
    d, gbar, r : float
        Parameters.
    phi, v0 : float
        Phase (rad) and pre-impact velocity of the bottom impact it starts from.
    impacts : int
        Events of the continuation.
    tol : float
        Periodicity tolerance: the continuation stops if it becomes periodic.

    Returns
    -------
    dict
        ``status``: ``"aperiodic"``, or ``"settles"`` when the continuation becomes periodic after all (a
        transient longer than the run that found no period: its statistics depend on where it settles, so
        none are given), or ``"stuck"``; the events ``t``, ``v_minus``, ``kind`` of the continuation
        (impacts and grazing contacts are ``kind`` 0 and 1); and ``exponents``, its Lyapunov exponents
        (:class:`~vibroimpact.analysis.lyapunov.Lyapunov`, the first tenth of it discarded) where it is
        aperiodic; where it settles, those of the same run continued to ``impacts`` impacts (the orbit it
        settles on); else None.

    Examples
    --------
    At d = 0.235 on the incline pi/3 the motion is chaotic: the largest exponent is positive, and the two add
    up to ``2 ln r = -1.386`` per impact (each impact contracts areas by ``r^2``), up to a boundary term of
    order ``1 / impacts``:

    >>> import math, vibroimpact as vi
    >>> gbar = vi.Device().gbar(math.pi / 3)
    >>> run = vi.long_run(0.235, gbar, 0.5, 0.42, 0.87, impacts=2000)
    >>> lam = run["exponents"]
    >>> run["status"], lam.per_impact[0] > 0.1, abs(sum(lam.per_impact) - 2 * math.log(0.5)) < 0.01
    ('aperiodic', True, True)
    """
    from ..dynamics.params import Params
    from ..dynamics.simulate import simulate

    run = simulate(Params(d=float(d), gbar=float(gbar), r=float(r)), float(phi), float(v0),
                   n_impacts=int(impacts), stop_when_periodic=True, tol=tol)
    from .lyapunov import exponents_of_run

    status = {"periodic": "settles", "stuck_forever": "stuck"}.get(run.attrs["status"], "aperiodic")
    lam = None
    if status == "aperiodic":
        lam = exponents_of_run(run, transient=int(impacts) // 10, batches=LONG_BATCHES)
    elif status == "settles":  # its exponents are those of the orbit it settles on: run on, all the impacts
        on = simulate(Params(d=float(d), gbar=float(gbar), r=float(r)), float(phi), float(v0), n_impacts=int(impacts))
        lam = exponents_of_run(on, transient=int(impacts) // 10, batches=LONG_BATCHES)
    return dict(status=status, t=run.t.values, v_minus=run.v_minus.values, kind=run.kind.values, exponents=lam)


def long_statistics(events: dict, batches: int = LONG_BATCHES):
    """Batch means of ``|Zdot-|`` over the impacts of a :func:`long_run`: ``(mean, se)``, NaN unless
    its status is ``"aperiodic"``."""
    if events["status"] != "aperiodic":
        return np.nan, np.nan
    hit = K.hits(events["kind"])
    return batch_means(np.abs(events["v_minus"][hit]), batches)
