"""The numbers of the speed-and-accuracy page, as a table generated from the benchmark datasets."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split

import logging

import pandas as pd
import xarray as xr

from vibroimpact.outputs.speed import speed_summary, speed_summary_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
i = snakemake.input
df = speed_summary(
    kernel=xr.load_dataset(i.kernel),
    simulator=xr.load_dataset(i.simulator),
    work_precision=xr.load_dataset(i.work_precision),
    matched_accuracy=xr.load_dataset(i.matched_accuracy),
    failure_map=xr.load_dataset(i.failure_map),
    analytics_accuracy=xr.load_dataset(i.analytics_accuracy),
    lyapunov_precision=xr.load_dataset(i.lyapunov_precision),
    workflow_cost=pd.read_csv(i.workflow_cost),
)
with open(snakemake.output.md, "w") as fh:
    fh.write(speed_summary_markdown(df))
logging.info("%d rows", len(df))
