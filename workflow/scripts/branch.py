"""Continue one periodic orbit in the cylinder length s (fixed force) or in the force F (fixed s)."""
import logging

import vibroimpact as vi
from vibroimpact.analysis.continuation import branch_from_simulation
from vibroimpact.analysis.energy import branch_energy
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
spec, vary = snakemake.params.spec, snakemake.params.vary
device = vi.Device.from_config(**snakemake.params.device).replace(r=snakemake.params.r)
if vary == "s":
    s, F = device.s(spec["start_d"]), device.F
    d_range = tuple(snakemake.params.d_range)
else:
    s = snakemake.params.force["s"]
    F = device.F_for(spec["start_d"], s)
    d_range = tuple(sorted(device.d(s, f) for f in snakemake.params.force["F_range"]))
params = device.params(s=s, beta=snakemake.params.beta, F=F)
ds = branch_from_simulation(params, snakemake.params.word, k=spec["k"], vary=vary, d_range=d_range,
                            step=snakemake.params.step, phi=spec["phi"], v0=spec["v0"])
ds.attrs.update(beta=snakemake.params.beta, **provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output.orbit)
en = branch_energy(ds, device)
en.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(en, snakemake.output.energy)
logging.info("%s beta=%s vary=%s: %s %s", snakemake.params.word, snakemake.params.beta, vary, ds.attrs["status"],
             ds.attrs.get("reason", ""))
