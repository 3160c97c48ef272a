"""Regime map: the attractor over two physical parameters."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numba
import numpy as np

from vibroimpact.analysis.regime_maps import regime_map
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.dynamics.device import Device

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
numba.set_num_threads(max(1, min(snakemake.threads, numba.config.NUMBA_NUM_THREADS)))
sp, device = snakemake.params.spec, Device.from_config(**snakemake.params.device)
nx, ny = snakemake.params.grid
fixed = {k: sp[k] for k in ("beta", "s", "F") if k in sp}
ds = regime_map(sp["x"], np.linspace(*sp["x_range"], nx), sp["y"], np.linspace(*sp["y_range"], ny),
                phi=sp["phi"], v0=sp["v0"], max_periods=snakemake.params.max_periods, tol=snakemake.params.tol,
                device=device, **fixed)
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
