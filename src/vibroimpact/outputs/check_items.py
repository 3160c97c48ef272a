"""The names of the items the paper-value check (:mod:`vibroimpact.outputs.checks`) produces, known before any job
runs: what the configuration's ``checks.known`` may name.

A module of its own, without pandas, xarray or numba: the workflow's check of its configuration reads it before
any job.
"""

from __future__ import annotations

import math

from ..analysis.motion_names import ONE_ONE, TWO_ONE
from .paper import CURVE_ORDER, STABLE_2TO1, caption_figure, figure_name

__all__ = ["BETA_NAMES", "D_GRAZ_ITEMS", "ENERGY_ITEMS", "beta_name", "printed_figure", "caption_item", "identity_item",
           "curve_order_item", "item_names"]

BETA_NAMES = {90.0: "pi/2", 60.0: "pi/3", 45.0: "pi/4", 30.0: "pi/6"}


def beta_name(beta):
    """``"pi/6"`` for an incline of 30 degrees (the paper's four inclines; others to four decimals, in radians)."""
    return BETA_NAMES.get(round(math.degrees(beta), 6), f"{beta:.4f}")


def printed_figure(stem):
    """``"Figure 5"`` for ``"fig2"``: the check table names a figure by its printed number."""
    return figure_name(stem, label=False)


def caption_item(name: str, what: str) -> str:
    """The check's item for a caption orbit's ``what``: ``"Figure 3 (a) (figFN2_a): motion"``, the printed
    figure and panel with the caption's config key (the key alone where it names no panel of a paper figure)."""
    fig = caption_figure(name)
    return f"{fig} ({name}): {what}" if fig else f"{name}: {what}"


#: the rows of :func:`~vibroimpact.outputs.checks.d_graz_rows` that every configuration has
D_GRAZ_ITEMS = [f"d_graz, beta=pi/6 ({figure_name('figFN2', 'f', label=False)}: the 1:1 motion grazes at d_graz)",
                f"d_graz rises with beta: the largest d of {TWO_ONE.label} (its fold)",
                "1:1 exit rises with beta (d_graz read as where the 1:1 motion leaves its family)",
                "1:1 period doubling rises with beta"]


def identity_item(name: str, scene: dict) -> str:
    """The check's item on the paper's identity along sweep ``name`` (its ``scene``: ``beta``, ``vary``)."""
    return (f"d_graz: the 1:1 motion grazes where 2:1 begins, beta={beta_name(float(scene['beta']))}, "
            f"{'length' if scene['vary'] == 's' else 'force'} sweep ({name})")


ENERGY_ITEMS = [f"U_I = U_T for {ONE_ONE.label} motion", "1:1 -> 2:1: U_I drops", "1:1 -> 2:1: U_T rises",
                "2:1 -> 3:1: U_I drops", "2:1 -> 3:1: U_T rises", "2:1 -> 3:1 at the same d: U_T rises", "1:1 output grows with s at fixed force",
                "1:1 output grows with F at fixed length", "max 1:1 output changes < 1 % with beta"]


def curve_order_item(fig, what, beta):
    """The check's item on the order of ``what``'s curves in figure ``fig`` at incline ``beta``."""
    return f"{printed_figure(fig)}: {what} curves top to bottom, beta={beta_name(beta)}"


def item_names(captions, betas, sweeps: dict[str, dict] | None = None) -> list[str]:
    """Every item the check produces for these caption names, inclines (rad) and the sweeps d_graz is read along
    (their scenes by name): what ``checks.known`` may name, known before any job runs."""
    names = [caption_item(c, what) for c in captions for what in ("motion", "Zdot(t0)", "phi")]
    for b in betas:
        if any(abs(b - pb) < 1e-9 for pb in STABLE_2TO1):
            name = beta_name(b)
            names += [f"2:1 stable interval, {end} end, beta={name}" for end in ("lower", "upper")
                      if not (name == "pi/6" and end == "lower")]
            if name == "pi/6":
                names.append("lambda_1 < -1 for d < 0.133 (d_B), beta=pi/6")
    names += ["G1: 2:1 -> 3:1 grazing, d decreasing, beta=pi/6", "G2: 3:1 -> 2:1, d increasing, beta=pi/6"]
    names += [curve_order_item(fig, what, beta) for (fig, what), per_beta in CURVE_ORDER.items() for beta in per_beta]
    return names + ENERGY_ITEMS + D_GRAZ_ITEMS + [identity_item(n, sc) for n, sc in (sweeps or {}).items()]
