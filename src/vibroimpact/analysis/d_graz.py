"""The paper's d_graz, "the maximum value for 2:1 period-2 solutions", and its identity with the 1:1 exit.

The paper defines d_graz twice (sections 2 and 5): "the maximum value for 2:1 period-2 solutions", and the d
where the 1:1 motion grazes: "at d = d_graz, Zdot_j = 0 and Z_j = d/2, and there is a transition to 2:1 motion
for d < d_graz".  The first is a property of the 2:1 orbit: d_graz is the largest d at which the 2:1 period-2
orbit exists, the fold of its branch (:func:`branch_d_graz`), and a sweep that follows the attractor with d
decreasing meets the 2:1 period-2 motion first at or below it (:func:`down_entry`).  The second is the
*1:1 exit* (:mod:`vibroimpact.analysis.family_exit`).  The paper's identity, "the 1:1 motion grazes where 2:1
begins", holds along a sweep when the 1:1 exit is a grazing and lies where the 2:1 begins: within the
sweep's grid step of the down sweep's entry into 2:1 and of the 2:1 fold.  Where it fails, the motions the
down sweep finds between the entry and the exit (the *band*) say what lies there instead.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import xarray as xr

from .motions import CHAOTIC, TWO_ONE

#: the motion whose largest d the paper calls d_graz
TWO_TO_ONE = TWO_ONE.label

__all__ = ["TWO_TO_ONE", "branch_d_graz", "down_entry", "sweep_d_graz"]


def branch_d_graz(branch: xr.Dataset) -> tuple[float, str]:
    """d_graz of a continued 2:1 branch: the largest d of its orbit, the admissible fold of largest d.

    Parameters
    ----------
    branch : xarray.Dataset
        A continued 2:1 (``BBT``) branch (:func:`vibroimpact.continue_orbit`) with its critical points.

    Returns
    -------
    tuple of (float, str)
        d_graz (NaN where the branch has no admissible fold) and where it comes from: ``"fold of the 2:1
        branch"``, or why there is none.

    Examples
    --------
    >>> import math, vibroimpact as vi
    >>> p = vi.Params.from_physical(s=0.14 / 0.6225, beta=math.pi / 6)       # d = 0.14
    >>> o = vi.find_orbit(p, "BBT", phi=5.855, v0=0.4185)
    >>> br = vi.continue_orbit(o, vary="s", d_range=(0.13, 0.23), step=2e-3)
    >>> d, source = vi.branch_d_graz(br)
    >>> round(d, 4), source                       # Table 1: the 2:1 fold at beta = pi/6
    (0.2158, 'fold of the 2:1 branch')
    """
    if branch.attrs.get("status") == "failed":
        return math.nan, f"no 2:1 branch: {branch.attrs.get('reason', '')}"
    if "critical_d" not in branch or str(branch.attrs.get("word", "BBT")) != "BBT":
        return math.nan, "not a continued 2:1 branch with critical points"
    sel = (branch.critical_kind.values.astype(str) == "fold") & branch.critical_admissible.values.astype(bool)
    if not sel.any():
        return math.nan, "the 2:1 branch has no admissible fold in its d range"
    return float(branch.critical_d.values[sel].max()), "fold of the 2:1 branch"


def down_entry(sw: xr.Dataset, label: str = TWO_TO_ONE) -> tuple[float, float]:
    """Where a sweep followed with d decreasing first finds the motion ``label``.

    Parameters
    ----------
    sw : xarray.Dataset
        A sweep (:func:`vibroimpact.sweep`) with its ``down`` direction.
    label : str
        The motion (default the 2:1 period-2).

    Returns
    -------
    tuple of (float, float)
        The largest d of the down direction's points with that motion and the spacing to the sweep's next
        point above it: the motion is entered in ``(d, d + step]``.  NaN, NaN where no point has it; the step
        is NaN where it is found at the sweep's largest d.

    Examples
    --------
    >>> import math, numpy as np, vibroimpact as vi
    >>> sw = vi.sweep("s", np.linspace(0.326, 0.338, 7), beta=math.pi / 6, phi=0.42, v0=0.87, long_impacts=0)
    >>> d, step = vi.down_entry(sw)         # beta = pi/6: the 2:1 below the chaos under the 1:1 exit
    >>> round(d, 4), round(step, 5)
    (0.2067, 0.00125)
    """
    dn = sw.sel(direction="down")
    d = dn.d.values
    hit = np.flatnonzero(dn.label.values.astype(str) == label)
    if not hit.size:
        return math.nan, math.nan
    top = float(d[hit].max())
    above = d[d > top]
    return top, float(above.min() - top) if above.size else math.nan


def _up_end(transitions: xr.Dataset | None) -> tuple[float, float]:
    """Where the up sweep's 2:1 period-2 ends (its located transition of largest d): d and bracket width."""
    if transitions is None or not transitions.sizes.get("transition", 0):
        return math.nan, math.nan
    sel = ((transitions.direction.values.astype(str) == "up")
           & (transitions.before.values.astype(str) == TWO_TO_ONE))
    if not sel.any():
        return math.nan, math.nan
    k = int(np.flatnonzero(sel)[np.argmax(transitions.d.values[sel])])
    return float(transitions.d.values[k]), float(transitions.d_width.values[k])


def _band(sw: xr.Dataset, lo: float, hi: float) -> dict:
    """The down direction's points strictly between ``lo`` and ``hi``: how many, how many chaotic, their motions
    by count, and the largest lambda_1 per impact among them."""
    dn = sw.sel(direction="down")
    d = dn.d.values
    inside = (d > lo) & (d < hi) if np.isfinite(lo) and np.isfinite(hi) else np.zeros(d.size, bool)
    lab = dn.label.values.astype(str)[inside]
    lam = dn.lyap1.values[inside] if "lyap1" in dn else np.full(lab.size, np.nan)
    counts = Counter(lab.tolist())
    return {"band_points": int(inside.sum()), "band_chaotic": int(counts.get(CHAOTIC, 0)),
            "band_motions": ", ".join(f"{n} {m}" for m, n in counts.most_common()),
            "band_lyap1_max": float(np.max(lam[np.isfinite(lam)])) if np.isfinite(lam).any() else math.nan}


def sweep_d_graz(sw: xr.Dataset, transitions: xr.Dataset | None, branch: xr.Dataset | None) -> dict:
    """The paper's d_graz along a sweep, read every way the data allow, and whether the paper's identity holds.

    Parameters
    ----------
    sw : xarray.Dataset
        A sweep (:func:`vibroimpact.sweep`), both directions, with its points' motions (and ``lyap1``).
    transitions : xarray.Dataset or None
        Its located transitions with its 1:1 exit (:func:`vibroimpact.locate_transitions` merged with
        :func:`vibroimpact.sweep_family_exit`).
    branch : xarray.Dataset or None
        The continued 2:1 branch along the same line (same incline, same parameter varied).

    Returns
    -------
    dict
        ``beta``, ``vary``; ``d_graz`` (:func:`branch_d_graz`: the 2:1 fold) and ``d_graz_source``;
        ``entry_d``, ``entry_step`` (:func:`down_entry`: the down sweep enters 2:1 period-2 in
        ``(entry_d, entry_d + entry_step]``) and ``d_graz_minus_entry``; ``up_end_d``, ``up_end_width`` (where
        the up sweep's 2:1 period-2 ends, located: the simulated reading of the fold); the 1:1 exit:
        ``exit_d``, ``exit_d_width``, ``exit_kind``, ``exit_clearance``, ``exit_status`` and ``exit_minus_d_graz``;
        the band between the 2:1 entry and the exit: ``band_width`` (``exit_d - entry_d``), ``band_points``,
        ``band_chaotic``, ``band_motions`` (the down sweep's motions there, by count) and ``band_lyap1_max``;
        ``tolerance`` (the sweep step, to which the entry is known) and ``identity``: the 1:1 exit is a
        grazing within ``tolerance`` of both the entry and d_graz.

    Examples
    --------
    >>> import math, numpy as np, vibroimpact as vi
    >>> sw = vi.sweep("s", np.linspace(0.326, 0.338, 7), beta=math.pi / 6, phi=0.42, v0=0.87, long_impacts=0)
    >>> p = vi.Params.from_physical(s=0.14 / 0.6225, beta=math.pi / 6)
    >>> br = vi.continue_orbit(vi.find_orbit(p, "BBT", 5.855, 0.4185), vary="s", d_range=(0.13, 0.23), step=2e-3)
    >>> r = vi.sweep_d_graz(sw, None, br)       # without the sweep's transitions: no 1:1 exit
    >>> round(r["d_graz"], 4), round(r["entry_d"], 4), round(r["d_graz_minus_entry"], 4), r["identity"]
    (0.2158, 0.2067, 0.0091, False)
    """
    fold, source = branch_d_graz(branch) if branch is not None else (math.nan, "no 2:1 branch")
    entry, step = down_entry(sw)
    up, up_w = _up_end(transitions)
    ex = {k: (transitions[f"exit_{k}"].values.item() if transitions is not None and f"exit_{k}" in transitions
              else (math.nan if k in ("d", "d_width", "clearance") else ""))
          for k in ("d", "d_width", "kind", "clearance", "status")}
    ex = {k: (str(v) if isinstance(v, str | bytes | np.str_) else float(v)) for k, v in ex.items()}
    grid = float(np.max(np.diff(np.sort(sw.d.values)))) if sw.sizes["point"] > 1 else math.nan
    tol = step if np.isfinite(step) else grid
    identity = bool(ex["kind"] == "grazing" and abs(ex["d"] - entry) <= tol and abs(ex["d"] - fold) <= tol)
    return {"beta": float(sw.attrs["beta"]), "vary": str(sw.attrs["vary"]), "d_graz": fold,
            "d_graz_source": source, "entry_d": entry, "entry_step": step, "d_graz_minus_entry": fold - entry,
            "up_end_d": up, "up_end_width": up_w,
            **{f"exit_{k}": v for k, v in ex.items()}, "exit_minus_d_graz": ex["d"] - fold,
            "band_width": ex["d"] - entry, **_band(sw, entry, ex["d"]), "tolerance": tol, "identity": identity}
