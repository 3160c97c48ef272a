"""All located transitions and bistable intervals as one Markdown table."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.outputs.tables import transitions_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
named = {n: xr.load_dataset(f, engine="netcdf4") for n, f in zip(snakemake.params.names, snakemake.input, strict=True)}
with open(snakemake.output[0], "w") as fh:
    fh.write(transitions_markdown(named))
