# vibroimpact: regenerate the paper's figures and this project's own from the code.
# Usage: snakemake --cores 2            (default target: every figure, table and dataset)
#        snakemake --cores 2 check      (which of the paper's numbers are reproduced; figures against references)
#        snakemake --cores 2 bench      (speed and accuracy of the simulator)
# first: Snakemake's own process and each `run:` job's collect their garbage less often (vibroimpact.outputs.job)
import vibroimpact.outputs.job  # noqa: F401

# isort: split
import atexit
import math
import os
import shutil
import sys
import tempfile

import yaml
from snakemake.utils import min_version

from vibroimpact.outputs.workflow_config import (
    ConfigError,
    check,
    coerce_studies,
    validate_schema,
)

# the jobs draw into files, never onto a screen: matplotlib's file backend (the package leaves the choice
# of backend to whoever imports it)
os.environ.setdefault("MPLBACKEND", "Agg")

min_version("8.0")


configfile: "config/config.yaml"


# a command line's `--config 'studies=[{beta: 0.4, r: 0.6}]'` reaches us as strings: its numbers made numbers; then
# the schema (each value, and no key it does not name), then the conditions across keys (the checked, typed config
# the rule files read): a refusal is one line naming the key, the value and what is allowed, before any job
try:
    config["studies"] = coerce_studies(config.get("studies"))
    with open(os.path.join(workflow.basedir, "config", "schema.yaml")) as f:
        # libyaml's parser where PyYAML has it (the same objects, parsed ten times faster)
        validate_schema(
            config, yaml.load(f, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
        )
    CFG = check(config)
except ConfigError as refusal:
    sys.exit(str(refusal))


report: "workflow/report/workflow.rst"


# each job imports the package afresh: its bytecode written once, before the first job, spares every job compiling
# the modules it imports where Python writes none itself (PYTHONDONTWRITEBYTECODE; vibroimpact._bytecode)
onstart:
    from vibroimpact._bytecode import write_bytecode

    write_bytecode()


include: "workflow/rules/common.smk"


# another device than the paper's writes everything (results, logs, benchmarks) under its own folder,
# results/devices/<name>/, never over the paper's results.  A dry run (-n) creates no folder: before the
# device's first run it plans in an empty scratch folder outside the repository (removed on exit), which
# holds what the device's folder would, nothing.
if not CFG.paper_device:
    dry_run = getattr(getattr(workflow, "output_settings", None), "dryrun", False)
    if dry_run and not os.path.isdir(CFG.results_dir):
        _plan_in = tempfile.mkdtemp(prefix="vibroimpact-dry-run-")
        atexit.register(shutil.rmtree, _plan_in, ignore_errors=True)
        workflow.workdir(_plan_in)
    else:
        workflow.workdir(CFG.results_dir)


include: "workflow/rules/orbits.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/orbits_branches.smk"
include: "workflow/rules/branch_figures.smk"
include: "workflow/rules/sweeps.smk"
include: "workflow/rules/energy.smk"
include: "workflow/rules/checks.smk"
include: "workflow/rules/bench.smk"
include: "workflow/rules/bifurcation.smk"
include: "workflow/rules/design.smk"
include: "workflow/rules/knocks.smk"


rule all:
    default_target: True
    input:
        "results/orbits/captions.nc",
        "results/tables/captions.md",
        # every figure of the registry (vibroimpact.outputs.registry) the default target draws
        figure_targets("all"),
        "results/tables/table1.csv",
        "results/tables/d_graz.md",
        [branch_path("orbit", math.pi / 3, "BT")] if "BT" in WORDS else [],  # 1:1 branch of Figure 2
        [sweep_path(n) for n in SWEEPS],
        [sweep_path(n, "-transitions") for n in SWEEPS],
        "results/tables/transitions.md",
        [basin_path(n) for n in config["basins"]],
        [map_path(n) for n in config["maps"]],
        "results/tables/design.md",
        "results/tables/knocks.md",
        "results/tables/chaos.md",
        "results/checks/paper_values.csv",
        "results/tables/workflow_cost.md",
        [study_figure(st) for st in STUDIES],
        "results/tables/table1.md",


# the documentation site builds on the default target (rule all, above): the paper's device's
if CFG.paper_device:

    include: "workflow/rules/docs.smk"


# last: one job for every branch the rules above name
include: "workflow/rules/branch_batch.smk"
