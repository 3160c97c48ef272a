"""Regime-map figure from its datasets."""
import logging

import xarray as xr

from vibroimpact import plotting
from vibroimpact.datasets import provenance

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
fig = plotting.fig_regime_map([xr.load_dataset(f, engine="netcdf4") for f in snakemake.input])
plotting.save(fig, snakemake.output.pdf.removesuffix(".pdf"), data=snakemake.output.data,
              attrs=provenance(**dict(snakemake.params)))
