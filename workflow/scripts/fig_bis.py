"""The paper's Figure 8 (figBiS) from the sweep, its transitions, the portraits and the analytic branches."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
i = snakemake.input
load = lambda f: xr.load_dataset(f, engine="netcdf4")
fig = plots.fig_bis(load(i.sweep), load(i.transitions), load(i.portraits), [load(i.branch21), load(i.branch31)])
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data,
           attrs=provenance(**dict(snakemake.params)))
