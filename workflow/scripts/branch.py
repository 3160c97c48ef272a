"""Continue periodic orbits in the cylinder length s (fixed force) or in the force F (fixed s), each with its
output voltages and averages, then simulate attractors along the stable part of the branches asked for (the
figures' open circles).  One branch per job (rule branch) or the branches the workflow names at an incline in
one job (rules branches_<incline>): the same datasets."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import xarray as xr

import vibroimpact as vi
from vibroimpact.analysis.continuation import branch_from_simulation, simulate_along
from vibroimpact.analysis.energy import branch_energy
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)


def paths(name):
    """The job's outputs of one kind (a path or a list of them), as a list."""
    got = snakemake.output.get(name, [])
    return [got] if isinstance(got, str) else list(got)


code = snakemake.params.code
for job, orbit_out, energy_out in zip(snakemake.params.jobs, paths("orbits"), paths("energies"), strict=True):
    spec, vary = job["spec"], job["vary"]
    device = vi.Device.from_config(**job["device"]).replace(r=job["r"])
    if vary == "s":
        s, F = device.s(spec["start_d"]), device.F
        d_range = tuple(job["d_range"])
    else:
        s = job["force"]["s"]
        F = device.F_for(spec["start_d"], s)
        d_range = tuple(sorted(device.d(s, f) for f in job["force"]["F_range"]))
    params = device.params(s=s, beta=job["beta"], F=F)
    ds = branch_from_simulation(params, job["word"], k=spec["k"], vary=vary, d_range=d_range, step=job["step"],
                                phi=spec["phi"], v0=spec["v0"])
    ds.attrs.update(beta=job["beta"], **provenance(**job, code=code))
    write_netcdf(ds, orbit_out)
    en = branch_energy(ds, device)
    en.attrs.update(provenance(**job, code=code))
    write_netcdf(en, energy_out)
    logging.info("%s beta=%s vary=%s: %s %s", job["word"], job["beta"], vary, ds.attrs["status"],
                 ds.attrs.get("reason", ""))

for sim_out in paths("sims"):
    # the branch it simulates along, as written above
    branch = xr.load_dataset(sim_out.replace("/sim-", "/orbit-"), engine="netcdf4")
    if branch.attrs.get("status") == "failed":
        ds = xr.Dataset(attrs=dict(status="failed", reason=branch.attrs["reason"]))
    else:
        ds = simulate_along(branch, snakemake.params.simulated["n"], tol=snakemake.params.simulated["tol"])
        ds.attrs.update(status="ok", beta=branch.attrs["beta"])
    ds.attrs.update(provenance(**snakemake.params.simulated, code=code))
    write_netcdf(ds, sim_out)
