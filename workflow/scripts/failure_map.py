"""Where each method fails: near grazing, chattering into sticking, a long chaotic run."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

from vibroimpact.benchmarks.workprecision import failure_map
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs.tables import failure_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = dict(snakemake.params)
ds = failure_map(**{k: v for k, v in p.items() if k != "code"})  # code: the package sources' hash
ds.attrs.update(provenance(**p))
write_netcdf(ds, snakemake.output.nc)
with open(snakemake.output.md, "w") as fh:
    fh.write(failure_markdown(ds))
