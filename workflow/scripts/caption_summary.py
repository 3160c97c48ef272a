"""Collect the caption orbits into one table (netCDF and Markdown)."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs.portraits import caption_summary, summary_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
sets = {n: xr.load_dataset(f, engine="netcdf4") for n, f in zip(snakemake.params.names, snakemake.input, strict=True)}
table = caption_summary(sets, snakemake.params.stated)
table.attrs.update(provenance(stated=snakemake.params.stated))
write_netcdf(table, snakemake.output.nc)
with open(snakemake.output.md, "w") as fh:
    fh.write(summary_markdown(table))
