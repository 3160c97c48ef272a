"""Accept the current figures: copy the data they draw over the committed references, but only
where the data or the rendered image changed (a copy with the same arrays and image would only change
the creation time), and the arrays' measured conditioning beside them."""
import logging
import shutil
from pathlib import Path

import pandas as pd
import xarray as xr

from vibroimpact.outputs.figdata import compare, compare_image

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
ref_dir = Path(snakemake.params.reference_dir)
ref_dir.mkdir(parents=True, exist_ok=True)
for f in snakemake.input.data:
    ref = ref_dir / Path(f).name
    if ref.exists():
        new, old = xr.load_dataset(f, engine="netcdf4"), xr.load_dataset(ref, engine="netcdf4")
        same_data = set(new.data_vars) == set(old.data_vars) and set(compare(new, old, rtol=0.0, atol=0.0).status) <= {"pass"}
        # what the check compares where an array is not well-posed (motions, statistics, sensitivities)
        # is part of the reference too
        same_data = same_data and all(new[v].equals(old[v]) for v in new.data_vars
                                      if new[v].attrs.get("role") == "wellposed")
        if same_data and compare_image(new, old, max_distance=0)["status"] == "pass":
            logging.info("unchanged: %s", ref)
            continue
    shutil.copy(f, ref)
    logging.info("reference updated: %s", ref)
# the measured figures' rows replace theirs; the other figures' rows (figure_checks.figures a subset) stay
measured = pd.read_csv(snakemake.input.conditioning)
old_file = ref_dir / "conditioning.csv"
if old_file.exists():
    kept = pd.read_csv(old_file)
    measured = pd.concat([kept[~kept.figure.isin(set(measured.figure))], measured], ignore_index=True)
measured.to_csv(old_file, index=False)
logging.info("conditioning updated for %s: %s", sorted(set(pd.read_csv(snakemake.input.conditioning).figure)), old_file)
