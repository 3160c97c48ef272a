"""Bifurcation curves over the regime map, from their datasets."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numpy as np
import xarray as xr

from vibroimpact.analysis.bifurcation import map_boundaries
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs import plots

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
curves = xr.load_dataset(snakemake.input.curves, engine="netcdf4")
regime_map = xr.load_dataset(snakemake.input.map, engine="netcdf4")
# which simulated boundaries a curve explains (saved beside the curves; the figure marks the others)
bounds = map_boundaries(regime_map, curves)
write_netcdf(bounds, snakemake.output.boundaries)
logging.info("boundaries by cause: %s", dict(zip(*np.unique(bounds.cause.values, return_counts=True), strict=True)))
fig = plots.fig_bifurcation_set(regime_map, curves, bounds, xr.load_dataset(snakemake.input.exit, engine="netcdf4"))
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data, attrs=provenance())
