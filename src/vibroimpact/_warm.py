"""Numba's on-disk cache filled once, before a workflow's jobs start.

Every compiled function is cached on disk (:mod:`vibroimpact._numba_cache`), but a job that finds its
functions missing compiles them itself, and two jobs started together compile the same functions twice.
:func:`warm` compiles them all up front, in two processes at once (the compiled functions fall in two
groups that share little: the runs and orbits, the attractors and knocks), and leaves a stamp in the cache
directory, so that a warm cache costs one file test.  The workflow calls it when it starts (``onstart``
of the Snakefile); ``python -m vibroimpact._warm`` does the same by hand.  Nothing is computed that a
result depends on: the calls are small runs whose outputs are thrown away.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import vibroimpact as vi

from . import _numba_cache
from .benchmarks.methods import run_rk4

#: the stamp left in the cache directory once every group has compiled
STAMP = "warm.done"


def _runs() -> None:
    """simulate (with the dense output), the batch of runs, periodic orbits and their continuation, the
    tangent map, RK4 of the compared methods."""
    p = vi.Params.from_physical(s=0.14 / 0.6225, beta=math.pi / 6)
    run = vi.simulate(p, phi=5.855, v0=0.4185, n_impacts=50)
    vi.identify_attractor(run)
    vi.trajectory(run, np.linspace(0.0, 1.0, 5))
    vi.simulate(p, phi=5.855, v0=0.4185, n_impacts=50, stop_when_periodic=True)
    vi.simulate_batch([p.d, p.d], p.gbar, p.r, [5.855, 1.0], 0.4185, n_impacts=20)
    orbit = vi.find_orbit(p, "BBT", phi=5.855, v0=0.4185)
    vi.continue_orbit(orbit, vary="s", d_range=(0.138, 0.142), step=2e-3)
    vi.lyapunov(p, 5.855, 0.4185, n_impacts=300)
    run_rk4(p, 5.855, 0.4185, 3, h=1e-2)


def _attractors() -> None:
    """A sweep (attractor windows, exact cycles, a long run with lambda_1), the attractor batch from impacts
    and from states in flight."""
    vi.sweep("s", [0.219, 0.30], beta=math.pi / 6, phi=5.855, v0=0.4185, long_impacts=200)
    gbar = vi.Params.from_physical(s=0.85, beta=math.pi / 6).gbar
    vi.attractor_batch(np.array([0.14, 0.15]), gbar, 0.5, np.array([5.855, 1.0]), np.array([0.4, 0.3]),
                       max_periods=5)
    vi.attractor_batch(np.array([0.14]), gbar, 0.5, np.array([0.2]), np.array([0.1]), t0=np.array([0.3]),
                       Z0=np.array([0.05]), max_periods=5)


GROUPS = {"runs": _runs, "attractors": _attractors}


def cache_dir() -> Path:
    """The numba cache directory this process (and the processes it starts) use."""
    return Path(os.environ.get("NUMBA_CACHE_DIR") or _numba_cache.cache_dir())


def warm(force: bool = False) -> bool:
    """Compile every group in its own process, at once, unless the cache holds the stamp (``force``: anyway).
    Returns whether it compiled.  A group that fails is reported on stderr and the stamp is not left: the
    jobs then compile what they miss, as without this step."""
    stamp = cache_dir() / STAMP
    if stamp.exists() and not force:
        return False
    procs = [subprocess.Popen([sys.executable, "-m", "vibroimpact._warm", name], env=os.environ.copy())
             for name in GROUPS]
    if all(p.wait() == 0 for p in procs):
        stamp.parent.mkdir(parents=True, exist_ok=True)
        stamp.touch()
    return True


if __name__ == "__main__":
    if len(sys.argv) == 2 and sys.argv[1] in GROUPS:
        GROUPS[sys.argv[1]]()
    else:
        warm(force="--force" in sys.argv)
