"""Compare the data every figure draws with its committed reference; fail if any figure moved."""
import logging
from pathlib import Path

import pandas as pd
import xarray as xr

from vibroimpact.checks import IMAGE_ROW
from vibroimpact.figdata import compare, compare_image

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = snakemake.params
frames = []
for fig, new, ref in zip(p.figures, snakemake.input.data, p.references, strict=True):
    if not Path(ref).exists():
        frames.append(pd.DataFrame([{"variable": "", "axes": "", "axis_label": "", "max_difference": float("nan"),
                                     "status": f"fail: no reference {ref}"}]).assign(figure=fig))
        continue
    new, ref = xr.load_dataset(new, engine="netcdf4"), xr.load_dataset(ref, engine="netcdf4")
    df = compare(new, ref, rtol=p.rtol, atol=p.atol, exclude=p.exclude_axis_labels, optional=p.optional_peers)
    image = compare_image(new, ref, max_distance=p.image_max_distance, draws_timings=bool((df.status == "excluded").any()))
    frames.append(pd.concat([df, pd.DataFrame([image])], ignore_index=True).assign(figure=fig))
df = pd.concat(frames, ignore_index=True)[["figure", "variable", "axes", "axis_label", "max_difference", "status"]]
image = df[df.variable == IMAGE_ROW].set_index("figure")
arrays = df[df.variable != IMAGE_ROW]
summary = (arrays.assign(failed=~arrays.status.isin(["pass", "excluded"]))
           .groupby("figure", sort=False)
           .agg(arrays=("variable", "size"), excluded=("status", lambda s: int((s == "excluded").sum())),
                failed=("failed", "sum"), max_difference=("max_difference", "max"))
           .reset_index())
summary["image"] = [f"{image.status.get(f, 'missing')} ({image.max_difference.get(f, float('nan')):g} bits)"
                    for f in summary.figure]
summary["status"] = [("pass" if n == 0 and image.status.get(f) in ("pass", "excluded") else "fail")
                     for n, f in zip(summary.failed, summary.figure, strict=True)]
table = (f"Figure data against the committed references (rtol {p.rtol:g}, atol {p.atol:g}; timings excluded), "
         f"and the rendered PNG (perceptual hash distance <= {p.image_max_distance} bits; figures with timings excluded).\n\n"
         + summary.to_markdown(index=False) + "\n")
logging.info("\n%s", table)
failed = df[~df.status.isin(["pass", "excluded"])]
if len(failed):
    raise SystemExit(f"{failed.figure.nunique()} figures differ from their references "
                     f"(accept deliberate changes with `snakemake --cores 2 update_figure_references`):\n"
                     + failed.head(40).to_markdown(index=False))
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(table)
