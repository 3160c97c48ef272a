"""
Design under multistability
===========================

Where motions coexist, what a device delivers depends on how it is switched on. A design map runs the
same start states (the ball at rest, the forcing phase uniform) at every point of a plane of design
parameters and gives, per point, the attractors reached with their shares, the expected output from a
random switch-on and the worst case.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import vibroimpact as vi

phi, v0 = vi.start_states(16, distribution="rest", seed=1)
ds = vi.design_map("s", np.linspace(0.3, 0.7, 6), "F", np.linspace(4, 8, 4), phi=phi, v0=v0, device=vi.Device(),
                   beta=math.pi / 6)
print(ds[["E_U_T", "worst_U_T", "n_attractors"]].to_dataframe().head())

# %%
# The best design whose tolerance box (±1 % in s, ±5 % in F) keeps the most output at its worst corner
# (no bifurcation curves here, so no margin is checked):
tol = vi.tolerance_analysis(ds, None, {"s": 0.01, "F": 0.05})
best = vi.best_designs(tol, {"s": 0.72, "F": 22.0})
print(best)

# %%
fig, ax = plt.subplots(figsize=(5, 3.5))
m = ax.pcolormesh(ds.s, ds.F, ds.E_U_T / 1e3, shading="nearest")
fig.colorbar(m, label=r"E[$\overline{U}_T$] (kV per unit of t)")
ax.set_xlabel("s (m)")
ax.set_ylabel(r"$\|\hat F\|$ (N)")
