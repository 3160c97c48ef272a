"""A workflow process's garbage collector (vibroimpact.outputs.job): collected less often while the process runs,
not at all once it ends, set before anything heavy is imported."""
import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = sorted((ROOT / "workflow" / "scripts").glob("*.py"))
JOB = "vibroimpact.outputs.job"


def python(code: str) -> str:
    """The standard output of a fresh interpreter running ``code``."""
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout


def test_the_youngest_generation_is_collected_ten_times_less_often_and_the_older_ones_as_before():
    before, after = python(f"import gc; t = gc.get_threshold(); import {JOB}; print(t); print(gc.get_threshold())"
                           ).split("\n")[:2]
    young, *older = ast.literal_eval(before)
    assert ast.literal_eval(after) == (10 * young, *older)
    # the older generations keep whatever thresholds the process had
    kept = python(f"import gc; gc.set_threshold(700, 11, 12); import {JOB}; print(gc.get_threshold())")
    assert ast.literal_eval(kept) == (10 * young, 11, 12)
    # a second call (the Snakefile's process imports the module and may call it again) changes nothing
    twice = python(f"import gc, {JOB} as j; j.collect_less(); j.collect_less(); import atexit; "
                   "print(gc.get_threshold()[0], atexit._ncallbacks())")
    once = python(f"import gc, {JOB}; import atexit; print(gc.get_threshold()[0], atexit._ncallbacks())")
    assert twice == once


def test_what_the_process_holds_is_frozen_at_exit_and_the_earlier_exit_handlers_still_run():
    # an exit handler registered before the import runs after the module's (exit handlers run last in, first out)
    code = ("import atexit, gc; atexit.register(lambda: print('frozen', gc.get_freeze_count())); {}"
            "held = [[i] for i in range(1000)]")
    said = python(code.format(f"import {JOB}; "))
    assert said.startswith("frozen ")
    frozen = int(said.split()[1])
    assert frozen > 1000  # the lists the process held, and everything imported
    assert python(code.format("")).split()[1] == "0"  # without the module: nothing frozen


def first_statement_after_docstring(tree: ast.Module) -> ast.stmt:
    body = tree.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    return body[0]


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_every_workflow_script_sets_the_collector_before_anything_else(script):
    first = first_statement_after_docstring(ast.parse(script.read_text()))
    assert isinstance(first, ast.Import) and [a.name for a in first.names] == [JOB], (
        f"{script.name}: its first statement must be `import {JOB}`")


def test_the_snakefile_sets_it_before_anything_else():
    code = [ln for ln in (ROOT / "Snakefile").read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    assert code[0].split("#")[0].strip() == f"import {JOB}"


def test_a_job_s_imports_leave_over_100_000_objects_which_the_default_collector_goes_over_while_they_load():
    """What the speed page says of the collector with CPython's defaults, and that the module spares those passes."""
    probe = ("{}import gc, json; n = [0, 0, 0]; "
             "gc.callbacks.append(lambda ph, i: n.__setitem__(i['generation'], n[i['generation']] + (ph == 'start'))); "
             "import snakemake.script, numpy, xarray, netCDF4, numba, matplotlib.pyplot, vibroimpact.datasets; "
             "print(json.dumps([n[2], len(gc.get_objects())]))")
    full_default, objects = json.loads(python(probe.format("")))
    full_job, _ = json.loads(python(probe.format(f"import {JOB}; ")))
    assert objects > 100_000
    assert full_default >= 2
    assert full_job < full_default


def test_the_test_processes_set_it_before_anything_else():
    first = first_statement_after_docstring(ast.parse((ROOT / "tests" / "conftest.py").read_text()))
    assert isinstance(first, ast.Import) and [a.name for a in first.names] == [JOB]
