"""
Grazing and the bistable band
=============================

At β = π/6 the 2:1 orbit loses its admissibility where its loop grazes the bottom wall (G1): below it
the 3:1 orbit is born. The 3:1 orbit in turn exists up to its fold (G2), so between G1 and G2 both
motions are stable: the paper's bistable band. The analytic points come from the continued branches;
a sweep up and down in d, following the attractor, sees the same band as hysteresis.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import vibroimpact as vi

p = vi.Params.from_physical(s=0.14 / 0.6225, beta=math.pi / 6)
o21 = vi.find_orbit(p, "BBT", phi=5.855, v0=0.4185)
o31 = vi.find_orbit(p, "BBBT", phi=5.88, v0=0.3967)
b21 = vi.continue_orbit(o21, vary="s", d_range=(0.135, 0.145), step=5e-4)
b31 = vi.continue_orbit(o31, vary="s", d_range=(0.135, 0.145), step=5e-4)
g1 = float(b21.critical_d.values[b21.critical_kind.values.astype(str) == "grazing"].max())
g2 = float(b31.critical_d.values[b31.critical_kind.values.astype(str) == "fold"].min())
print(f"G1 = {g1:.7f} (2:1 grazes), G2 = {g2:.7f} (3:1 fold)")

# %%
# A sweep of s through the band, up and down, each point started from the last attractor:
sw = vi.sweep("s", np.linspace(0.1365, 0.1425, 25) / 0.6225, beta=math.pi / 6, phi=5.855, v0=0.4185,
              long_impacts=0)
tr = vi.locate_transitions(sw, xtol=1e-8)
band = vi.bistable_intervals(sw, tr)
print(band[["d_lo", "d_hi", "label_up", "label_down"]].to_dataframe())

# %%
fig, ax = plt.subplots(figsize=(6, 3))
for k, (direction, marker) in enumerate((("up", "+"), ("down", "o"))):
    lab = sw.label.sel(direction=direction).values.astype(str)
    ax.plot(sw.d, np.where(lab == "2:1 period-2", 2, np.where(lab == "3:1 period-2", 3, np.nan)) + 0.05 * k,
            marker, mfc="none", ls="none", label=f"d {'increasing' if direction == 'up' else 'decreasing'}")
for g, name in ((g1, "G1"), (g2, "G2")):
    ax.axvline(g, color="k", ls="-.", lw=0.8)
    ax.annotate(name, (g, 3.3))
ax.set_yticks([2, 3], ["2:1", "3:1"])
ax.set_xlabel("d")
ax.legend(fontsize=7)
