"""Output voltages and averages for one branch or one sweep."""
import logging

import xarray as xr

from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.energy import Membrane, branch_energy, sweep_energy

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
mb = Membrane(**snakemake.params.membrane)
ph = snakemake.params.physics
src = xr.load_dataset(snakemake.input[0], engine="netcdf4")
if snakemake.rule == "branch_energy":
    ds = branch_energy(src, mb, M=ph["M"], omega=ph["omega"])
else:
    ds = sweep_energy(src, mb, M=ph["M"], omega=ph["omega"], window_time=snakemake.params.window_time)
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
