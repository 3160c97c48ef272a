import vibroimpact.outputs.job  # noqa: F401  (first: the test processes collect their garbage less often)

# isort: split
import math

import numpy as np
import pytest

import vibroimpact as vi

#: The one tolerance of the exact simulator against a high-precision reference, for impact times
#: (absolute, or relative beyond t = 1), velocities and positions: the flight is closed-form, so the
#: only error is rounding: ~1e-16 per operation, amplified by the root's conditioning (1 / |Zdot-|
#: for times, capped by the double-double polish below |Zdot-| = 1e-3) and accumulated over the
#: few hundred events a test follows.  1e-12 leaves that four orders of magnitude.  A root is found
#: to relative rounding, so a flight time far below 1 (an impact just after a start) is held to
#: TOL_T relative to itself.
TOL_T = 1e-12


def flight_state(theta, z0, u, gbar, tau):
    """Relative position and velocity ``tau`` after a state ``(z0, u)`` at forcing phase ``theta``:
    the closed-form solution of ``Z'' = gbar + cos(pi t + phi)`` (docs/guide/model.md, paper eqs. zdot_t, z_t), written
    here from the equation, independently of the package's cancellation-free evaluation."""
    x = np.pi * tau
    v = u + gbar * tau + (np.sin(theta + x) - np.sin(theta)) / np.pi
    z = z0 + u * tau + gbar * tau**2 / 2 - (np.cos(theta + x) - np.cos(theta) + x * np.sin(theta)) / np.pi**2
    return z, v

#: Paper defaults (docs/guide/model.md)
M, F, OMEGA, G = 0.1245, 5.0, 5 * math.pi, 9.8


def gbar_of(beta, force=F):
    return M * G * math.sin(beta) / force


#: Caption orbits of docs/guide/model.md and Fig FN2: name -> (beta, d, Zdot(t0), phi, n_bottom, n_top,
#: period in forcing periods, force in N); Fig FN2 (a)-(c) state 61 N.
CAPTIONS = {
    "figFN2_a": (math.pi / 2, 0.197, 0.5474, 6.211, 1, 1, 1, 61.0),
    "figFN2_b": (math.pi / 2, 0.193, 0.561, 6.229, 2, 2, 2, 61.0),
    "figFN2_c": (math.pi / 2, 0.189, 0.465, 6.177, 2, 1, 1, 61.0),
    "figFN2_e": (math.pi / 6, 0.222, 0.676, 0.242, 4, 4, 4),
    "figFN2_f": (math.pi / 6, 0.213, 0.674, 0.321, 5, 5, 5),
    "fig0b_a": (math.pi / 3, 0.38, 0.8673, 0.4217, 1, 1, 1),
    "fig0b_b": (math.pi / 3, 0.184, 0.2164, 1.21, 2, 1, 1),
    "fig0b_c": (math.pi / 3, 0.137, 0.2059, 0.6503, 3, 1, 1),
    "figFN2_d": (math.pi / 6, 0.252, 0.669, 0.128, 1, 1, 1),
    "figFN2_g": (math.pi / 6, 0.204, 0.532, 6.106, 2, 1, 1),
    "fig4_a": (math.pi / 6, 0.16, 0.1924, 1.015, 2, 1, 1),
    "fig4_d": (math.pi / 6, 0.139, 0.1959, 0.7788, 2, 1, 1),
    "fig4_g": (math.pi / 6, 0.138, 0.1845, 0.7342, 3, 1, 1),
    "figBiS_d": (math.pi / 6, 0.1378, 0.416, 5.842, 2, 1, 1),
    "figBiS_e": (math.pi / 6, 0.14, 0.4185, 5.855, 2, 1, 1),
    "figBiS_f": (math.pi / 6, 0.14, 0.3967, 5.88, 3, 1, 1),
    "figBiS_g": (math.pi / 6, 0.1419, 0.4069, 5.864, 3, 1, 1),
}


@pytest.fixture
def pi6():
    return vi.Params(d=0.16, gbar=gbar_of(math.pi / 6), r=0.5)


# ---- the Snakemake workflow in a temporary copy (tests/test_workflow.py, tests/test_report.py) ----
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import yaml  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _copy_workflow(tmp_path):
    for item in ("Snakefile", "workflow", "config", "profiles", "reference"):
        src = ROOT / item
        if not src.exists():
            continue
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    return yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


def _snakemake(tmp_path, *args):
    return subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *args], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)


# ---- README.md's commands, executed as written (tests/test_readme.py) -----------------------------
import os  # noqa: E402
import re  # noqa: E402
import time  # noqa: E402

#: a shell block of a document, with the marker before it naming what runs it:
#: <!-- tested by tests/test_x.py::test_name -->  or  <!-- run by .ci/run -->
SHELL_BLOCK = re.compile(r"(?:<!--\s*(tested by|run by)\s+(\S+)\s*-->\s*\n)?```(?:bash|sh|shell|console)\n(.*?)```", re.S)


def shell_blocks(path):
    """``(marker, target, command)`` of every shell block of a Markdown file (marker None where none)."""
    return [(m.group(1), m.group(2), m.group(3).strip()) for m in SHELL_BLOCK.finditer(Path(path).read_text())]


#: the documents whose shell blocks a user is told to run
DOCUMENTS = [ROOT / "README.md", ROOT / "config" / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def readme_command(test_id):
    """The command of the block (README.md or a documentation page) whose marker names ``test_id``: what the
    documents show, run as is.  A command shown on two pages must be the same on both."""
    found = {cmd for doc in DOCUMENTS if doc.exists() and "_generated" not in doc.parts
             for kind, target, cmd in shell_blocks(doc) if kind == "tested by" and target == test_id}
    assert len(found) == 1, f"the documents have {len(found)} distinct commands marked 'tested by {test_id}'"
    return found.pop()


def scratch_clone(dest, git=False):
    """The repository as a fresh clone has it (the files git tracks, and new ones it does not ignore), in
    ``dest``: what a user has after ``git clone``, with this working tree's changes; with ``git``, a git work
    tree whose one commit holds them (so that ``git status`` shows what a run changed)."""
    files = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, capture_output=True,
                           check=True).stdout.decode().split("\0")
    now = time.time()  # one modification time for every file, as a fresh clone has them: a copy that kept the
    for f in filter(None, files):  # working tree's would leave a figure newer than its code, never redrawn
        src = ROOT / f
        if src.is_file():
            (dest / f).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / f)
            os.utime(dest / f, (now, now))
    if git:
        cmd = ["git", "-C", str(dest), "-c", "user.name=test", "-c", "user.email=test@localhost"]
        subprocess.run(cmd[:3] + ["init", "-q"], check=True)
        subprocess.run(cmd + ["add", "-A"], check=True)
        subprocess.run(cmd + ["commit", "-q", "-m", "clone"], check=True)
    return dest


def run_readme(cwd, command, env=None, timeout=3600):
    """A README command run as a user runs it: in bash, from the clone's root."""
    return subprocess.run(["bash", "-c", command], cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          env=os.environ | (env or {}))


#: the fixtures of README's scratch clone: with the suite spread over processes (pytest-xdist, ``--dist loadgroup``),
#: every test that needs the clone runs in one of them, so that the clone is set up and run once
CLONE_FIXTURES = {"readme_clone", "default_run", "docs_build"}


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist's, which reads the groups
def pytest_collection_modifyitems(config, items):
    try:  # pytest >= 9 keeps a node's id in `_id`: pytest-xdist 3.8 writes its group suffix to `_nodeid`, unread
        from _pytest.nodeid import coerce_node_id
    except ImportError:  # pytest 8: pytest-xdist adds the suffix of the marker itself
        coerce_node_id = None
    if getattr(config.option, "dist", "no") != "no":  # spread over processes: the slowest first (below)
        seconds = _recorded_seconds()
        items.sort(key=lambda item: -seconds.get(item.nodeid.partition("@")[0], 0.0))
    for item in items:
        if CLONE_FIXTURES & set(getattr(item, "fixturenames", ())) or item.get_closest_marker("xdist_group"):
            item.add_marker(pytest.mark.xdist_group("readme_clone"))
            if coerce_node_id is not None and getattr(config.option, "loadgroup", False) and "@" not in item.nodeid:
                item._id = coerce_node_id(f"{item.nodeid}@readme_clone")


def _recorded_seconds() -> dict[str, float]:
    """Each test's seconds in the kept record of a whole run (reference/test_durations.csv, without the group
    suffix): the processes take the tests slowest first, so that the last tests to finish are short ones and no
    process waits long for another at the end (tests the record does not hold keep their order, after the
    others)."""
    import csv

    path = ROOT / "reference" / "test_durations.csv"
    if not path.exists():
        return {}
    rows = csv.reader(line for line in path.read_text().splitlines() if not line.startswith("#"))
    return {test.partition("@")[0]: float(sec) for test, sec in rows if test != "test" and sec.replace(".", "").isdigit()}


@pytest.fixture(scope="session")
def readme_clone(tmp_path_factory):
    """A scratch clone set up and run by README.md's first command, as on another machine: under glibc's
    other libm code path (vibroimpact.outputs.conditioning.LIBM_SWITCH) for the whole process tree.  Returns the
    clone, the first command's result and the result of README's check command run after it."""
    from vibroimpact.outputs.conditioning import LIBM_SWITCH

    clone = scratch_clone(tmp_path_factory.mktemp("clone"), git=True)
    first = run_readme(clone, readme_command("tests/test_readme.py::test_the_first_command_sets_up_and_runs_the_default_target"),
                       LIBM_SWITCH)
    check = run_readme(clone, readme_command("tests/test_readme.py::test_the_check_passes_under_another_libm"),
                       LIBM_SWITCH) if first.returncode == 0 else first
    return clone, first, check


@pytest.fixture(scope="session")
def docs_build(readme_clone):
    """README's docs command run once in the scratch clone after its first command and its check (it runs the
    bench, bifurcation and design_maps targets too): the clone and the command's result."""
    clone, first, _ = readme_clone
    if first.returncode:
        return clone, first
    return clone, run_readme(clone, readme_command("tests/test_docs.py::test_the_docs_build_with_warnings_as_errors"))


@pytest.fixture(scope="session")
def default_run(readme_clone):
    """The default target and `check` as README.md runs them (in a scratch clone, under another libm)."""
    clone, _, check = readme_clone
    return clone, check


# ---- the suite's durations, for the testing page (tools/test_durations.py) ----------------------------------

#: where a run of the whole suite (no paths, no -m, no -k) leaves every test's seconds (setup, call and teardown
#: summed), read by tools/test_durations.py; results/ is not tracked, so the clone stays clean
DURATIONS = ROOT / "results" / "tests" / "durations.csv"
_seconds: dict[str, float] = {}
_started = time.perf_counter()


def pytest_runtest_logreport(report):
    _seconds[report.nodeid] = _seconds.get(report.nodeid, 0.0) + report.duration


def pytest_sessionfinish(session, exitstatus):
    opt = session.config.option
    if hasattr(session.config, "workerinput"):  # a pytest-xdist worker: the controller gets every report
        return
    whole = not session.config.args_source.name == "ARGS" and not opt.markexpr and not opt.keyword
    if whole and _seconds:
        DURATIONS.parent.mkdir(parents=True, exist_ok=True)
        rows = sorted(_seconds.items(), key=lambda kv: -kv[1])
        DURATIONS.write_text("test,seconds\n" + "".join(f'"{k}",{v:.2f}\n' for k, v in rows)
                             + f'"(the whole run, wall)",{time.perf_counter() - _started:.2f}\n')
