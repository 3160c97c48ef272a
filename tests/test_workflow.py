"""The Snakemake workflow end to end on a tiny config, and config validation before any job."""

import os
import re
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
import yaml
from conftest import ROOT, _copy_workflow, _snakemake, scratch_clone


@pytest.mark.slow
def test_workflow_runs_end_to_end_on_a_tiny_config(tmp_path):
    cfg = _copy_workflow(tmp_path)
    cfg["captions"] = {k: cfg["captions"][k] for k in ("fig0b_a", "fig4_a", "fig4_g")}
    cfg["scenes"] = {"fig0b": {"captions": ["fig0b_a"], "t_show": 2.0},
                     "fig4": {"captions": ["fig4_a", "fig4_g"], "t_show": 2.0}}
    cfg["resolution"]["draft"]["samples_per_unit"] = 50
    cfg["resolution"]["draft"]["branch_step"] = 4e-3
    cfg["branches"]["simulated_points"] = 3
    cfg["branches"]["d_range"] = [0.13, 0.25]
    cfg["branches"]["words"] = {"BBT": cfg["branches"]["words"]["BBT"]}
    cfg["resolution"]["draft"].update(sweep_points=12, basin_grid=[6, 4], map_grid=[5, 3],
                                      figure_formats=["png", "pdf"])  # the paper preset's formats
    cfg["sweeps"]["scenes"] = {"figBiS": cfg["sweeps"]["scenes"]["figBiS"]}
    cfg["sweeps"]["locate"].update(xtol=1e-5, max_trials=20)
    cfg["branches"]["words"]["BBBT"] = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["branches"]["words"]["BBBT"]
    cfg["bifurcation"]["words"] = ["BBT", "BBBT"]  # the bifurcation set starts from continued branches only
    cfg["energy"]["figures"] = {"fig5": {"panels": ["figBiS"]}}
    cfg["chaos"] = {"panels": ["figBiS"]}
    cfg["energy"]["design"] = {"s": ["figBiS"], "F": []}
    cfg["checks"]["known"] = {}
    for scene in ("fig2", "fig3"):
        cfg["branch_scenes"][scene] = {"word": "BBT", "betas": [1.0471975511965976], "s_ranges": [[0.25, 0.37]]}
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))
    stems = ("fig0b", "fig4", "fig2", "fig3", "figBiS", "basins", "regime_map", "fig5", "lyapunov", "design")
    targets = [f"results/figures/{s}.png" for s in stems] + ["results/tables/table1.csv", "results/orbits/captions.nc"]
    res = _snakemake(tmp_path, *targets)
    assert res.returncode == 0, res.stderr[-3000:]
    for stem in stems:
        for ext in ("pdf", "png"):
            assert (tmp_path / "results" / "figures" / f"{stem}.{ext}").stat().st_size > 1000
    ds = xr.open_dataset(tmp_path / "results" / "orbits" / "caption-fig4_g.nc", engine="netcdf4")
    for var in ("Z", "Zdot", "X", "x", "t", "wall", "v_minus", "phase", "cycle_v_minus"):
        assert var in ds and "units" in ds[var].attrs
    assert ds.attrs["motion"] == "3:1 period-2" and "vibroimpact_version" in ds.attrs
    br = xr.open_dataset(tmp_path / "results" / "branches" / "beta-1.0472_r-0.5000" / "orbit-BBT_vary-s.nc", engine="netcdf4")
    for var in ("v_minus", "phase", "dt", "eig_real", "trace", "det", "discriminant", "stable", "admissible", "critical_d"):
        assert var in br
    assert "B" in br.critical_kind.values
    assert "d_B" in (tmp_path / "results" / "tables" / "table1.csv").read_text()
    sw = xr.open_dataset(tmp_path / "results" / "sweeps" / "beta-0.5236_r-0.5000" / "figBiS.nc", engine="netcdf4")
    assert sw.sizes["point"] == 12 and list(sw.direction.values) == ["up", "down"] and "label" in sw
    tr = xr.open_dataset(tmp_path / "results" / "sweeps" / "beta-0.5236_r-0.5000" / "figBiS-transitions.nc", engine="netcdf4")
    assert {"d", "kind", "d_lo", "d_hi"} <= set(tr.variables)
    # the energy written beside the sweep, from the same job
    en = xr.open_dataset(tmp_path / "results" / "energy" / "beta-0.5236_r-0.5000" / "figBiS.nc", engine="netcdf4")
    assert en.sizes["point"] == 12 and "units" in en["U_T"].attrs
    # every point's largest Lyapunov exponent with its interval, and the table of chaotic windows
    for var in ("lyap1", "lyap1_low", "lyap1_high", "lyap1_time", "lyap1_source"):
        assert var in sw and "long_name" in sw[var].attrs
    est = sw.lyap1.notnull().values
    assert (sw.lyap1_low.values[est] <= sw.lyap1_high.values[est]).all()
    assert all(str(x).startswith("not estimated: ") for x in sw.lyap1_source.values[~est])  # each NaN says why
    assert "chaotic for d in" in (tmp_path / "results" / "tables" / "chaos.md").read_text()
    table = xr.open_dataset(tmp_path / "results" / "orbits" / "captions.nc", engine="netcdf4")
    assert bool(table["reproduced"].all())
    # a second run has nothing to do
    again = _snakemake(tmp_path, "-n", *targets)
    assert "Nothing to be done" in again.stdout + again.stderr


@pytest.mark.parametrize("key, value, words", [
    # an impact that gains energy, a membrane force beyond a membrane's cubic stiffening
    (("physics", "r"), 1.0, ["config: physics.r = 1.0 is not allowed; allowed: a number >= 0 and < 1"]),
    (("membrane", "h"), 3.5, ["config: membrane.h = 3.5 is not allowed; allowed: a number >= 1 and <= 3"]),
    (("quality",), "best", ["config: quality = 'best' is not allowed; allowed: one of 'draft', 'paper', 'smoke'"]),
    (("captions", "fig4_a", "beta"), 3.0, ["config: captions.fig4_a.beta = 3.0 is not allowed", "<= 1.5707963267948966"]),
    (("resolution", "draft", "figure_formats"), ["pdf"],
     ["config: resolution.draft.figure_formats = ['pdf'] is not allowed", "including 'png'"]),
    # design maps: fewer than 8 starts, a negative tolerance, an empty box of start states
    (("resolution", "draft", "design", "starts"), 4, ["resolution.draft.design.starts", "4", ">= 8"]),
    (("design", "tolerance", "s"), -0.01, ["design.tolerance.s", "-0.01", ">= 0"]),
    (("design", "starts"), {"distribution": "box", "seed": 1, "phi_range": [0.0, 6.0], "v0_range": [0.5, 0.5]},
     ["v0_range", "0.5", "lo < hi"]),
])
def test_bad_config_fails_before_any_job(tmp_path, key, value, words):
    cfg = _copy_workflow(tmp_path)
    node = cfg
    for k in key[:-1]:
        node = node[k]
    node[key[-1]] = value
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))
    res = _snakemake(tmp_path, "-n")
    assert res.returncode != 0
    out = res.stdout + res.stderr
    for w in words:
        assert w in out, out[-2000:]
    assert not (tmp_path / "results").exists()
    assert res.stderr.strip().splitlines()[-1].startswith("config: ") and "Traceback" not in out  # one line


#: a device file with a misspelt top-level key, and the one line that refuses it
MISSPELT = "physiks:\n  omega: 14.137166941154069\n"
REFUSAL = ("config: physiks = {'omega': 14.137166941154069} is not allowed; allowed: one of the keys device, quality, "
           "physics, captions, scenes, resolution, attractor, branches, branch_scenes, sweeps, basins, maps, design, knocks, "
           "membrane, energy, chaos, studies, study_defaults, checks, figure_checks, bifurcation, work_precision, "
           "lyapunov_precision, failure_map, bench; did you mean physics?")


def test_a_misspelt_top_level_key_in_a_configfile_is_refused_in_one_line_before_any_job(tmp_path):
    """`physiks:` in a --configfile is refused, not ignored (else the paper's device would run): the dry run
    stops with the one line naming the key, its value, the keys allowed and the closest one, and nothing else
    (no schema dump, no traceback); no folder is made."""
    _copy_workflow(tmp_path)
    (tmp_path / "mine.yaml").write_text(MISSPELT)
    res = _snakemake(tmp_path, "-n", "--configfile", "mine.yaml")
    assert res.returncode == 1
    assert res.stderr.strip().splitlines()[-1] == REFUSAL, res.stderr[-2000:]
    said = [line for line in (res.stdout + res.stderr).splitlines()
            if not line.startswith(("Using workflow specific profile", "Config file config/config.yaml is extended"))]
    assert said == [REFUSAL], said
    assert not (tmp_path / "results").exists()


def _tree(root):
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*"))


def test_a_dry_run_creates_no_folder(tmp_path):
    """`snakemake -n` on a scratch copy: for another device (config/example_device.yaml, whose results go to
    results/devices/<name>/) the tree after is the tree before, not even that folder made; the plan is the
    device's whole default target (nothing of it exists yet).  For the paper's device only Snakemake's own
    state folder .snakemake/ appears (where Snakemake is started)."""
    _copy_workflow(tmp_path)
    before = _tree(tmp_path)
    res = _snakemake(tmp_path, "-n", "--configfile", "config/example_device.yaml")
    assert res.returncode == 0, res.stderr[-2000:]
    assert _tree(tmp_path) == before
    # 17 branches: those the figures draw, and the 1:1 and 2:1 along every sweep's line (its period doublings; where
    # the d_graz table reads d_graz), one job per incline (4) and none in a job of its own
    out = res.stdout
    assert len(set(re.findall(r"^(branches_\w+)\s+1$", out, re.M))) == 4 and re.search(r"^all\s+1$", out, re.M), out[-3000:]
    assert not re.search(r"^branch\s+\d+$", out, re.M), out[-3000:]
    assert len(set(re.findall(r"results/branches/beta-[0-9.]+_r-[0-9.]+/orbit-\w+_vary-[sF]\.nc", out))) == 17
    res = _snakemake(tmp_path, "-n")
    assert res.returncode == 0, res.stderr[-2000:]
    assert [p for p in _tree(tmp_path) if p not in before and not p.startswith(".snakemake")] == []


@pytest.mark.parametrize("edit, words", [
    # a force sweep needs the fixed length s
    (lambda c: c["sweeps"]["scenes"]["fig0_F"].pop("s"), ["sweeps.scenes.fig0_F.s", "fixed length s"]),
    # a map's two axes differ
    (lambda c: c["maps"]["s_F"].update(y="s"), ["maps.s_F.y", "'s'", "different from x"]),
    # start_d inside d_range
    (lambda c: c["branches"]["words"]["BBT"].update(start_d=0.6), ["branches.words.BBT.start_d", "0.6", "inside branches.d_range"]),
    # the bifurcation set starts from branches the config continues
    (lambda c: c["bifurcation"].update(words=["BBT", "BBBBT"]), ["bifurcation.words", "BBBBT", "words of branches.words"]),
    # the bifurcation set's own planes are non-dimensional, and take their fixed parameter from the physics
    (lambda c: c["bifurcation"]["maps"]["d_gbar"].update(x="s"), ["bifurcation.maps.d_gbar.x", "'s'", "one of d, gbar, r"]),
    (lambda c: c["bifurcation"]["maps"]["d_r"].update(beta=0.3), ["bifurcation.maps.d_r.beta", "0.3", "bifurcation.beta"]),
    # reversed or empty ranges, wherever a range is given
    (lambda c: c["branch_scenes"]["fig2"]["s_ranges"].__setitem__(0, [0.37, 0.27]),
     ["branch_scenes.fig2.s_ranges[0]", "[0.37, 0.27]", "s_min < s_max"]),
    (lambda c: c["branches"]["force"].update(F_range=[22.0, 22.0]), ["branches.force.F_range", "[22.0, 22.0]"]),
    (lambda c: c["basins"]["figBiS"].update(v0_range=[1.2, 0.02]), ["basins.figBiS.v0_range", "[1.2, 0.02]"]),
    # figure_checks.figures names figures the workflow draws
    (lambda c: c["figure_checks"].update(figures=["fig9"]), ["figure_checks.figures", "fig9", "'all' or a list"]),
    # checks.known names an item the check produces
    (lambda c: c["checks"]["known"].update({"G3: no such point": "a reason long enough for the schema to accept it"}), ["checks.known", "G3: no such point", "an item of the paper-value check"]),
])
def test_cross_key_config_errors_fail_before_any_job(tmp_path, edit, words):
    cfg = _copy_workflow(tmp_path)
    edit(cfg)
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))
    res = _snakemake(tmp_path, "-n")
    out = res.stdout + res.stderr
    assert res.returncode != 0
    for w in words:
        assert w in out, out[-2000:]
    assert not (tmp_path / "results").exists()


def test_unknown_caption_in_a_scene_is_named(tmp_path):
    cfg = _copy_workflow(tmp_path)
    cfg["scenes"]["fig4"]["captions"].append("fig9_z")
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))
    res = _snakemake(tmp_path, "-n")
    assert res.returncode != 0 and "scenes.fig4.captions" in res.stderr + res.stdout and "fig9_z" in res.stderr + res.stdout


@pytest.mark.slow
def test_check_target_passes_on_the_default_config(default_run):
    """`snakemake check` on the shipped config: every published value reproduced or a listed
    discrepancy with its evidence; nothing fails."""
    tmp_path, res = default_run
    assert res.returncode == 0, res.stderr[-3000:]
    import pandas as pd

    df = pd.read_csv(tmp_path / "results" / "checks" / "paper_values.csv")
    assert len(df) > 50
    assert set(df["status"]) <= {"pass", "known discrepancy"}
    assert (df["status"] == "pass").sum() > 50
    assert df.loc[df["status"] == "known discrepancy", "note"].str.len().min() > 20
    # every figure draws the data of its committed reference
    figs = pd.read_csv(tmp_path / "results" / "checks" / "figures.csv")
    assert set(figs["status"]) <= {"pass", "excluded"} and figs["figure"].nunique() >= 14
    assert (figs["status"] == "pass").sum() > 100


@pytest.mark.parametrize("studies, edit, words", [
    # a reversed and an empty s range
    ("[{beta: 0.4, r: 0.6, s_range: [0.5, 0.2]}]", None, ["studies[0].s_range", "[0.5, 0.2]", "s_min < s_max"]),
    ("[{beta: 0.4, r: 0.6, s_range: [0.3, 0.3]}]", None, ["studies[0].s_range", "[0.3, 0.3]", "s_min < s_max"]),
    # a study repeating another (the same paths to 4 decimals)
    ("[{beta: 0.4, r: 0.6}, {beta: 0.40001, r: 0.6}]", None,
     ["studies[1]", "repeats studies[0]", "results/studies/beta-0.4000_r-0.6000"]),
    # a value of the command line that is no number
    ("[{beta: 0.4, r: 0.6x}]", None, ["config: studies[0].r = '0.6x' is not allowed; allowed: a number"]),
    # an impact that gains energy (r = 0, a plastic impact, is allowed)
    ("[{beta: 0.4, r: 1}]", None, ["config: studies[0].r = 1.0 is not allowed; allowed: a number >= 0 and < 1"]),
    # a device too weak to lift the ball off the bottom membrane at this incline
    ("[{beta: 1.5, r: 0.6}]", lambda c: c["physics"].update(F=1.0), ["studies[0].beta", "1.5", "gbar", "< 1"]),
    # the defaults' range, reversed
    ("[{beta: 0.4, r: 0.6}]", lambda c: c["study_defaults"].update(s_range=[0.72, 0.19]),
     ["study_defaults.s_range", "[0.72, 0.19]"]),
])
def test_a_bad_study_is_refused_before_any_job(tmp_path, studies, edit, words):
    """Bad study input fails the dry run, naming the key, the value and what is allowed."""
    cfg = _copy_workflow(tmp_path)
    if edit:
        edit(cfg)
        (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))
    res = _snakemake(tmp_path, "-n", "--config", f"studies={studies}")
    out = res.stdout + res.stderr
    assert res.returncode != 0
    for w in words:
        assert w in out, (w, out[-2000:])
    assert not (tmp_path / "results").exists()


def test_a_study_adds_only_its_own_jobs(tmp_path):
    """`--config 'studies=[...]'` plans only the study's jobs (dry run on top of a finished
    default run is covered in README; here: the study's targets and no default ones)."""
    _copy_workflow(tmp_path)
    res = _snakemake(tmp_path, "-n", "results/studies/beta-0.4000_r-0.6000/study.png",
                     "--config", "studies=[{beta: 0.4, r: 0.6}]")
    assert res.returncode == 0, res.stderr[-2000:]
    out = res.stdout + res.stderr
    for rule in ("branch", "sweep", "study_figure"):
        assert rule in out
    for rule in ("fig2", "caption_orbits", "regime_map", "check"):
        assert f"rule {rule}:" not in out and f"\n{rule} " not in out
    bad = _snakemake(tmp_path, "-n", "--config", "studies=[{beta: 3.0, r: 0.6}]")
    assert bad.returncode != 0 and "3.0" in bad.stdout + bad.stderr


def test_every_benchmark_file_is_attributed_to_the_rule_that_writes_it():
    """The workflow-cost table's per-rule rows: each rule's ``benchmark:`` path, with its wildcards
    filled in, maps back to that rule's name (vibroimpact.outputs.tables.rule_of_benchmark)."""
    import re

    from vibroimpact.outputs.tables import rule_of_benchmark

    root = ROOT
    seen = 0
    for smk in sorted((root / "workflow" / "rules").glob("*.smk")):
        text = smk.read_text()
        for m in re.finditer(r"^rule (\w+):\n(.*?)(?=^rule |\Z)", text, re.S | re.M):
            b = re.search(r'benchmark:\n\s+"benchmarks/([^"]+)"', m.group(2))
            if b:
                path = re.sub(r"\{(\w+)\}", lambda w: {"word": "BBT", "vary": "s"}.get(w.group(1), "x1"), b.group(1))
                assert rule_of_benchmark(path) == m.group(1), (m.group(1), path)
                seen += 1
    assert seen >= 25


def test_the_bifurcation_target_plans_its_rules_from_the_branches(tmp_path):
    """`snakemake bifurcation`: one curve set and one figure per regime map, from the start branches."""
    _copy_workflow(tmp_path)
    res = _snakemake(tmp_path, "-n", "bifurcation")
    assert res.returncode == 0, res.stderr[-2000:]
    out = res.stdout + res.stderr
    for rule in ("bifurcation_set", "fig_bifurcation_set", "regime_map"):
        assert f"rule {rule}:" in out or f"\n{rule} " in out or f" {rule} " in out, rule
    assert re.search(r"^branches_\w+\s+1$", out, re.M)  # the branches at the bifurcation set's incline
    assert "results/bifurcation/s_beta.nc" in out and "results/figures/bifurcation_set_s_F.png" in out


def test_the_paper_preset_splits_each_design_map_into_chunk_jobs(tmp_path):
    """`snakemake design_maps --config quality=paper`: each design map is planned as the preset's number
    of chunk jobs (so a cluster profile runs them as separate jobs), merged by one job per map."""
    cfg = _copy_workflow(tmp_path)
    n = cfg["resolution"]["paper"]["design"]["chunks"]
    res = _snakemake(tmp_path, "-n", "design_maps", "--config", "quality=paper")
    assert res.returncode == 0, res.stderr[-2000:]
    counts = dict(re.findall(r"^(design_chunk|design_map|fig_design_map)\s+(\d+)$", res.stdout + res.stderr, re.M))
    maps = len(cfg["design"]["maps"])
    assert counts == {"design_chunk": str(n * maps), "design_map": str(maps), "fig_design_map": str(maps)}
    assert f"results/design/s_beta/chunk-{n - 1}.nc" in res.stdout + res.stderr


@pytest.mark.slow
def test_every_dataset_the_workflow_writes_has_units_and_long_names(default_run):
    """CF style: every variable and coordinate of every netCDF file under results/ (datasets and the
    figures' own data) has a long_name, and every numeric one (not a flag or a label) has units."""
    tmp_path, res = default_run
    assert res.returncode == 0, res.stderr[-2000:]
    files = sorted((tmp_path / "results").rglob("*.nc"))
    assert len(files) > 60
    missing = []
    for f in files:
        ds = xr.open_dataset(f, engine="netcdf4")
        for name in [*ds.data_vars, *ds.coords]:
            attrs = ds[name].attrs
            if "long_name" not in attrs:
                missing.append(f"{f.relative_to(tmp_path)}:{name}: long_name")
            if ds[name].dtype.kind in "fiu" and "units" not in attrs:
                missing.append(f"{f.relative_to(tmp_path)}:{name}: units")
        ds.close()
    assert not missing, missing[:20]


def test_the_workflow_follows_snakemake_s_conventions():
    """`snakemake --lint` and `snakefmt --check` are clean, and every rule that runs something uses the
    one conda environment (or none does)."""
    import re
    import shutil
    import subprocess
    import sys

    lint = subprocess.run([sys.executable, "-m", "snakemake", "--lint"], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)
    assert lint.returncode == 0 and "good condition" in lint.stdout + lint.stderr, (lint.stdout + lint.stderr)[-2000:]
    fmt = shutil.which("snakefmt") or str(ROOT / ".venv" / "bin" / "snakefmt")
    files = ["Snakefile", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "workflow" / "rules").glob("*.smk"))]
    res = subprocess.run([fmt, "--check", *files], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    envs = set()
    for smk in [ROOT / "Snakefile", *(ROOT / "workflow" / "rules").glob("*.smk")]:
        for m in re.finditer(r"^rule (\w+):\n(.*?)(?=^rule |\Z)", smk.read_text(), re.S | re.M):
            body = m.group(2)
            if re.search(r"^\s+(script|shell|run):", body, re.M):
                env = re.search(r'conda:\n\s+"([^"]+)"', body)
                envs.add(env.group(1) if env else None)
    assert envs == {"../envs/vibroimpact.yaml"}, envs


@pytest.mark.slow  # ~30 s: one real run of three cheap jobs, three dry runs
def test_a_package_change_reruns_the_jobs_whose_scripts_import_it(tmp_path):
    """Every rule's `code` parameter (vibroimpact._code_version) in a scratch clone, with the clone's
    sources the ones imported: after a run of one figure's caption orbits, the figure and the captions'
    summary, an edit to a module none of them imports plans nothing; to a plot module, the figure and not
    the simulation; to the dynamics, every job."""
    clone = scratch_clone(tmp_path)
    cfg = yaml.safe_load((clone / "config" / "config.yaml").read_text())
    cfg["captions"] = {k: cfg["captions"][k] for k in cfg["scenes"]["fig0b"]["captions"]}
    cfg["scenes"] = {"fig0b": cfg["scenes"]["fig0b"]}
    cfg["checks"]["known"] = {}
    cfg["resolution"]["draft"]["samples_per_unit"] = 50
    (clone / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))
    env = os.environ | {"PYTHONPATH": str(clone / "src")}  # the clone's package, not the installed one
    targets = ["results/figures/fig0b.png", "results/tables/captions.md"]

    def snakemake(*args):
        res = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "1", *args, *targets], cwd=clone,
                             capture_output=True, text=True, timeout=600, env=env)
        assert res.returncode == 0, res.stderr[-3000:]
        return res.stdout + res.stderr

    def planned_after_editing(module):
        with open(clone / "src" / "vibroimpact" / module, "a") as fh:
            fh.write("# an edit\n")
        out = snakemake("-n")
        if "Nothing to be done" in out:
            return set()
        assert "params have changed since last execution" in out.lower(), out[-3000:]  # the trigger: `code`
        return set(re.findall(r"^(\w+)\s+\d+$", out.split("Job stats:")[1], re.M)) - {"total"}

    snakemake()
    assert planned_after_editing("analysis/design.py") == set()
    assert planned_after_editing("outputs/plots/orbits.py") == {"scene_figure"}
    assert planned_after_editing("dynamics/flight.py") == {"caption_orbits", "caption_summary", "scene_figure"}


@pytest.mark.slow
def test_the_default_target_knocks_every_design_of_its_plane(default_run):
    """The default target's knock map (README's first command, in a scratch clone under another libm): every
    attractor of every design either has a critical shock or says why not; the table names the knock and both
    designs over the map; the figures are drawn."""
    tmp_path, res = default_run
    assert res.returncode == 0, res.stderr[-2000:]
    km = xr.open_dataset(tmp_path / "results" / "knocks" / "map.nc", engine="netcdf4")
    present = km["label"].values != ""
    known = ~np.isnan(km["shock"].values)
    assert present.any() and np.all(present <= (known | (km["shock_reason"].values != "")))
    runs = km["shock_runs"].values[known]
    assert np.all(runs > 0) and np.median(runs) <= 2000  # ten times fewer than a 20 000-sample random search
    table = (tmp_path / "results" / "tables" / "knocks.md").read_text()
    assert f"The knock: {km.attrs['knock']:g} m/s" in table and re.search(r"\| whole map +\| best output", table)
    for stem in ("knocks", "knock_section"):
        assert (tmp_path / "results" / "figures" / f"{stem}.png").stat().st_size > 1000
