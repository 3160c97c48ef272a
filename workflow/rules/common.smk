# Shared helpers: config checks that a schema cannot express, and parameter lookups.
import math
import os

from vibroimpact._code_version import code_version


def code(script=None):
    """A rule's `code` parameter: a hash of the package sources workflow/scripts/<script> depends on
    (of the whole package without a script), so that its jobs rerun when they change."""
    return code_version(
        script and os.path.join(workflow.basedir, "workflow", "scripts", script)
    )


def _fail(key, value, allowed):
    raise ValueError(f"config: {key} = {value!r} is not allowed; allowed: {allowed}")


def _check_range(key, value, what="[low, high] with low < high"):
    """A range of two numbers, increasing (a reversed or empty range is refused)."""
    if len(value) != 2 or not value[0] < value[1]:
        _fail(key, list(value), what)


CAPTIONS = config["captions"]
SCENES = list(config["scenes"])
QUALITY = config["quality"]
RESOLUTION = config["resolution"][QUALITY]

for _scene, _spec in config["scenes"].items():
    for _name in _spec["captions"]:
        if _name not in CAPTIONS:
            _fail(
                f"scenes.{_scene}.captions",
                _name,
                f"a caption defined under 'captions': {sorted(CAPTIONS)}",
            )


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
        gbar=ph["M"] * ph["g"] * math.sin(c["beta"]) / c.get("F", ph["F"]),
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
BRANCH_SCENES = config["branch_scenes"]
WORDS = config["branches"]["words"]


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
    betas.append(math.pi / 3)  # Fig 0's 1:1 branch
    for b in betas:
        if fmt(b) == key:
            return b
    raise ValueError(
        f"beta {key} is not among the configured betas {sorted({fmt(b) for b in betas})}"
    )


def branch_path(kind, beta, word, vary="s"):
    r = fmt(config["physics"]["r"])
    return f"results/branches/beta-{fmt(beta)}_r-{r}/{kind}-{word}_vary-{vary}.nc"


def scene_branch_files(scene, kind="orbit"):
    s = BRANCH_SCENES[scene]
    files = [branch_path(kind, b, s["word"]) for b in s["betas"]]
    if "grazing" in s:
        files.append(branch_path(kind, s["grazing"]["beta"], s["grazing"]["word"]))
    return files


for _scene, _spec in BRANCH_SCENES.items():
    if len(_spec["betas"]) != len(_spec["s_ranges"]):
        _fail(
            f"branch_scenes.{_scene}.s_ranges",
            _spec["s_ranges"],
            "one [s_min, s_max] per beta",
        )
    for _i, _r in enumerate(_spec["s_ranges"]):
        _check_range(
            f"branch_scenes.{_scene}.s_ranges[{_i}]",
            _r,
            "[s_min, s_max] with s_min < s_max",
        )
    for _w in [_spec["word"]] + (
        [_spec["grazing"]["word"]] if "grazing" in _spec else []
    ):
        if _w not in WORDS:
            _fail(
                f"branch_scenes.{_scene}.word",
                _w,
                f"a word defined under branches.words: {sorted(WORDS)}",
            )


_lo, _hi = config["branches"]["d_range"]
_check_range("branches.d_range", [_lo, _hi], "[d_min, d_max] with d_min < d_max")
_check_range(
    "branches.force.F_range",
    config["branches"]["force"]["F_range"],
    "[F_min, F_max] with F_min < F_max",
)
for _name, _b in config["basins"].items():
    for _k in ("phi_range", "v0_range"):
        if _k in _b:
            _check_range(f"basins.{_name}.{_k}", _b[_k])
for _w, _spec in WORDS.items():
    if not _lo < _spec["start_d"] < _hi:
        _fail(
            f"branches.words.{_w}.start_d",
            _spec["start_d"],
            f"inside branches.d_range = {[_lo, _hi]}",
        )


# ---- sweeps ------------------------------------------------------------------------------------
SWEEPS = config["sweeps"]["scenes"]

for _name, _sc in SWEEPS.items():
    _fixed = "s" if _sc["vary"] == "F" else "F"
    if _fixed not in _sc:
        _fail(
            f"sweeps.scenes.{_name}.{_fixed}",
            None,
            f"a value: a sweep of {_sc['vary']} needs the fixed {'length s (m)' if _fixed == 's' else 'force F (N)'}",
        )
    if _sc["vary"] in _sc:
        _fail(
            f"sweeps.scenes.{_name}.{_sc['vary']}",
            _sc[_sc["vary"]],
            f"nothing: {_sc['vary']} is the swept parameter (see range)",
        )
    if not _sc["range"][0] < _sc["range"][1]:
        _fail(
            f"sweeps.scenes.{_name}.range", _sc["range"], "[low, high] with low < high"
        )
# the regime maps (config maps) and the bifurcation set's own non-dimensional planes (bifurcation.maps)
ALL_MAPS = dict(config["maps"]) | dict(config["bifurcation"].get("maps", {}))
if set(config["maps"]) & set(config["bifurcation"].get("maps", {})):
    _fail(
        "bifurcation.maps",
        sorted(set(config["maps"]) & set(config["bifurcation"]["maps"])),
        "names not already used by maps",
    )
for _name, _m in ALL_MAPS.items():
    _key = f"maps.{_name}" if _name in config["maps"] else f"bifurcation.maps.{_name}"
    _phys = _name in config["maps"]
    _axes = ("s", "F", "beta") if _phys else ("d", "gbar", "r")
    if _m["x"] == _m["y"]:
        _fail(
            f"{_key}.y",
            _m["y"],
            f"an axis different from x = {_m['x']!r} (one of {', '.join(_axes)})",
        )
    for _axis in ("x", "y"):
        if _m[_axis] not in _axes:
            _fail(
                f"{_key}.{_axis}",
                _m[_axis],
                f"one of {', '.join(_axes)}"
                + (
                    ""
                    if _phys
                    else " (the regime maps take the physical axes; these planes the non-dimensional ones)"
                ),
            )
        if _m[_axis] in _m:
            _fail(
                f"{_key}.{_m[_axis]}",
                _m[_m[_axis]],
                f"nothing: {_m[_axis]} is the map's {_axis} axis",
            )
        if not _m[f"{_axis}_range"][0] < _m[f"{_axis}_range"][1]:
            _fail(
                f"{_key}.{_axis}_range",
                _m[f"{_axis}_range"],
                "[low, high] with low < high",
            )
    if not _phys and set(_m) & {"s", "F", "beta"}:
        _fail(
            f"{_key}.{sorted(set(_m) & {'s', 'F', 'beta'})[0]}",
            _m[sorted(set(_m) & {"s", "F", "beta"})[0]],
            "nothing: a non-dimensional plane takes its fixed parameter from the physics at bifurcation.beta",
        )


def sweep_path(name, suffix=""):
    sc = SWEEPS[name]
    return f"results/sweeps/beta-{fmt(sc['beta'])}_r-{fmt(config['physics']['r'])}/{name}{suffix}.nc"


def basin_path(name):
    return f"results/basins/beta-{fmt(config['basins'][name]['beta'])}_r-{fmt(config['physics']['r'])}/{name}.nc"


def map_path(name):
    return f"results/maps/{name}_r-{fmt(config['physics']['r'])}.nc"


if "figBiS" in SWEEPS and "figBiS" not in config["basins"]:
    _fail(
        "basins.figBiS",
        None,
        "an entry with the bistable point d where Fig BiS draws both motions",
    )
if "figBiS" in SWEEPS and not {"BBT", "BBBT"} <= set(WORDS):
    _fail("branches.words", sorted(WORDS), "BBT and BBBT, which Fig BiS draws")


def length_sweeps(betas):
    """The widest sweep of s at the physics' force for each incline (Fig 5's (a)-(d)), where there is one."""
    found = {}
    for name, sc in SWEEPS.items():
        if (
            sc["vary"] != "s"
            or sc.get("F", config["physics"]["F"]) != config["physics"]["F"]
        ):
            continue
        for b in betas:
            width = sc["range"][1] - sc["range"][0]
            if abs(sc["beta"] - b) < 1e-9 and width > found.get(b, ("", -1.0))[1]:
                found[b] = (name, width)
    return {b: name for b, (name, _) in found.items()}


# ---- energy ------------------------------------------------------------------------------------
def energy_path(kind, beta, name, vary=None):
    r = fmt(config["physics"]["r"])
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


for _fig, _spec in config["energy"]["figures"].items():
    for _p in _spec["panels"]:
        if _p not in SWEEPS:
            _fail(
                f"energy.figures.{_fig}.panels",
                _p,
                f"a sweep under sweeps.scenes: {sorted(SWEEPS)}",
            )
for _p in config["chaos"]["panels"]:
    if _p not in SWEEPS:
        _fail("chaos.panels", _p, f"a sweep under sweeps.scenes: {sorted(SWEEPS)}")
for _v in ("s", "F"):
    for _p in config["energy"]["design"][_v]:
        if _p not in SWEEPS or SWEEPS[_p]["vary"] != _v:
            _fail(
                f"energy.design.{_v}",
                _p,
                f"a sweep under sweeps.scenes with vary: {_v}",
            )


# ---- studies: new beta or r beside the defaults ------------------------------------------------
STUDIES = config.get("studies", []) or []

_check_range(
    "study_defaults.s_range",
    config["study_defaults"]["s_range"],
    "[s_min, s_max] with s_min < s_max",
)
_seen_studies = {}
for _i, _st in enumerate(STUDIES):
    if "s_range" in _st:
        _check_range(
            f"studies[{_i}].s_range",
            _st["s_range"],
            "[s_min, s_max] with s_min < s_max (m)",
        )
    _key = f"beta-{_st['beta']:.4f}_r-{_st['r']:.4f}"
    if _key in _seen_studies:
        _j = _seen_studies[_key]
        _fail(
            f"studies[{_i}]",
            _st,
            f"a study of its own (beta, r): it repeats studies[{_j}] = {STUDIES[_j]!r} (both would write "
            f"results/studies/{_key}; beta and r are told apart to 4 decimals)",
        )
    _seen_studies[_key] = _i
    if not _st["r"] > 0:
        _fail(
            f"studies[{_i}].r",
            _st["r"],
            "r > 0 (with r = 0 the ball never rebounds: every impact ends at rest on the wall, so no impact "
            "orbit exists and no branch can start)",
        )
    # the ball must be able to leave the bottom membrane, or no orbit (and no branch) can start
    _gbar = (
        config["physics"]["M"]
        * config["physics"]["g"]
        * math.sin(_st["beta"])
        / config["physics"]["F"]
    )
    if _gbar >= 1:
        _fail(
            f"studies[{_i}].beta",
            _st["beta"],
            f"an incline with gbar = M g sin(beta) / F < 1 (here {_gbar:.4g}: the forcing can never lift the ball "
            "off the bottom membrane, so no impact orbit exists and no branch can start)",
        )


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


# ---- checks: the known discrepancies must name items the check produces -------------------------
def _check_items():
    from vibroimpact.outputs.checks import item_names

    betas = sorted({b for sc in BRANCH_SCENES.values() for b in sc["betas"]})
    return item_names(list(CAPTIONS), betas)


for _item in config["checks"]["known"]:
    if _item not in _check_items():
        _fail(
            "checks.known", _item, f"an item of the paper-value check: {_check_items()}"
        )


#: every figure whose plotted data the `check` target compares with its committed reference
ALL_FIGURES = (
    list(SCENES)
    + list(BRANCH_SCENES)
    + ["figBiS", "basins", "regime_map"]
    + list(config["energy"]["figures"])
    + ["lyapunov"]
    + ["design", "work_precision", "failure_map", "analytics_accuracy"]
    + [f"bifurcation_set_{m}" for m in ALL_MAPS]
    + [f"design_map_{m}" for m in config["design"]["maps"]]
)
# figure_checks.figures: every figure ("all"), or the ones a list names (e.g. while working on one)
_chosen = config["figure_checks"].get("figures", "all")
if _chosen != "all":
    for _f in _chosen:
        if _f not in ALL_FIGURES:
            _fail(
                "figure_checks.figures",
                _f,
                f"'all' or a list of figures of {ALL_FIGURES}",
            )
FIGURES = ALL_FIGURES if _chosen == "all" else list(_chosen)


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

# read by workflow/report/*.rst too: the number the published paper prints for each of its figures
from vibroimpact.outputs.paper import FIGURE_NUMBERS

config["_figure_numbers"] = FIGURE_NUMBERS


def figure_formats(stem):
    """A figure's outputs besides its PNG: the quality preset's other ``figure_formats`` (PDF at paper
    quality; the draft preset writes the PNG only, a quicker look)."""
    return {f: f"{stem}.{f}" for f in RESOLUTION["figure_formats"] if f != "png"}


# ---- design under multistability: value ranges and cross-key conditions, before any job --------------
from vibroimpact.analysis.design import check_design

DESIGN = config["design"]
try:
    check_design(
        DESIGN,
        {q: config["resolution"][q]["design"] for q in config["resolution"]},
        config["maps"],
    )
except ValueError as err:
    raise ValueError(f"config: {err}") from None


def design_chunks(name):
    """The chunk files of a design map: consecutive blocks of its grid rows, one job each."""
    return [
        f"results/design/{name}/chunk-{i}.nc"
        for i in range(RESOLUTION["design"]["chunks"])
    ]
