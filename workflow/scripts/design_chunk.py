"""One chunk of a design map: consecutive rows of its grid, every point run from the same start states
to its attractors, with their shares and outputs."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numba
import numpy as np

from vibroimpact.analysis.design import design_map, grid_axes, start_states
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.dynamics.device import Device

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
numba.set_num_threads(max(1, min(snakemake.threads, numba.config.NUMBA_NUM_THREADS)))
sp, de, pre = snakemake.params.spec, snakemake.params.design, snakemake.params.preset
device = Device.from_config(**snakemake.params.device)
xs, ys = grid_axes(sp, pre["grid"], de["table_betas"])
rows = np.array_split(np.arange(ys.size), pre["chunks"])[int(snakemake.wildcards.chunk)]
st = de["starts"]
phi, v0 = start_states(pre["starts"], distribution=st["distribution"], seed=st["seed"], phi_range=st["phi_range"],
                       v0_range=st["v0_range"])
fixed = {k: sp[k] for k in ("beta", "s", "F") if k in sp}
ds = design_map(sp["x"], xs, sp["y"], ys[rows], phi=phi, v0=v0, device=device,
                max_periods=snakemake.params.max_periods, tol=snakemake.params.tol, window=snakemake.params.window,
                window_time=snakemake.params.window_time, min_share=de["min_share"], confidence=de["confidence"],
                **fixed)
ds.attrs.update(provenance(**dict(snakemake.params)), chunk=int(snakemake.wildcards.chunk), rows=f"{rows[0]}-{rows[-1]}",
                distribution=st["distribution"], seed=st["seed"])
write_netcdf(ds, snakemake.output[0])
logging.info("rows %s: %d points x %d starts, %d events", ds.attrs["rows"], ds["E_U_T"].size, phi.size,
             ds.attrs["events"])
