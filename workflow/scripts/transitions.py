"""Locate the transitions of a sweep and its bistable intervals."""
import logging

import xarray as xr

from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.sweeps import bistable_intervals, locate_transitions

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
sw = xr.load_dataset(snakemake.input[0], engine="netcdf4")
loc = snakemake.params.locate
tr = locate_transitions(sw, xtol=loc["xtol"], max_periods=loc["max_periods"], max_trials=loc["max_trials"])
ds = xr.merge([tr, bistable_intervals(sw, tr)], combine_attrs="drop_conflicts")
ds.attrs.update(provenance(**loc), beta=sw.attrs["beta"], vary=sw.attrs["vary"])
write_netcdf(ds, snakemake.output[0])
logging.info("%d transitions, %d bistable intervals", ds.sizes["transition"], ds.sizes["interval"])
