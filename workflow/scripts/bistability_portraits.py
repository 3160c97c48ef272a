"""Phase portraits of the bistable 2:1 and 3:1 orbits at G1, d = 0.14 and G2 (Figure 8 (d)-(g))."""
import logging

import numpy as np
import xarray as xr

from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.outputs.portraits import bistability_dataset

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
b21 = xr.load_dataset(snakemake.input.branch21, engine="netcdf4")
b31 = xr.load_dataset(snakemake.input.branch31, engine="netcdf4")
tr = xr.load_dataset(snakemake.input.transitions, engine="netcdf4")
(i,) = np.flatnonzero(tr.label_down.values == "2:1 period-2")[:1]
ds = bistability_dataset(b21, b31, float(tr.d_lo[i]), float(tr.d_hi[i]), d_mid=snakemake.params.d_mid,
                         samples_per_unit=snakemake.params.samples_per_unit)
ds.attrs.update(provenance(**dict(snakemake.params)))
write_netcdf(ds, snakemake.output[0])
