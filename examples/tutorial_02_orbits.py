"""
Find a periodic orbit and continue it with its stability
========================================================

A periodic impact orbit solves the impact maps' equations (paper eqs. ``zdotj_p1``, ``zj_p1``);
:func:`vibroimpact.find_orbit` solves them by Newton's method from a guess and gives the eigenvalues of
the linearised map over one period (eq. ``Lin2``). :func:`vibroimpact.continue_orbit` follows the orbit
along a parameter and locates where its stability changes (period doubling B, node-focus A, fold) and
where it grazes a wall.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

import vibroimpact as vi

# %%
# The 2:1 orbit (word BBT: two bottom impacts and one top per forcing period) of Figure 8 (e):
p = vi.Params.from_physical(s=0.14 / 0.6225, beta=math.pi / 6)
o = vi.find_orbit(p, "BBT", phi=5.855, v0=0.4185)
print(o.stability, np.round(np.abs(o.eigenvalues), 4), "admissible:", o.admissible)

# %%
# Continue it in the cylinder length s (at fixed force) over 0.13 < d < 0.23:
br = vi.continue_orbit(o, vary="s", d_range=(0.13, 0.23), step=2e-3)
crit = br.critical_kind.values.astype(str), br.critical_d.values
for kind, d in zip(*crit, strict=True):
    print(f"{kind:8s} at d = {d:.6f}")

# %%
# Impact velocities along the branch: solid where stable, dashed where unstable, on the admissible
# stretch (no flight crosses a wall).
fig, ax = plt.subplots(figsize=(6, 3.5))
adm = br.admissible.values
for j in range(br.sizes["impact"]):
    v = np.abs(br.v_minus.values[:, j])
    ax.plot(br.d[adm], np.where(br.stable.values[adm], v[adm], np.nan), "-", color=f"C{j}")
    ax.plot(br.d[adm], np.where(br.stable.values[adm], np.nan, v[adm]), "--", color=f"C{j}")
for kind, d in zip(*crit, strict=True):
    ax.axvline(d, color="0.6", lw=0.6)
    ax.annotate(kind, (d, 0.02), xycoords=("data", "axes fraction"), fontsize=7, rotation=90)
ax.set_xlabel("d")
ax.set_ylabel(r"$|\dot Z_k|$")
