"""Each figure array's spread under perturbations that stand for another machine (vibroimpact.outputs.conditioning)."""
import logging
from pathlib import Path

import pandas as pd
import xarray as xr

from vibroimpact.outputs.checks import IMAGE_ROW
from vibroimpact.outputs.conditioning import (
    PERTURBATIONS,
    image_spread,
    libm_switch_works,
    regenerate,
    spreads,
)

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = snakemake.params
if not libm_switch_works():
    raise SystemExit("the libm switch changes nothing on this machine (glibc does not dispatch sin on FMA/AVX2 "
                     "here): the conditioning would miss the other machine's libm; measure on an x86-64 machine "
                     "with FMA and AVX2")
targets = list(snakemake.input)
copies = {}
for name in PERTURBATIONS:
    scratch = Path(p.scratch) / name.replace(" ", "_").replace(",", "").replace("+", "plus").replace("-", "minus")
    logging.info("regenerating the figure data under %s in %s", name, scratch)
    copies[name] = regenerate(Path.cwd(), scratch, name, targets)
frames = []
for fig, f in zip(p.figures, targets, strict=True):
    ref = xr.load_dataset(f, engine="netcdf4")
    pert = {name: xr.load_dataset(copies[name] / f, engine="netcdf4") for name in PERTURBATIONS}
    df = spreads(ref, pert, rtol=p.rtol, atol=p.atol, exclude=p.exclude, optional=p.optional)
    bits = image_spread(ref, pert)
    image = pd.DataFrame([dict(variable=IMAGE_ROW, spread=float(bits), ratio=float("nan"), moved_by="",
                               conditioning="strict" if bits == 0 else "ill-conditioned", wellposed="")])
    frames.append(pd.concat([df, image], ignore_index=True).assign(figure=fig))
table = pd.concat(frames, ignore_index=True)[["figure", "variable", "conditioning", "wellposed", "spread", "ratio",
                                              "moved_by"]]
table.attrs = {}
table.to_csv(snakemake.output.csv, index=False)
ill = table[table.conditioning == "ill-conditioned"]
summary = (table[table.variable != IMAGE_ROW].groupby("figure", sort=False)
           .agg(arrays=("variable", "size"), ill_conditioned=("conditioning", lambda s: int((s == "ill-conditioned").sum())))
           .reset_index())
with open(snakemake.output.md, "w") as fh:
    fh.write(f"Figure arrays recomputed under {len(PERTURBATIONS)} perturbations ({', '.join(PERTURBATIONS)}); an array "
             "is ill-conditioned where any copy moves it beyond the strict tolerance.\n\n")
    fh.write(summary.to_markdown(index=False) + "\n\n")
    fh.write(ill.to_markdown(index=False) + "\n")
missing = ill[(ill.variable != IMAGE_ROW) & (ill.wellposed == "")]
logging.info("%d ill-conditioned arrays, %d without a well-posed rule", len(ill), len(missing))
if len(missing):
    logging.warning("ill-conditioned arrays with no well-posed rule (they will fail the check):\n%s",
                    missing.to_markdown(index=False))
