#!/usr/bin/env python3
"""Is a surviving mutant of events.py / kernels.py equivalent?  A differential probe.

``tools/mutation_probe.py events|kernels OUT.npz`` evaluates the (possibly mutated) package on a
fixed, seeded input set wider than the tests (near-grazing states at every eps down to 1e-15,
finite horizons, gbar = 0, 1 and > 1, starts at rest on a wall, sticking / chattering / periodic
runs, batch and window kernels) and saves the outputs; ``compare A.npz B.npz`` prints the largest
difference.  ``survivors MODULE`` applies each survivor of ``tools/mutation.py run`` in turn (in a
private copy) and compares its outputs with the clean ones: a survivor whose outputs agree to
rounding (relative 1e-13) on every probe input is reported as equivalent.  Some probe inputs
start outside the walls (|z0| > d/2): a difference only there is no behaviour of a valid run.
"""

import math
import sys
import warnings

import numpy as np

warnings.simplefilter("ignore")


def events_probe():
    from vibroimpact.dynamics.events import next_impact
    from vibroimpact.dynamics.reference import grazing_state

    rng = np.random.default_rng(12345)
    taus, walls = [], []

    def call(theta, z0, u, d, gbar, tau_max):
        t, w = next_impact(theta, z0, u, d, gbar, tau_max)
        taus.append(t)
        walls.append(w)

    for _ in range(3000):
        d = rng.uniform(0.05, 1.0)
        gbar = rng.choice([rng.uniform(0.0, 0.99), 0.0, 1.0, rng.uniform(1.0, 1.5)])
        theta = rng.uniform(-10, 20)
        x = rng.random()
        if x < 0.3:
            w = rng.choice([-1, 1])
            z0, u = w * d / 2, -w * rng.uniform(0.0, 2.0)
        elif x < 0.4:
            w = rng.choice([-1, 1])
            z0, u = w * d / 2, 0.0
        else:
            z0, u = rng.uniform(-d / 2, d / 2), rng.uniform(-2.0, 2.0)
        tau_max = rng.choice([math.inf if gbar > 0 else 60.0, rng.uniform(0.0, 3.0)])
        call(theta, z0, u, d, gbar, tau_max)
    for _ in range(300):  # releases: at rest on a wall exactly at the phase where w Z'' changes sign
        d, gbar = rng.uniform(0.05, 1.0), rng.uniform(0.0, 0.99)
        alpha = math.acos(-gbar)
        w = rng.choice([-1, 1])
        call(alpha if w == 1 else 2 * math.pi - alpha, w * d / 2, 0.0, d, gbar, rng.choice([math.inf, 3.0]))
    for _ in range(100):  # zero horizon (t == t_end)
        d, gbar = rng.uniform(0.05, 1.0), rng.uniform(0.0, 0.99)
        w = rng.choice([-1, 1])
        call(rng.uniform(0, 6.3), w * d / 2, -w * rng.uniform(0.0, 1.0), d, gbar, 0.0)
    d, gbar = 0.3, 0.2
    for wall in (1, -1):
        for eps in (1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15, 0.0,
                    -1e-15, -1e-14, -1e-13, -1e-12, -1e-11, -1e-9, -1e-7, -1e-5, -1e-3):
            for _ in range(6):
                while True:
                    theta_e = rng.uniform(0, 2 * np.pi)
                    if wall * (math.cos(theta_e) + gbar) < -0.05:
                        break
                th0, z0, u0 = grazing_state(theta_e, rng.uniform(0.02, 0.6), d, gbar, wall, eps)
                call(th0, z0, u0, d, gbar, math.inf)
                call(th0, z0, u0, d, gbar, 5.0)
    return {"tau": np.array(taus), "wall": np.array(walls)}


def kernels_probe():
    import vibroimpact as vi
    from vibroimpact.analysis.windows import attractor_batch

    out = {}
    G6 = 0.1245 * 9.8 * math.sin(math.pi / 6) / 5.0
    G3 = 0.1245 * 9.8 * math.sin(math.pi / 3) / 5.0
    runs = [
        (vi.Params(d=0.16, gbar=G6, r=0.5), 1.015, 0.1924, dict(n_impacts=3000)),
        (vi.Params(d=0.16, gbar=G6, r=0.5), 1.015, 0.1924, dict(n_impacts=100_000, stop_when_periodic=True)),
        (vi.Params(d=0.24, gbar=G6, r=0.5), 0.4, 0.6, dict(n_impacts=20_000, stop_when_periodic=True)),
        (vi.Params(d=0.252, gbar=G6, r=0.5), 0.128, 0.669, dict(n_impacts=50_000, stop_when_periodic=True)),
        (vi.Params(d=0.3, gbar=0.9, r=0.5), 0.3, 0.5, dict(t_end=60.0)),
        (vi.Params(d=0.3, gbar=0.9, r=0.5), 0.3, 0.5, dict(n_impacts=3000, stop_when_periodic=True)),
        (vi.Params(d=0.3, gbar=0.97, r=0.8), 0.3, 0.05, dict(t_end=20.0)),
        (vi.Params(d=0.3, gbar=0.5, r=0.0), 0.3, 0.5, dict(t_end=20.0)),
        (vi.Params(d=0.3, gbar=0.122, r=0.5), 1.2, 0.3, dict(t_end=40.0, v_chatter=1e-6)),
        (vi.Params(d=0.3, gbar=1.2, r=0.5), 0.3, 0.5, dict(n_impacts=1000)),
        (vi.Params(d=0.3, gbar=1.0, r=0.5), 0.3, 0.5, dict(n_impacts=1000)),
        (vi.Params(d=0.3, gbar=0.0, r=0.5), 0.3, 0.0, dict(t_end=50.0)),
        (vi.Params(d=0.5, gbar=0.2, r=0.7), 2.0, 0.4, dict(n_impacts=500, t_end=30.0)),
        (vi.Params(d=0.235, gbar=G3, r=0.5), 0.4, 0.6, dict(n_impacts=5000, stop_when_periodic=True)),
        (vi.Params(d=0.2, gbar=0.3, r=0.6), 0.1, 0.2, dict(t0=3.7, Z0=0.05, n_impacts=400)),
    ]
    for i, (p, phi, v0, kw) in enumerate(runs):
        try:
            ds = vi.simulate(p, phi, v0, **kw)
            for k in ("t", "wall", "v_minus", "v_plus", "phase", "kind", "z"):
                out[f"run{i}_{k}"] = ds[k].values
            out[f"run{i}_status"] = np.array(str(ds.attrs["status"]))
            out[f"run{i}_lag"] = np.array(int(ds.attrs.get("period_events", 0) or 0))
        except Exception as e:
            out[f"run{i}_error"] = np.array(type(e).__name__)
    for key, kw in (("batch", dict(n_impacts=400)), ("batchp", dict(n_impacts=5000, stop_when_periodic=True))):
        b = vi.simulate_batch([0.16, 0.24, 0.3, 0.3, 0.2], [G6, G6, 0.9, 1.2, 0.3], 0.5,
                              [1.015, 0.4, 0.3, 0.3, 0.1], [0.19, 0.6, 0.5, 0.5, 0.2], **kw)
        for k in ("t", "v_minus", "kind", "n_events", "status", "period_events"):
            out[f"{key}_{k}"] = b[k].values
    ab = attractor_batch(np.array([0.16, 0.24, 0.3, 0.235, 0.3]), np.array([G6, G6, 0.9, G3, 1.2]),
                         np.full(5, 0.5), np.array([1.015, 0.4, 0.3, 0.4, 0.3]), np.array([0.19, 0.6, 0.5, 0.6, 0.5]), window=65)
    for k in ab.data_vars:
        out[f"ab_{k}"] = ab[k].values
    return out


def compare(a, b):
    A, B = np.load(a, allow_pickle=True), np.load(b, allow_pickle=True)
    msgs, worst = [], 0.0
    for k in sorted(set(A) | set(B)):
        if k not in A or k not in B:
            msgs.append(f"{k}: only in one")
            worst = math.inf
            continue
        x, y = A[k], B[k]
        if x.shape != y.shape:
            msgs.append(f"{k}: shape {x.shape} vs {y.shape}")
            worst = math.inf
            continue
        if x.dtype.kind in "fc":
            same_nan = np.isnan(x) == np.isnan(y)
            fin = np.isfinite(x) & np.isfinite(y)
            inf_mismatch = (~same_nan) | (np.isinf(x) != np.isinf(y)) | (np.isinf(x) & (x != y))
            rel = np.abs(x - y)[fin] / np.maximum(1.0, np.abs(x)[fin])
            r = float(rel.max()) if rel.size else 0.0
            if inf_mismatch.any():
                msgs.append(f"{k}: {int(inf_mismatch.sum())} nan/inf mismatches")
                worst = math.inf
            if r > 0:
                msgs.append(f"{k}: max rel diff {r:.2e} ({int((rel > 1e-13).sum())} > 1e-13)")
                worst = max(worst, r)
        else:
            if not np.array_equal(x, y):
                msgs.append(f"{k}: {int(np.sum(x != y)) if x.shape else 1} differ")
                worst = math.inf
    return worst, msgs


def survivors(mod):
    import json
    import os
    import shutil
    import subprocess
    import tempfile

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import mutation

    tree = os.path.join(mutation.OUT, "probe_tree")
    if not os.path.isdir(tree):
        shutil.copytree(os.path.join(mutation.ROOT, "src"), os.path.join(tree, "src"))
        for f in os.listdir(os.path.join(mutation.ROOT, "pristine")):
            m = f.removesuffix(".py")
            shutil.copy(os.path.join(mutation.ROOT, "pristine", f),
                        os.path.join(tree, "src", "vibroimpact", mutation.LAYER.get(m, ""), f))
    path = os.path.join(tree, "src", "vibroimpact", mutation.LAYER.get(mod, ""), mod + ".py")
    src, muts = mutation.mutants_of(os.path.join(mutation.ROOT, "pristine", mod + ".py"))

    def probe(tag):
        cache = tempfile.mkdtemp(prefix="mutprobe_nb_")
        shutil.rmtree(os.path.join(tree, "src", "vibroimpact", "__pycache__"), ignore_errors=True)
        env = dict(os.environ, PYTHONPATH=os.path.join(tree, "src"), NUMBA_CACHE_DIR=cache, NUMBA_NUM_THREADS="1",
                   PYTHONDONTWRITEBYTECODE="1")
        out = os.path.join(tree, f"{mod}_{tag}.npz")
        try:
            p = subprocess.run([mutation.PY, os.path.abspath(__file__), mod, out], env=env, capture_output=True,
                               text=True, timeout=300, cwd=tree)
            ok, err = p.returncode == 0, (p.stderr.strip().splitlines()[-1:] if p.returncode else [])
        except subprocess.TimeoutExpired:
            ok, err = False, ["timeout"]
        shutil.rmtree(cache, ignore_errors=True)
        return (out if ok else None), err

    base, err = probe("clean")
    assert base, err
    rows = [json.loads(line) for line in open(os.path.join(mutation.OUT, f"results_{mod}.jsonl"))]
    for r in (r for r in rows if r["status"] == "survived"):
        m = muts[r["id"]]
        with open(path, "wb") as f:
            f.write(mutation.apply(src, m))
        try:
            out, err = probe(str(r["id"]))
        finally:
            with open(path, "wb") as f:
                f.write(src)
        if out is None:
            print(f"#{r['id']} L{m['line']} {m['kind']}: probe crashed {err}", flush=True)
            continue
        w, msgs = compare(base, out)
        print(f"#{r['id']} L{m['line']} {m['kind']}: worst={w:.3g} " + "; ".join(msgs[:4]), flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "survivors":
        survivors(sys.argv[2])
    elif sys.argv[1] == "compare":
        w, m = compare(sys.argv[2], sys.argv[3])
        print(f"worst={w:.3g}", "; ".join(m[:6]))
    else:
        res = events_probe() if sys.argv[1] == "events" else kernels_probe()
        np.savez(sys.argv[2], **res)
