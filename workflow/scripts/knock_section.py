"""The basins a knock crosses: at the configured design, its highest-output attractor (from the design maps' start
states), that motion's critical shock and the basins in the (Z, Zdot) section at the shock's forcing phase."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numba
import numpy as np

from vibroimpact.analysis.design import design_map, start_states
from vibroimpact.analysis.robust import knock_section, point_params
from vibroimpact.analysis.shocks import critical_shock
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.dynamics.device import Device

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
numba.set_num_threads(max(1, min(snakemake.threads, numba.config.NUMBA_NUM_THREADS)))
kn, de, pre = snakemake.params.knocks, snakemake.params.design, snakemake.params.preset
device = Device.from_config(**snakemake.params.device)
sec = kn["section"]
st = de["starts"]
phi, v0 = start_states(pre["starts"], distribution=st["distribution"], seed=st["seed"], phi_range=st["phi_range"],
                       v0_range=st["v0_range"])
held = {"F": sec.get("F", device.F)}
dm = design_map("s", [sec["s"]], "beta", [sec["beta"]], phi=phi, v0=v0, device=device,
                max_periods=snakemake.params.max_periods, tol=snakemake.params.tol, window=snakemake.params.window,
                window_time=snakemake.params.window_time, min_share=de["min_share"], confidence=de["confidence"], **held)
params = point_params(dm, 0, 0, device)
order = np.argsort(-np.nan_to_num(dm["U_T"].values[0, 0], nan=-np.inf))
sh, start = None, (0.0, 0.0)
for a in order:  # the highest-output periodic attractor whose critical shock is found
    ph, vm = float(dm["impact_phase"].values[0, 0, a]), float(dm["impact_v_minus"].values[0, 0, a])
    if not (np.isfinite(ph) and np.isfinite(vm)):
        continue
    try:
        found = critical_shock(params, ph, vm, kind=kn["kind"], device=device)
    except ValueError as err:  # its start finds no period within the cap: recorded, the next one is tried
        logging.info("attractor %s: %s", dm["label"].values[0, 0, a], err)
        continue
    if sh is None:
        sh, start = found, (ph, vm)
    if np.isfinite(found.size):
        sh, start = found, (ph, vm)
        break
half = 0.5 * params.d
speeds = [abs(start[1])] + ([abs(sh.state[1]), abs(sh.state[1]) + sh.size * (sh.kind == "velocity")]
                            if sh is not None and np.isfinite(sh.size) else [])
vmax = 1.25 * max(max(speeds), float(np.nanmax(np.abs(dm["impact_v_minus"].values), initial=0.0)), 0.1)
nz, nv = pre["section"]
ds = knock_section(params, sh, start[0], np.linspace(-half, half, nz), np.linspace(-vmax, vmax, nv),
                   max_periods=snakemake.params.max_periods)
ds.attrs.update(provenance(**dict(snakemake.params)), s=sec["s"], beta=sec["beta"], F=held["F"],
                size_unit="m/s" if kn["kind"] == "velocity" else "m")
if sh is not None:
    ds.attrs.update(U_T=sh.U_T, reached_U_T=sh.reached_U_T, simulations=sh.simulations, tolerance=sh.tolerance,
                    delay=sh.delay)
write_netcdf(ds, snakemake.output[0])
logging.info("section at phase %.4f: %s", ds.attrs["phase"], ds.attrs["reason"] or f"shock {sh.size_si:.4g}")
