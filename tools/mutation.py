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
whose numba dependencies are unchanged), run the module's test files with
`pytest -x -q -p no:cacheprovider --hypothesis-seed=0` under a timeout (5x the clean run, min 60 s),
restore the file bytes and mtime.  Exit status 0 -> survived, timeout -> timed out (counted as
killed), anything else -> killed.  Results are appended to results/mutation/results_<module>.jsonl
(resumable).  A surviving mutant is either equivalent (no input changes the result beyond the
stated tolerance) or a blind spot of the tests; the report lists survivors with their diff.

Usage (from the repository root, with the project's venv):
  .venv/bin/python tools/mutation.py list   MODULE                 # count all mutants
  .venv/bin/python tools/mutation.py run    MODULE [--n N] [--seed S] [--fresh]
  .venv/bin/python tools/mutation.py show   MODULE ID              # diff of one mutant
  .venv/bin/python tools/mutation.py report MODULE
"""

import argparse
import ast
import difflib
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.join(REPO, "results", "mutation", "tree")  # the private copy the mutants live in
OUT = os.path.join(REPO, "results", "mutation")
PKG = os.path.join(ROOT, "src", "vibroimpact")
#: the layer of the package each module lives in
LAYER = {**{m: "dynamics" for m in ("params", "flight", "events", "kernels", "simulate", "reference")},
         **{m: "analysis" for m in ("orbits", "grazing", "continuation", "bifurcation", "settled", "sweeps", "energy",
                                    "design", "lyapunov", "family_exit")},
         **{m: "benchmarks" for m in ("methods", "peer_heyoka", "peer_siconos", "workprecision", "bench")},
         **{m: "outputs" for m in ("tables", "checks", "paper", "portraits", "figdata", "figcheck", "conditioning")}}


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
    "events": ["tests/test_impact_times.py", "tests/test_properties.py", "tests/test_sticking.py"],
    "kernels": ["tests/test_kernels.py", "tests/test_sticking.py", "tests/test_attractor.py",
                "tests/test_properties.py", "tests/test_impact_times.py"],
    "orbits": ["tests/test_orbits.py", "tests/test_captions.py"],
    "continuation": ["tests/test_orbits.py"],
    "sweeps": ["tests/test_sweeps.py"],
    "energy": ["tests/test_energy.py"],
    "design": ["tests/test_design.py"],
    "settled": ["tests/test_settled.py", "tests/test_energy.py"],
    "lyapunov": ["tests/test_lyapunov.py"],
    "family_exit": ["tests/test_family_exit.py"],
    "figcheck": ["tests/test_figcheck.py"],
    "figdata": ["tests/test_figdata.py", "tests/test_figcheck.py"],
    # its unit tests (the workflow-level test regenerates the whole figure set: minutes a mutant)
    "conditioning": [f"tests/test_conditioning.py::{t}" for t in (
        "test_an_array_is_ill_conditioned_when_any_perturbation_moves_it_beyond_the_strict_tolerance",
        "test_timings_and_optional_peers_are_excluded_as_in_the_check",
        "test_the_mass_moves_by_the_given_number_of_ulps_and_nothing_else",
        "test_a_move_between_one_and_two_tolerances_is_a_move",
        "test_the_image_spread_and_the_ill_conditioned_variables_of_a_figure",
        "test_a_perturbed_regeneration_runs_the_workflow_in_a_copy_with_the_switch_and_the_moved_mass")]
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
    return "\n".join(l for l in difflib.unified_diff(old, new, lineterm="", n=0) if not l.startswith(("---", "+++")))


CLEAN_CACHE = os.path.join(OUT, "numba_cache_clean")


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
    failed = [l for l in out.splitlines() if l.startswith(("FAILED", "ERROR"))]
    return status, dt, failed, out, proc.returncode


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cmd", choices=["list", "run", "show", "report", "retest"])
    ap.add_argument("module", choices=list(TESTS))
    ap.add_argument("id", nargs="?", type=int)
    ap.add_argument("--n", type=int, default=50)
    ap.add_argument("--seed", type=int, default=20240601)
    ap.add_argument("--ids", default="", help="retest: comma-separated mutant ids")
    ap.add_argument("--tests", default="", help="retest: comma-separated test files to run instead")
    ap.add_argument("--fresh", action="store_true", help="remake the private copy from the working tree")
    a = ap.parse_args()
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
        rows = [json.loads(l) for l in open(res_path)]
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
        sample = [int(x) for x in a.ids.split(",")]
    else:
        sample = None
    # run
    rng = random.Random(a.seed)
    if sample is not None:
        pass
    else:
      sample = rng.sample(range(len(muts)), min(a.n, len(muts)))
      # optional cap (time budget): keep the first N of the random draw, still a uniform sample
      cap_file = os.path.join(OUT, f"cap_{a.module}")
      if os.path.exists(cap_file):
          sample = sample[:int(open(cap_file).read())]
    sample = sorted(sample)
    done = set()
    if os.path.exists(res_path):
        done = {json.loads(l)["id"] for l in open(res_path)}
    # warm shared cache for pure-Python modules (their numba dependencies are never mutated here)
    if a.module not in NUMBA_MODULES and not os.path.isdir(CLEAN_CACHE):
        os.makedirs(CLEAN_CACHE)
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
