"""Every figure's check (rule check_figure) in one table, with the rule each array was compared by and why."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging
from pathlib import Path

import pandas as pd

from vibroimpact.outputs.checks import figure_check_markdown, not_compared_figures

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
p = snakemake.params
if not snakemake.input:  # another device: its figures have no committed reference
    df = not_compared_figures(p.figures, p.device)
    table = df.to_markdown(index=False) + "\n"
else:
    cond = pd.read_csv(p.conditioning) if Path(p.conditioning).exists() else None
    df = pd.concat([pd.read_csv(f, keep_default_na=False, na_values=[""]) for f in snakemake.input], ignore_index=True)
    table = figure_check_markdown(df, cond, rtol=p.rtol, atol=p.atol)
logging.info("\n%s", table.split("\n## ")[0])
df.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(table)
