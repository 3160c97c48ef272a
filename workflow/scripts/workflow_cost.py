"""Each figure's cost from the Snakemake benchmark files."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

from vibroimpact.outputs.tables import workflow_cost, workflow_cost_markdown

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
jobs, per_fig = workflow_cost(snakemake.params.bench_dir)
jobs.to_csv(snakemake.output.csv, index=False)
with open(snakemake.output.md, "w") as fh:
    fh.write(workflow_cost_markdown(jobs, per_fig))
