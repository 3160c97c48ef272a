"""Work-precision of every method on the 1:1, 2:1, 3:1 and chaotic scenes."""
import logging

from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.tables import work_precision_markdown
from vibroimpact.workprecision import work_precision

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = dict(snakemake.params)
ds = work_precision(n_err=p["n_err"], n_cost=p["n_cost"], ivp_methods=p["ivp_methods"], ivp_tols=p["ivp_tols"],
                    rk4_steps=p["rk4_steps"])
ds.attrs.update(provenance(**p))
write_netcdf(ds, snakemake.output.nc)
with open(snakemake.output.md, "w") as fh:
    fh.write(work_precision_markdown(ds))
