"""The paper's d_graz along each sweep of the check (every incline, by length and by force): the 2:1 fold, where
the sweeps meet the 2:1 period-2, the 1:1 exit and the band between (vibroimpact.sweep_d_graz)."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.analysis.d_graz import sweep_d_graz
from vibroimpact.outputs.tables import d_graz_markdown, d_graz_table

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
load = lambda f: xr.load_dataset(f, engine="netcdf4")
i = snakemake.input
readings = {name: sweep_d_graz(load(sw), load(tr), load(br)) for name, sw, tr, br in
            zip(snakemake.params.names, i.sweeps, i.transitions, i.branches, strict=True)}
df = d_graz_table(readings)
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(d_graz_markdown(df))
logging.info("\n%s", df.to_string())
