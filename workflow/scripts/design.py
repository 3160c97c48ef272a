"""Design guidance: per incline, the length and the force that maximise each average output."""
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots
from vibroimpact.outputs.tables import design_markdown, design_table

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
s_sets = [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.s]
F_sets = [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.F]
df = design_table(s_sets + F_sets)
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(design_markdown(df))
plots.save_outputs(plots.fig_design(s_sets, F_sets, df), snakemake.output, data=snakemake.output.data,
           attrs=provenance(**dict(snakemake.params)))
