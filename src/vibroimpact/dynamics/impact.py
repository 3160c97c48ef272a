"""The impact law: the ball's velocity relative to the cylinder after an impact, from the one before.

The law is Newton's, ``Zdot+ = -r Zdot-`` with a constant coefficient of restitution ``r``
(docs/guide/model.md).  Every part of the package that rebounds the ball calls :func:`rebound`,
and every derivative of the impact map (the orbits' Newton Jacobian, the step Jacobian of the
tangent map) calls :func:`rebound_slope`, ``dZdot+/dZdot-``: the event loop, the step Jacobian,
Newton's periodic orbits, grazing and admissibility, the family exit, the compared methods and the
peers, and the 40-digit reference simulator.

Both are numba functions inlined into the compiled kernels (``inline="always"``): with the constant
law the kernels compile to the same instructions as the inline product, so they run as fast and give
the same bits.  Their Python form (``rebound.py_func``, ``rebound_slope.py_func``) serves any number
type that supports the arithmetic: NumPy arrays, mpmath's numbers in the reference simulator.

Two results hold only for a constant ``r``, and ask :data:`CONSTANT_RESTITUTION` first:

* the chattering sum (``_accumulation_time`` in :mod:`~vibroimpact.dynamics.kernels`): the rebound speeds of a
  chattering sequence shrink by ``r`` at each bounce, so their flight times form a geometric series
  summed in closed form; with another law the event loop follows the bounces one by one instead;
* the sum of the two Lyapunov exponents, ``2 ln r`` per impact (:func:`exponent_sum`): each impact
  multiplies areas of the ``(t, Zdot)`` plane by ``r^2 Zdot_k / Zdot_{k+1}``; with another law
  :func:`exponent_sum` refuses, and the exponents themselves, computed from the step Jacobians, hold.

Another law replaces the two functions and the flag here, before the kernels are first compiled (the
compiled code takes them in as it was compiled; numba's cache is keyed by the package's sources,
:mod:`vibroimpact._numba_cache`, so a swapped law needs a cache directory of its own).
"""

import math

from numba import njit

#: Whether :func:`rebound` is ``-r v`` with ``r`` independent of the impact: the chattering sum and the
#: exponents' sum ``2 ln r`` hold only then.
CONSTANT_RESTITUTION = True


@njit(cache=True, error_model="numpy", inline="always")
def rebound(v, r):
    """Post-impact relative velocity ``Zdot+`` of an impact with pre-impact velocity ``v``.

    Parameters
    ----------
    v : float
        Pre-impact relative velocity ``Zdot-`` (positive on the bottom wall, negative on the top).
    r : float
        Coefficient of restitution.

    Returns
    -------
    float
        ``-r v``.
    """
    return -r * v


@njit(cache=True, error_model="numpy", inline="always")
def rebound_slope(v, r):
    """Derivative ``dZdot+/dZdot-`` of :func:`rebound` at ``v``, the impact's factor in the derivatives
    of the impact map.

    Parameters
    ----------
    v : float
        Pre-impact relative velocity ``Zdot-``.
    r : float
        Coefficient of restitution.

    Returns
    -------
    float
        ``-r`` (independent of ``v``).
    """
    return -r


def exponent_sum(r: float) -> float:
    """The sum of the two Lyapunov exponents per impact of a motion with no sticks: ``2 ln r``.

    Each impact multiplies areas of the ``(t, Zdot)`` plane by ``r^2 Zdot_k / Zdot_{k+1}``, and the velocity
    ratios cancel along a run up to its ends.

    Parameters
    ----------
    r : float
        Coefficient of restitution, in (0, 1].

    Returns
    -------
    float
        ``2 ln r``.

    Raises
    ------
    ValueError
        When the impact law's restitution is not constant (:data:`CONSTANT_RESTITUTION`), or ``r`` is not
        in (0, 1].
    """
    if not CONSTANT_RESTITUTION:
        raise ValueError("exponent_sum: the impact law's restitution depends on the impact "
                         "(CONSTANT_RESTITUTION is False), so the exponents' sum is not 2 ln r; "
                         "use the exponents computed from the step Jacobians")
    if not 0.0 < r <= 1.0:
        raise ValueError(f"r = {r!r}; allowed: a coefficient of restitution in (0, 1]")
    return 2.0 * math.log(r)
