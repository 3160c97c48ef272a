"""Build the documentation site with Sphinx, warnings as errors (an unresolved reference, a public
docstring without its sections, a failing tutorial all fail it)."""
import shutil
import sys

from sphinx.cmd.build import build_main

p = snakemake.params
shutil.rmtree(p.doctrees, ignore_errors=True)  # a full build: every page checked each time
with open(snakemake.log[0], "w") as log:
    sys.stdout = sys.stderr = log
    code = build_main(["-W", "--keep-going", "-b", "html", "-d", p.doctrees, p.source, p.html])
sys.stdout, sys.stderr = sys.__stdout__, sys.__stderr__
if code:
    raise SystemExit(f"the documentation failed to build (warnings are errors): see {snakemake.log[0]}")
