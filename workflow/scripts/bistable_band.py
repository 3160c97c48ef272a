"""Where 2:1 and 3:1 coexist, per incline: [G1, G2] from the followed curves, with the physics' scaling."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging
import math

import xarray as xr

from vibroimpact.analysis.bifurcation import bistable_band
from vibroimpact.datasets import provenance, write_netcdf

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
curves = xr.load_dataset(snakemake.input[0], engine="netcdf4")
band = bistable_band(curves, snakemake.params.betas)
band.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(band, snakemake.output.nc)
rows = ["| beta | G1: s (m) | G2: s (m) | bistable for s in |", "|---|---|---|---|"]
for b, g1, g2, w in zip(band.beta.values, band.s_G1.values, band.s_G2.values, band.width.values, strict=True):
    span = f"({g1:.6f}, {g2:.6f})" if w > 0 else ("none" if g1 == g1 and g2 == g2 else "a curve does not reach this incline")
    rows.append(f"| {b:.4f} ({b / math.pi:.3f} pi) | {g1:.6f} | {g2:.6f} | {span} |")
if band.attrs["status"] != "ok":
    rows += ["", f"Not found: {band.attrs['status']}."]
with open(snakemake.output.md, "w") as fh:
    fh.write("\n".join(rows) + "\n")
logging.info("\n".join(rows))
