"""Phase portraits of the bistable 2:1 and 3:1 orbits at G1, d = 0.14 and G2 (Figure 8 (d)-(g)); a portrait that
another device does not have (no G1, no 2:1 branch, ...) is recorded with the reason (vibroimpact.outputs.portraits)."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numpy as np
import xarray as xr

from vibroimpact.analysis.motions import THREE_ONE, TWO_ONE
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs.portraits import bistability_dataset

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
b21 = xr.load_dataset(snakemake.input.branch21, engine="netcdf4")
b31 = xr.load_dataset(snakemake.input.branch31, engine="netcdf4")
tr = xr.load_dataset(snakemake.input.transitions, engine="netcdf4")
# [G1, G2]: the bistable interval where the down sweep follows 2:1 and the up sweep 3:1, where the sweep finds one
both = np.flatnonzero((tr.label_down.values == TWO_ONE.label) & (tr.label_up.values == THREE_ONE.label))
g1, g2 = (float(tr.d_lo[both[0]]), float(tr.d_hi[both[0]])) if both.size else (np.nan, np.nan)
d = xr.load_dataset(snakemake.input.sweep, engine="netcdf4").d.values
missing = "" if both.size else (f"the sweep over d in [{d.min():.4g}, {d.max():.4g}] finds no interval where "
                                "the down sweep follows 2:1 and the up sweep 3:1")
ds = bistability_dataset(b21, b31, g1, g2, d_mid=snakemake.params.d_mid, missing=missing,
                         samples_per_unit=snakemake.params.samples_per_unit)
logging.info("G1 = %s, G2 = %s; panels: %s", g1, g2, list(ds.status.values))
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
