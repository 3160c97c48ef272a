"""Accuracy of the located critical and grazing points against resolution and cost."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.benchmarks.workprecision import analytics_accuracy
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs.tables import stable_interval

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
# G1: where the 2:1 branch's stable, admissible run ends by grazing; G2: the 3:1 branch's fold
g1 = stable_interval(xr.load_dataset(snakemake.input.branch21, engine="netcdf4"))[0]
g2 = stable_interval(xr.load_dataset(snakemake.input.branch31, engine="netcdf4"))[1]
logging.info("reference G1 = %.13g, G2 = %.13g (from the analytic branches)", g1, g2)
ds = analytics_accuracy(g1=g1, g2=g2)
ds.attrs.update(provenance(G1_from=snakemake.input.branch21, G2_from=snakemake.input.branch31))
write_netcdf(ds, snakemake.output.nc)
