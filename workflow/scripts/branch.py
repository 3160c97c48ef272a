"""Continue one periodic orbit in the cylinder length s (fixed force) or in the force F (fixed s)."""
import logging
import math

import vibroimpact as vi
from vibroimpact.analysis.continuation import branch_from_simulation
from vibroimpact.analysis.energy import Membrane, branch_energy
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ph, spec, vary = snakemake.params.physics, snakemake.params.spec, snakemake.params.vary
k = ph["M"] * ph["omega"] ** 2 / math.pi**2  # d = k s / F
if vary == "s":
    s, F = spec["start_d"] * ph["F"] / k, ph["F"]
    d_range = tuple(snakemake.params.d_range)
else:
    s = snakemake.params.force["s"]
    F = k * s / spec["start_d"]
    d_range = tuple(sorted(k * s / f for f in snakemake.params.force["F_range"]))
params = vi.Params.from_physical(s=s, beta=snakemake.params.beta, M=ph["M"], F=F, omega=ph["omega"],
                                 r=snakemake.params.r, g=ph["g"])
ds = branch_from_simulation(params, snakemake.params.word, k=spec["k"], vary=vary, d_range=d_range,
                            step=snakemake.params.step, phi=spec["phi"], v0=spec["v0"])
ds.attrs.update(beta=snakemake.params.beta, **provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output.orbit)
en = branch_energy(ds, Membrane(**snakemake.params.membrane), M=ph["M"], omega=ph["omega"])
en.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(en, snakemake.output.energy)
logging.info("%s beta=%s vary=%s: %s %s", snakemake.params.word, snakemake.params.beta, vary, ds.attrs["status"],
             ds.attrs.get("reason", ""))
