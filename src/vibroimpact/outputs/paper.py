"""Values published in the paper (docs/guide/model.md), for comparison only: never used to compute."""

import math

from .registry import figure_numbers, latex_label

__all__ = ["FIGURE_NUMBERS", "figure_name", "latex_label", "caption_figure", "STABLE_2TO1", "PI6_D_B", "PI6_G1",
           "PI6_G2", "PI6_D_GRAZ", "CURVE_ORDER", "paper_stable", "printed_unit", "agreement_tolerance"]

#: the number the published paper prints for each of its figures, by the project's file stem (the
#: LaTeX label: ``fig0`` is ``\label{Fig0}``), in the paper's order; Figure 1, the device, is not regenerated.
#: Derived from the registry of figures (:mod:`vibroimpact.outputs.registry`, where the numbers are written).
FIGURE_NUMBERS = figure_numbers()


def figure_name(stem: str, panel: str = "", *, label: bool = True) -> str:
    """A paper figure named for text: its printed number, a panel, and its LaTeX label beside it.

    Parameters
    ----------
    stem : str
        The figure's file stem, a key of :data:`FIGURE_NUMBERS`.
    panel : str, optional
        The panel letter(s), e.g. ``"a"`` or ``"a)-(c"``.
    label : bool, optional
        Add the LaTeX label in parentheses.

    Returns
    -------
    str
        The name, e.g. ``"Figure 2 (Fig 0)"``.

    Examples
    --------
    >>> figure_name("fig0")
    'Figure 2 (Fig 0)'
    >>> figure_name("figFN2", "f", label=False)
    'Figure 3 (f)'
    """
    name = f"Figure {FIGURE_NUMBERS[stem]}" + (f" ({panel})" if panel else "")
    return f"{name} ({latex_label(stem)})" if label else name


def caption_figure(name: str) -> str | None:
    """The printed figure and panel of a caption orbit named ``<stem>_<panel>`` in the config.

    Parameters
    ----------
    name : str
        The caption's config key, e.g. ``"figFN2_a"``.

    Returns
    -------
    str or None
        ``"Figure 3 (a)"``, or None where the name is not a panel of a paper figure.
    """
    stem, _, panel = name.partition("_")
    return figure_name(stem, panel, label=False) if stem in FIGURE_NUMBERS and panel else None



def printed_unit(x: float) -> float:
    """One unit in the last digit of ``x`` as printed (``repr`` of the value as typed from the paper)."""
    s = repr(float(x)).rstrip("0")
    frac = s.split(".")[1] if "." in s else ""
    return 10.0 ** -len(frac)


def agreement_tolerance(x: float, *, range_end: bool = False) -> float:
    """The one rule for comparing a computed number with a published one.

    A published number is reproduced when the computed one rounds to it: it lies within half a unit
    of its last printed digit.  Where the paper states a range whose ends it rounds (``0.158 < d <
    0.22``, ``d < 0.133``), the end is only known to one unit of its last digit (the paper does not
    say whether it rounded in or out), so one unit is allowed.  Nothing else widens a tolerance.
    """
    return printed_unit(x) * (1.0 if range_end else 0.5)

#: 2:1 period-2 motion stable for lo < d < hi (paper section 3, r = 0.5, F = 5 N, omega = 5 pi)
STABLE_2TO1 = {
    math.pi / 2: (0.167, 0.22),
    math.pi / 3: (0.158, 0.22),
    math.pi / 4: (0.147, 0.214),
    math.pi / 6: (0.1378, 0.205),
}
#: beta = pi/6: lambda_1 < -1 for d < 0.133; grazing G1 (2:1 -> 3:1, d decreasing), G2 (3:1 -> 2:1)
PI6_D_B = 0.133
PI6_G1 = 0.1378
PI6_G2 = 0.1419
#: beta = pi/6: Figure 3 (f) (Fig FN2), "grazing behavior of 1:1 period-10 motion", d = 0.213: the paper's d_graz at
#: this incline, where it says the 1:1 motion grazes and 2:1 follows for smaller d (sections 2 and 5)
PI6_D_GRAZ = 0.213


def paper_stable(beta):
    """Paper's stable interval of the 2:1 motion for ``beta`` (None if the paper gives none)."""
    for b, v in STABLE_2TO1.items():
        if abs(b - beta) < 1e-9:
            return v
    return None


#: the 2:1 period-2 curves from top to bottom, named by their transitions (P1 bottom -> bottom, P2 bottom
#: -> top, P3 top -> bottom), as the captions state: (figure stem, quantity) -> {beta: order}.  Zdot_k and U_k
#: follow a transition (the flight into the impact), Delta t_j is its flight, phi_k is the phase before it.
CURVE_ORDER = {
    ("fig2", "Zdot_k"): {b: "P3, P1, P2" for b in (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)},
    ("fig2", "Delta t_j"): {b: "P2, P3, P1" for b in (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)},
    ("fig2", "phi_k"): {b: "P1, P3, P2" for b in (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)},
    ("fig0", "Zdot_k"): {math.pi / 3: "P3, P1, P2"},
    ("fig0", "U_k"): {math.pi / 3: "P3, P2, P1"},
    ("fig5", "U_k"): {math.pi / 2: "P3, P2, P1", math.pi / 3: "P3, P2, P1", math.pi / 4: "P3, P2, P1",
                       math.pi / 6: "P2, P3, P1"},
}


def pi_tex(x, fmt=".4g"):
    """``x`` in TeX as a fraction of pi when it is one (``\\pi/6``, ``5\\pi``), else formatted with ``fmt``."""

    for den in (1, 2, 3, 4, 6, 12):
        num = x * den / math.pi
        if abs(num - round(num)) < 1e-9 and round(num):
            n = int(round(num))
            top = r"\pi" if n == 1 else f"{n}\\pi"
            return top if den == 1 else f"{top}/{den}"
    return format(x, fmt)
