"""
Simulate an impacting motion and identify it
============================================

The ball's flight between impacts is known in closed form, so :func:`vibroimpact.simulate` only
locates impacts, and never misses one (a tangential, grazing one included). Here: the paper's Figure 7 (a)
caption orbit, β = π/6, d = 0.16, from the caption's bottom impact.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import vibroimpact as vi

# %%
# Parameters from the physical device (cylinder length s, incline β; the paper's defaults otherwise):
p = vi.Params.from_physical(s=0.16 / 0.6225, beta=math.pi / 6)
print(f"d = {p.d:.4f}, gbar = {p.gbar:.4f}, r = {p.r}")

# %%
# A run of 500 impacts from the caption's first bottom impact, and the motion it settles on:
run = vi.simulate(p, phi=1.015, v0=0.1924, n_impacts=500)
att = vi.identify_attractor(run)
print(att.label, "from t =", round(att.t_settled, 3))
run[["t", "wall", "v_minus", "phase", "kind"]].isel(impact=slice(0, 5)).to_dataframe()

# %%
# The exact state at any time (no interpolation): the phase portrait of the last two periods, with the
# two walls at Z = ±d/2.
t_end = float(run.t[-1])
tr = vi.trajectory(run, np.linspace(t_end - 4, t_end, 2001))
fig, ax = plt.subplots(figsize=(5, 3.5))
ax.plot(tr.Z, tr.Zdot, lw=0.8)
for z in (p.d / 2, -p.d / 2):
    ax.axvline(z, ls="--", color="0.5")
ax.set_xlabel("Z")
ax.set_ylabel(r"$\dot Z$")
ax.set_title(att.label)

# %%
# A run can stop as soon as its motion repeats: a few dozen events instead of a million.
short = vi.simulate(p, 1.015, 0.1924, n_impacts=10**6, stop_when_periodic=True)
print(short.sizes["impact"], "events;", short.attrs["status"])
