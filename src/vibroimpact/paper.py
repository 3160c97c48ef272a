"""Values published in the paper (MODEL.md section 5), for comparison only: never used to compute."""

import math

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


def paper_stable(beta):
    """Paper's stable interval of the 2:1 motion for ``beta`` (None if the paper gives none)."""
    for b, v in STABLE_2TO1.items():
        if abs(b - beta) < 1e-9:
            return v
    return None
