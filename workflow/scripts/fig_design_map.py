"""Design map figure: expected and worst-case output with the bifurcation curves, multistable regions and
the best robust designs, from the design dataset."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.analysis.design import table_designs
from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ds = xr.load_dataset(snakemake.input.design, engine="netcdf4")
curves = xr.load_dataset(snakemake.input.curves, engine="netcdf4")
best = table_designs(ds, snakemake.params.budget, snakemake.params.table_betas)
fig = plots.fig_design_map(ds, curves, best)
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data, attrs=provenance(**dict(snakemake.params)))
