"""Draw a figure of the registry (vibroimpact.outputs.registry) whose rule is the generic one: its plot function,
called on the datasets its row names, saved with the arrays it draws."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import importlib
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
module, _, name = snakemake.params.plot.partition(":")
draw = getattr(importlib.import_module(module), name)
fig = draw(*[xr.load_dataset(f, engine="netcdf4") for f in snakemake.input])
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data, attrs=provenance(plot=snakemake.params.plot))
