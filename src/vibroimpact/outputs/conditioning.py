"""How well each figure's arrays are determined: their spread when the figure data is recomputed under
perturbations that stand for another machine, and whether the check's declared rules tolerate it.

Another CPU runs other code paths of glibc's ``sin``, ``cos``, ``exp`` (they agree to an ulp, not bit
for bit), OpenBLAS picks other kernels (a matrix product summed in another order), and the same physical
inputs can arrive rounded differently.  :data:`PERTURBATIONS` emulate them on one machine: glibc's libm with
its FMA and AVX2 paths masked (``GLIBC_TUNABLES``), OpenBLAS's kernels of other CPUs
(``OPENBLAS_CORETYPE``; the machine's own is left out, :func:`perturbations`), and the ball's mass moved by a
few ulps (every non-dimensional gravity and gap moves with it).  :func:`spreads` compares each perturbed
regeneration with the unperturbed figure data, array by array: how far it moved (against the strict
tolerance) and whether the rule the figure declared for it (:mod:`vibroimpact.outputs.figcheck`) passes it.
The rules are declared where the arrays are drawn, from what produced them; this measurement does not
choose them, it shows what they tolerate and finds an array that moves without a rule.  It is run by the
workflow's ``figure_conditioning`` target and kept with the committed references (``conditioning.csv``, and
``conditioning_summary.csv`` per figure and perturbation).
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

from .checks import IMAGE_ROW
from .figdata import compare, hash_distance
from .paper import FIGURE_NUMBERS, figure_name

__all__ = ["PERTURBATIONS", "LIBM_SWITCH", "BLAS_CORETYPES", "libm_switch_works", "openblas_core", "perturbations",
           "spreads", "summary", "ill_conditioned", "perturbed_config", "regenerate"]

#: glibc's libm with its FMA and AVX2 code paths masked: the other machine's ``sin`` (glibc >= 2.33 names;
#: the older ``-AVX2_Usable,-FMA_Usable`` are ignored by glibc 2.36)
LIBM_SWITCH = {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA"}
#: OpenBLAS kernel sets any x86-64 CPU runs (``OPENBLAS_CORETYPE``): Haswell's (AVX2, as Zen's), Sandybridge's
#: (AVX) and Nehalem's (SSE4); a machine with AVX-512 picks SkylakeX's, which only such a machine can run
BLAS_CORETYPES = ("Haswell", "Sandybridge", "Nehalem")
#: name -> (environment, relative change of the ball's mass M in ulps); the OpenBLAS kernel sets of
#: :data:`BLAS_CORETYPES` that are not the machine's own are added by :func:`perturbations`
PERTURBATIONS = {
    "libm": (LIBM_SWITCH, 0),
    "mass +2 ulp": ({}, 2),
    "libm, mass -2 ulp": (LIBM_SWITCH, -2),
    **{f"OpenBLAS {c}": ({"OPENBLAS_CORETYPE": c}, 0) for c in BLAS_CORETYPES},
}


def openblas_core(python: str = sys.executable, env: dict | None = None) -> str:
    """The kernel set numpy's OpenBLAS picks in a fresh ``python`` (with ``env`` added to the environment):
    ``"Haswell"``, ``"SkylakeX"``, ... (``""`` where numpy's BLAS is not an OpenBLAS that says)."""
    code = ("import ctypes, glob, os, numpy\n"
            "libs = glob.glob(os.path.join(os.path.dirname(numpy.__path__[0]), 'numpy.libs', '*openblas*'))\n"
            "name = ''\n"
            "for lib in libs:\n"
            "    dll = ctypes.CDLL(lib)\n"
            "    for f in ('scipy_openblas_get_corename64_', 'openblas_get_corename64_', 'openblas_get_corename'):\n"
            "        if hasattr(dll, f):\n"
            "            fn = getattr(dll, f); fn.restype = ctypes.c_char_p; name = fn().decode(); break\n"
            "print(name)")
    res = subprocess.run([python, "-c", code], capture_output=True, text=True, env=os.environ | (env or {}))
    return res.stdout.strip() if res.returncode == 0 else ""


def perturbations(python: str = sys.executable) -> dict:
    """:data:`PERTURBATIONS` that perturb something on this machine: an OpenBLAS kernel set that is the one the
    machine picks anyway is left out (and so is one the CPU cannot run, which OpenBLAS replaces)."""
    own = openblas_core(python)
    out = {}
    for name, (env, ulps) in PERTURBATIONS.items():
        core = env.get("OPENBLAS_CORETYPE")
        if core and (core == own or openblas_core(python, env) != core):
            continue
        out[name] = (env, ulps)
    return out


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
    # a machine's own setting of the kernels would otherwise win over the perturbation's, or leak into another
    base = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "GLIBC_TUNABLES")}
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
                         capture_output=True, text=True, env=base | env)
    if res.returncode:
        raise RuntimeError(f"the workflow under perturbation {name!r} failed:\n{res.stderr[-3000:]}")
    return scratch


def spreads(reference: xr.Dataset, perturbed: dict[str, xr.Dataset], *, rtol: float, atol: float,
            optional=()) -> pd.DataFrame:
    """Per array of one figure: how far each perturbed copy moved it, and whether its declared rule passes it.

    Returns one row per reference variable with its declared ``rule`` (``"strict"``: none) and ``provenance``,
    ``spread`` (the largest ``|perturbed - reference|`` over the perturbations; infinite where a copy changed
    shape or where it is NaN), ``ratio`` (that in units of the strict tolerance ``atol + rtol |reference|``),
    ``moved_by`` (the perturbations that moved it beyond the strict tolerance), ``conditioning``
    (``"strict"`` or ``"ill-conditioned"``), ``judged`` (``"pass"`` where every perturbed copy passes the
    declared rule, else the perturbations it fails under) and ``by_perturbation`` (each perturbation's ratio).
    Optional peers are ``"excluded"``, as in the check.
    """
    opts = [p.lower() for p in optional]
    verdicts = {name: compare(ds, reference, rtol=rtol, atol=atol, optional=optional).set_index("variable")
                for name, ds in perturbed.items()}
    rows = []
    for name in reference.data_vars:
        r = reference[name]
        if r.attrs.get("role") == "wellposed":
            continue
        rule, prov = r.attrs.get("wellposed", "strict"), r.attrs.get("provenance", "exact")
        text = (r.attrs.get("label", "") + " " + r.attrs.get("axes_title", "")).lower()
        if any(p in text for p in opts):
            rows.append(dict(variable=name, rule=rule, provenance=prov, spread=np.nan, ratio=np.nan, moved_by="",
                             conditioning="excluded", judged="excluded", by_perturbation=""))
            continue
        b = np.asarray(r.values, float)
        spread, ratio, moved, each, failed = 0.0, 0.0, [], [], []
        for pname, ds in perturbed.items():
            verdict = verdicts[pname].status.get(name, "fail: missing")
            if verdict not in ("pass", "excluded"):
                failed.append(pname)
            a = np.asarray(ds[name].values, float) if name in ds else None
            if a is None or a.shape != b.shape or np.any(np.isnan(a) != np.isnan(b)):
                spread, ratio = math.inf, math.inf
                moved.append(pname)
                each.append(f"{pname}: moved")
                continue
            ok = ~np.isnan(b)
            d = np.abs(a[ok] - b[ok])
            q = d / (atol + rtol * np.abs(b[ok])) if d.size else np.zeros(0)
            spread = max(spread, float(d.max(initial=0.0)))
            ratio = max(ratio, float(q.max(initial=0.0)))
            each.append(f"{pname}: {float(q.max(initial=0.0)):.3g}")
            if q.size and q.max() > 1.0:
                moved.append(pname)
        rows.append(dict(variable=name, rule=rule, provenance=prov, spread=spread, ratio=ratio,
                         moved_by="; ".join(moved), conditioning="ill-conditioned" if moved else "strict",
                         judged="pass" if not failed else "fail under " + "; ".join(failed),
                         by_perturbation="; ".join(each)))
    return pd.DataFrame(rows, columns=["variable", "rule", "provenance", "spread", "ratio", "moved_by", "conditioning",
                                       "judged", "by_perturbation"])


def summary(table: pd.DataFrame, names) -> pd.DataFrame:
    """Per figure and perturbation (``names``): the arrays compared, how many moved beyond the strict tolerance,
    the largest move of an array compared pointwise (in units of its tolerance), and how many of the moved
    arrays the declared rules fail (0: the check passes on a machine so perturbed)."""
    rows = []
    data = table[(table.variable != IMAGE_ROW) & (table.conditioning != "excluded")]
    for fig, sub in data.groupby("figure", sort=False):
        for name in names:
            moved = sub.moved_by.fillna("").str.split("; ").apply(lambda m, n=name: n in m)
            failed = sub.judged.fillna("").apply(
                lambda j, n=name: j.startswith("fail under ") and n in j.removeprefix("fail under ").split("; "))
            strict = sub[sub.rule == "strict"]
            ratios = [float(part.split(": ")[1]) for b in strict.by_perturbation.fillna("") for part in b.split("; ")
                      if part.startswith(name + ": ") and part.split(": ")[1] not in ("moved",)]
            rows.append(dict(figure=fig, perturbation=name, arrays=len(sub), moved=int(moved.sum()),
                             moved_pointwise=int((moved & (sub.rule == "strict")).sum()),
                             largest_pointwise_ratio=max(ratios, default=0.0), failed=int(failed.sum())))
    return pd.DataFrame(rows, columns=["figure", "perturbation", "arrays", "moved", "moved_pointwise",
                                       "largest_pointwise_ratio", "failed"])


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


def conditioning_markdown(table: pd.DataFrame, per: pd.DataFrame) -> str:
    """The testing page's account of the measured conditioning (``conditioning.csv`` and
    ``conditioning_summary.csv`` as :func:`spreads` and :func:`summary` write them): per figure and perturbation,
    how many arrays moved beyond the strict tolerance and how many of those the declared rules fail; then every
    array that moved, with its rule, its provenance and how far each perturbation moved it (in units of the
    strict tolerance)."""
    names = list(dict.fromkeys(per.perturbation))
    own = str(per.machine_openblas.iloc[0]) if "machine_openblas" in per and len(per) else ""
    cell = {(r.figure, r.perturbation): f"{r.moved} ({r.failed})" for r in per.itertuples()}
    # the paper's figures by their printed numbers first, then the project's own
    figs = sorted(dict.fromkeys(per.figure), key=lambda f: FIGURE_NUMBERS.get(f, len(FIGURE_NUMBERS) + 2))
    pivot = pd.DataFrame([{"figure": figure_name(f) if f in FIGURE_NUMBERS else f,
                           "arrays": int(per.arrays[per.figure == f].iloc[0]),
                           **{n: cell.get((f, n), "") for n in names}} for f in figs])
    moved = table[(table.variable != IMAGE_ROW) & (table.conditioning == "ill-conditioned")]
    moved = moved.iloc[np.argsort([FIGURE_NUMBERS.get(f, len(FIGURE_NUMBERS) + 2) for f in moved.figure], kind="stable")]
    moved = moved.assign(figure=[figure_name(f) if f in FIGURE_NUMBERS else f for f in moved.figure])
    moved = moved[["figure", "variable", "rule", "provenance", "by_perturbation", "judged"]].rename(
        columns={"by_perturbation": "largest move / strict tolerance, per perturbation", "judged": "declared rule"})
    head = (f"Measured on a machine whose OpenBLAS picks its {own or 'unreported'} kernels, under "
            f"{len(names)} perturbations ({', '.join(names)}).  Per figure and perturbation: the arrays moved beyond "
            "the strict tolerance, and in brackets how many of them their declared rule fails (a timing always "
            "moves: it is the machine's speed, and not compared).\n\n")
    return (head + pivot.to_markdown(index=False) + "\n\nThe arrays that moved, and by how much:\n\n"
            + moved.to_markdown(index=False) + "\n")
