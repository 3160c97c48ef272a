"""The largest Lyapunov exponent by every method against a long reference run, error against cost."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

from vibroimpact.benchmarks.lyapunov_precision import lyapunov_precision
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs.tables import lyapunov_precision_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = dict(snakemake.params)
sizes = {k: (tuple(v) if isinstance(v, list) else v) for k, v in p.items() if k != "code"}  # code: the sources' hash
ds = lyapunov_precision(**sizes)
ds.attrs.update(provenance(**p))
write_netcdf(ds, snakemake.output.nc)
with open(snakemake.output.md, "w") as fh:
    fh.write(lyapunov_precision_markdown(ds))
logging.info("%d solvers x %d motions x %d repeats", ds.sizes["solver"], ds.sizes["motion"], ds.sizes["repeat"])
