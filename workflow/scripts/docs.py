"""Build the documentation site with Sphinx, warnings as errors (an unresolved reference, a public
docstring without its sections, a failing tutorial all fail it).  The warnings are also written to
their own file (the rule's second log) and quoted in the job's error, so a failed build says why."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import shutil
import sys
from pathlib import Path

from sphinx.cmd.build import build_main

p = snakemake.params
warnings = Path(snakemake.log.warnings)
shutil.rmtree(p.doctrees, ignore_errors=True)  # a full build: every page checked each time
with open(snakemake.log.build, "w") as log:
    sys.stdout = sys.stderr = log
    code = build_main(["-W", "--keep-going", "--no-color", "-w", str(warnings), "-b", "html", "-d", p.doctrees,
                       p.source, p.html])
sys.stdout, sys.stderr = sys.__stdout__, sys.__stderr__
if code:
    said = warnings.read_text().strip() if warnings.exists() else ""
    raise SystemExit(f"the documentation failed to build (warnings are errors; whole log: {snakemake.log.build}):\n"
                     + (said or "no warning recorded"))
