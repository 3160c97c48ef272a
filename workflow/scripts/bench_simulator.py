"""Benchmark the exact simulator against solve_ivp and write the dataset and its table."""
import logging

import xarray as xr

from vibroimpact.bench import branch_benchmark, report, simulator_benchmark, sweep_benchmark
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = dict(snakemake.params)
ds = xr.merge([simulator_benchmark(p["n_impacts"], p["n_impacts_ivp"], p["n_flights_accuracy"]), branch_benchmark(1000), sweep_benchmark(1000)])
ds.attrs.update(provenance(**p))
write_netcdf(ds, snakemake.output.nc)
with open(snakemake.output.md, "w") as fh:
    fh.write(report(ds))
logging.info(report(ds))
