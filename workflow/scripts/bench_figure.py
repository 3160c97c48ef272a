"""Draw a speed-and-accuracy figure (work-precision, failure map, accuracy of the analytics) from its dataset."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import json
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ds = xr.load_dataset(snakemake.input[0], engine="netcdf4")
fig = getattr(plots, f"fig_{snakemake.wildcards.bench}")(ds)
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data,
           attrs=provenance(**json.loads(ds.attrs.get("config", "{}"))))
