"""Basins of attraction over first bottom impacts (phase x velocity) at one parameter point."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numba
import numpy as np

import vibroimpact as vi
from vibroimpact.analysis.basins import basins
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
numba.set_num_threads(max(1, min(snakemake.threads, numba.config.NUMBA_NUM_THREADS)))
sp, device = snakemake.params.spec, vi.Device.from_config(**snakemake.params.device)
p = device.params(s=device.s(sp["d"]), beta=sp["beta"])
n_phi, n_v = snakemake.params.grid
ds = basins(p, np.linspace(0, 2 * np.pi, n_phi, endpoint=False), np.linspace(*sp["v0_range"], n_v),
            max_periods=sp["max_periods"], tol=snakemake.params.tol)
ds.attrs.update(beta=sp["beta"], **provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
