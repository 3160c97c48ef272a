"""The paper's Figure 2 or 9 (fig0, fig5): voltages (and for Figure 2 impact velocities) against d, from saved datasets."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.datasets import provenance
from vibroimpact.outputs import plots

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
load = lambda f: xr.load_dataset(f, engine="netcdf4")
i = snakemake.input
panels = snakemake.params.panels
n_w = len(snakemake.params.words)
per = 1 + n_w  # per panel: the sweep's energy, then the energies of the branches
energies = [load(i.energies[k * per]) for k in range(len(panels))]
branches = [[load(f) for f in i.energies[k * per + 1:(k + 1) * per]] for k in range(len(panels))]
orbits = [[load(f) for f in i.orbits[k * n_w:(k + 1) * n_w]] for k in range(len(panels))]
sweeps = [load(f) for f in i.sweeps]
transitions = [load(f) for f in i.transitions]
fig = plots.fig_energy(panels, sweeps, energies, branches, velocities=snakemake.params.velocities, orbit_sets=orbits,
                       transitions=transitions)
plots.save_outputs(fig, snakemake.output, data=snakemake.output.data,
           attrs=provenance(**dict(snakemake.params)))
