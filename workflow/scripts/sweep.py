"""One numerical sweep (up and down), following the attractor; its located transitions (the period doublings
among them placed at the branches' flips) and bistable intervals; its output voltages and averages."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numba
import numpy as np
import xarray as xr

from vibroimpact.analysis.bistability import bistable_intervals
from vibroimpact.analysis.energy import sweep_energy
from vibroimpact.analysis.family_exit import sweep_family_exit
from vibroimpact.analysis.sweeps import sweep
from vibroimpact.analysis.transitions import locate_transitions, period_doublings
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.dynamics.device import Device

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
# the cores the scheduler gave the job: the directions, long runs and transitions go side by side on them
numba.set_num_threads(max(1, min(snakemake.threads, numba.config.NUMBA_NUM_THREADS)))
sc, sw = snakemake.params.scene, snakemake.params.sweeps
device = Device.from_config(**snakemake.params.device).replace(r=snakemake.params.r)
values = np.linspace(sc["range"][0], sc["range"][1], snakemake.params.points)
fixed = {"F": sc.get("F", device.F)} if sc["vary"] == "s" else {"s": sc["s"]}
ds = sweep(sc["vary"], values, beta=sc["beta"], phi=sc["phi"], v0=sc["v0"], max_periods=sw["max_periods"],
           tol=sw["tol"], window=sw["window"], device=device, **fixed)
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output.sweep)
en = sweep_energy(ds, device, window_time=snakemake.params.window_time)
en.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(en, snakemake.output.energy)
logging.info("labels: %s", sorted(set(ds.label.values.ravel())))
loc = snakemake.params.locate
tr = locate_transitions(ds, xtol=loc["xtol"], max_periods=loc["max_periods"], max_trials=loc["max_trials"])
# a period lost where the detector gave up short of a flip (critical slowing) is a period doubling, at the flip
tr = period_doublings(tr, ds, [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.branches])
# the 1:1 exit: where the 1:1 attractor followed down leaves the 1:1 family (by grazing or by a jump)
trs = xr.merge([tr, bistable_intervals(ds, tr), sweep_family_exit(ds, xtol=loc["xtol"])], combine_attrs="drop_conflicts")
trs.attrs.update(provenance(**loc), beta=ds.attrs["beta"], vary=ds.attrs["vary"])
write_netcdf(trs, snakemake.output.transitions)
logging.info("%d transitions, %d bistable intervals; 1:1 exit: %s %s at %.7f", trs.sizes["transition"],
             trs.sizes["interval"], trs.exit_status.values, trs.exit_kind.values, trs.exit_d.values)
