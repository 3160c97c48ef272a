"""The best robust designs per incline, from the design maps, and what the design maps cost."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import pandas as pd
import xarray as xr

from vibroimpact.analysis.design import table_designs
from vibroimpact.outputs.tables import design_cost_markdown, design_robust_markdown, design_robust_table

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
rows, sizes, seconds = {}, {}, {}
for path in snakemake.input.maps:
    ds = xr.load_dataset(path, engine="netcdf4")
    name = path.rsplit("/", 1)[-1].removesuffix(".nc")
    rows[name] = table_designs(ds, snakemake.params.budget, snakemake.params.table_betas)
    sizes[name] = (int(ds["E_U_T"].size * ds.attrs["starts"]), int(ds.attrs["events"]))
    seconds[name] = sum(float(pd.read_csv(f, sep="\t")["s"].iloc[0]) for f in snakemake.input.cost
                        if f.rsplit("/", 1)[-1].startswith(f"{name}-"))
df = design_robust_table(rows)
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(design_robust_markdown(df))
with open(snakemake.output.cost, "w") as fh:
    fh.write(design_cost_markdown(sizes, seconds))
