"""The 1:1 exit as a curve in a map's plane: where the 1:1 motion, followed with d decreasing along lines of the
plane, leaves the 1:1 family, by grazing or by a jump (vibroimpact.family_exit_curve)."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numpy as np

from vibroimpact.analysis.family_exit import family_exit_curve
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.dynamics.device import Device

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
sp, device = snakemake.params.spec, Device.from_config(**snakemake.params.device)
nx, ny = snakemake.params.grid
fixed = {k: sp[k] for k in ("beta", "s", "F") if k in sp}
lines = snakemake.params.lines
# the lines: the map's grid along the axis that changes d, `lines` values of the other axis
xs = np.linspace(*sp["x_range"], nx if sp["x"] in ("s", "F", "d") else lines)
ys = np.linspace(*sp["y_range"], lines if sp["x"] in ("s", "F", "d") else ny)
ds = family_exit_curve(sp["x"], xs, sp["y"], ys, phi=sp["phi"], v0=sp["v0"], xtol=snakemake.params.xtol,
                       device=device, **fixed)
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
logging.info("%s: %s", ds.attrs["status"], list(zip(ds.get("at", []).values.tolist() if "at" in ds else [],
                                                     ds.get("exit_kind", []).values.tolist() if "at" in ds else [],
                                                     strict=True)))
