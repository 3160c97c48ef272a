"""How well each figure's arrays are determined: their spread when the figure data is recomputed under
perturbations that stand for another machine.

Another CPU runs other code paths of glibc's ``sin``, ``cos``, ``exp`` (they agree to an ulp, not bit
for bit), and the same physical inputs can arrive rounded differently.  :data:`PERTURBATIONS` emulate
both on one machine: glibc's libm with its FMA and AVX2 paths masked (``GLIBC_TUNABLES``), and the ball's
mass moved by a few ulps (every non-dimensional gravity and gap moves with it).  :func:`spreads`
compares each perturbed regeneration with the unperturbed figure data, array by array: an array whose
every perturbed copy passes the strict comparison is well-conditioned and keeps it; any other is
ill-conditioned and is compared by what its figure recorded as well-posed (:mod:`vibroimpact.outputs.figcheck`).
The measurement is run by the workflow's ``figure_conditioning`` target and kept with the committed
references (``conditioning.csv``).
"""

from __future__ import annotations

import copy
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from .figdata import hash_distance

__all__ = ["PERTURBATIONS", "LIBM_SWITCH", "libm_switch_works", "spreads", "ill_conditioned", "perturbed_config",
           "regenerate"]

#: glibc's libm with its FMA and AVX2 code paths masked: the other machine's ``sin`` (glibc >= 2.33 names;
#: the older ``-AVX2_Usable,-FMA_Usable`` are ignored by glibc 2.36)
LIBM_SWITCH = {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA"}
#: name -> (environment, relative change of the ball's mass M in ulps)
PERTURBATIONS = {
    "libm": (LIBM_SWITCH, 0),
    "mass +2 ulp": ({}, 2),
    "libm, mass -2 ulp": (LIBM_SWITCH, -2),
}


def libm_switch_works(python: str = sys.executable) -> bool:
    """Whether :data:`LIBM_SWITCH` changes ``sin`` on this machine (it does where glibc dispatches ``sin``
    on FMA or AVX2: x86-64 CPUs that have them); without it the libm perturbation emulates nothing."""
    code = ("import numpy as np, hashlib; x = np.random.default_rng(1).uniform(-50, 50, 200000); "
            "print(hashlib.sha1(np.sin(x).tobytes()).hexdigest())")
    out = [subprocess.run([python, "-c", code], capture_output=True, text=True, check=True,
                          env=os.environ | env).stdout for env in ({}, LIBM_SWITCH)]
    return out[0] != out[1]


def perturbed_config(cfg: dict, ulps: int) -> dict:
    """A copy of the workflow config with the ball's mass ``M`` moved by ``ulps`` units in the last place."""

    out = copy.deepcopy(cfg)
    m = float(out["physics"]["M"])
    for _ in range(abs(int(ulps))):
        m = math.nextafter(m, math.inf if ulps > 0 else -math.inf)
    out["physics"]["M"] = m
    return out


def regenerate(root: Path, scratch: Path, name: str, targets: list[str], *, cores: int = 2) -> Path:
    """The workflow at ``root`` run under perturbation ``name`` in a scratch copy ``scratch``; returns the
    copy (its ``results/figures/data`` hold the perturbed figure data)."""
    import yaml

    env, ulps = PERTURBATIONS[name]
    if scratch.exists():
        shutil.rmtree(scratch)
    scratch.mkdir(parents=True)
    for item in ("Snakefile", "workflow", "config", "profiles", "reference"):
        src = root / item
        if src.exists():
            (shutil.copytree if src.is_dir() else shutil.copy)(src, scratch / item)
    cfg_file = scratch / "config" / "config.yaml"
    cfg = yaml.safe_load(cfg_file.read_text())
    cfg_file.write_text(yaml.safe_dump(perturbed_config(cfg, ulps), sort_keys=False))
    res = subprocess.run([sys.executable, "-m", "snakemake", "--cores", str(cores), *targets], cwd=scratch,
                         capture_output=True, text=True, env=os.environ | env)
    if res.returncode:
        raise RuntimeError(f"the workflow under perturbation {name!r} failed:\n{res.stderr[-3000:]}")
    return scratch


def spreads(reference: xr.Dataset, perturbed: dict[str, xr.Dataset], *, rtol: float, atol: float,
            exclude=(), optional=()) -> pd.DataFrame:
    """Per array of one figure: how far each perturbed copy moved it.

    Returns one row per reference variable with ``spread`` (the largest ``|perturbed - reference|`` over
    the perturbations; infinite where a copy changed shape or where it is NaN), ``ratio`` (that in units
    of the strict tolerance ``atol + rtol |reference|``), ``moved_by`` (the perturbations that moved it
    beyond the strict tolerance), ``conditioning`` (``"strict"`` or ``"ill-conditioned"``) and the
    ``wellposed`` rule its figure recorded (``""`` where none).  Timings and optional peers are
    ``"excluded"``, as in the check.
    """
    pats = [p.lower() for p in exclude]
    opts = [p.lower() for p in optional]
    rows = []
    for name in reference.data_vars:
        r = reference[name]
        if r.attrs.get("role") == "wellposed":
            continue
        text = (r.attrs.get("label", "") + " " + r.attrs.get("axes_title", "")).lower()
        if any(p in r.attrs.get("axis_label", "").lower() for p in pats) or any(p in text for p in opts):
            rows.append(dict(variable=name, spread=np.nan, ratio=np.nan, moved_by="", conditioning="excluded",
                             wellposed=""))
            continue
        b = np.asarray(r.values, float)
        spread, ratio, moved = 0.0, 0.0, []
        for pname, ds in perturbed.items():
            a = np.asarray(ds[name].values, float) if name in ds else None
            if a is None or a.shape != b.shape or np.any(np.isnan(a) != np.isnan(b)):
                spread, ratio = math.inf, math.inf
                moved.append(pname)
                continue
            ok = ~np.isnan(b)
            d = np.abs(a[ok] - b[ok])
            q = d / (atol + rtol * np.abs(b[ok])) if d.size else np.zeros(0)
            spread = max(spread, float(d.max(initial=0.0)))
            ratio = max(ratio, float(q.max(initial=0.0)))
            if q.size and q.max() > 1.0:
                moved.append(pname)
        rows.append(dict(variable=name, spread=spread, ratio=ratio, moved_by="; ".join(moved),
                         conditioning="ill-conditioned" if moved else "strict",
                         wellposed=r.attrs.get("wellposed", "")))
    return pd.DataFrame(rows, columns=["variable", "spread", "ratio", "moved_by", "conditioning", "wellposed"])


def image_spread(reference: xr.Dataset, perturbed: dict[str, xr.Dataset]) -> int:
    """Largest perceptual-hash distance (bits) of the perturbed copies' images from the reference's."""

    a = reference.attrs.get("png_phash")
    return max((hash_distance(a, ds.attrs["png_phash"]) for ds in perturbed.values()
                if a and ds.attrs.get("png_phash")), default=0)


def ill_conditioned(table: pd.DataFrame | None, figure: str) -> set[str]:
    """The variables of ``figure`` the conditioning table measured ill-conditioned."""
    if table is None or not len(table):
        return set()
    sel = table[(table.figure == figure) & (table.conditioning == "ill-conditioned")]
    return set(sel.variable)
