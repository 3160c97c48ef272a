"""Table 1: stability intervals and critical points of the 2:1 branches, per incline."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.outputs.tables import table1, table1_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
df = table1([xr.load_dataset(f, engine="netcdf4") for f in snakemake.input])
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(table1_markdown(df))
