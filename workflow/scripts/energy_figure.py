"""Fig 0 or Fig 5: voltages (and for Fig 0 impact velocities) against d, from saved datasets."""
import logging

import xarray as xr

from vibroimpact import plotting
from vibroimpact.datasets import provenance

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
load = lambda f: xr.load_dataset(f, engine="netcdf4")
n_w = len(snakemake.params.words)
files = list(snakemake.input)
panels = snakemake.params.panels
per = 1 + n_w
energies = [load(files[i * per]) for i in range(len(panels))]
branches = [[load(f) for f in files[i * per + 1:(i + 1) * per]] for i in range(len(panels))]
sweeps = [load(f) for f in files[len(panels) * per:]]
fig = plotting.fig_energy(panels, sweeps, energies, branches, velocities=snakemake.params.velocities)
plotting.save(fig, snakemake.output.pdf.removesuffix(".pdf"), data=snakemake.output.data,
              attrs=provenance(**dict(snakemake.params)))
