"""Bifurcation curves over the regime map, from their datasets."""
import logging

import xarray as xr

from vibroimpact import plots
from vibroimpact.datasets import provenance

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
curves = xr.load_dataset(snakemake.input.curves, engine="netcdf4")
fig = plots.fig_bifurcation_set(xr.load_dataset(snakemake.input.map, engine="netcdf4"), curves)
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data, attrs=provenance())
