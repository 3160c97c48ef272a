"""
Is it chaos? Lyapunov exponents
===============================

Between the period-doubled 1:1 motions and the 2:1 at β = π/3 the paper sees "an apparently chaotic
motion". The largest Lyapunov exponent λ₁ of the impact map answers whether it is: positive on chaos,
zero at a bifurcation, ln max|μ| / N < 0 on a stable periodic orbit. ``vi.lyapunov`` computes both
exponents of a run from the exact Jacobians of its impact-to-impact steps, with a confidence interval.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import vibroimpact as vi

K_S = 0.6225  # d = K_S s at the paper's force
chaos = vi.Params.from_physical(s=0.235 / K_S, beta=math.pi / 3)
lam = vi.lyapunov(chaos, 0.0, 0.5, n_impacts=20_000)
lo, hi = lam.interval[0]
print(f"d = 0.235: lambda_1 = {lam.per_impact[0]:.3f} per impact (95 % interval {lo:.3f} to {hi:.3f}), "
      f"{lam.per_time[0]:.3f} per unit time; lambda_2 = {lam.per_impact[1]:.3f}")
# the exponents sum to the exact phase-space contraction: 2 ln r per impact, up to the ends of the run
print(f"lambda_1 + lambda_2 = {sum(lam.per_impact):.4f}, 2 ln r = {2 * math.log(chaos.r):.4f}")

# %%
# On a periodic orbit the exponents are the logarithms of its multipliers per impact: the 2:1 orbit at
# d = 0.20, from ``find_orbit``'s eigenvalues and from a run of the simulator.
p21 = vi.Params.from_physical(s=0.20 / K_S, beta=math.pi / 3)
o = vi.find_orbit(p21, "BBT", phi=1.21, v0=0.2164)
exact = np.sort(np.log(np.abs(o.eigenvalues)))[::-1] / o.n
run = vi.lyapunov(p21, o.phi, float(o.v_minus[0]), n_impacts=3000)
print(f"2:1 orbit: ln|mu| / N = {exact.round(4)}, the run gives {np.round(run.per_impact, 4)}")

# %%
# A sweep gives every point its λ₁ and names the motions with no period by its interval: ``chaotic``
# (above 0), ``quasi-periodic`` (containing 0) or ``unsettled`` (below 0: a transient longer than the cap).
sw = vi.sweep("s", np.linspace(0.20, 0.30, 21) / K_S, beta=math.pi / 3, phi=0.42, v0=0.87, long_impacts=4000)
down = sw.sel(direction="down")
fig, ax = plt.subplots(figsize=(6, 3))
colors = {"chaotic": "tab:red", "quasi-periodic": "tab:orange", "unsettled": "0.5"}
for label in np.unique(down.label.values.astype(str)):
    k = down.label.values.astype(str) == label
    err = np.abs(np.vstack([down.lyap1[k] - down.lyap1_low[k], down.lyap1_high[k] - down.lyap1[k]]))
    ax.errorbar(down.d[k], down.lyap1[k], yerr=err, fmt="o", ms=3, mfc="none", color=colors.get(label, "k"),
                label=label if label in colors else None)
ax.axhline(0, color="0.3", lw=0.6)
ax.set_xlabel("d")
ax.set_ylabel(r"$\lambda_1$ per impact")
ax.legend(fontsize=7, title="black: periodic (exact)", title_fontsize=7)
fig.tight_layout()
