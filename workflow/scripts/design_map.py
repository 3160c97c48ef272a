"""A design map from its chunks, with the tolerance box of every design: the lowest expected output over
it and the margin to the bifurcation curves of the same plane."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.analysis.design import merge_chunks, tolerance_analysis
from vibroimpact.datasets import write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ds = merge_chunks([xr.load_dataset(f, engine="netcdf4") for f in snakemake.input.chunks])
ds = tolerance_analysis(ds, xr.load_dataset(snakemake.input.curves, engine="netcdf4"), snakemake.params.tolerance)
write_netcdf(ds, snakemake.output[0])
logging.info("%d points, %d multistable, %d robust", ds["E_U_T"].size, int(ds.multistable.sum()), int(ds.robust.sum()))
