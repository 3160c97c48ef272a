"""One-off measurement of the Siconos peer (not a benchmark: short, single-threaded, on a shared machine).

For two scenes (the periodic 2:1 orbit of Fig 4a and a chaotic one) and each Siconos setting:
microseconds per impact over the first ``--n`` impacts (simulation loop only; model construction
apart) and the largest impact-time error over the first ``--compare`` impacts against the 40-digit
``vibroimpact.dynamics.reference.trajectory``, with the first wall mismatch if any; then whether each method
sees a near-grazing contact (an extremum 1e-8 inside and 1e-8 beyond a wall).

Usage: ``.venv/bin/python tools/siconos_measure.py [--n 100] [--compare 20]`` (needs python3-siconos:
``tools/install_siconos.sh``).
"""

from __future__ import annotations

import argparse
import math

import mpmath as mp

from vibroimpact.benchmarks import peer_siconos as ps
from vibroimpact.benchmarks.methods import run_exact
from vibroimpact.dynamics.params import Params
from vibroimpact.dynamics.reference import first_impact, grazing_state, trajectory

M, F, G = 0.1245, 5.0, 9.8
SCENES = {
    "2:1 (beta=pi/6, d=0.16)": (math.pi / 6, 0.16, 1.015, 0.1924),
    "chaotic (beta=pi/3, d=0.235)": (math.pi / 3, 0.235, 0.4, 0.6),
}
SETTINGS = [
    ("event-driven, default tol", "event-driven", {}),
    ("event-driven, tol 1e-10", "event-driven", {"tol": 1e-10}),
    ("event-driven, default tol, Python forcing", "event-driven", {"force": "python"}),
    ("moreau-jean, h 1e-3", "moreau-jean", {"h": 1e-3}),
    ("moreau-jean, h 1e-4", "moreau-jean", {"h": 1e-4}),
    ("moreau-jean, h 1e-4, Python forcing", "moreau-jean", {"h": 1e-4, "force": "python"}),
]


def compare(run, ref, k):
    """(max |dt| over the first k matching impacts, index of the first wall mismatch or None, compared)."""
    m = min(k, len(run.t), len(ref))
    worst, bad = 0.0, None
    for i in range(m):
        if int(run.wall[i]) != ref[i][1]:
            bad = i
            break
        worst = max(worst, abs(float(run.t[i]) - float(ref[i][0])))
    return worst, bad, m


def scenes(n, k, max_seconds):
    print(f"| scene | method | impacts | status | us/impact | setup ms | max dt (first {k}) "
          "| wall mismatch |")
    print("|---|---|---|---|---|---|---|---|")
    # Siconos rows use the compiled forcing plugin unless marked "Python forcing"
    for name, (beta, d, phi, v0) in SCENES.items():
        p = Params(d=d, gbar=M * G * math.sin(beta) / F, r=0.5)
        ref = trajectory(p.d, p.gbar, p.r, phi, v0, k)
        ex = run_exact(p, phi, v0, n)
        w, bad, m = compare(ex, ref, k)
        us = 1e6 * ex.seconds / max(len(ex.t), 1)
        print(f"| {name} | exact (numba) | {len(ex.t)} | {ex.status} | {us:.1f} | - | {w:.1e} | {bad} |")
        for label, method, setting in SETTINGS:
            run = ps.run_siconos(p, phi, v0, n, method=method, max_seconds=max_seconds, **setting)
            w, bad, m = compare(run, ref, k)
            us, ms = 1e6 * run.seconds / max(len(run.t), 1), 1e3 * run.setup_seconds
            print(f"| {name} | {label} | {len(run.t)} | {run.status} | {us:.1f} | {ms:.1f} "
                  f"| {w:.1e} (of {m}) | {bad} |")


def grazing():
    d, gbar, tau_e, theta_e = 0.16, 0.1, 0.7, math.pi  # a maximum of Z near the bottom wall (Z'' < 0 there)
    print("\n| near-grazing flight (bottom wall, extremum at tau = 0.7) | method | first impact tau | wall |")
    print("|---|---|---|---|")
    for eps in (1e-8, -1e-8):
        th0, z0, u0 = grazing_state(theta_e, tau_e, d, gbar, +1, eps)
        assert abs(z0) < d / 2
        if eps > 0:
            tau, wall, _ = first_impact(th0, z0, u0, d, gbar, horizon=12.0)
            truth = f"{float(tau):.9f} (wall {wall}): misses by 1e-8 at 0.7"
        else:  # crossing by 1e-8: the impact is the first root just before tau_e (Z'' ~ -(1 - gbar) there)
            half = math.sqrt(2 * 1e-8 / (1 - gbar))
            def gap(s, th0=th0, z0=z0, u0=u0):
                x = mp.pi * s
                return z0 + u0 * s + gbar / 2 * s**2 - (mp.cos(th0 + x) - math.cos(th0)) / mp.pi**2 \
                    - math.sin(th0) / mp.pi * s - d / 2

            tau = mp.findroot(gap, (tau_e - 2 * half, tau_e), solver="anderson")
            truth = f"{float(tau):.9f} (wall 1): crosses by 1e-8"
        tau_s, wall_s, _ = first_impact(th0, z0, u0, d, gbar)
        print(f"| eps = {eps:+.0e}, truth {truth} | reference.first_impact (sampled) | {float(tau_s):.9f} "
              f"| {wall_s} |")
        for label, method, setting in SETTINGS[:2] + SETTINGS[3:5]:
            res = ps.siconos_flights([(th0, z0, u0, d, gbar)], method, **setting)[0]
            print(f"| eps = {eps:+.0e} | {label} | {res.tau:.9f} | {res.wall} ({res.status}) |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100, help="impacts per run (timing)")
    ap.add_argument("--compare", type=int, default=20, help="impacts compared with the reference")
    ap.add_argument("--max-seconds", type=float, default=60.0)
    a = ap.parse_args()
    if not ps.available():
        raise SystemExit(ps.unavailable_reason())
    print(f"Siconos {ps.version()}\n")
    scenes(a.n, a.compare, a.max_seconds)
    grazing()


if __name__ == "__main__":
    main()
