"""
Sweeps and basins of attraction
===============================

A sweep follows the attractor along a parameter, each point started from the last one's; a basin map
runs every start of a grid at one parameter point (all runs in parallel). Where no period is found
within the cap, the sweep continues the motion for a long run and keeps its statistics.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import vibroimpact as vi

# %%
# The length sweep of Figure 2 at β = π/3, coarse: 1:1, its period doublings, an aperiodic window, 2:1.
sw = vi.sweep("s", np.linspace(0.19, 0.72, 60), beta=math.pi / 3, phi=0.42, v0=0.87)
dn = sw.sel(direction="down")
print(sorted(set(dn.label.values.astype(str))))
fig, ax = plt.subplots(figsize=(6, 3.5))
for i in range(dn.sizes["point"]):
    cyc = dn.cycle_v_minus.values[i]
    v = cyc[np.isfinite(cyc)] if dn.settled.values[i] else dn.v_minus.values[i][np.isfinite(dn.v_minus.values[i])][-24:]
    ax.plot(np.full(v.size, float(dn.d[i])), np.abs(v), "o", ms=2, mfc="none",
            color="k" if dn.settled.values[i] else "0.6")
ax.set_xlabel("d")
ax.set_ylabel(r"$|\dot Z_k|$ (black: exact cycle; grey: no period found)")

# %%
# Basins at the bistable point of Figure 8 (d = 0.14, β = π/6): the attractor reached from each first
# bottom impact (phase, pre-impact velocity).
p = vi.Params.from_physical(s=0.14 / 0.6225, beta=math.pi / 6)
b = vi.basins(p, np.linspace(0, 2 * np.pi, 48), np.linspace(0.02, 1.2, 30))
print({lab: int((b.label.values == lab).sum()) for lab in np.unique(b.label.values)})
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.pcolormesh(b.phi, b.v0, b.attractor.T, shading="nearest", cmap="tab10")
ax.set_xlabel(r"$\varphi$ of the first bottom impact")
ax.set_ylabel(r"$\dot Z(t_0)$")
