"""Values published in the paper (docs/guide/model.md), for comparison only: never used to compute."""

import math

__all__ = ["STABLE_2TO1", "PI6_D_B", "PI6_G1", "PI6_G2", "PI6_D_GRAZ", "CURVE_ORDER", "paper_stable",
           "printed_unit", "agreement_tolerance"]


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
#: beta = pi/6: Fig FN2 (f), "grazing behavior of 1:1 period-10 motion", d = 0.213: the paper's d_graz, where
#: the 1:1 motion grazes and 2:1 follows for smaller d (sections 2 and 5)
PI6_D_GRAZ = 0.213


def paper_stable(beta):
    """Paper's stable interval of the 2:1 motion for ``beta`` (None if the paper gives none)."""
    for b, v in STABLE_2TO1.items():
        if abs(b - beta) < 1e-9:
            return v
    return None


#: the 2:1 period-2 curves from top to bottom, named by their transitions (P1 bottom -> bottom, P2 bottom
#: -> top, P3 top -> bottom), as the captions state: (figure, quantity) -> {beta: order}.  Zdot_k and U_k
#: follow a transition (the flight into the impact), Delta t_j is its flight, phi_k is the phase before it.
CURVE_ORDER = {
    ("Fig 2", "Zdot_k"): {b: "P3, P1, P2" for b in (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)},
    ("Fig 2", "Delta t_j"): {b: "P2, P3, P1" for b in (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)},
    ("Fig 2", "phi_k"): {b: "P1, P3, P2" for b in (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)},
    ("Fig 0", "Zdot_k"): {math.pi / 3: "P3, P1, P2"},
    ("Fig 0", "U_k"): {math.pi / 3: "P3, P2, P1"},
    ("Fig 5", "U_k"): {math.pi / 2: "P3, P2, P1", math.pi / 3: "P3, P2, P1", math.pi / 4: "P3, P2, P1",
                       math.pi / 6: "P2, P3, P1"},
}
