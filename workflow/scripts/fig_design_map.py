"""Design map figure: expected and worst-case output with the bifurcation curves, multistable regions and
the best robust designs, from the design dataset."""
import logging

import xarray as xr

from vibroimpact import plots
from vibroimpact.datasets import provenance
from vibroimpact.design import best_designs

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ds = xr.load_dataset(snakemake.input.design, engine="netcdf4")
curves = xr.load_dataset(snakemake.input.curves, engine="netcdf4")
best = best_designs(ds, snakemake.params.budget, per="beta" if ds.attrs["y"] == "beta" else None)
if ds.attrs["y"] == "beta":  # the table's inclines
    best = [b for b in best if min(abs(b["beta"] - t) for t in snakemake.params.table_betas) < 1e-12]
fig = plots.fig_design_map(ds, curves, best)
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data, attrs=provenance(**dict(snakemake.params)))
