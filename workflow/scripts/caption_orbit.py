"""Simulate the caption orbits and write one dataset per caption."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import vibroimpact as vi
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs import portraits

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
for p, out in zip(snakemake.params.p, snakemake.output, strict=True):
    params = vi.Params(d=p["d"], gbar=p["gbar"], r=p["r"])
    ds = portraits.orbit_dataset(params, p["phi"], p["v0"], t_show=p["t_show"], samples_per_unit=p["samples_per_unit"],
                                     name=p["name"], max_events=p["max_events"], tol=p["tol"])
    if p["grazing"]:  # the caption shows "grazing behaviour": the same orbit where it does graze
        ds = portraits.add_located_grazing(ds, params, samples_per_unit=p["samples_per_unit"])
        logging.info("%s: located grazing %s", p["name"], {k: v for k, v in ds.attrs.items() if k.startswith("grazing")})
    ds.attrs.update(beta=p["beta"], beta_assumed=int(p["beta_assumed"]), F=p["F"], omega=p["omega"],
                    motion_stated=p["motion"], **provenance(**p, code=snakemake.params.code))
    write_netcdf(ds, out)
    logging.info("%s: %s (stated %s)", p["name"], ds.attrs["motion"], p["motion"])
