"""Compare every published number and claim with the datasets; fail if anything unexpected fails."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import pandas as pd
import xarray as xr

from vibroimpact.analysis.windows import window_motions
from vibroimpact.outputs import checks

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
load = lambda f: xr.load_dataset(f, engine="netcdf4")
i = snakemake.input
rows = (checks.caption_rows(load(i.captions)) + checks.stability_rows(pd.read_csv(i.table1))
        + checks.grazing_rows(load(i.bis)) + checks.simulation_rows([load(f) for f in i.sims])
        + checks.energy_rows([load(f) for f in i.branches_s], [load(f) for f in i.branches_F], [load(f) for f in i.sweeps],
                             [window_motions(load(f).sel(direction="down")) for f in i.motion_sweeps])
        + checks.curve_order_rows([load(f) for f in i.order_orbits], [load(f) for f in i.order_energy])
        + checks.d_graz_rows(pd.read_csv(i.d_graz), [load(f) for f in i.bt_branches], snakemake.params.d_graz_scenes))
if snakemake.params.paper_device:
    df = checks.apply_known(pd.DataFrame(rows), snakemake.params.known)
else:  # the paper's numbers are its device's: only what holds for any device is compared
    df = checks.for_another_device(pd.DataFrame(rows), snakemake.params.device)
table = checks.markdown(df, None if snakemake.params.paper_device else snakemake.params.device)
logging.info("\n%s", table)
failed = df[df["status"] == "fail"]
if len(failed):
    raise SystemExit(f"{len(failed)} of the paper's values are not reproduced:\n{checks.markdown(failed)}")
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(table)
