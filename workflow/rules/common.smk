# Shared helpers: path and parameter lookups on the checked config (CFG: the Snakefile checks the config
# with vibroimpact.outputs.workflow_config, every check across keys, before any job).
import math
import os

from vibroimpact._code_version import code_version
from vibroimpact.outputs.workflow_config import d_graz_sweeps


def code(script=None):
    """A rule's `code` parameter: a hash of the package sources workflow/scripts/<script> depends on
    (of the whole package without a script), so that its jobs rerun when they change."""
    return code_version(
        script and os.path.join(workflow.basedir, "workflow", "scripts", script)
    )


#: the device the config describes, as every job builds it (vibroimpact.Device.from_config)
DEVICE_SPEC = CFG.device_spec()


CAPTIONS = CFG.captions
SCENES = CFG.scenes
QUALITY = CFG.quality
RESOLUTION = CFG.resolution


wildcard_constraints:
    name="|".join(CAPTIONS),
    word="[BT]+",
    vary="s|F",
    sweep="|".join(list(config["sweeps"]["scenes"]) + ["study_s"]),
    basin="|".join(config["basins"]),
    map="|".join(list(config["maps"]) + list(config["bifurcation"].get("maps", {}))),
    beta=r"[0-9.]+",
    r=r"[0-9.]+",
    scene="|".join(SCENES),


def caption_params(name):
    """Everything a caption run needs, from the config (physics + the caption's own values)."""
    c = CAPTIONS[name]
    ph = config["physics"]
    return dict(
        name=name,
        d=c["d"],
        gbar=CFG.device.gbar(c["beta"], c.get("F", ph["F"])),
        F=c.get("F", ph["F"]),
        omega=c.get("omega", ph["omega"]),
        period=c.get("period", 0),
        beta=c["beta"],
        r=ph["r"],
        phi=c["phi"],
        v0=c["v0"],
        motion=c["motion"],
        grazing=c.get("grazing", False),
        beta_assumed=c.get("beta_assumed", False),
        tol=config["attractor"]["tol"],
        max_events=config["attractor"]["max_events"],
        samples_per_unit=RESOLUTION["samples_per_unit"],
        t_show=(
            max(s["t_show"] for s in config["scenes"].values() if name in s["captions"])
            if any(name in s["captions"] for s in config["scenes"].values())
            else 4.0
        ),
    )


# ---- branches ----------------------------------------------------------------------------------
BRANCH_SCENES = CFG.branch_scenes
WORDS = CFG.words


def fmt(x):
    """Path form of a parameter value (4 decimals), e.g. beta-0.5236."""
    return f"{x:.4f}"


def beta_value(key):
    """Exact beta (rad) for its path form, from every incline the config names."""
    betas = [b for s in BRANCH_SCENES.values() for b in s["betas"]]
    betas += [s["grazing"]["beta"] for s in BRANCH_SCENES.values() if "grazing" in s]
    betas += [s["beta"] for s in config["sweeps"]["scenes"].values()]
    betas += [s["beta"] for s in config["basins"].values()] + [
        c["beta"] for c in CAPTIONS.values()
    ]
    betas += [st["beta"] for st in config.get("studies", [])]
    betas.append(math.pi / 3)  # Figure 2's 1:1 branch
    for b in betas:
        if fmt(b) == key:
            return b
    raise ValueError(
        f"beta {key} is not among the configured betas {sorted({fmt(b) for b in betas})}"
    )


#: every branch a rule names (its incline, word and parameter varied -> whether its simulated attractors are
#: named too), in the order named: an incline's computed together by one job (workflow/rules/branch_batch.smk)
NAMED_BRANCHES = {}


def branch_job(beta, r, word, vary):
    """What the branch job of an incline, restitution (path forms), word and parameter varied computes."""
    b, rr = beta_value(beta), r_value(r)
    return dict(
        beta=b,
        device=DEVICE_SPEC,
        r=rr,
        word=word,
        vary=vary,
        spec=WORDS[word],
        # branches.d_range and .force, widened to the d every figure draws these branches over
        d_range=CFG.branch_d_range(b, rr),
        force=CFG.branch_force(b),
        step=RESOLUTION["branch_step"],
    )


def batch_rule(beta_key):
    """The name of the rule of an incline's branches (workflow/rules/branch_batch.smk), e.g. branches_1_0472."""
    return f"branches_{beta_key.replace('.', '_')}"


def branch_path(kind, beta, word, vary="s"):
    r = fmt(config["physics"]["r"])
    key = (fmt(beta), word, vary)
    NAMED_BRANCHES[key] = NAMED_BRANCHES.get(key, False) or kind == "sim"
    return f"results/branches/beta-{fmt(beta)}_r-{r}/{kind}-{word}_vary-{vary}.nc"


def scene_branch_files(scene, kind="orbit"):
    s = BRANCH_SCENES[scene]
    files = [branch_path(kind, b, s["word"]) for b in s["betas"]]
    if "grazing" in s:
        files.append(branch_path(kind, s["grazing"]["beta"], s["grazing"]["word"]))
    return files


# ---- sweeps ------------------------------------------------------------------------------------
SWEEPS = CFG.sweeps

#: the regime maps (config maps) and the bifurcation set's own non-dimensional planes (bifurcation.maps)
ALL_MAPS = CFG.maps


def sweep_path(name, suffix=""):
    sc = SWEEPS[name]
    return f"results/sweeps/beta-{fmt(sc['beta'])}_r-{fmt(config['physics']['r'])}/{name}{suffix}.nc"


def basin_path(name):
    return f"results/basins/beta-{fmt(config['basins'][name]['beta'])}_r-{fmt(config['physics']['r'])}/{name}.nc"


def map_path(name):
    return f"results/maps/{name}_r-{fmt(config['physics']['r'])}.nc"


#: the sweeps the paper's d_graz is read along (its table and the check): each incline's length and force sweep
D_GRAZ_SWEEPS = list(d_graz_sweeps(config))


# ---- energy ------------------------------------------------------------------------------------
def energy_path(kind, beta, name, vary=None):
    r = fmt(config["physics"]["r"])
    if kind == "branch":  # a branch's energy is written by the branch's job
        NAMED_BRANCHES.setdefault((fmt(beta), name, vary), False)
    stem = f"orbit-{name}_vary-{vary}" if kind == "branch" else name
    return f"results/energy/beta-{fmt(beta)}_r-{r}/{stem}.nc"


def energy_panel_inputs(sweep_name):
    """A sweep's energy and the energies of the 1:1 and 2:1 branches at its incline and parameterisation."""
    sc = SWEEPS[sweep_name]
    return [energy_path("sweep", sc["beta"], sweep_name)] + [
        energy_path("branch", sc["beta"], w, sc["vary"])
        for w in ("BT", "BBT")
        if w in WORDS
    ]


# ---- studies: new beta or r beside the defaults ------------------------------------------------
STUDIES = CFG.studies


def r_value(key):
    """Exact restitution for its path form: the physics' r or a study's."""
    for r in [config["physics"]["r"]] + [st["r"] for st in STUDIES]:
        if fmt(r) == key:
            return r
    raise ValueError(f"r {key} is neither physics.r nor a study's r")


def study_dir(st):
    return f"results/studies/beta-{fmt(st['beta'])}_r-{fmt(st['r'])}"


def study_figure(st):
    return os.path.join(study_dir(st), "study.png")


def study_for(beta_key, r_key):
    for st in STUDIES:
        if fmt(st["beta"]) == beta_key and fmt(st["r"]) == r_key:
            return st
    raise ValueError(f"no study with beta-{beta_key}_r-{r_key} in the config")


def sweep_scene(wc):
    if (
        wc.sweep == "study_s"
    ):  # a study's length sweep: its beta and r come from the path
        st = study_for(wc.beta, wc.r)
        start = config["study_defaults"]
        return dict(
            beta=st["beta"],
            vary="s",
            range=st.get("s_range", start["s_range"]),
            F=config["physics"]["F"],
            phi=st.get("phi", start["phi"]),
            v0=st.get("v0", start["v0"]),
        )
    sc = SWEEPS[wc.sweep]
    if wc.beta != fmt(sc["beta"]) or wc.r != fmt(config["physics"]["r"]):
        raise ValueError(
            f"sweep {wc.sweep}: the path's beta-{wc.beta}_r-{wc.r} does not match the config"
        )
    return sc


def sweep_branches(wc):
    """The 1:1 and 2:1 branches at a sweep's incline and restitution, continued in its swept parameter."""
    vary = sweep_scene(wc)["vary"]
    return [
        f"results/branches/beta-{wc.beta}_r-{wc.r}/orbit-{w}_vary-{vary}.nc"
        for w in ("BT", "BBT")
        if w in WORDS
    ]


#: every figure whose plotted data the `check` target compares with its committed reference, and the ones
#: figure_checks.figures chooses
ALL_FIGURES = CFG.all_figures
FIGURES = CFG.figures


# ---- the registry of figures (vibroimpact.outputs.registry): targets, captions, the generic rule ------------
from vibroimpact.outputs import registry


def figure_targets(target, formats=None):
    """The files of the registry's figures a target draws (``all``, ``bifurcation``, ``design_maps``): each
    figure in the quality preset's ``figure_formats`` (or ``formats``)."""
    return [
        f"results/figures/{f.stem}.{ext}"
        for f in registry.figures(config, target=target, paper_device=CFG.paper_device)
        for ext in (formats or RESOLUTION["figure_formats"])
    ]


def figure_caption(rule_name):
    """The report caption (relative to the rule files) of the figures a rule draws, from the registry."""
    captions = {f.caption for f in registry.REGISTRY if f.rule == rule_name}
    if len(captions) != 1:
        raise ValueError(
            f"the registry gives the figures of {rule_name} the captions {sorted(captions)}, not one"
        )
    return f"../report/{captions.pop()}"


def figure_category(rule_name):
    """The report category of the figures a rule draws, from the registry."""
    return next(f.category for f in registry.REGISTRY if f.rule == rule_name)


#: the figures the generic rule `registry_figure` draws (the rows whose rule it is)
REGISTRY_FIGURES = {
    f.stem: f for f in registry.figures(config) if f.rule == "registry_figure"
}


def figure_reference(fig):
    """The committed reference of a figure's data."""
    return f"{config['figure_checks']['reference_dir']}/{fig}.nc"


# ---- the report's captions: each figure's check result, from the last `check` run -------------------
def _check_summaries():
    import pandas as pd

    from vibroimpact.outputs.checks import check_summaries

    read = lambda f: pd.read_csv(f) if os.path.exists(f) else None
    return check_summaries(
        read("results/checks/paper_values.csv"), read("results/checks/figures.csv")
    )


# read by workflow/report/*.rst when `snakemake --report` renders the captions; not a setting
config["_check_results"] = _check_summaries()

# read by workflow/report/*.rst too: the number the published paper prints for each of its figures (from the
# registry of figures)
from vibroimpact.outputs.paper import FIGURE_NUMBERS

config["_figure_numbers"] = FIGURE_NUMBERS


def _registry_captions():
    """The captions of the figures the generic rule draws, rendered from their templates as the documentation
    renders them (the report's `registry_figure.rst` shows them)."""
    report_dir = os.path.join(workflow.basedir, "workflow", "report")
    return {
        stem: registry.render_caption(report_dir, f, config["_check_results"])
        for stem, f in REGISTRY_FIGURES.items()
    }


# read by workflow/report/registry_figure.rst: not a setting
config["_registry_captions"] = _registry_captions()


def figure_formats(stem):
    """A figure's outputs besides its PNG: the quality preset's other ``figure_formats`` (PDF at paper
    quality; the draft preset writes the PNG only, a quicker look)."""
    return {f: f"{stem}.{f}" for f in RESOLUTION["figure_formats"] if f != "png"}


# ---- design under multistability ----------------------------------------------------------------
DESIGN = config["design"]


def design_chunks(name):
    """The chunk files of a design map: consecutive blocks of its grid rows, one job each."""
    return [
        f"results/design/{name}/chunk-{i}.nc"
        for i in range(RESOLUTION["design"]["chunks"])
    ]
