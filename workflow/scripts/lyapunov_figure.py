"""The lambda_1 figure (the registry's row ``lyapunov``: under the velocity bifurcation diagrams of Figures 2
and 9) and the table of chaotic windows and chaotic outputs, from the saved sweeps, their energies and the
continued branches."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots
from vibroimpact.outputs.tables import between_markdown, chaos_markdown, chaotic_outputs, chaotic_windows

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
load = lambda f: xr.load_dataset(f, engine="netcdf4")
i, o = snakemake.input, snakemake.output
panels = snakemake.params.panels
n_w = len(snakemake.params.words)
sweeps = [load(f) for f in i.sweeps]
orbits = [[load(f) for f in i.orbits[k * n_w:(k + 1) * n_w]] for k in range(len(panels))]
fig = plots.fig_lyapunov(sweeps, orbits, [load(f) for f in i.transitions])
plots.save_outputs(fig, o, data=o.data, attrs=provenance(**dict(snakemake.params)))
# the table: every sweep of the workflow, drawn in this figure or not
names = snakemake.params.table_sweeps
table_sweeps = {n: load(f) for n, f in zip(names, i.table_sweeps, strict=True)}
windows = chaotic_windows(table_sweeps)
outputs = chaotic_outputs({n: load(f) for n, f in zip(names, i.table_energies, strict=True)})
windows.to_csv(o.windows, index=False)
outputs.to_csv(o.outputs, index=False)
with open(o.md, "w") as fh:
    fh.write(chaos_markdown(windows, outputs, between_markdown(
        {n: (table_sweeps[n], load(f)) for n, f in zip(names, i.table_transitions, strict=True)})))
