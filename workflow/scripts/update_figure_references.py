"""Accept the current figures: copy the data they draw over the committed references, but only
where the data or the rendered image changed (a copy with the same arrays and image would only change
the creation time), and the arrays' measured conditioning beside them."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging
import shutil
from pathlib import Path

import pandas as pd
import xarray as xr

from vibroimpact.outputs.figdata import compare_image

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ref_dir = Path(snakemake.params.reference_dir)
ref_dir.mkdir(parents=True, exist_ok=True)
for f in snakemake.input.data:
    ref = ref_dir / Path(f).name
    if ref.exists():
        new, old = xr.load_dataset(f, engine="netcdf4"), xr.load_dataset(ref, engine="netcdf4")
        # every array, with its declared rule and what the rule compares (motions, statistics, floors), to the bit
        same_data = set(new.data_vars) == set(old.data_vars) and all(new[v].identical(old[v]) for v in new.data_vars)
        if same_data and compare_image(new, old, max_distance=0)["status"] == "pass":
            logging.info("unchanged: %s", ref)
            continue
    shutil.copy(f, ref)
    logging.info("reference updated: %s", ref)
# the measured figures' rows replace theirs; the other figures' rows (figure_checks.figures a subset) stay
for new_file, name in ((snakemake.input.conditioning, "conditioning.csv"),
                       (snakemake.input.summary, "conditioning_summary.csv")):
    measured = pd.read_csv(new_file)
    old_file = ref_dir / name
    if old_file.exists():
        kept = pd.read_csv(old_file)
        if set(kept.columns) == set(measured.columns):  # a table of another layout is replaced whole
            measured = pd.concat([kept[~kept.figure.isin(set(measured.figure))], measured], ignore_index=True)
    measured.to_csv(old_file, index=False)
    logging.info("%s updated for %s", old_file, sorted(set(pd.read_csv(new_file).figure)))
