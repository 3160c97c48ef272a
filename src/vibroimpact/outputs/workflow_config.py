"""The workflow's configuration, checked as a whole and typed.

:func:`coerce_studies` turns the strings a command line's ``--config`` gives into numbers;
``config/schema.yaml`` checks each value on its own (types, ranges, enums, and no key it does not name);
:func:`validate_schema` applies it and turns its first error into one line (:func:`schema_error`).
:func:`check` checks what a schema cannot express, across keys (a scene's caption must exist, a range must
increase, a sweep of F needs its fixed s, a map's axes differ, ...), before any job runs, and returns a
:class:`WorkflowConfig` that the rule files read instead of raw keys.  Every refusal is one line naming the
key, the value and what is allowed, and for a misspelt key or choice the closest valid one.
"""

from __future__ import annotations

import difflib
import math
import re
import reprlib
from dataclasses import dataclass, field

from jsonschema import Draft202012Validator
from jsonschema.exceptions import best_match, by_relevance

from ..analysis.starts import DESIGN_AXES, DISTRIBUTIONS, KNOCK_KINDS, MIN_STARTS, RELATIVE, start_states
from ..dynamics.device import Device
from .check_items import item_names
from .registry import REGISTRY, figures

__all__ = ["STUDY_NUMBERS", "ConfigError", "WorkflowConfig", "check", "check_design", "check_knocks", "coerce_studies", "figure_names",
           "schema_error", "validate_schema"]

#: how a value is shown in a refusal: on one line, a long value cut short (``...``) at about 120 characters
_SHORT = reprlib.Repr()
_SHORT.maxlevel, _SHORT.maxdict, _SHORT.maxlist, _SHORT.maxstring, _SHORT.maxother = 2, 4, 8, 80, 80


def _shown(value) -> str:
    text = _SHORT.repr(value)
    return text if len(text) <= 120 else text[:117] + "..."


class ConfigError(ValueError):
    """A config value that is not allowed: its key, the value and what is allowed, on one line.

    ``suggestion``, where given, is the closest valid key or choice (a misspelling's correction).
    """

    def __init__(self, key: str, value, allowed: str, suggestion: str | None = None):
        self.key, self.value, self.allowed, self.suggestion = key, value, allowed, suggestion
        hint = f"; did you mean {suggestion}?" if suggestion else ""
        text = f"config: {key} = {_shown(value)} is not allowed; allowed: {allowed}{hint}"
        super().__init__(" ".join(text.split()))


# ---------------------------------------------------------------------------------------------------------------------
# The command line's values
# ---------------------------------------------------------------------------------------------------------------------
#: the keys of a study (``studies``) whose values are numbers, or lists of numbers (``s_range``)
STUDY_NUMBERS = ("beta", "r", "s_range", "phi", "v0")
#: how a number reads on the command line
_NUMERIC = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")
#: a study as ``--config`` writes it
_STUDY_EXAMPLE = "studies=[{beta: 0.4, r: 0.6}]"


def _number(key: str, value):
    """``value`` as a number where it is a string that reads as one; another string is refused (``key`` names it)."""
    if not isinstance(value, str):
        return value
    if _NUMERIC.fullmatch(value):
        return float(value)
    raise ConfigError(key, value, f"a number, such as 0.4 (as in --config '{_STUDY_EXAMPLE}')")


def _study(i: int, study) -> dict:
    if not isinstance(study, dict):
        raise ConfigError(f"studies[{i}]", study, f"a mapping of a study's keys, such as {{beta: 0.4, r: 0.6}} "
                          f"(--config '{_STUDY_EXAMPLE}')")
    out = {}
    for k, v in study.items():
        if k not in STUDY_NUMBERS:  # an unknown key: the schema names it and the closest known one
            out[k] = v
        elif isinstance(v, list):
            out[k] = [_number(f"studies[{i}].{k}[{j}]", x) for j, x in enumerate(v)]
        else:
            out[k] = _number(f"studies[{i}].{k}", v)
    return out


def coerce_studies(studies) -> list:
    """The config's ``studies`` with the strings of a command line made numbers.

    ``--config 'studies=[{beta: 0.4, r: 0.6}]'`` reaches the workflow as strings (Snakemake parses nested values
    with YAML's base loader, which types nothing): each value of :data:`STUDY_NUMBERS` that reads as a number
    becomes one (a float); values that are already typed (the config file's) are kept.  The schema then checks
    each value (:func:`validate_schema`).

    Parameters
    ----------
    studies : list or None
        The config's ``studies``.

    Returns
    -------
    list
        The studies, ``[]`` for none.

    Raises
    ------
    ConfigError
        Where ``studies`` is not a list, a study not a mapping, or a value of :data:`STUDY_NUMBERS` a string that is
        not a number; it names the key (``studies[0].beta``), the value and what is allowed.

    Examples
    --------
    >>> coerce_studies([{"beta": "0.4", "r": ".6", "s_range": ["0.2", "7e-1"]}])
    [{'beta': 0.4, 'r': 0.6, 's_range': [0.2, 0.7]}]
    """
    if studies is None:
        return []
    if not isinstance(studies, list):
        raise ConfigError("studies", studies, f"a list of studies, such as --config '{_STUDY_EXAMPLE}'")
    return [_study(i, st) for i, st in enumerate(studies)]


#: a schema type in words
_TYPES = {"number": "a number", "integer": "an integer", "string": "a string", "boolean": "true or false",
          "object": "a mapping", "array": "a list", "null": "nothing"}
_BOUNDS = (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="), ("exclusiveMaximum", "<"))


def _resolve(node: dict, schema: dict) -> dict:
    """A schema node with its local ``$ref`` (``#/definitions/...``) followed."""
    while isinstance(node, dict) and "$ref" in node:
        target = schema
        for part in node["$ref"].lstrip("#/").split("/"):
            target = target[part]
        node = target
    return node


def _describe(node, schema: dict, depth: int = 0) -> str:
    """What a schema node allows, in words, on one line (nested nodes one level deep)."""
    node = _resolve(node, schema)
    if node is True or node == {}:
        return "any value"
    if "enum" in node:
        text = ("one of " if len(node["enum"]) > 1 else "") + ", ".join(repr(x) for x in node["enum"])
    elif "const" in node:
        text = repr(node["const"])
    elif "oneOf" in node or "anyOf" in node:
        text = " or ".join(_describe(n, schema, depth) for n in node.get("oneOf", node.get("anyOf")))
    else:
        kinds = node.get("type", [])
        text = " or ".join(_TYPES[k] for k in ([kinds] if isinstance(kinds, str) else kinds)) or "a value"
        bounds = [f"{op} {node[k]!r}" for k, op in _BOUNDS if k in node]
        text += (" " + " and ".join(bounds)) if bounds else ""
        if "pattern" in node:
            text += f" matching {node['pattern']}"
        if "minLength" in node:
            text += f" of at least {_count(node['minLength'], 'character')}"
        lo, hi = node.get("minItems"), node.get("maxItems")
        if lo is not None and lo == hi:
            text += f" of {_count(lo, 'item')}"
        elif lo is not None or hi is not None:
            text += " of " + " and ".join(w for w in (lo and f"at least {lo}", hi and f"at most {hi}") if w)
            text += " items" if (hi or lo) > 1 else " item"
        if "items" in node and depth < 2:
            text += ", each " + _describe(node["items"], schema, depth + 1)
        if "contains" in node:
            text += ", including " + _describe(node["contains"], schema, depth + 1)
        if node.get("uniqueItems"):
            text += ", without repeats"
        if "properties" in node and depth < 1:
            text += " of the keys " + ", ".join(node["properties"])
    if "description" in node and depth < 1:
        text += f" ({node['description']})"
    return text


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


def _closest(word, choices) -> str | None:
    """The valid key or choice closest to a misspelt ``word`` (difflib's ratio >= 0.6), if any."""
    names = [str(c) for c in choices]
    found = difflib.get_close_matches(str(word), names, n=1) if isinstance(word, str) else []
    return found[0] if found else None


def _path(parts) -> str:
    """A key's path as the refusals write it: ``studies[0].r``, ``physics.omega``."""
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "(the config)"


def schema_error(error, schema: dict) -> ConfigError:
    """One line for a schema error: the key (its path), the value, what is allowed, the closest valid key.

    Parameters
    ----------
    error : jsonschema.exceptions.ValidationError
        An error of ``config/schema.yaml`` on a config.
    schema : dict
        The schema (for its ``$ref`` definitions).

    Returns
    -------
    ConfigError
        The refusal: e.g. ``config: physiks = {...} is not allowed; allowed: one of the keys device, quality,
        physics, ...; did you mean physics?`` for a misspelt top-level key, not the schema's dump.
    """
    path, node, kind = list(error.absolute_path), error.schema, error.validator
    if kind == "additionalProperties" and isinstance(error.instance, dict):
        known = list(node.get("properties", {}))
        extra = [k for k in error.instance if k not in known]
        key = extra[0]
        allowed = "one of the keys " + ", ".join(known) if known else "no key"
        if len(extra) > 1:
            allowed += f" (not allowed either: {', '.join(map(str, extra[1:]))})"
        return ConfigError(_path([*path, key]), error.instance[key], allowed, _closest(key, known))
    if kind == "required":
        missing = next(k for k in error.validator_value if k not in error.instance)
        wanted = _describe(node.get("properties", {}).get(missing, {}), schema)
        return ConfigError(_path([*path, missing]), None, f"a value, which is required: {wanted}")
    if "propertyNames" in list(error.absolute_schema_path)[-2:]:  # a name of a mapping, not a value
        return ConfigError(_path(path) + " name", error.instance, _describe(node, schema).replace("a value", "a name"))
    parent = _resolve(error.parent.schema, schema) if error.parent is not None else None
    whole = parent if kind in ("oneOf", "anyOf") and parent is not None else node
    choices = node.get("enum", [])
    return ConfigError(_path(path), error.instance, _describe(whole, schema), _closest(error.instance, choices))


def validate_schema(config: dict, schema: dict) -> None:
    """Check a config against the schema (``config/schema.yaml``, JSON Schema 2020-12), refusing in one line.

    Parameters
    ----------
    config : dict
        The merged config (``config/config.yaml``, ``--configfile`` and ``--config``).
    schema : dict
        The schema, as loaded from YAML.

    Raises
    ------
    ConfigError
        The most relevant schema error (the shallowest key; at one key, an unknown key before a missing one,
        which is often the same key misspelt), as :func:`schema_error` writes it.
    """
    relevance = by_relevance(strong={"additionalProperties"})
    error = best_match(Draft202012Validator(schema).iter_errors(config), key=relevance)
    if error is not None:
        raise schema_error(error, schema)


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
    d_range, force, study_s_range
        ``branches.d_range``, ``branches.force`` and ``study_defaults.s_range``: where the branches are continued
        at least (:meth:`branch_d_range`, :meth:`branch_force` widen them to what the figures draw).
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
    d_range: list = field(default_factory=lambda: [0.11, 0.46])
    force: dict = field(default_factory=dict)
    study_s_range: list = field(default_factory=lambda: [0.19, 0.72])

    def device_spec(self) -> dict:
        """The device as a rule parameter (``Device.from_config(**spec)`` rebuilds it in a job)."""
        return dict(physics=self.device.physics(), membrane=vars(self.device.membrane).copy(), name=self.device.name)

    def branch_d_range(self, beta: float, r: float) -> list[float]:
        """The d range over which the branches of s at incline ``beta`` and restitution ``r`` are continued.

        ``branches.d_range``, widened to every d a figure draws these branches over: the sweeps of s at the
        device's force at this incline (Figures 2 and 9, the lambda_1 figure, Figure 8), the branch scenes' rows
        at it (Figures 5 and 6) and a study's sweep at this (beta, r).  The sweeps' d follows from the device
        (d = s M omega^2 / (F pi^2)): a lighter device driven faster reaches larger d over the same lengths, and
        its branches are continued as far.  The paper's device's sweeps lie inside ``branches.d_range``, which
        it keeps as it is.

        Parameters
        ----------
        beta, r : float
            The branches' incline (rad) and restitution, told apart from others to 4 decimals (as their paths).

        Returns
        -------
        list of float
            ``[d_min, d_max]``.
        """
        same = lambda a, b: f"{a:.4f}" == f"{b:.4f}"
        lengths = []
        if same(r, self.device.r):
            lengths += [sc["range"] for sc in self.sweeps.values()
                        if sc["vary"] == "s" and sc["F"] == self.device.F and same(sc["beta"], beta)]
            lengths += [s for sc in self.branch_scenes.values() for b, s in zip(sc["betas"], sc["s_ranges"], strict=True)
                        if same(b, beta)]
        lengths += [st.get("s_range", self.study_s_range) for st in self.studies
                    if same(st["beta"], beta) and same(st["r"], r)]
        lo, hi = self.d_range
        for s_lo, s_hi in lengths:
            lo, hi = min(lo, float(self.device.d(s_lo))), max(hi, float(self.device.d(s_hi)))
        return [lo, hi]

    def branch_force(self, beta: float) -> dict:
        """The continuation in F of the branches at incline ``beta``: ``branches.force``, its ``F_range`` widened
        to every sweep of F at this incline and at its fixed length ``s`` (drawn with these branches).

        Parameters
        ----------
        beta : float
            The branches' incline (rad), told apart from others to 4 decimals.

        Returns
        -------
        dict
            ``{"s": s, "F_range": [F_min, F_max]}``.
        """
        lo, hi = self.force["F_range"]
        for sc in self.sweeps.values():
            if sc["vary"] == "F" and sc["s"] == self.force["s"] and f"{sc['beta']:.4f}" == f"{beta:.4f}":
                lo, hi = min(lo, sc["range"][0]), max(hi, sc["range"][1])
        return {**self.force, "F_range": [lo, hi]}


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
    check_knocks(config["knocks"], config["maps"], device)
    _lift(config, device)
    paper = device.same_physics(Device())
    if paper:  # the known discrepancies are the paper's device's: another device's check does not read them
        _known(config)
    all_maps = dict(config["maps"]) | dict(config["bifurcation"].get("maps", {}))
    _registered(config)
    figures = figure_names(config)
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
        figures=figures if chosen == "all" else list(chosen), all_figures=figures,
        d_range=list(config["branches"]["d_range"]), force=dict(config["branches"]["force"]),
        study_s_range=list(config["study_defaults"]["s_range"]))


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


def figure_names(config: dict) -> list[str]:
    """Every figure whose plotted data the ``check`` target compares with its committed reference: the figures
    of the registry (:mod:`vibroimpact.outputs.registry`) the config draws and a check rule compares."""
    return [f.stem for f in figures(config) if f.check]


def _registered(config):
    """Each figure a config section names (a scene, a branch scene, an energy figure) is a row of the registry."""
    for section in ("scenes", "branch_scenes", "energy.figures"):
        rows = [r.stem for r in REGISTRY if r.configured == section]
        node = config
        for key in section.split("."):
            node = node[key]
        for name in node:
            if name not in rows:
                raise ConfigError(f"{section}.{name}", name, f"a figure of the registry drawn this way: {rows} "
                                  "(add a row to vibroimpact.outputs.registry)")


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


def check_knocks(knocks: dict, maps: dict, device: Device) -> None:
    """Refuse a knocks config that makes no sense, naming the key, the value and what is allowed: the plane a
    design map can be made on, a knock of the device's kind, a section design the device can be built as."""
    name = knocks["map"]
    if name not in maps:
        raise ConfigError("knocks.map", name, f"a regime map of `maps` ({', '.join(maps)}), whose plane it knocks")
    axes = (maps[name]["x"], maps[name]["y"])
    if not set(axes) <= set(DESIGN_AXES):
        raise ConfigError(f"knocks.map ({name})", list(axes), f"a plane of two of {', '.join(DESIGN_AXES)} (physical axes)")
    if knocks["kind"] not in KNOCK_KINDS:
        raise ConfigError("knocks.kind", knocks["kind"], " or ".join(KNOCK_KINDS))
    if not (isinstance(knocks["knock"], (int, float)) and 0 < knocks["knock"] < math.inf):
        raise ConfigError("knocks.knock", knocks["knock"], "a finite knock > 0 (m/s for velocity, m for position)")
    try:
        device.params(**knocks["section"])
    except (ValueError, TypeError) as err:
        raise ConfigError("knocks.section", knocks["section"], f"a design the device can be built as ({err})") from None
