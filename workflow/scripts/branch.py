"""Continue one periodic orbit in the cylinder length s (fixed force) and write its branch."""
import logging

import vibroimpact as vi
from vibroimpact.continuation import branch_from_simulation
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ph, spec = snakemake.params.physics, snakemake.params.spec
k_s = ph["M"] * ph["omega"] ** 2 / (ph["F"] * 3.141592653589793**2)  # d = k_s s
params = vi.Params.from_physical(s=spec["start_d"] / k_s, beta=snakemake.params.beta, M=ph["M"], F=ph["F"],
                                 omega=ph["omega"], r=ph["r"], g=ph["g"])
ds = branch_from_simulation(params, snakemake.params.word, k=spec["k"], vary="s",
                            d_range=tuple(snakemake.params.d_range), step=snakemake.params.step,
                            phi=spec["phi"], v0=spec["v0"])
ds.attrs.update(beta=snakemake.params.beta, **provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
logging.info("%s beta=%s: %s %s", snakemake.params.word, snakemake.params.beta, ds.attrs["status"], ds.attrs.get("reason", ""))
