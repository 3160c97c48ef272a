"""The knock map's table: the best design, the best that survives the configured knock (over the map and at each
incline of the design table), and what the shocks cost."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import pandas as pd
import xarray as xr

from vibroimpact.analysis.robust import table_choices
from vibroimpact.outputs.tables import knocks_markdown, knocks_table

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
km = xr.load_dataset(snakemake.input[0], engine="netcdf4")
choices = table_choices(km, float(km.attrs["knock"]), snakemake.params.table_betas if km.attrs["y"] == "beta" else ())
df = knocks_table(choices, km)
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(knocks_markdown(df, km, seconds=float(pd.read_csv(snakemake.input.cost, sep="\t")["s"].iloc[0])))
