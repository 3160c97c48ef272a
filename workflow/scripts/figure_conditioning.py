"""Each figure array's spread under perturbations that stand for another machine, and whether the rule its figure
declared tolerates it (vibroimpact.outputs.conditioning)."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging
from pathlib import Path

import pandas as pd
import xarray as xr

from vibroimpact.outputs.checks import IMAGE_ROW
from vibroimpact.outputs.conditioning import (
    image_spread,
    libm_switch_works,
    openblas_core,
    perturbations,
    regenerate,
    spreads,
    summary,
)

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = snakemake.params
if not libm_switch_works():
    raise SystemExit("the libm switch changes nothing on this machine (glibc does not dispatch sin on FMA/AVX2 "
                     "here): the conditioning would miss the other machine's libm; measure on an x86-64 machine "
                     "with FMA and AVX2")
chosen = perturbations()
own = openblas_core()
logging.info("OpenBLAS picks %r here; perturbations: %s", own, ", ".join(chosen))
targets = list(snakemake.input)
copies = {}
for name in chosen:
    scratch = Path(p.scratch) / name.replace(" ", "_").replace(",", "").replace("+", "plus").replace("-", "minus")
    logging.info("regenerating the figure data under %s in %s", name, scratch)
    copies[name] = regenerate(Path.cwd(), scratch, name, targets)
frames = []
for fig, f in zip(p.figures, targets, strict=True):
    ref = xr.load_dataset(f, engine="netcdf4")
    pert = {name: xr.load_dataset(copies[name] / f, engine="netcdf4") for name in chosen}
    df = spreads(ref, pert, rtol=p.rtol, atol=p.atol, optional=p.optional)
    bits = image_spread(ref, pert)
    image = pd.DataFrame([dict(variable=IMAGE_ROW, rule="", provenance="", spread=float(bits), ratio=float("nan"),
                               moved_by="", conditioning="strict" if bits == 0 else "ill-conditioned", judged="",
                               by_perturbation="")])
    frames.append(pd.concat([df, image], ignore_index=True).assign(figure=fig))
table = pd.concat(frames, ignore_index=True)[["figure", "variable", "rule", "provenance", "conditioning", "spread",
                                              "ratio", "moved_by", "judged", "by_perturbation"]]
table.attrs = {}
table.to_csv(snakemake.output.csv, index=False)
per = summary(table, list(chosen)).assign(machine_openblas=own)
per.to_csv(snakemake.output.summary, index=False)
ill = table[table.conditioning == "ill-conditioned"]
with open(snakemake.output.md, "w") as fh:
    fh.write(f"Figure arrays recomputed under {len(chosen)} perturbations ({', '.join(chosen)}; OpenBLAS picks "
             f"{own or 'no reported kernel set'} on the measuring machine); an array moved where a copy moves it "
             "beyond the strict tolerance, and failed where its declared rule fails a copy.\n\n")
    fh.write(per.to_markdown(index=False) + "\n\n")
    fh.write(ill.to_markdown(index=False) + "\n")
bad = table[(table.variable != IMAGE_ROW) & table.judged.fillna("").str.startswith("fail")]
logging.info("%d arrays moved, %d failing their declared rule", len(ill), len(bad))
if len(bad):
    logging.warning("arrays whose declared rule fails under a perturbation (the check would fail on such a "
                    "machine):\n%s", bad.to_markdown(index=False))
