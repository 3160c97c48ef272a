"""``python -m vibroimpact`` (or the ``vibroimpact`` command): the version, where the package and the
workflow are, and what the optional parts need."""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

from . import _numba_cache
from ._version import __version__
from .benchmarks.peer_siconos import available

REPOSITORY = "the vibroimpact source repository (git clone; the workflow is not part of the wheel)"

#: the workflow's named targets (the rules no other rule's input needs, and the conditioning run that
#: ``update_figure_references`` reads) -> what each writes; tests/test_workflow_graph.py holds this to the
#: Snakefile's rule graph, and the documentation's target list is generated from it
TARGETS = {
    "all": "the default: every figure of the paper, its datasets, the arrays each figure draws, the tables "
           "and the check of the paper's published values",
    "check": "the paper's values, and every figure's arrays against its committed reference",
    "bench": "speed against accuracy of the simulator and its peers, and of the largest Lyapunov exponent",
    "bifurcation": "bifurcation curves in two parameters over brute-force maps",
    "design_maps": "expected and worst-case output under multistability, robust designs",
    "docs": "the documentation site",
    "figure_conditioning": "each figure array's spread under another libm, other OpenBLAS kernels and inputs moved by ulps",
    "update_figure_references": "accepting the current figures' arrays as the new references",
}


def find_workflow(start: Path | None = None) -> Path | None:
    """The workflow's directory (holding ``Snakefile`` and ``workflow/rules``): the current directory
    or one above it, else the source tree of an editable install; None when neither has it."""
    here = Path(start or os.getcwd()).resolve()
    for d in (here, *here.parents):
        if (d / "Snakefile").is_file() and (d / "workflow" / "rules").is_dir():
            return d
    src = Path(__file__).resolve().parents[2]  # <repo>/src/vibroimpact/__main__.py in an editable install
    if (src / "Snakefile").is_file() and (src / "workflow" / "rules").is_dir():
        return src
    return None


def _have(module: str) -> bool:
    return importlib.util.find_spec(module) is not None


def report(start: Path | None = None) -> str:

    wf = find_workflow(start)
    lines = [
        f"vibroimpact {__version__}",
        f"package: {Path(__file__).resolve().parent}",
        f"python: {sys.executable} ({sys.version.split()[0]})",
        f"numba cache: {os.environ.get('NUMBA_CACHE_DIR') or _numba_cache.cache_dir()}",
    ]
    if wf is None:
        lines += [f"workflow: none here; it lives in {REPOSITORY}.",
                  "  The library works on its own: import vibroimpact as vi; vi.simulate(...)."]
    else:
        lines += [f"workflow: {wf / 'Snakefile'} (config: {wf / 'config' / 'config.yaml'})",
                  f"  run it: cd {wf} && snakemake --cores 2        (needs snakemake, installed with the package)",
                  "  targets besides the default: " + ", ".join(t for t in TARGETS if t != "all")]
    siconos = "unknown"
    try:

        siconos = "available" if available() else "not installed (tools/install_siconos.sh, root)"
    except Exception as err:  # the probe itself failed: say so, do not fail the report
        siconos = f"probe failed ({err})"
    lines += [
        "optional parts:",
        f"  heyoka (benchmark peer): {'installed' if _have('heyoka') else 'not installed (pip extra peers)'}",
        f"  Siconos (benchmark peer): {siconos}",
        f"  SLURM executor plugin: {'installed' if _have('snakemake_executor_plugin_slurm') else 'not installed (pip extra cluster)'}",
        f"  progress bars (tqdm): {'installed' if _have('tqdm') else 'not installed'}",
    ]
    return "\n".join(lines)


def main() -> int:
    print(report())
    return 0


if __name__ == "__main__":
    sys.exit(main())
