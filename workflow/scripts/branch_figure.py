"""Draw a branch figure (the paper's Figure 5 or 6: fig2, fig3) from the saved branch datasets."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots
from vibroimpact.outputs.tables import grazing_lines

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
scene, k_s = snakemake.params.scene, snakemake.params.k_s
n = len(scene["betas"])
branches = [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.branches]
sims = [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.sims]
d_ranges = [(lo * k_s, hi * k_s) for lo, hi in scene["s_ranges"]]
name = snakemake.rule
if name == "fig2":
    grazing = grazing_lines(branches, scene) if "grazing" in scene else None
    fig = plots.fig2(branches[:n], sims[:n], d_ranges, grazing)
else:
    fig = plots.fig3(branches[:n], d_ranges)
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data,
           attrs=provenance(**dict(snakemake.params)))
