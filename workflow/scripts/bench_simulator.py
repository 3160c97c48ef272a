"""Benchmark the exact simulator against solve_ivp and write the dataset and its table."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

from vibroimpact.benchmarks.bench import (
    branch_benchmark,
    curve_benchmark,
    kernel_profile,
    report,
    simulator_benchmark,
    sweep_benchmark,
)
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = dict(snakemake.params)
ds = xr.merge([simulator_benchmark(p["n_impacts"], p["n_impacts_ivp"], p["n_flights_accuracy"]), branch_benchmark(1000), curve_benchmark(200),
               sweep_benchmark(1000)])
ds.attrs.update(provenance(**p))
write_netcdf(ds, snakemake.output.nc)
kp = kernel_profile(p["n_impacts"])
kp.attrs.update(provenance(**p))
write_netcdf(kp, snakemake.output.kernel)
with open(snakemake.output.md, "w") as fh:
    fh.write(report(ds))
    fh.write("\nThe exact kernel on the two target scenes (one thread; batch on 1 and all cores; counts per impact):\n\n")
    fh.write(kp.to_dataframe().T.to_markdown() + "\n")
logging.info(report(ds))
