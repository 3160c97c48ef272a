#!/usr/bin/env python3
"""Mutation testing of the vibroimpact core modules: one mutant at a time, in a private copy.

Why not mutmut: mutmut 3 instruments code with "trampolines" and does not mutate decorated
functions, so every @njit function of events.py / kernels.py would be skipped (and a trampoline
cannot be called from nopython code anyway).  To keep the six modules comparable, one script is
used for all of them.

Mutation operators (AST-located, applied as a text edit on the source bytes):
  binop    + <-> -,  * <-> /,  // -> /,  % -> /,  ** -> *          (also augmented assignments)
  compare  < <-> <=,  > <-> >=,  == <-> !=,  is <-> is not,  in <-> not in
  boolop   and <-> or
  unary    `not x` -> `x`,  `-x` -> `x`
  const    numeric c -> c+1, c -> 0 (c != 0);  True <-> False
  delete   a `return` / `continue` / `break` statement -> `pass`
Not mutated: docstrings, strings, decorators, annotations, `__all__`.

Everything happens in a private copy of the repository's files (every file git tracks, and new ones it
does not ignore: what a clone holds, so the tests find the pages, examples and config they read;
``results/mutation/tree``, made on first use; ``--fresh`` remakes it), never in the working tree.  For each mutant: write the mutated file, delete
its __pycache__, use a fresh
NUMBA_CACHE_DIR (numba modules) or a private warm copy of the clean cache (pure-Python modules,
whose numba dependencies are unchanged; the clean cache starts as a copy of the package's own numba cache
of the same sources, where there is one), run the module's test files with
`pytest -x -q -p no:cacheprovider --hypothesis-seed=0` under a timeout (5x the clean run, min 60 s),
restore the file bytes and mtime.  Exit status 0 -> survived, timeout -> timed out (counted as
killed), anything else -> killed.  Results are appended to results/mutation/results_<module>.jsonl
(resumable).  A surviving mutant is either equivalent (no input changes the result beyond the
stated tolerance) or a blind spot of the tests; the report lists survivors with their diff.

A run's first record describes its sample (module, seed, size, the module source's SHA-256, the commit
and the test files); ``keep`` copies a finished sample (and its retest) into ``tools/mutation_samples/``,
which the repository carries, beside ``verdicts.toml``: for each surviving mutant, the change it makes
(``mutation``, so a verdict never passes to another mutant a new sample numbers alike) and equivalent (with
the reason no input changes the result) or a blind spot (with the test it led to, run by ``retest``).
``scores`` writes the testing page's table and list of equivalent survivors from those files.

Usage (from the repository root, with the project's venv):
  .venv/bin/python tools/mutation.py list   MODULE                 # count all mutants
  .venv/bin/python tools/mutation.py run    MODULE [--n N] [--seed S] [--fresh]
  .venv/bin/python tools/mutation.py show   MODULE ID              # diff of one mutant
  .venv/bin/python tools/mutation.py report MODULE
  .venv/bin/python tools/mutation.py retest MODULE --ids I,J --tests FILES
  .venv/bin/python tools/mutation.py keep   MODULE                 # into tools/mutation_samples/
  .venv/bin/python tools/mutation.py scores [--out FILE]           # the testing page's Markdown
"""

import argparse
import ast
import datetime
import difflib
import functools
import hashlib
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.join(REPO, "results", "mutation", "tree")  # the private copy the mutants live in
OUT = os.path.join(REPO, "results", "mutation")
PKG = os.path.join(ROOT, "src", "vibroimpact")
#: the samples the repository carries (``keep`` copies them there) and the verdicts on their survivors
SAMPLES = os.path.join(REPO, "tools", "mutation_samples")
#: the layer of the package each module lives in
LAYER = {**{m: "dynamics" for m in ("params", "flight", "events", "kernels", "runs", "reference", "device")},
         **{m: "analysis" for m in ("orbits", "grazing", "continuation", "bifurcation", "settled", "sweeps", "energy",
                                    "design", "lyapunov", "family_exit", "d_graz", "motions", "motion_names", "windows",
                                    "transitions", "bistability", "grids", "basins", "regime_maps", "shocks",
                                    "basin_stability", "robust")},
         **{m: "benchmarks" for m in ("methods", "peer_heyoka", "peer_siconos", "workprecision", "bench")},
         **{m: "outputs" for m in ("tables", "checks", "paper", "portraits", "figdata", "figcheck", "conditioning", "job")}}


def module_path(mod):
    """The module's file in the private copy."""
    return os.path.join(PKG, LAYER.get(mod, ""), mod + ".py")
PY = os.environ.get("MUT_PYTHON", sys.executable)


#: what a working tree holds beside a clone's files (made by runs), left out where git cannot say
NOT_CLONED = {".git", ".venv", "results", ".snakemake", "__pycache__", ".hypothesis", ".pytest_cache", "logs",
              "build", "dist"}


def repository_files():
    """The working tree's files a clone holds: those git tracks and new ones it does not ignore; in a copy
    that is not a git repository (a tree copied from a clone), every file outside :data:`NOT_CLONED`."""
    out = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=REPO, capture_output=True)
    if out.returncode == 0:
        return [f for f in out.stdout.decode().split("\0") if f and os.path.isfile(os.path.join(REPO, f))]
    files = []
    for top, dirs, names in os.walk(REPO):
        dirs[:] = [d for d in dirs if d not in NOT_CLONED and not d.endswith(".egg-info")]
        files += [os.path.relpath(os.path.join(top, n), REPO) for n in names]
    return sorted(files)


def make_tree(fresh=False):
    """Copy the repository's files (:func:`repository_files`: src/, tests/, config/, docs/, examples/, ...,
    whatever the tests read) into ROOT, and the modules' pristine sources."""
    if fresh and os.path.isdir(ROOT):
        shutil.rmtree(ROOT)
    if os.path.isdir(ROOT):
        return
    for f in repository_files():
        os.makedirs(os.path.dirname(os.path.join(ROOT, f)), exist_ok=True)
        shutil.copy2(os.path.join(REPO, f), os.path.join(ROOT, f))
    os.makedirs(os.path.join(ROOT, "pristine"))
    for mod in TESTS:
        shutil.copy(module_path(mod), os.path.join(ROOT, "pristine", mod + ".py"))

TESTS = {
    # with the test of accel_zero, which the grazing search's pieces use (it lives with the kernels' tests)
    "events": ["tests/test_impact_times.py", "tests/test_properties.py", "tests/test_sticking.py",
               "tests/test_kernels.py::test_acceleration_zero_comes_with_the_sign_of_the_sine_there"],
    "kernels": ["tests/test_kernels.py", "tests/test_sticking.py", "tests/test_attractor.py",
                "tests/test_properties.py", "tests/test_impact_times.py", "tests/test_impact_law.py",
                "tests/test_kernel_signatures.py", "tests/test_sweep_batch.py"],
    "orbits": ["tests/test_orbits.py", "tests/test_captions.py", "tests/test_impact_law.py"],
    "continuation": ["tests/test_orbits.py"],
    "motions": ["tests/test_motion_names.py", "tests/test_sweeps.py", "tests/test_attractor.py"],
    # with the module's own examples (its doctests)
    "motion_names": ["tests/test_motion_names.py", "tests/test_sweeps.py", "tests/test_attractor.py",
                     "src/vibroimpact/analysis/motion_names.py"],
    "windows": ["tests/test_sweeps.py", "tests/test_kernels.py", "tests/test_progress.py"],
    "transitions": ["tests/test_sweeps.py", "tests/test_period_doublings.py"],
    "bistability": ["tests/test_sweeps.py"],
    "sweeps": ["tests/test_sweeps.py", "tests/test_sweep_batch.py"],
    "energy": ["tests/test_energy.py"],
    "design": ["tests/test_design.py"],
    "robust": ["tests/test_robust.py"],
    "basin_stability": ["tests/test_basin_stability.py"],
    "shocks": ["tests/test_shocks.py"],
    "settled": ["tests/test_settled.py", "tests/test_energy.py", "tests/test_sweep_batch.py", "tests/test_sweeps.py"],
    "lyapunov": ["tests/test_lyapunov.py", "tests/test_impact_law.py"],
    "family_exit": ["tests/test_family_exit.py"],
    "d_graz": ["tests/test_d_graz.py"],
    "figcheck": ["tests/test_figcheck.py", "tests/test_provenance.py"],
    "job": ["tests/test_job.py"],
    "figdata": ["tests/test_figdata.py", "tests/test_figcheck.py", "tests/test_provenance.py"],
    # its unit tests (the workflow-level test regenerates the whole figure set: minutes a mutant)
    "conditioning": [f"tests/test_conditioning.py::{t}" for t in (
        "test_an_array_is_ill_conditioned_when_any_perturbation_moves_it_beyond_the_strict_tolerance",
        "test_optional_peers_are_excluded_and_each_array_is_judged_by_its_declared_rule",
        "test_the_openblas_kernel_sets_are_read_from_openblas_and_the_machine_s_own_is_left_out",
        "test_the_mass_moves_by_the_given_number_of_ulps_and_nothing_else",
        "test_a_move_between_one_and_two_tolerances_is_a_move",
        "test_the_image_spread_and_the_ill_conditioned_variables_of_a_figure",
        "test_a_perturbed_regeneration_runs_the_workflow_in_a_copy_with_the_switch_and_the_moved_mass",
        "test_a_probe_of_the_libm_switch_that_cannot_run_is_an_error_not_a_no",
        "test_the_summary_and_the_testing_page_count_each_figure_s_moved_and_failed_arrays")]
    + ["tests/test_readme.py::test_the_libm_switch_changes_sin_where_glibc_dispatches_it"],
}
NUMBA_MODULES = {"events", "kernels"}

BINOP = {ast.Add: [("+", "-")], ast.Sub: [("-", "+")], ast.Mult: [("*", "/")], ast.Div: [("/", "*")],
         ast.FloorDiv: [("//", "/")], ast.Mod: [("%", "/")], ast.Pow: [("**", "*")]}
CMPOP = {ast.Lt: ("<", "<="), ast.LtE: ("<=", "<"), ast.Gt: (">", ">="), ast.GtE: (">=", ">"),
         ast.Eq: ("==", "!="), ast.NotEq: ("!=", "=="), ast.Is: ("is", "is not"),
         ast.IsNot: ("is not", "is"), ast.In: ("in", "not in"), ast.NotIn: ("not in", "in")}


def line_offsets(src: bytes):
    offs, pos = [0], 0
    for line in src.split(b"\n"):
        pos += len(line) + 1
        offs.append(pos)
    return offs


def mutants_of(path):
    src = open(path, "rb").read()
    offs = line_offsets(src)
    tree = ast.parse(src)
    pos = lambda ln, col: offs[ln - 1] + col
    start = lambda n: pos(n.lineno, n.col_offset)
    end = lambda n: pos(n.end_lineno, n.end_col_offset)

    skip = set()  # ids of nodes not to mutate (docstrings, decorators, annotations, __all__)
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.ClassDef, ast.Module, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                skip.update(id(x) for x in ast.walk(body[0]))
            if not isinstance(node, ast.Module):
                for dec in node.decorator_list:
                    skip.update(id(x) for x in ast.walk(dec))
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for a in node.args.args + node.args.kwonlyargs + node.args.posonlyargs:
                    if a.annotation is not None:
                        skip.update(id(x) for x in ast.walk(a.annotation))
                if node.returns is not None:
                    skip.update(id(x) for x in ast.walk(node.returns))
        if isinstance(node, ast.AnnAssign):
            skip.update(id(x) for x in ast.walk(node.annotation))
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            skip.update(id(x) for x in ast.walk(node))

    muts = []

    def add(a, b, new, kind, node):
        muts.append({"start": a, "end": b, "old": src[a:b].decode(), "new": new, "kind": kind,
                     "line": node.lineno})

    def find_op(a, b, token):
        """Byte span of operator `token` in src[a:b] (the gap between two operands)."""
        seg = src[a:b].decode()
        i = 0
        while i < len(seg):
            ch = seg[i]
            if ch == "#":
                while i < len(seg) and seg[i] != "\n":
                    i += 1
                continue
            if seg.startswith(token, i):
                # word operators need word boundaries
                if token[0].isalpha():
                    before = seg[i - 1] if i else " "
                    after = seg[i + len(token)] if i + len(token) < len(seg) else " "
                    if before.isalnum() or after.isalnum() or before == "_" or after == "_":
                        i += 1
                        continue
                if token == "*" and seg.startswith("**", i):
                    i += 2
                    continue
                if token == "/" and seg.startswith("//", i):
                    i += 2
                    continue
                if token in ("<", ">") and seg.startswith(token + "=", i):
                    i += 2
                    continue
                if token == "is" and seg.startswith("is not", i):
                    i += 1
                    continue
                if token == "in" and i >= 4 and seg[i - 4:i] == "not ":
                    i += 1
                    continue
                pa = a + len(seg[:i].encode())
                return pa, pa + len(token.encode())
            i += 1
        return None

    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.BinOp) and type(node.op) in BINOP:
            for old, new in BINOP[type(node.op)]:
                sp = find_op(end(node.left), start(node.right), old)
                if sp:
                    add(*sp, new, f"binop {old}->{new}", node)
        elif isinstance(node, ast.AugAssign) and type(node.op) in BINOP:
            for old, new in BINOP[type(node.op)]:
                sp = find_op(end(node.target), start(node.value), old + "=")
                if sp:
                    add(*sp, new + "=", f"augassign {old}=->{new}=", node)
        elif isinstance(node, ast.Compare):
            left = node.left
            for op, right in zip(node.ops, node.comparators, strict=True):
                old, new = CMPOP[type(op)]
                sp = find_op(end(left), start(right), old)
                if sp:
                    add(*sp, new, f"compare {old}->{new}", node)
                left = right
        elif isinstance(node, ast.BoolOp):
            old, new = ("and", "or") if isinstance(node.op, ast.And) else ("or", "and")
            for x, y in zip(node.values, node.values[1:], strict=False):
                sp = find_op(end(x), start(y), old)
                if sp:
                    add(*sp, new, f"boolop {old}->{new}", node)
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.Not, ast.USub)):
            add(start(node), end(node), src[start(node.operand):end(node.operand)].decode(),
                "unary not x->x" if isinstance(node.op, ast.Not) else "unary -x->x", node)
        elif isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, bool):
                add(start(node), end(node), str(not v), f"const {v}->{not v}", node)
            elif isinstance(v, (int, float)):
                add(start(node), end(node), repr(v + 1), f"const {v!r}->{v + 1!r}", node)
                if v != 0:
                    add(start(node), end(node), "0", f"const {v!r}->0", node)
        elif isinstance(node, (ast.Return, ast.Continue, ast.Break)):
            add(start(node), end(node), "pass", f"delete {type(node).__name__.lower()}", node)
    muts.sort(key=lambda m: (m["start"], m["kind"], m["new"]))
    for i, m in enumerate(muts):
        m["id"] = i
    return src, muts


def apply(src, m):
    return src[:m["start"]] + m["new"].encode() + src[m["end"]:]


def diff(src, m):
    new = apply(src, m).decode().splitlines()
    old = src.decode().splitlines()
    return "\n".join(x for x in difflib.unified_diff(old, new, lineterm="", n=0) if not x.startswith(("---", "+++")))


CLEAN_CACHE = os.path.join(OUT, "numba_cache_clean")


@functools.cache
def package_numba():
    """The private copy's (as yet unmutated) numba cache outside this tool and the locator that files it: the
    package's own, which every copy of the same sources shares (vibroimpact._numba_cache), as
    ``(directory, locator)``; ``(None, None)`` where the package cannot name them."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"} | {"PYTHONPATH": os.path.join(ROOT, "src")}
    out = subprocess.run([PY, "-c", "from vibroimpact._numba_cache import LOCATOR, cache_dir; print(cache_dir()); "
                                    "print(LOCATOR)"], env=env, capture_output=True, text=True)
    lines = out.stdout.split()
    return (lines[0], lines[1]) if out.returncode == 0 and len(lines) == 2 else (None, None)


def run_tests(module, timeout, cache=None):
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "src"), NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1",
               OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1", PYTHONDONTWRITEBYTECODE="1")
    for sub in ("", *set(LAYER.values())):
        shutil.rmtree(os.path.join(PKG, sub, "__pycache__"), ignore_errors=True)
    shutil.rmtree(os.path.join(ROOT, ".hypothesis"), ignore_errors=True)
    keep = cache is not None
    if cache is None:
        cache = tempfile.mkdtemp(prefix="mut_nb_")
        if module not in NUMBA_MODULES and os.path.isdir(CLEAN_CACHE):
            shutil.rmtree(cache)
            shutil.copytree(CLEAN_CACHE, cache)
    env["NUMBA_CACHE_DIR"] = cache
    # numba files the package's functions by their place in the package (vibroimpact._numba_cache), as in the
    # package's own cache the clean cache starts from, unless the user named another locator
    locator = package_numba()[1]
    if locator:
        env.setdefault("NUMBA_CACHE_LOCATOR_CLASSES", locator)
    cmd = [PY, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "--hypothesis-seed=0", *TESTS[module]]
    t0 = time.time()
    proc = subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            start_new_session=True)
    try:
        out, _ = proc.communicate(timeout=timeout)
        status = "survived" if proc.returncode == 0 else "killed"
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, 9)  # only the process group this script started
        out, _ = proc.communicate()
        status = "timeout"
    dt = time.time() - t0
    if not keep:
        shutil.rmtree(cache, ignore_errors=True)
    out = out.decode(errors="replace")
    failed = [x for x in out.splitlines() if x.startswith(("FAILED", "ERROR"))]
    return status, dt, failed, out, proc.returncode


def records(path):
    """The mutant records of a results file (its header records left out)."""
    return [r for r in map(json.loads, open(path).read().split("\n")[:-1] if os.path.exists(path) else [])
            if "id" in r]


def header(path):
    """The sample a results file holds (its first record), or None."""
    if not os.path.exists(path):
        return None
    first = open(path).readline()
    return json.loads(first).get("sample") if first.strip() else None


def retest_sources(path):
    """The module source's SHA-256 of each rerun a retest file holds (one header per ``retest`` call)."""
    if not os.path.exists(path):
        return set()
    rows = map(json.loads, filter(None, open(path).read().split("\n")))
    return {r["retest"]["source_sha256"] for r in rows if "retest" in r}


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def commit():
    out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPO, capture_output=True, text=True)
    return out.stdout.strip() if out.returncode == 0 else "unknown"


def keep(module):
    """Copy the module's finished sample (and its retests) into :data:`SAMPLES`."""
    res = os.path.join(OUT, f"results_{module}.jsonl")
    head = header(res)
    if head is None:
        sys.exit(f"{res} holds no sample: run `tools/mutation.py run {module}` first")
    missing = set(head["ids"]) - {r["id"] for r in records(res)}
    if missing:
        sys.exit(f"the sample of {module} is unfinished: {len(missing)} of {len(head['ids'])} mutants not run; "
                 f"rerun `tools/mutation.py run {module} --n {head['n']} --seed {head['seed']}` to finish it")
    os.makedirs(SAMPLES, exist_ok=True)
    shutil.copy(res, os.path.join(SAMPLES, f"{module}.jsonl"))
    retest = os.path.join(OUT, f"results_{module}_retest.jsonl")
    kept_retest = os.path.join(SAMPLES, f"{module}_retest.jsonl")
    if os.path.exists(retest) and retest_sources(retest) - {head["source_sha256"]}:
        sys.exit(f"{retest} reruns mutants of another source than the sample's: remove it and rerun the blind spots")
    if os.path.exists(retest):
        shutil.copy(retest, kept_retest)
    elif os.path.exists(kept_retest):
        os.remove(kept_retest)
    print(f"kept {module}: {len(head['ids'])} mutants (seed {head['seed']}) in {SAMPLES}")


def live_source(module):
    """The module's source in this repository (not the private copy)."""
    return os.path.join(REPO, "src", "vibroimpact", LAYER[module], module + ".py")


def module_scores(sample, verdicts, retest=()):
    """Counts of one sample: ``sample`` its mutant records, ``verdicts`` {id: verdict table} for the
    survivors, ``retest`` the records of their reruns against the tests they led to.  Timeouts count as
    killed; invalid mutants (a syntax error) are left out; an unjudged survivor counts as a blind spot."""
    valid = [r for r in sample if r["status"] != "invalid"]
    killed = sum(r["status"] in ("killed", "timeout") for r in valid)
    survivors = [r["id"] for r in valid if r["status"] == "survived"]
    equivalent = [i for i in survivors if verdicts.get(i, {}).get("verdict") == "equivalent"]
    blind = [i for i in survivors if i not in equivalent]
    rekilled = {r["id"] for r in retest if r["status"] in ("killed", "timeout")}
    changing = len(valid) - len(equivalent)
    return {"sampled": len(valid), "killed": killed, "equivalent": len(equivalent), "blind": len(blind),
            "unjudged": sum(i not in verdicts for i in survivors), "changing": changing,
            "after": killed + sum(i in rekilled for i in blind)}


def mutation_of(record) -> str:
    """What a mutant changes, as a verdict names it (``"line 235: 0 -> 1"``): a verdict holds only for the
    mutant it was written for, not for another that a new sample gives the same id."""
    return f"line {record['line']}: {record['old']} -> {record['new']}"


def judged_verdicts(by_id, verdicts):
    """The verdicts of ``verdicts`` ({id: table}) whose ``mutation`` is that of the sample's mutant with their id
    (``by_id``: the sample's records by id)."""
    return {i: v for i, v in verdicts.items() if i in by_id and v.get("mutation") == mutation_of(by_id[i])}


def load_verdicts(path=None):
    """``verdicts.toml``: {module: {id: {"mutation": ..., "verdict": ..., "reason": ..., "test": ...}}}."""
    path = path or os.path.join(SAMPLES, "verdicts.toml")
    if not os.path.exists(path):
        return {}
    with open(path, "rb") as f:
        raw = tomllib.load(f)
    return {m: {int(i): v for i, v in table.items()} for m, table in raw.items()}


def scores(samples=SAMPLES, verdicts_path=None):
    """The testing page's Markdown: one row per kept sample and each survivor's verdict."""
    verdicts = load_verdicts(verdicts_path or os.path.join(samples, "verdicts.toml"))
    rows = ["| module | sample | of the current source | killed | equivalent | blind spots | "
            "killed of those that change behaviour | after the tests the blind spots led to |",
            "|---|---|---|---|---|---|---|---|"]
    notes = []
    for module in TESTS:
        path = os.path.join(samples, f"{module}.jsonl")
        head = header(path)
        if head is None:
            rows.append(f"| {module} | none kept | | | | | | |")
            continue
        sample = records(path)
        by_id = {r["id"]: r for r in sample}
        judged = judged_verdicts(by_id, verdicts.get(module, {}))
        s = module_scores(sample, judged, records(os.path.join(samples, f"{module}_retest.jsonl")))
        current = (os.path.exists(live_source(module))
                   and sha256(open(live_source(module), "rb").read()) == head["source_sha256"])
        source = "yes" if current else f"no (commit {head['commit'][:7]})"
        share = f"{s['killed']} of {s['changing']} ({s['killed'] / max(1, s['changing']):.0%})"
        rows.append(f"| {module} | {s['sampled']} of {head['mutants']} (seed {head['seed']}) | {source} | "
                    f"{s['killed']} | {s['equivalent']} | {s['blind']} | {share} | {s['after']} of {s['changing']} |")
        lines = []
        for i in sorted(r["id"] for r in sample if r["status"] == "survived"):
            r, v = by_id[i], judged.get(i, {})
            what = f"`{r['old']}` → `{r['new']}` (line {r['line']}, #{i})"
            if v.get("verdict") == "equivalent":
                lines.append(f"  - {what}: equivalent: {v['reason']}")
            elif v:
                lines.append(f"  - {what}: blind spot, now tested by `{v['test']}`: {v['reason']}")
            else:
                lines.append(f"  - {what}: not judged yet")
        if lines:
            notes.append(f"- **{module}**\n" + "\n".join(lines))
        else:
            notes.append(f"- **{module}**: no mutant of the sample survived")
    return "\n".join(rows) + "\n\nThe survivors, sample by sample:\n\n" + "\n".join(notes) + "\n"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cmd", choices=["list", "run", "show", "report", "retest", "keep", "scores"])
    ap.add_argument("module", nargs="?", choices=list(TESTS))
    ap.add_argument("id", nargs="?", type=int)
    ap.add_argument("--n", type=int, default=50)
    ap.add_argument("--seed", type=int, default=20240601)
    ap.add_argument("--ids", default="", help="retest: comma-separated mutant ids")
    ap.add_argument("--tests", default="", help="retest: comma-separated test files to run instead")
    ap.add_argument("--fresh", action="store_true",
                    help="remake the private copy from the working tree and start the module's sample anew")
    ap.add_argument("--out", help="scores: the Markdown file to write (default: standard output)")
    a = ap.parse_args()
    if a.cmd == "scores":
        text = scores()
        if a.out:
            os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
            with open(a.out, "w") as f:
                f.write(text)
        else:
            print(text, end="")
        return
    if a.module is None:
        ap.error(f"{a.cmd} needs a MODULE (one of {', '.join(TESTS)})")
    if a.cmd == "keep":
        keep(a.module)
        return
    make_tree(a.fresh)
    path = module_path(a.module)
    # mutants are always generated from the pristine copy (the live file may carry a mutant while a
    # run is in progress); `run` refuses to start unless the live file equals it
    pristine = os.path.join(ROOT, "pristine", a.module + ".py")
    src, muts = mutants_of(pristine if os.path.exists(pristine) else path)
    if a.cmd in ("run", "retest") and open(path, "rb").read() != src:
        sys.exit(f"{path} differs from {pristine}: restore it first")
    res_path = os.path.join(OUT, f"results_{a.module}.jsonl")

    if a.cmd == "list":
        from collections import Counter
        print(len(muts), Counter(m["kind"].split()[0] for m in muts))
        return
    if a.cmd == "show":
        m = muts[a.id]
        print(f"{a.module}.py:{m['line']} [{m['kind']}]\n{diff(src, m)}")
        return
    if a.cmd == "report":
        rows = records(res_path)
        from collections import Counter
        c = Counter(r["status"] for r in rows)
        n = len(rows)
        k = c["killed"] + c["timeout"]
        print(f"{a.module}: tried {n} (of {len(muts)}), killed {c['killed']}, timeout {c['timeout']}, "
              f"survived {c['survived']}, invalid {c['invalid']}, kill share {k / max(1, n - c['invalid']):.0%}")
        for r in rows:
            if r["status"] == "survived":
                m = muts[r["id"]]
                print(f"\n#{r['id']} {a.module}.py:{m['line']} [{m['kind']}]\n{diff(src, m)}")
        return

    if a.cmd == "retest":
        TESTS[a.module] = a.tests.split(",")
        res_path = os.path.join(OUT, f"results_{a.module}_retest.jsonl")
        sample = sorted(int(x) for x in a.ids.split(","))
        head = {"retest": {"module": a.module, "ids": sample, "tests": TESTS[a.module],
                           "source_sha256": sha256(src), "commit": commit(),
                           "date": datetime.date.today().isoformat()}}
        done = set()  # a retest reruns its mutants against the tests named
    else:
        sample = random.Random(a.seed).sample(range(len(muts)), min(a.n, len(muts)))
        # optional cap (time budget): keep the first N of the random draw, still a uniform sample
        cap_file = os.path.join(OUT, f"cap_{a.module}")
        if os.path.exists(cap_file):
            sample = sample[:int(open(cap_file).read())]
        sample = sorted(sample)
        if a.fresh and os.path.exists(res_path):
            os.remove(res_path)
        head = {"sample": {"module": a.module, "seed": a.seed, "n": a.n, "ids": sample, "mutants": len(muts),
                           "source_sha256": sha256(src), "commit": commit(),
                           "date": datetime.date.today().isoformat(), "tests": TESTS[a.module]}}
        old = header(res_path)
        if os.path.exists(res_path) and (old is None or any(
                old.get(k) != head["sample"][k] for k in ("seed", "n", "ids", "source_sha256"))):
            sys.exit(f"{res_path} holds another sample ({'no header' if old is None else 'seed ' + str(old['seed'])}"
                     f", n {None if old is None else old['n']}, or another source): pass --fresh to start anew")
        done = {r["id"] for r in records(res_path)}
    if not done:
        with open(res_path, "a") as f:
            f.write(json.dumps(head) + "\n")
    # warm shared cache for pure-Python modules (their numba dependencies are never mutated here): the package's
    # own cache of the same sources where it has one (numba checks every function it loads against its source),
    # then filled by a clean run
    if a.module not in NUMBA_MODULES and not os.path.isdir(CLEAN_CACHE):
        own = package_numba()[0]
        if own and os.path.isdir(own):
            shutil.copytree(own, CLEAN_CACHE)
        os.makedirs(CLEAN_CACHE, exist_ok=True)
        run_tests(a.module, 3600, cache=CLEAN_CACHE)
    # baseline timing (unmutated, same protocol as the mutants) decides the timeout
    st, base, failed, out, rc = run_tests(a.module, 3600)
    if st != "survived":
        sys.exit(f"clean run fails: {failed}\n{out[-3000:]}")
    timeout = max(60.0, 5 * base)
    print(f"{a.module}: {len(muts)} mutants, sample {len(sample)} (seed {a.seed}), clean {base:.1f}s, "
          f"timeout {timeout:.0f}s", flush=True)
    st_info = os.stat(path)
    for mid in sample:
        if mid in done:
            continue
        m = muts[mid]
        new = apply(src, m)
        try:
            ast.parse(new)
            valid = True
        except SyntaxError:
            valid = False
        rec = {"id": mid, "line": m["line"], "kind": m["kind"], "old": m["old"], "new": m["new"]}
        if not valid:
            rec.update(status="invalid", dt=0.0, failed=[])
        else:
            try:
                with open(path, "wb") as f:
                    f.write(new)
                st, dt, failed, out, rc = run_tests(a.module, timeout)
            finally:
                with open(path, "wb") as f:
                    f.write(src)
                os.utime(path, ns=(st_info.st_atime_ns, st_info.st_mtime_ns))
            rec.update(status=st, dt=round(dt, 1), failed=failed[:3], rc=rc)
        with open(res_path, "a") as f:
            f.write(json.dumps(rec) + "\n")
        print(f"#{mid:4d} L{m['line']:<4d} {m['kind']:<28s} {rec['status']:<9s} {rec['dt']:6.1f}s "
              f"{(rec['failed'] or [''])[0][:90]}", flush=True)
    for sub in ("", *set(LAYER.values())):
        shutil.rmtree(os.path.join(PKG, sub, "__pycache__"), ignore_errors=True)


if __name__ == "__main__":
    main()
