"""The workflow through profiles/slurm on a real SLURM (a one-node cluster started by
workflow/cluster/setup_slurm.sh): jobs go through sbatch, the outputs equal a local run's, and a job
cancelled with scancel ends the run with an error (no hang), after which a rerun completes.

Skipped, with the reason, where no SLURM answers or the executor plugin is not installed."""

import importlib.util
import re
import shutil
import subprocess
import sys
import time

import pytest
import xarray as xr
import yaml
from conftest import _copy_workflow

pytestmark = pytest.mark.slurm

#: a slice of the workflow: a branch (the job of the branches at its incline, with their energies), one sweep (with
#: transitions and energy) and one chunk of a design map (a 2-thread job)
TARGETS = ["results/branches/beta-1.0472_r-0.5000/orbit-BBT_vary-s.nc",
           "results/sweeps/beta-0.5236_r-0.5000/figBiS.nc",
           "results/design/s_F/chunk-1.nc"]


def _partition():
    out = subprocess.run(["sinfo", "-h", "-o", "%P %T"], capture_output=True, text=True, timeout=30)
    if out.returncode != 0:
        raise OSError((out.stderr.strip().splitlines() or [f"exit {out.returncode}"])[-1])
    for line in out.stdout.split("\n"):
        if line.split() and line.split()[1] in ("idle", "mixed", "allocated"):
            return line.split()[0].rstrip("*")
    return None


def _why_not():
    if importlib.util.find_spec("snakemake_executor_plugin_slurm") is None:
        return "snakemake-executor-plugin-slurm is not installed (pip install -e '.[cluster]')"
    if shutil.which("sinfo") is None or shutil.which("sbatch") is None:
        return "no SLURM on this machine (as root: workflow/cluster/setup_slurm.sh sets up a one-node one)"
    try:
        part = _partition()
    except (OSError, subprocess.SubprocessError) as err:
        return f"SLURM does not answer sinfo ({err})"
    return None if part else "no SLURM partition with an available node (workflow/cluster/setup_slurm.sh)"


WHY = _why_not()
if WHY:
    pytestmark = [pytest.mark.slurm, pytest.mark.skip(reason=WHY)]


def _small_config(tmp_path):
    cfg = _copy_workflow(tmp_path)
    cfg["resolution"]["draft"].update(branch_step=4e-3, sweep_points=12)
    cfg["sweeps"]["locate"].update(xtol=1e-5, max_trials=20)
    cfg["resolution"]["draft"]["design"] = {"grid": [6, 4], "starts": 8, "chunks": 2}
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))


def _slurm_args(tmp_path, *targets, extra=()):
    """The profile as shipped, with this cluster's partition and quick status checks (targets first:
    options such as --set-resources take every word after them)."""
    return [sys.executable, "-m", "snakemake", *targets, "--profile", "profiles/slurm", "--jobs", "2",
            "--slurm-no-account", "--slurm-init-seconds-before-status-checks", "1",
            "--seconds-between-status-checks", "2", "--latency-wait", "5", *extra,
            "--default-resources", f"slurm_partition={_partition()}", "runtime=10", "mem_mb=1000", "cpus_per_task=1"]


def test_a_slice_of_the_workflow_runs_through_sbatch_and_equals_a_local_run(tmp_path):
    slurm, local = tmp_path / "slurm", tmp_path / "local"
    for d in (slurm, local):
        d.mkdir()
        _small_config(d)
    res = subprocess.run(_slurm_args(slurm, *TARGETS), cwd=slurm, capture_output=True, text=True, timeout=900)
    out = res.stdout + res.stderr
    assert res.returncode == 0, out[-3000:]
    # each job went through sbatch: SLURM knows them (finished jobs stay in squeue for MinJobAge) under the
    # job name the plugin gives every job of this run, and they completed
    run_id = re.search(r"SLURM run ID: (\S+)", out).group(1)
    jobs = subprocess.run(["squeue", "-h", "-t", "all", "-n", run_id, "-o", "%i %T"], capture_output=True,
                          text=True, timeout=30).stdout.split("\n")
    states = [line.split()[1] for line in jobs if line.strip()]
    ran = int(re.findall(r"(\d+) of \1 steps \(100%\) done", out)[-1])  # every job the slice needs, and no more
    assert ran >= len(TARGETS) and states == ["COMPLETED"] * ran, jobs
    ref = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *TARGETS], cwd=local,
                         capture_output=True, text=True, timeout=900)
    assert ref.returncode == 0, ref.stderr[-2000:]
    for t in TARGETS + ["results/energy/beta-0.5236_r-0.5000/figBiS.nc",
                        "results/sweeps/beta-0.5236_r-0.5000/figBiS-transitions.nc"]:
        xr.testing.assert_identical(xr.load_dataset(slurm / t, engine="netcdf4").drop_attrs(),
                                    xr.load_dataset(local / t, engine="netcdf4").drop_attrs())


def test_a_job_cancelled_with_scancel_fails_the_run_and_a_rerun_completes(tmp_path):
    _small_config(tmp_path)
    target = TARGETS[:1]
    proc = subprocess.Popen(_slurm_args(tmp_path, *target), cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    job = None
    deadline = time.monotonic() + 120
    while job is None and time.monotonic() < deadline and proc.poll() is None:
        # this run's job only (its working directory is this test's): another run on the same cluster is left alone
        q = subprocess.run(["squeue", "-h", "-o", "%i|%T|%Z"], capture_output=True, text=True, timeout=30).stdout
        mine = [line.split("|") for line in q.splitlines()
                if line.count("|") == 2 and line.split("|")[2].startswith(str(tmp_path))]
        job = next((i for i, state, _ in mine if state in ("RUNNING", "PENDING", "CONFIGURING")), None)
        time.sleep(0.2)
    assert job is not None, "no job appeared in squeue"
    subprocess.run(["scancel", job], check=True, timeout=30)
    try:
        out, _ = proc.communicate(timeout=300)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("the run hung after its job was cancelled")
    assert proc.returncode != 0, out[-2000:]
    assert "Error" in out or "failed" in out, out[-2000:]
    again = subprocess.run(_slurm_args(tmp_path, *target), cwd=tmp_path, capture_output=True, text=True, timeout=900)
    assert again.returncode == 0, (again.stdout + again.stderr)[-3000:]
    assert (tmp_path / target[0]).exists()


def test_a_job_asking_more_than_the_node_has_is_refused_with_sbatch_s_reason(tmp_path):
    """The profile's 16 cores for the grids do not fit a 2-CPU node: with EnforcePartLimits (set by
    setup_slurm.sh) sbatch refuses such a job, and the run ends at once with its reason, not PENDING
    forever.  Here the job of the branches at pi/3 asks for 64."""
    _small_config(tmp_path)
    t0 = time.monotonic()
    res = subprocess.run(_slurm_args(tmp_path, TARGETS[0], extra=("--set-threads", "branches_1_0472=64",
                                                                  "--set-resources", "branches_1_0472:cpus_per_task=64")),
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)
    out = res.stdout + res.stderr
    assert res.returncode != 0
    assert "sbatch failed" in out and "More processors requested than permitted" in out, out[-2000:]
    assert time.monotonic() - t0 < 120
