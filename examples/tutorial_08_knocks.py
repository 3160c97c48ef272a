"""
A harvest that survives knocks
==============================

A harvester mounted on a vehicle or a bridge is knocked. Where two motions coexist, a knock can drop it from
its high-output motion to a low-output one. This tutorial measures, for the long cylinder at β = π/3
(s = 0.6 m, where the 1:1 motion coexists with a stick–release cycle on the bottom membrane): the shares of
both motions from switch-on and from anywhere in the state space, the smallest knock that drops each motion
(its critical shock), and the basins the knock crosses; then the critical shocks of a small design map and
the design that keeps its output under a given knock.
"""

import json
import math

import matplotlib.pyplot as plt
import numpy as np

import vibroimpact as vi

p = vi.Params.from_physical(s=0.6, beta=math.pi / 3)

# %%
# Basin stability: which motion the device settles on, from switch-on (at rest on the bottom membrane) and
# from starts anywhere in a box of the state space, with 95 % Clopper–Pearson intervals.
bs = vi.basin_stability(p, n=400, seed=0)
for dist in bs.distribution.values:
    sel = bs.sel(distribution=dist)
    for lab, sh, lo, hi, u in zip(sel.label.values, sel.share.values, sel.share_low.values, sel.share_high.values,
                                  sel.U_T.values, strict=True):
        print(f"{dist:12s} {lab:45s} share {sh:.3f} ({lo:.3f}-{hi:.3f}), U_T {u / 1e3:.1f} kV")

# %%
# The critical shock of each motion: the smallest jump of the ball's velocity relative to the cylinder, at the
# worst phase of its cycle, that sends it to the other attractor. A start on each: the ball at rest on the bottom
# membrane at two forcing phases, whose runs settle on the two motions.
one_one = vi.critical_shock(p, phi=2 * math.pi / 3, v0=0.0)
stick = vi.critical_shock(p, phi=0.0, v0=0.0)
for sh in (one_one, stick):
    print(f"{sh.motion} ({sh.U_T / 1e3:.1f} kV): {sh.size_si:.3f} m/s at phase {sh.phase:.2f} rad "
          f"drops it to the {sh.reached} ({sh.reached_U_T / 1e3:.1f} kV), in {sh.simulations} runs")

# %%
# The basins a knock crosses: the motion reached from each state (Z, Zdot) at the forcing phase of the 1:1
# motion's critical shock, with the state the knock hits and the knocked state.
sec = vi.knock_section(p, one_one, 2 * math.pi / 3, np.linspace(-p.d / 2, p.d / 2, 120), np.linspace(-1, 1, 90))
legend = json.loads(sec.attrs["legend"])
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.pcolormesh(sec.Z, sec.Zdot, sec.attractor, shading="nearest", cmap="Set2")
ax.annotate("", xy=(sec.attrs["Z_knocked"], sec.attrs["Zdot_knocked"]),
            xytext=(sec.attrs["Z_state"], sec.attrs["Zdot_state"]), arrowprops=dict(arrowstyle="->"))
ax.set_xlabel("Z")
ax.set_ylabel(r"$\dot Z$")
ax.set_title(" / ".join(legend), fontsize=8)
fig.tight_layout()

# %%
# Robust design: the critical shock of every attractor over a few lengths at two inclines, then, at each incline,
# the design of highest output beside the one of highest output whose highest-output motion survives a knock of
# 2 m/s (``inf``: no admissible knock drops it).
phi, v0 = vi.start_states(16, distribution="rest", seed=1)
dm = vi.design_map("s", [0.4, 0.5, 0.6, 0.7], "beta", [math.pi / 6, math.pi / 3], phi=phi, v0=v0)
km = vi.knock_map(dm, phases=12, refine=3)
print(km[["top_label", "top_U_T", "top_shock"]].to_dataframe())
for row, beta in enumerate(km.beta.values):
    choice = vi.robust_choice(km, knock=2.0, row=row)
    best, robust = choice["best"], choice["robust"]
    print(f"beta = {beta:.3f}: best s = {best['s']} m ({best['U_T'] / 1e3:.1f} kV, shock {best['shock']:.3g} m/s); "
          f"surviving 2 m/s: s = {robust['s']} m ({robust['U_T'] / 1e3:.1f} kV)")
