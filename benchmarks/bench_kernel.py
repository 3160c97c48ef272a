"""The kernel's cost per impact, the working tree against a baseline commit, measured in one run.

    .venv/bin/python benchmarks/bench_kernel.py BASELINE [--rounds N] [--out FILE]

Each side's own ``vibroimpact.benchmarks.bench.kernel_profile`` (the baseline commit's files from ``git archive``,
the working tree's as git sees them), in a fresh interpreter with that side's package first on the path and a numba
cache of its own: microseconds per impact of ``simulate`` on one thread (dataset included) on the 2:1 and the
chaotic scene, and, where the side measures them, what bounds it (the event finder alone over the run's own
flights, the same operations to the last bit; its sines and cosines alone, as a dependent chain) and heyoka's
stepping cost per impact in the same process.  The sides alternate ``--rounds`` times (baseline first; default 3),
and each number is the fastest of its side's rounds (each round's own is already the fastest of the profile's
repeats), so that a noisy stretch of a shared machine slows one round of each side.  Prints a Markdown table with
the machine and the command; ``--out`` also writes it to a file.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_default_target import baseline_copy  # noqa: E402
from bench_devices import baseline_args, publish, scratch_copy  # noqa: E402

#: the profile's variables this benchmark reports (a side that has no such variable: NaN), by their column
MEASURES = {"us_per_impact": "µs per impact", "finder_us_per_impact": "event finder alone, µs",
            "trig_floor_us_per_impact": "sines and cosines alone, µs",
            "heyoka_stepping_us_per_impact": "heyoka's stepping, µs"}
#: the goal on the kernel's cost, µs per impact
GOAL = 0.10
#: run in each side's interpreter: its profile's measures per scene, as JSON
PROFILE = ("import json, math; from vibroimpact.benchmarks.bench import kernel_profile; ds = kernel_profile(); "
           "print(json.dumps({str(s): {v: (float(ds[v].sel(scene=s)) if v in ds else math.nan) for v in %r} "
           "for s in ds.scene.values}))" % list(MEASURES))


def profile(tree: Path, cache: Path) -> dict:
    """``{scene: {measure: value}}`` of ``tree``'s own kernel profile, in a fresh interpreter."""
    env = os.environ | {"PYTHONPATH": str(tree / "src"), "NUMBA_CACHE_DIR": str(cache)}
    env.pop("VIRTUAL_ENV", None)
    out = subprocess.run([sys.executable, "-c", PROFILE], cwd=tree, env=env, capture_output=True, text=True,
                         check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def fastest(runs: list[dict]) -> dict:
    """Each scene's each measure, the least over ``runs`` (NaN where every run has NaN)."""
    scenes = runs[0]
    return {s: {m: min((r[s][m] for r in runs if not math.isnan(r[s][m])), default=math.nan) for m in scenes[s]}
            for s in scenes}


def table(sides: dict[str, dict]) -> pd.DataFrame:
    """One row per side and scene (``sides``: name -> :func:`fastest`), with the ratio to the baseline's (the first
    side's) cost on the same scene and whether it meets :data:`GOAL`."""
    base = next(iter(sides.values()))
    rows = []
    for name, scenes in sides.items():
        for scene, m in scenes.items():
            rows.append({"tree": name, "scene": scene, **{MEASURES[k]: v for k, v in m.items()},
                         "ratio to the baseline": round(m["us_per_impact"] / base[scene]["us_per_impact"], 2),
                         f"≤ {GOAL} µs": m["us_per_impact"] <= GOAL})
    return pd.DataFrame(rows)


def main(baseline: str, rounds: int = 3) -> pd.DataFrame:
    sides = {f"baseline ({baseline})": lambda d: baseline_copy(baseline, d), "this tree": scratch_copy}
    runs = {name: [] for name in sides}
    with tempfile.TemporaryDirectory() as tmp:
        trees = {}
        for name, copy in sides.items():
            where = Path(tmp) / name.split()[0]
            (where / "tree").mkdir(parents=True)
            trees[name] = (copy(where / "tree"), where / "numba")
        for _ in range(rounds):
            for name, (tree, cache) in trees.items():
                runs[name].append(profile(tree, cache))
    return table({name: fastest(r) for name, r in runs.items()})


if __name__ == "__main__":
    a = baseline_args(__doc__, rounds=3)
    df = main(a.baseline, a.rounds)
    shown = df.round(3).astype(object).where(df.notna(), None)  # a measure the side does not take: "not measured"
    publish(shown.to_markdown(index=False, missingval="not measured"),
            f"python benchmarks/bench_kernel.py {a.baseline} --rounds {a.rounds}", a.out)
