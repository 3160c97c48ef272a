"""Work-precision of every method on the 1:1, 2:1, 3:1 and chaotic scenes."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

from vibroimpact.benchmarks.workprecision import matched_accuracy, work_precision
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs.tables import matched_accuracy_markdown, work_precision_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = dict(snakemake.params)
ds = work_precision(**{k: v for k, v in p.items() if k != "code"})  # code: the package sources' hash
ds.attrs.update(provenance(**p))
write_netcdf(ds, snakemake.output.nc)
with open(snakemake.output.md, "w") as fh:
    fh.write(work_precision_markdown(ds))
ma = matched_accuracy(ds)
ma.attrs.update(provenance(**p))
write_netcdf(ma, snakemake.output.matched)
with open(snakemake.output.matched_md, "w") as fh:
    fh.write(matched_accuracy_markdown(ma))
