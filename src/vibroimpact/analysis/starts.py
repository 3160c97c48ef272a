"""Start states of the design maps and the names their configuration allows: the same states at every point of a
map, so that neighbouring points are compared on the same starts (:mod:`vibroimpact.analysis.design`); and the
kinds of knock the critical shock can give (:mod:`vibroimpact.analysis.shocks`).

A module of its own, on numpy alone: the workflow's check of its configuration reads it before any job, without
loading what a design map or a knock computes with (scipy's statistics, numba and xarray among it).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["DISTRIBUTIONS", "MIN_STARTS", "DESIGN_AXES", "RELATIVE", "KNOCK_KINDS", "start_states"]

#: start-state distributions: at rest on the bottom membrane (uniform phase), or a box of bottom impacts
DISTRIBUTIONS = ("rest", "box")
#: fewest starts per point: below this a share's confidence interval spans most of [0, 1]
MIN_STARTS = 8
#: the axes a design map can have: the device's length, its forcing amplitude and its incline
DESIGN_AXES = ("s", "F", "beta")
#: tolerances relative to the nominal value (the others, beta, are absolute in radians)
RELATIVE = ("s", "F")
#: what a knock changes: the velocity ``Zdot`` or the position ``Z`` (:data:`vibroimpact.analysis.shocks.KINDS`)
KNOCK_KINDS = ("velocity", "position")


def fail(key, value, allowed):
    """Refuse ``value`` of ``key``: a ValueError naming the key, the value and what is allowed."""
    raise ValueError(f"{key} = {value!r} is not allowed; allowed: {allowed}")


def start_states(n, *, distribution: str = "rest", seed: int = 0, phi_range=(0.0, 2 * math.pi),
                 v0_range=(0.02, 1.2)):
    """``n`` start states: first bottom impacts at phase ``phi`` with pre-impact velocity ``v0``.

    They are drawn with ``numpy.random.default_rng(seed)``: the same seed gives the same states.

    Parameters
    ----------
    n : int
        How many (at least :data:`~vibroimpact.analysis.starts.MIN_STARTS`).
    distribution : {"rest", "box"}
        ``"rest"``: the ball at rest on the bottom membrane (``v0 = 0``; the kernel then sticks until the
        forcing lifts it), ``phi`` uniform in ``[0, 2 pi)``.  ``"box"``: ``phi`` uniform in ``phi_range``
        and ``v0`` uniform in ``v0_range``.
    seed : int
        Seed of the generator (recorded with the design map).
    phi_range, v0_range : (float, float)
        The box of ``"box"``.

    Returns
    -------
    phi, v0 : numpy.ndarray
        The start states.

    Examples
    --------
    >>> import numpy as np, vibroimpact as vi
    >>> phi, v0 = vi.start_states(8)                    # at rest on the bottom membrane
    >>> phi.shape, bool(((0 <= phi) & (phi < 2 * np.pi)).all()), v0.tolist() == [0.0] * 8
    ((8,), True, True)
    >>> phi, v0 = vi.start_states(8, distribution="box", seed=1, v0_range=(0.1, 0.5))
    >>> bool(((0.1 <= v0) & (v0 <= 0.5)).all()), bool((phi == vi.start_states(8, distribution="box", seed=1,
    ...                                                   v0_range=(0.1, 0.5))[0]).all())
    (True, True)
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < MIN_STARTS:
        fail("starts", n, f"an integer >= {MIN_STARTS}")
    if distribution not in DISTRIBUTIONS:
        fail("distribution", distribution, " or ".join(DISTRIBUTIONS))
    rng = np.random.default_rng(seed)
    if distribution == "rest":
        return rng.uniform(0.0, 2 * math.pi, n), np.zeros(n)
    (p0, p1), (v0, v1) = phi_range, v0_range
    if not p0 < p1:
        fail("phi_range", [p0, p1], "[lo, hi] with lo < hi (a box with some width)")
    if not 0 <= v0 < v1:
        fail("v0_range", [v0, v1], "[lo, hi] with 0 <= lo < hi (a box with some width)")
    return rng.uniform(p0, p1, n), rng.uniform(v0, v1, n)
