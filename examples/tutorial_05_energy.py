"""
Voltage per impact and its averages
===================================

Each impact deflects a dielectric-elastomer membrane and raises its output voltage; a motion delivers
the average per impact Ū_I and per unit time Ū_T (the paper's eq. ``V1``). For a periodic orbit the
averages are exact over one period; where no period is found, a long run gives them with a standard
error.
"""

import math
from pathlib import Path

import numpy as np
import yaml

import vibroimpact as vi

# %%
# The device of the workflow's config, its physics and membrane constants (run from the repository or from
# its ``examples/``):
config = next(p for p in (Path("config/config.yaml"), Path("../config/config.yaml")) if p.exists())
cfg = yaml.safe_load(config.read_text())
device = vi.Device.from_config(cfg["physics"], cfg["membrane"])

# %%
# The 2:1 orbit of Figure 7 (a) and the 1:1 orbit of Figure 4 (a): gains per impact and averages.
for s, beta, word, phi, v0 in ((0.16 / 0.6225, math.pi / 6, "BBT", 1.015, 0.1924),
                               (0.38 / 0.6225, math.pi / 3, "BT", 0.4217, 0.8673)):
    o = vi.find_orbit(device.params(s=s, beta=beta), word, phi, v0)
    e = vi.orbit_energy(o, device)
    print(word, np.round(e["gain"]), f"U_I = {e['U_I']:.0f} V, U_T = {e['U_T']:.0f} V per unit time")

# %%
# Along a sweep: where the motion is periodic the exact cycle's averages, where it is not the long run's.
sw = vi.sweep("F", np.linspace(20, 22, 6), beta=math.pi / 3, s=0.85, phi=0.42, v0=0.87, device=device)
en = vi.sweep_energy(sw, device)
value, se = vi.delivered(en, "U_T")
for i, lab in enumerate(en.label.sel(direction="down").values.astype(str)):
    print(f"F = {float(en.F[i]):5.2f} N  {lab:18s} U_T = {value[1, i]:9.0f} ± {se[1, i]:.0f} V")
