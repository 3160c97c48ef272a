"""Follow each critical point of the start branches as a curve in the map's parameter plane."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.analysis.bifurcation import curve_set
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.dynamics.device import Device

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
mp, bf = snakemake.params.map, snakemake.params.bifurcation
ph = Device.from_config(**snakemake.params.device).physics()
branches = [xr.load_dataset(f, engine="netcdf4") for f in snakemake.input]
ranges = (tuple(mp["x_range"]), tuple(mp["y_range"]))
ds = curve_set(branches, (mp["x"], mp["y"]), ranges, kinds=bf["kinds"], step=bf["step"],
               physics=dict(beta=bf["beta"], M=ph["M"], F=ph["F"], omega=ph["omega"], r=ph["r"], g=ph["g"]))
for i in range(ds.sizes["curve"]):
    logging.info("%s %s from s=%.6g: %s %s", ds.curve_word.values[i], ds.curve_kind.values[i],
                 ds.curve_start_s.values[i], ds.curve_status.values[i], ds.curve_reason.values[i])
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
