"""Design guidance: per incline, the length and the force that maximise each average output, and where each
average rises and falls along the sweeps."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots
from vibroimpact.outputs.tables import design_markdown, design_table, design_trends, design_trends_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
s_sets = [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.s]
F_sets = [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.F]
df = design_table(s_sets + F_sets)
df.to_csv(snakemake.output.csv, index=False)
trends = design_trends(s_sets + F_sets)
trends.to_csv(snakemake.output.trends, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(design_markdown(df))
    fh.write("\nAlong each sweep, d decreasing (as the figure draws it), as the swept parameter grows: how many steps "
             "between neighbouring points raise each average, and its largest fall (a run of falling steps; a point "
             "whose transient outlasts the cap breaks the line):\n\n")
    fh.write(design_trends_markdown(trends))
plots.save_outputs(plots.fig_design(s_sets, F_sets, df), snakemake.output, data=snakemake.output.data,
           attrs=provenance(**dict(snakemake.params)))
