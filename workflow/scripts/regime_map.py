"""Regime map: the attractor over two physical parameters."""
import logging

import numba
import numpy as np

from vibroimpact.analysis.sweeps import regime_map
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
numba.set_num_threads(max(1, min(snakemake.threads, numba.config.NUMBA_NUM_THREADS)))
sp, ph = snakemake.params.spec, snakemake.params.physics
nx, ny = snakemake.params.grid
fixed = {k: sp[k] for k in ("beta", "s", "F") if k in sp}
ds = regime_map(sp["x"], np.linspace(*sp["x_range"], nx), sp["y"], np.linspace(*sp["y_range"], ny),
                phi=sp["phi"], v0=sp["v0"], max_periods=snakemake.params.max_periods, tol=snakemake.params.tol,
                M=ph["M"], omega=ph["omega"], g=ph["g"], r=ph["r"], **({"F": ph["F"]} | fixed))
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
