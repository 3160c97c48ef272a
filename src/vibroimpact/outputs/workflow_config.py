"""The workflow's configuration, checked as a whole and typed.

``config/schema.yaml`` checks each value on its own (types, ranges, enums); :func:`check` checks what a
schema cannot express, across keys (a scene's caption must exist, a range must increase, a sweep of F
needs its fixed s, a map's axes differ, ...), before any job runs, and returns a :class:`WorkflowConfig`
that the rule files read instead of raw keys.  Every refusal names the key, the value and what is allowed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..analysis.design import DESIGN_AXES, DISTRIBUTIONS, MIN_STARTS, RELATIVE, start_states
from ..dynamics.device import Device
from .checks import item_names

__all__ = ["ConfigError", "WorkflowConfig", "check", "check_design", "figure_names"]


class ConfigError(ValueError):
    """A config value that is not allowed: its key, the value and what is allowed."""

    def __init__(self, key: str, value, allowed: str):
        self.key, self.value, self.allowed = key, value, allowed
        super().__init__(f"config: {key} = {value!r} is not allowed; allowed: {allowed}")


def _range(key, value, what="[low, high] with low < high"):
    """A range of two numbers, increasing (a reversed or empty range is refused)."""
    if len(value) != 2 or not value[0] < value[1]:
        raise ConfigError(key, list(value), what)


@dataclass(frozen=True)
class WorkflowConfig:
    """What the rule files need of a checked config.

    Attributes
    ----------
    device : Device
        The harvester (physics and membrane; named ``paper`` when it is the paper's device).
    paper_device : bool
        Whether it is the paper's device: the checks against the paper's numbers and the committed figure
        references apply to it only.
    results_dir : str
        Where the workflow writes (relative to the repository): ``.`` for the paper's device,
        ``results/devices/<name>`` for another.
    quality : str
        The resolution preset's name; ``resolution`` its values.
    resolution : dict
        The preset's values.
    captions, scenes, branch_scenes, words, sweeps, maps, studies
        The config's sections (``maps``: the regime maps and the bifurcation set's own planes; ``sweeps``: each
        sweep of s with its force, the physics' where it gives none).
    figures : list of str
        The figures the figure check compares (``figure_checks.figures``).
    all_figures : list of str
        Every figure the workflow draws whose arrays are checked.
    """

    device: Device
    paper_device: bool
    results_dir: str
    quality: str
    resolution: dict
    captions: dict
    scenes: list
    branch_scenes: dict
    words: dict
    sweeps: dict
    maps: dict
    studies: list
    figures: list
    all_figures: list = field(default_factory=list)

    def device_spec(self) -> dict:
        """The device as a rule parameter (``Device.from_config(**spec)`` rebuilds it in a job)."""
        return dict(physics=self.device.physics(), membrane=vars(self.device.membrane).copy(), name=self.device.name)


def check(config: dict) -> WorkflowConfig:
    """Check a schema-valid config across keys and type it.

    Raises
    ------
    ConfigError
        The first value not allowed, with its key and what is allowed.
    """
    device = _device(config)
    _captions_and_scenes(config)
    _branches(config)
    _sweeps_and_maps(config)
    _energy(config)
    _studies(config)
    check_design(config["design"], {q: config["resolution"][q]["design"] for q in config["resolution"]},
                 config["maps"])
    _lift(config, device)
    paper = device.same_physics(Device())
    if paper:  # the known discrepancies are the paper's device's: another device's check does not read them
        _known(config)
    all_maps = dict(config["maps"]) | dict(config["bifurcation"].get("maps", {}))
    figures = figure_names(config, all_maps)
    chosen = config["figure_checks"].get("figures", "all")
    if chosen != "all":
        for f in chosen:
            if f not in figures:
                raise ConfigError("figure_checks.figures", f, f"'all' or a list of figures of {figures}")
    return WorkflowConfig(
        device=device, paper_device=paper, results_dir="." if paper else f"results/devices/{device.name}",
        quality=config["quality"], resolution=config["resolution"][config["quality"]], captions=config["captions"],
        scenes=list(config["scenes"]), branch_scenes=config["branch_scenes"], words=config["branches"]["words"],
        sweeps={n: _at_force(sc, config["physics"]["F"]) for n, sc in config["sweeps"]["scenes"].items()}, maps=all_maps, studies=list(config.get("studies") or []),
        figures=figures if chosen == "all" else list(chosen), all_figures=figures)


def _at_force(scene: dict, F: float) -> dict:
    """A sweep with its fixed force: a sweep of s that gives none is at the physics' force ``F``."""
    if scene["vary"] != "s" or "F" in scene:
        return scene
    keys = list(scene)
    keys.insert(keys.index("range") + 1 if "range" in keys else len(keys), "F")
    return {k: F if k == "F" else scene[k] for k in keys}


def _device(config) -> Device:
    name, mem = config.get("device"), config["membrane"]
    if not mem["R"] > mem["r_b"]:
        raise ConfigError("membrane.R", mem["R"], f"a radius > membrane.r_b = {mem['r_b']!r} m: the ball presses into "
                          "the membrane's active area (the energy model's stretched cap has no solution otherwise)")
    try:
        dev = Device.from_config(config["physics"], config["membrane"], name)
    except ValueError as err:
        raise ConfigError("physics / membrane", {**config["physics"], **config["membrane"]}, str(err)) from None
    if name == "paper" and not dev.same_physics(Device()):
        raise ConfigError("device", name, "another name: 'paper' is the paper's device, whose physics and membrane "
                          "these are not (its results would be written over the paper's)")
    return dev


def _captions_and_scenes(config):
    for scene, spec in config["scenes"].items():
        for name in spec["captions"]:
            if name not in config["captions"]:
                raise ConfigError(f"scenes.{scene}.captions", name,
                                  f"a caption defined under 'captions': {sorted(config['captions'])}")


def _branches(config):
    words = config["branches"]["words"]
    for scene, spec in config["branch_scenes"].items():
        if len(spec["betas"]) != len(spec["s_ranges"]):
            raise ConfigError(f"branch_scenes.{scene}.s_ranges", spec["s_ranges"], "one [s_min, s_max] per beta")
        for i, r in enumerate(spec["s_ranges"]):
            _range(f"branch_scenes.{scene}.s_ranges[{i}]", r, "[s_min, s_max] with s_min < s_max")
        if "grazing" in spec and not any(abs(spec["grazing"]["beta"] - b) < 1e-9 for b in spec["betas"]):
            raise ConfigError(f"branch_scenes.{scene}.grazing.beta", spec["grazing"]["beta"],
                              f"one of the scene's betas {spec['betas']} (its G1 and G2 lines are drawn in that row)")
        for w in [spec["word"]] + ([spec["grazing"]["word"]] if "grazing" in spec else []):
            if w not in words:
                raise ConfigError(f"branch_scenes.{scene}.word", w, f"a word defined under branches.words: {sorted(words)}")
    lo, hi = config["branches"]["d_range"]
    _range("branches.d_range", [lo, hi], "[d_min, d_max] with d_min < d_max")
    _range("branches.force.F_range", config["branches"]["force"]["F_range"], "[F_min, F_max] with F_min < F_max")
    for name, b in config["basins"].items():
        for k in ("phi_range", "v0_range"):
            if k in b:
                _range(f"basins.{name}.{k}", b[k])
    for w, spec in words.items():
        if not lo < spec["start_d"] < hi:
            raise ConfigError(f"branches.words.{w}.start_d", spec["start_d"], f"inside branches.d_range = {[lo, hi]}")
    if not set(config["bifurcation"]["words"]) <= set(words):
        raise ConfigError("bifurcation.words", config["bifurcation"]["words"],
                          f"words of branches.words ({', '.join(words)})")


def _sweeps_and_maps(config):
    sweeps = config["sweeps"]["scenes"]
    with_branches = {p for f in config["energy"]["figures"].values() for p in f["panels"]}
    with_branches |= set(config["chaos"]["panels"]) | {"figBiS"}
    for name, sc in sweeps.items():
        if sc["vary"] == "F" and "s" not in sc:
            raise ConfigError(f"sweeps.scenes.{name}.s", None, "a value: a sweep of F needs the fixed length s (m)")
        F = config["physics"]["F"]
        if sc["vary"] == "s" and sc.get("F", F) != F and name in with_branches:
            raise ConfigError(f"sweeps.scenes.{name}.F", sc["F"], f"none (the sweep is then at physics.F = {F:g} N) "
                              f"or physics.F: a figure draws this sweep with the analytic branches, continued at physics.F")
        if sc["vary"] in sc:
            raise ConfigError(f"sweeps.scenes.{name}.{sc['vary']}", sc[sc["vary"]],
                              f"nothing: {sc['vary']} is the swept parameter (see range)")
        _range(f"sweeps.scenes.{name}.range", sc["range"])
    bif_maps = config["bifurcation"].get("maps", {})
    if set(config["maps"]) & set(bif_maps):
        raise ConfigError("bifurcation.maps", sorted(set(config["maps"]) & set(bif_maps)), "names not already used by maps")
    for name, m in (dict(config["maps"]) | dict(bif_maps)).items():
        physical = name in config["maps"]
        key = f"maps.{name}" if physical else f"bifurcation.maps.{name}"
        axes = ("s", "F", "beta") if physical else ("d", "gbar", "r")
        if m["x"] == m["y"]:
            raise ConfigError(f"{key}.y", m["y"], f"an axis different from x = {m['x']!r} (one of {', '.join(axes)})")
        for axis in ("x", "y"):
            if m[axis] not in axes:
                raise ConfigError(f"{key}.{axis}", m[axis], f"one of {', '.join(axes)}" + (
                    "" if physical else " (the regime maps take the physical axes; these planes the non-dimensional ones)"))
            if m[axis] in m:
                raise ConfigError(f"{key}.{m[axis]}", m[m[axis]], f"nothing: {m[axis]} is the map's {axis} axis")
            _range(f"{key}.{axis}_range", m[f"{axis}_range"])
        held = sorted(set(m) & {"s", "F", "beta"})
        if not physical and held:
            raise ConfigError(f"{key}.{held[0]}", m[held[0]], "nothing: a non-dimensional plane takes its fixed "
                              "parameter from the physics at bifurcation.beta")
    if "figBiS" in sweeps and "figBiS" not in config["basins"]:
        raise ConfigError("basins.figBiS", None, "an entry with the bistable point d where Figure 8 draws both motions")
    if "figBiS" in sweeps and not {"BBT", "BBBT"} <= set(config["branches"]["words"]):
        raise ConfigError("branches.words", sorted(config["branches"]["words"]), "BBT and BBBT, which Figure 8 draws")


def _energy(config):
    sweeps = config["sweeps"]["scenes"]
    for fig, spec in config["energy"]["figures"].items():
        for p in spec["panels"]:
            if p not in sweeps:
                raise ConfigError(f"energy.figures.{fig}.panels", p, f"a sweep under sweeps.scenes: {sorted(sweeps)}")
    for p in config["chaos"]["panels"]:
        if p not in sweeps:
            raise ConfigError("chaos.panels", p, f"a sweep under sweeps.scenes: {sorted(sweeps)}")
    for v in ("s", "F"):
        for p in config["energy"]["design"][v]:
            if p not in sweeps or sweeps[p]["vary"] != v:
                raise ConfigError(f"energy.design.{v}", p, f"a sweep under sweeps.scenes with vary: {v}")


def _studies(config):
    _range("study_defaults.s_range", config["study_defaults"]["s_range"], "[s_min, s_max] with s_min < s_max")
    studies = list(config.get("studies") or [])
    seen = {}
    ph = config["physics"]
    for i, st in enumerate(studies):
        if "s_range" in st:
            _range(f"studies[{i}].s_range", st["s_range"], "[s_min, s_max] with s_min < s_max (m)")
        key = f"beta-{st['beta']:.4f}_r-{st['r']:.4f}"
        if key in seen:
            j = seen[key]
            raise ConfigError(f"studies[{i}]", st, f"a study of its own (beta, r): it repeats studies[{j}] = "
                              f"{studies[j]!r} (both would write results/studies/{key}; beta and r are told apart to "
                              "4 decimals)")
        seen[key] = i
        if not st["r"] > 0:
            raise ConfigError(f"studies[{i}].r", st["r"], "r > 0 (with r = 0 the ball never rebounds: every impact "
                              "ends at rest on the wall, so no impact orbit exists and no branch can start)")
        gbar = ph["M"] * ph["g"] * math.sin(st["beta"]) / ph["F"]
        if gbar >= 1:
            raise ConfigError(f"studies[{i}].beta", st["beta"], f"an incline with gbar = M g sin(beta) / F < 1 (here "
                              f"{gbar:.4g}: the forcing can never lift the ball off the bottom membrane, so no impact "
                              "orbit exists and no branch can start)")


def _lift(config, device: Device):
    """Refuse a scene at an incline where the forcing can never lift the ball off the bottom membrane.

    With ``gbar = M g sin(beta) / F >= 1`` the ball rests on the bottom for good: no impact orbit, branch or
    motion exists there.  Every scene at one incline and force is checked: captions, branch scenes, sweeps (a
    sweep of F at the lowest force of its range; the force branches at theirs) and basins.  The regime maps span
    planes in which such a region is a regime of its own: they run and record it (at rest for good).
    """
    ph, force = config["physics"], config["branches"]["force"]
    scenes = [(f"captions.{n}.beta", c["beta"], c.get("F", ph["F"]), f"captions.{n}.F" if "F" in c else "physics.F")
              for n, c in config["captions"].items()]
    for name, sc in config["branch_scenes"].items():
        scenes += [(f"branch_scenes.{name}.betas[{i}]", b, ph["F"], "physics.F") for i, b in enumerate(sc["betas"])]
        if "grazing" in sc:
            scenes.append((f"branch_scenes.{name}.grazing.beta", sc["grazing"]["beta"], ph["F"], "physics.F"))
    for name, sc in config["sweeps"]["scenes"].items():
        key = f"sweeps.scenes.{name}"
        if sc["vary"] == "s":
            scenes.append((f"{key}.beta", sc["beta"], sc.get("F", ph["F"]), f"{key}.F" if "F" in sc else "physics.F"))
        else:  # the lowest force of the sweep and of the force branches drawn with it
            scenes.append((f"{key}.beta", sc["beta"], min(sc["range"]), f"the lowest force of {key}.range"))
            scenes.append((f"{key}.beta", sc["beta"], min(force["F_range"]), "the lowest force of branches.force.F_range"))
    scenes += [(f"basins.{n}.beta", b["beta"], ph["F"], "physics.F") for n, b in config["basins"].items()]
    for key, beta, F, source in scenes:
        gbar = device.gbar(beta, F)
        if gbar >= 1:
            weight = device.M * device.g
            raise ConfigError(key, beta, f"an incline where the forcing can lift the ball off the bottom membrane, gbar = "
                              f"M g sin(beta) / F < 1 (here {gbar:.4g} at F = {F:g} N, {source}: the ball rests on the "
                              f"bottom for good, no impact motion exists): sin(beta) < {F / weight:.4g}, or a force "
                              f"F > M g sin(beta) = {weight * math.sin(beta):.4g} N")


def d_graz_sweeps(config: dict) -> dict[str, dict]:
    """The sweeps the paper's d_graz is read along (its table and the check's rows): every incline's length and
    force sweep (``energy.design``), by name, each its scene (``sweeps.scenes``)."""
    return {p: config["sweeps"]["scenes"][p] for v in ("s", "F") for p in config["energy"]["design"][v]}


def _known(config):

    betas = sorted({b for sc in config["branch_scenes"].values() for b in sc["betas"]})
    items = item_names(list(config["captions"]), betas, d_graz_sweeps(config))
    for item in config["checks"]["known"]:
        if item not in items:
            raise ConfigError("checks.known", item, f"an item of the paper-value check: {items}")


def figure_names(config: dict, all_maps: dict) -> list[str]:
    """Every figure whose plotted data the ``check`` target compares with its committed reference."""
    return (list(config["scenes"]) + list(config["branch_scenes"]) + ["figBiS", "basins", "regime_map"]
            + list(config["energy"]["figures"]) + ["lyapunov"]
            + ["design", "work_precision", "failure_map", "analytics_accuracy"]
            + [f"bifurcation_set_{m}" for m in all_maps] + [f"design_map_{m}" for m in config["design"]["maps"]])


def check_design(design: dict, presets: dict, maps: dict) -> None:
    """Refuse a design config that makes no sense, naming the key, the value and what is allowed.

    ``design``: the config's ``design`` section; ``presets``: each quality preset's ``design`` entry
    (``grid``, ``starts``, ``chunks``); ``maps``: the regime maps whose planes the design maps share.
    """

    st = design["starts"]
    if st["distribution"] not in DISTRIBUTIONS:
        raise ConfigError("design.starts.distribution", st["distribution"], " or ".join(DISTRIBUTIONS))
    if st["distribution"] == "box":
        try:
            start_states(MIN_STARTS, distribution="box", phi_range=st["phi_range"], v0_range=st["v0_range"])
        except ValueError as err:
            raise ConfigError("design.starts", st, str(err)) from None
    for axis, tol in design["tolerance"].items():
        if axis not in DESIGN_AXES:
            raise ConfigError(f"design.tolerance.{axis}", tol, f"a tolerance of {', '.join(DESIGN_AXES)}")
        if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol >= 0):
            kind = "relative, e.g. 0.01 for 1 %" if axis in RELATIVE else "in radians"
            raise ConfigError(f"design.tolerance.{axis}", tol, f"a number >= 0 ({kind})")
        if axis in RELATIVE and tol >= 1:
            raise ConfigError(f"design.tolerance.{axis}", tol, "a relative tolerance < 1 (e.g. 0.01 for 1 %)")
    for name in design["maps"]:
        if name not in maps:
            raise ConfigError("design.maps", name, f"a regime map of `maps` ({', '.join(maps)}), whose plane it shares")
        axes = (maps[name]["x"], maps[name]["y"])
        if not set(axes) <= set(DESIGN_AXES):
            raise ConfigError(f"design.maps ({name})", list(axes),
                              f"a plane of two of {', '.join(DESIGN_AXES)} (physical axes)")
        if "beta" in axes:
            lo, hi = maps[name]["x_range" if axes[0] == "beta" else "y_range"]
            for b in design["table_betas"]:
                if not lo <= b <= hi:
                    raise ConfigError("design.table_betas", b, f"an incline in the beta range [{lo}, {hi}] of map {name}")
        if not any(design["tolerance"].get(a, 0) > 0 for a in axes):
            raise ConfigError(f"design.tolerance ({name})", {a: design["tolerance"].get(a, 0) for a in axes},
                              f"a tolerance > 0 on at least one of the map's axes {axes} (else the box is empty)")
    for key, hi in design["budget"].items():
        if key not in DESIGN_AXES or not (isinstance(hi, (int, float)) and hi > 0):
            raise ConfigError(f"design.budget.{key}", hi, f"an upper bound > 0 on one of {', '.join(DESIGN_AXES)}")
    if not 0 < design["confidence"] < 1:
        raise ConfigError("design.confidence", design["confidence"], "a level in (0, 1), e.g. 0.95")
    if not 0 <= design["min_share"] < 1:
        raise ConfigError("design.min_share", design["min_share"], "a share in [0, 1), e.g. 0.01")
    for q, pre in presets.items():
        n = pre["starts"]
        if isinstance(n, bool) or not isinstance(n, int) or n < MIN_STARTS:
            raise ConfigError(f"resolution.{q}.design.starts", n, f"an integer >= {MIN_STARTS}")
        nx, ny = pre["grid"]
        if nx < 2 or ny < 2:
            raise ConfigError(f"resolution.{q}.design.grid", pre["grid"], "[nx, ny], each >= 2")
        if not 1 <= pre["chunks"] <= ny:
            raise ConfigError(f"resolution.{q}.design.chunks", pre["chunks"], f"an integer in [1, {ny}] (grid rows: {ny})")
