"""Basins-of-attraction figure from its dataset."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
fig = plots.fig_basins(xr.load_dataset(snakemake.input[0], engine="netcdf4"))
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data,
           attrs=provenance(**dict(snakemake.params)))
