"""Simulated attractors along the stable part of a branch (the figures' open circles)."""
import logging

import xarray as xr

from vibroimpact.analysis.continuation import simulate_along
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
branch = xr.load_dataset(snakemake.input[0], engine="netcdf4")
if branch.attrs.get("status") == "failed":
    ds = xr.Dataset(attrs=dict(status="failed", reason=branch.attrs["reason"]))
else:
    ds = simulate_along(branch, snakemake.params.n, tol=snakemake.params.tol)
    ds.attrs.update(status="ok", beta=branch.attrs["beta"])
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
