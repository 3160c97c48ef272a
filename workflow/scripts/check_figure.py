"""One figure's data against its committed reference, each array by the rule its figure declared from what
produced it (vibroimpact.outputs.figcheck); fails, naming the arrays, if the figure moved."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging
from pathlib import Path

import pandas as pd
import xarray as xr

from vibroimpact.outputs.figdata import compare, compare_image, image_allowance

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = snakemake.params
fig = snakemake.wildcards.fig
cond = pd.read_csv(p.conditioning) if Path(p.conditioning).exists() else None
if not Path(p.reference).exists():
    raise SystemExit(f"{fig}: no committed reference {p.reference} (accept the figure with "
                     "`snakemake --cores 2 figure_conditioning update_figure_references`)")
new, ref = xr.load_dataset(snakemake.input.data, engine="netcdf4"), xr.load_dataset(p.reference, engine="netcdf4")
df = compare(new, ref, rtol=p.rtol, atol=p.atol, optional=p.optional_peers)
allowed, why = image_allowance(cond, fig, p.image_max_distance)
image = compare_image(new, ref, max_distance=allowed, draws_timings=bool((df.status == "excluded").any()))
df = pd.concat([df, pd.DataFrame([image | {"rule": why, "detail": ""}])], ignore_index=True).assign(figure=fig)
df = df[["figure", "variable", "axes", "axis_label", "rule", "provenance", "max_difference", "status", "detail"]]
failed = df[~df.status.isin(["pass", "excluded"])]
logging.info("%s: %d arrays, %d failed", fig, len(df), len(failed))
if len(failed):
    raise SystemExit(f"{fig} differs from its reference (run `snakemake --cores 2 -k check` to see every figure; "
                     "accept deliberate changes with `snakemake --cores 2 figure_conditioning "
                     "update_figure_references`):\n" + failed.drop(columns=["axes"]).head(40).to_markdown(index=False))
df.to_csv(snakemake.output[0], index=False)
