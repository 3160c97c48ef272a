"""Probe heyoka as a benchmark peer: compile time, cost per impact and error on two scenes.

Run: ``.venv/bin/python tools/probe_heyoka.py [n_cost]``.  Single-threaded (``heyoka.set_nthreads(1)``);
timings on a shared machine are indicative only.
"""

import math
import sys
import time

import numpy as np

from vibroimpact.benchmarks import peer_heyoka as H
from vibroimpact.dynamics.params import Params
from vibroimpact.dynamics.reference import trajectory

SCENES = {"2:1": (math.pi / 6, 0.16, 1.015, 0.1924), "chaotic": (math.pi / 3, 0.235, 0.4, 0.6)}
EPS = float(np.finfo(float).eps)


def main(n_cost=2000, n_err=20, repeats=3):
    import heyoka as hy

    hy.set_nthreads(1)
    hy.llvm_state.set_diskcache_enabled(False)  # this process only: time a cold build
    print(f"heyoka {H.heyoka_version()}")
    for tol in (EPS, 1e-6):
        print(f"compile tol={tol:.3g}: {H.compile_seconds(tol):.3f} s (cold: no disk cache)")
    for name, (beta, d, phi, v0) in SCENES.items():
        p = Params(d=d, gbar=0.1245 * 9.8 * math.sin(beta) / 5, r=0.5)
        ref = trajectory(p.d, p.gbar, p.r, phi, v0, n_err)
        rt = np.array([float(x[0]) for x in ref])
        rw = np.array([x[1] for x in ref])
        for tol in (EPS, 1e-6):
            for restart in ("offset", "cooldown"):
                run = H.run_heyoka(p, phi, v0, n_err, tol=tol, restart=restart)
                walls_ok = len(run.t) >= n_err and bool(np.all(run.wall[:n_err] == rw))
                err = float(np.max(np.abs(run.t[:n_err] - rt))) if walls_ok else math.inf
                best = math.inf
                for _ in range(repeats):
                    run = H.run_heyoka(p, phi, v0, n_cost, tol=tol, restart=restart)
                    best = min(best, run.seconds / max(len(run.t), 1) * 1e6)
                print(f"{name:8s} tol={tol:.3g} restart={restart:8s}: max |t err| over {n_err} = {err:.2e}, "
                      f"{best:.1f} us/impact (best of {repeats}, {len(run.t)} impacts, {run.status})")


if __name__ == "__main__":
    start = time.perf_counter()
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2000)
    print(f"probe took {time.perf_counter() - start:.1f} s")
