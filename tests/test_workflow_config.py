"""The workflow config checked across keys and typed (vibroimpact.outputs.workflow_config), and the device it
describes: the paper's, or another written under its own folder."""

import copy
import math

import numpy as np
import pytest
import yaml
from conftest import ROOT

import vibroimpact as vi
from vibroimpact.outputs.workflow_config import ConfigError, check, validate_schema

CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
EXAMPLE = yaml.safe_load((ROOT / "config" / "example_device.yaml").read_text())


def merged(over):
    """The defaults with ``over`` merged in, as Snakemake merges a --configfile over the configfile."""
    out = copy.deepcopy(CONFIG)

    def deep(a, b):
        for k, v in b.items():
            if isinstance(v, dict) and isinstance(a.get(k), dict):
                deep(a[k], v)
            else:
                a[k] = v
    deep(out, over)
    return out


def test_the_shipped_config_is_the_paper_s_device_written_in_the_repository():
    cfg = check(CONFIG)
    assert cfg.paper_device and cfg.device.name == "paper" and cfg.results_dir == "."
    # the device's numbers, typed once in the package, are the config's (they cannot drift apart)
    assert cfg.device.physics() == CONFIG["physics"]
    assert vars(cfg.device.membrane) == CONFIG["membrane"]
    assert cfg.device == vi.Device()


def test_the_example_device_is_another_device_written_under_its_own_folder():
    cfg = check(merged(EXAMPLE))
    assert not cfg.paper_device
    assert cfg.device.name == EXAMPLE["device"] and cfg.results_dir == f"results/devices/{EXAMPLE['device']}"
    assert (cfg.device.M, cfg.device.F, cfg.device.omega) == tuple(EXAMPLE["physics"][k] for k in ("M", "F", "omega"))
    assert cfg.device.membrane == vi.Device().membrane  # what the file does not give is the paper's
    assert vi.Device.from_config(**cfg.device_spec()) == cfg.device  # as a job rebuilds it


def test_a_device_without_a_name_is_named_after_its_values_and_never_paper():
    a = check(merged({"physics": {"F": 6.0}}))
    b = check(merged({"physics": {"F": 6.5}}))
    assert a.device.name.startswith("device-") and a.device.name != b.device.name
    assert a.results_dir == f"results/devices/{a.device.name}"
    assert check(merged({"physics": {"F": 6.0}})).device.name == a.device.name  # the same values, the same name
    with pytest.raises(ConfigError, match=r"config: device = 'paper' is not allowed; allowed: another name"):
        check(merged({"device": "paper", "physics": {"F": 6.0}}))


def test_a_value_moved_by_rounding_is_the_paper_s_device_and_a_larger_change_is_not():
    """The figure check regenerates the paper's figures with M moved by 2 ulps: that run must write where the
    paper's run writes (its results read in place); a change a user makes (1e-9 relative) is another device."""
    from vibroimpact.outputs.conditioning import perturbed_config

    for ulps in (2, -2):
        cfg = check(perturbed_config(CONFIG, ulps))
        assert cfg.paper_device and cfg.results_dir == "." and cfg.device.M != CONFIG["physics"]["M"]
    other = check(merged({"physics": {"M": CONFIG["physics"]["M"] * (1 + 1e-9)}}))
    assert not other.paper_device and other.results_dir.startswith("results/devices/device-")


@pytest.mark.parametrize("edit, key, value, allowed", [
    (lambda c: c["sweeps"]["scenes"]["fig0_F"].pop("s"), "sweeps.scenes.fig0_F.s", None, "fixed length s"),
    (lambda c: c["maps"]["s_F"].update(y="s"), "maps.s_F.y", "s", "different from x"),
    (lambda c: c["branches"]["words"]["BBT"].update(start_d=0.6), "branches.words.BBT.start_d", 0.6,
     "inside branches.d_range"),
    (lambda c: c["branch_scenes"]["fig2"]["s_ranges"].__setitem__(0, [0.37, 0.27]), "branch_scenes.fig2.s_ranges[0]",
     [0.37, 0.27], "s_min < s_max"),
    (lambda c: c["scenes"]["fig4"]["captions"].append("fig9_z"), "scenes.fig4.captions", "fig9_z", "a caption defined"),
    (lambda c: c["branch_scenes"]["fig2"]["grazing"].update(beta=0.4), "branch_scenes.fig2.grazing.beta", 0.4,
     "one of the scene's betas"),
    (lambda c: c["bifurcation"].update(words=["BBT", "BBBBT"]), "bifurcation.words", ["BBT", "BBBBT"],
     "words of branches.words"),
    (lambda c: c["design"]["tolerance"].update(s=-0.01), "design.tolerance.s", -0.01, ">= 0"),
    (lambda c: c["resolution"]["paper"]["design"].update(chunks=500), "resolution.paper.design.chunks", 500,
     "an integer in [1, 97]"),
    (lambda c: c["figure_checks"].update(figures=["fig9"]), "figure_checks.figures", "fig9", "'all' or a list"),
    (lambda c: c["checks"]["known"].update({"G3": "x"}), "checks.known", "G3", "an item of the paper-value check"),
    (lambda c: c.update(studies=[{"beta": 0.4, "r": 0.6}, {"beta": 0.40001, "r": 0.6}]), "studies[1]",
     {"beta": 0.40001, "r": 0.6}, "repeats studies[0]"),
    (lambda c: c.update(studies=[{"beta": math.pi / 2, "r": 0.5}]) or c["physics"].update(F=1.0),
     "studies[0].beta", math.pi / 2, "gbar = M g sin(beta) / F < 1"),
    (lambda c: c["membrane"].update(R=4e-3), "membrane.R", 4e-3, "a radius > membrane.r_b = 0.005 m"),
    # a sweep drawn with the analytic branches (continued at physics.F) at another force
    (lambda c: c["sweeps"]["scenes"]["fig0_s"].update(F=6.0), "sweeps.scenes.fig0_s.F", 6.0,
     "none (the sweep is then at physics.F = 5 N) or physics.F: a figure draws this sweep with the analytic branches"),
    # a device too weak to lift the ball at a scene's incline (gbar = M g sin(beta) / F >= 1), wherever the scene is
    (lambda c: c["physics"].update(F=1.0), "captions.fig0b_a.beta", math.pi / 3, "gbar = M g sin(beta) / F < 1"),
    (lambda c: c["physics"].update(M=0.55), "branch_scenes.fig2.betas[0]", math.pi / 2,
     "(here 1.078 at F = 5 N, physics.F: the ball rests on the bottom for good"),
    (lambda c: c["physics"].update(M=0.35) or c["sweeps"]["scenes"]["fig5_pi2_F"].update(range=[3.0, 22.0]),
     "sweeps.scenes.fig5_pi2_F.beta", math.pi / 2, "the lowest force of sweeps.scenes.fig5_pi2_F.range"),
])
def test_each_cross_key_error_names_the_key_the_value_and_what_is_allowed(edit, key, value, allowed):
    cfg = copy.deepcopy(CONFIG)
    edit(cfg)
    with pytest.raises(ConfigError) as err:
        check(cfg)
    assert (err.value.key, err.value.value) == (key, value)
    assert allowed in err.value.allowed
    assert str(err.value).startswith(f"config: {key} = {value!r} is not allowed; allowed: ")


def test_a_device_too_weak_for_a_map_s_corner_runs_and_another_device_s_inclines_are_its_own():
    """A regime map spans a plane where the ball may rest for good in a corner (recorded, not refused); another
    device's own inclines are not refused for the paper's known discrepancies, which name the paper's inclines
    (its check does not read them; the paper's device's still must name items of its check)."""
    weak = merged({"physics": {"M": 0.35}, "maps": {"s_F": {"y_range": [1.0, 22.0]}}})  # stuck below F = 1.7 N
    assert check(weak).device.gbar(weak["maps"]["s_F"]["beta"], 1.0) > 1
    tilted = {"branch_scenes": {f: {"betas": [1.2, 1.0471975511965976, 0.7853981633974483, 0.5235987755982988]}
                                for f in ("fig2", "fig3")}}
    assert check(merged({"device": "tilted", "physics": {"F": 6.0}} | tilted)).device.name == "tilted"
    with pytest.raises(ConfigError, match="checks.known = '2:1 stable interval, lower end, beta=pi/2'"):
        check(merged(tilted))


def test_a_sweep_of_s_is_at_the_device_s_force_unless_it_gives_its_own():
    """The paper's sweeps of s give no force: they are at physics.F, the paper's 5 N and another device's own
    (where they were at 5 N whatever the device, its figures drew them with branches at its force); the typed
    sweep carries the force in the place the config would give it."""
    paper, other = check(CONFIG).sweeps, check(merged(EXAMPLE)).sweeps
    assert list(paper["fig0_s"]) == ["beta", "vary", "range", "F", "phi", "v0"] and paper["fig0_s"]["F"] == 5.0
    assert {other[n]["F"] for n in other if other[n]["vary"] == "s"} == {EXAMPLE["physics"]["F"]}
    assert "F" not in other["fig0_F"] and other["fig0_F"] == CONFIG["sweeps"]["scenes"]["fig0_F"]
    own = merged({"sweeps": {"scenes": {"fig9_s": {"beta": 0.3, "vary": "s", "range": [0.2, 0.3], "F": 7.0,
                                                   "phi": 0.4, "v0": 0.8}}}})
    assert check(own).sweeps["fig9_s"]["F"] == 7.0  # drawn with no branch: its own force


def test_the_typed_config_carries_what_the_rules_read():
    cfg = check(CONFIG)
    assert cfg.resolution == CONFIG["resolution"]["draft"] and cfg.quality == "draft"
    assert set(cfg.maps) == set(CONFIG["maps"]) | set(CONFIG["bifurcation"]["maps"])
    assert "fig2" in cfg.all_figures and "bifurcation_set_d_r" in cfg.all_figures and cfg.figures == cfg.all_figures
    one = copy.deepcopy(CONFIG)
    one["figure_checks"]["figures"] = ["fig4"]
    assert check(one).figures == ["fig4"]


def test_a_device_s_d_is_params_d_to_the_last_bit():
    """The device's conversion and Params.from_physical round alike: a sweep (built through Params) and a
    conversion of the same s give the same d, bit for bit (a 1-ulp difference moved a marginal sweep point's
    settle verdict in Figure 2's lambda_1 panel)."""
    rng = np.random.default_rng(5)
    for dev in (vi.Device(), check(merged(EXAMPLE)).device):
        s, F = rng.uniform(0.05, 1.0, 200), rng.uniform(1.0, 20.0, 200)
        d = dev.d(s, F=F)
        assert all(d[i] == dev.params(s=s[i], beta=0.5, F=F[i]).d for i in range(s.size))
        assert np.allclose(dev.s(d, F=F), s, rtol=1e-15, atol=0)


# ---- the schema's refusals: one line, the key's path, the value, what is allowed, the closest valid key ----
SCHEMA = yaml.safe_load((ROOT / "config" / "schema.yaml").read_text())


def refusal(cfg) -> ConfigError:
    with pytest.raises(ConfigError) as err:
        validate_schema(cfg, SCHEMA)
    assert "\n" not in str(err.value)
    return err.value


def test_the_shipped_config_and_the_example_device_pass_the_schema():
    validate_schema(CONFIG, SCHEMA)
    validate_schema(merged(EXAMPLE), SCHEMA)


@pytest.mark.parametrize("over, line", [
    # a misspelt top-level key in a device file: refused, with the key it was meant to be
    ({"physiks": {"omega": 14.0}},
     "config: physiks = {'omega': 14.0} is not allowed; allowed: one of the keys device, quality, physics, captions, "
     "scenes, resolution, attractor, branches, branch_scenes, sweeps, basins, maps, design, knocks, membrane, energy, chaos, "
     "studies, study_defaults, checks, figure_checks, bifurcation, work_precision, lyapunov_precision, failure_map, bench; "
     "did you mean physics?"),
    # a misspelt nested key
    ({"physics": {"omgea": 14.0}},
     "config: physics.omgea = 14.0 is not allowed; allowed: one of the keys M, F, omega, g, r; did you mean omega?"),
    ({"sweeps": {"locate": {"x_tol": 1e-7}}},
     "config: sweeps.locate.x_tol = 1e-07 is not allowed; allowed: one of the keys xtol, max_periods, max_trials; "
     "did you mean xtol?"),
    # a misspelt choice
    ({"quality": "paer"}, "config: quality = 'paer' is not allowed; allowed: one of 'draft', 'paper', 'smoke'; "
                          "did you mean paper?"),
    # a value out of its range, the bounds in words
    ({"attractor": {"tol": 0.01}}, "config: attractor.tol = 0.01 is not allowed; allowed: a number > 0 and <= 0.001"),
    ({"resolution": {"smoke": {"basin_grid": [6, 1]}}},
     "config: resolution.smoke.basin_grid[1] = 1 is not allowed; allowed: an integer >= 2 and <= 4000"),
    # a list's items, a mapping's names
    ({"figure_checks": {"figures": 3}},
     "config: figure_checks.figures = 3 is not allowed; allowed: 'all' or a list of at least 1 item, each a string of "
     "at least 1 character"),
    ({"branches": {"words": {"TT": {"start_d": 0.2, "k": 1, "phi": 1.0, "v0": 0.2}}}},
     "config: branches.words name = 'TT' is not allowed; allowed: a name matching ^[BT]*B[BT]*$"),
    # a key nothing resembles: no guess
    ({"zzz": 1}, None),
])
def test_a_schema_error_is_one_line_naming_the_key_the_value_what_is_allowed_and_the_closest_key(over, line):
    err = refusal(merged(over))
    if line is None:
        assert err.key == "zzz" and err.suggestion is None and "did you mean" not in str(err)
    else:
        assert str(err) == line


def test_a_missing_key_and_a_study_s_key_are_named_by_their_path():
    cfg = copy.deepcopy(CONFIG)
    del cfg["physics"]["omega"]
    assert str(refusal(cfg)) == ("config: physics.omega = None is not allowed; allowed: a value, which is required: "
                                 "a number > 0")
    cfg = merged({"studies": [{"beta": 0.4, "r": 0.6}, {"beta": 0.5, "rr": 0.6}]})
    err = refusal(cfg)
    assert (err.key, err.value, err.suggestion) == ("studies[1].rr", 0.6, "r")


def test_a_long_value_is_cut_short_not_dumped():
    """A misspelt section holding the whole captions table: the line shows the start of its value, not all of it
    (nor the schema)."""
    err = refusal(merged({"capitons": CONFIG["captions"]}))
    assert err.key == "capitons" and err.suggestion == "captions"
    assert "..." in str(err) and len(str(err)) < 600 and "figBiS_g" not in str(err) and "'type'" not in str(err)


def _mappings(node, path=()):
    """Every mapping of a config with its path (keys and list indices)."""
    if isinstance(node, dict):
        yield path, node
        for k, v in node.items():
            yield from _mappings(v, (*path, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _mappings(v, (*path, i))


def _ref(node):
    while "$ref" in node:
        node = SCHEMA["definitions"][node["$ref"].rsplit("/", 1)[1]]
    return node


def _schema_at(path):
    """The schema node of a config path (through properties, additionalProperties and items)."""
    node = SCHEMA
    for k in path:
        node = _ref(node)
        node = node["items"] if isinstance(k, int) else node.get("properties", {}).get(k, node.get("additionalProperties"))
    return _ref(node)


def _written(path):
    """A path as the refusals write it: ``studies[0].r``."""
    return "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in path).lstrip(".")


def test_an_unknown_key_anywhere_is_refused_in_one_line_at_its_path_unless_the_mapping_takes_any_name():
    """A key added to each mapping of the shipped config: refused, one line, its path named (as an unknown key
    with the keys allowed, or as a new entry whose value is not an entry), or accepted only where the mapping's
    names are the user's own (the methods' costs, the design's tolerances and budget)."""
    refused = accepted = 0
    for path, _ in list(_mappings(CONFIG)):
        cfg = copy.deepcopy(CONFIG)
        node = cfg
        for k in path:
            node = node[k]
        node["zzz"] = 1
        free = _schema_at(path).get("additionalProperties", True) is not False
        where = _written([*path, "zzz"])
        try:
            validate_schema(cfg, SCHEMA)
        except ConfigError as err:
            refused += 1
            assert "\n" not in str(err) and len(str(err)) < 1000, str(err)
            assert err.key in (where, _written(path) + " name"), (err.key, where)
            assert free or str(err).startswith(f"config: {where} = 1 is not allowed; allowed: one of the keys ")
        else:
            accepted += 1
            assert free, f"{where}: an unknown key accepted where the schema names the keys"
    assert refused > 60 and accepted <= 4, (refused, accepted)


def test_r_0_is_allowed_and_its_impacts_end_at_rest_until_the_forcing_pulls_the_ball_off():
    """r = 0 is a plastic impact, which the package supports (Params allows 0 <= r < 1; a branch of plastic
    impacts is continued in tests/test_orbits.py) and the whole default target runs for: the schema and the
    cross-key check accept it for the device and for a study, and its motions are what the schema says: every
    impact leaves the ball at rest against the wall (v_plus = 0) and a stuck ball is released where the
    relative acceleration turns away from the bottom wall, cos(phase) = -gbar (the closed form of the release)."""
    validate_schema(merged({"physics": {"r": 0.0}, "studies": [{"beta": 0.4, "r": 0.0}]}), SCHEMA)
    assert check(merged({"physics": {"r": 0.0}, "studies": [{"beta": 0.4, "r": 0.0}]})).device.r == 0.0
    desc = SCHEMA["properties"]["physics"]["properties"]["r"]["description"]
    assert "0 <= r < 1" in desc and "r = 0 is a plastic impact" in desc and "no impact motion" not in desc
    p = vi.Device().replace(r=0.0).params(s=0.30, beta=math.pi / 3)
    run = vi.simulate(p, phi=0.42, v0=0.87, n_impacts=400)
    kind = run.kind.values
    impacts = np.flatnonzero(kind == 0)
    assert impacts.size > 20 and np.all(run.v_plus.values[impacts[1:]] == 0.0)  # the first is the start
    releases = np.flatnonzero((kind == 3) & (run.wall.values == 1))
    assert releases.size > 5
    assert np.allclose(np.cos(run.phase.values[releases]), -p.gbar, rtol=0, atol=1e-12)


#: the paper's inclines, which every scene of the shipped config uses
PAPER_BETAS = (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)


def test_the_paper_s_branches_keep_their_ranges():
    """The paper's device's sweeps lie inside branches.d_range: its branches are continued over that range and
    its force branches over branches.force as the config gives them (their jobs and datasets unchanged)."""
    cfg = check(CONFIG)
    for beta in PAPER_BETAS:
        assert cfg.branch_d_range(beta, CONFIG["physics"]["r"]) == CONFIG["branches"]["d_range"]
        assert cfg.branch_force(beta) == CONFIG["branches"]["force"]


@pytest.mark.parametrize("physics", [
    EXAMPLE["physics"],                                    # heavier, slower: its sweeps start below d = 0.11
    {"M": 0.1, "omega": 8 * math.pi},                      # lighter, faster: its sweeps reach d = 0.92
])
def test_another_device_s_branches_span_the_d_of_every_sweep_and_row_drawn_with_them(physics):
    """For another device the branches of s at an incline are continued over branches.d_range and over the d
    every figure draws them with: each sweep of s at the device's force at that incline, each branch-scene row
    and a study's sweep (at its own restitution), d = s M omega^2 / (F pi^2) (the paper's scaling, written here
    from the model); the force branches over every sweep of F at their s."""
    over = {"physics": physics, "studies": [{"beta": 0.4, "r": 0.6, "s_range": [0.05, 0.9]}],
            "sweeps": {"scenes": {"fig5_pi2_F": {"range": [3.0, 25.0]}}}}
    cfg = check(merged(over))
    ph = {**CONFIG["physics"], **physics}
    d = lambda s: s * ph["M"] * ph["omega"] ** 2 / (ph["F"] * math.pi ** 2)
    for beta in PAPER_BETAS:
        lo, hi = cfg.branch_d_range(beta, ph["r"])
        drawn = [sc["range"] for sc in CONFIG["sweeps"]["scenes"].values()
                 if sc["vary"] == "s" and abs(sc["beta"] - beta) < 1e-12]
        drawn += [r for sc in CONFIG["branch_scenes"].values() for b, r in zip(sc["betas"], sc["s_ranges"], strict=True)
                  if abs(b - beta) < 1e-12]
        want = (min([CONFIG["branches"]["d_range"][0]] + [d(s) for s, _ in drawn]),
                max([CONFIG["branches"]["d_range"][1]] + [d(s) for _, s in drawn]))
        assert (lo, hi) == pytest.approx(want, rel=1e-15, abs=0)
    (lo, hi), (d_lo, d_hi) = CONFIG["branches"]["d_range"], (d(0.05), d(0.9))
    assert cfg.branch_d_range(0.4, 0.6) == pytest.approx([min(lo, d_lo), max(hi, d_hi)], rel=1e-15, abs=0)
    assert cfg.branch_d_range(0.4, ph["r"]) == CONFIG["branches"]["d_range"]  # no figure draws branches there
    assert cfg.branch_force(math.pi / 2)["F_range"] == [3.0, 25.0]
    assert cfg.branch_force(math.pi / 3) == CONFIG["branches"]["force"]


# ---- the command line's values (--config), made numbers before the schema sees them ------------------------------
def test_the_command_line_s_studies_become_numbers_and_typed_values_stay():
    from vibroimpact.outputs.workflow_config import coerce_studies

    given = [{"beta": "0.4", "r": ".6", "s_range": ["0.2", "7e-1"], "phi": "-1.5", "v0": "+2"},
             {"beta": 0.5, "r": 0.25, "s_range": [0.3, 0.6]}]
    got = coerce_studies(given)
    assert got == [{"beta": 0.4, "r": 0.6, "s_range": [0.2, 0.7], "phi": -1.5, "v0": 2.0},
                   {"beta": 0.5, "r": 0.25, "s_range": [0.3, 0.6]}]
    assert all(type(v) is float for v in (got[0]["beta"], *got[0]["s_range"]))
    assert given[0]["beta"] == "0.4"  # the config it was given is left as it was
    assert coerce_studies(None) == [] and coerce_studies([]) == []
    # a key no study has is left for the schema, which names the closest one
    assert coerce_studies([{"beta": "0.4", "rr": "0.6"}]) == [{"beta": 0.4, "rr": "0.6"}]


@pytest.mark.parametrize("studies, key, value, allowed", [
    ([{"beta": "0.4", "r": "abc"}], "studies[0].r", "abc", "a number, such as 0.4"),
    ([{"beta": "0.4", "r": "0.6"}, {"beta": "pi/4", "r": "0.6"}], "studies[1].beta", "pi/4", "a number"),
    ([{"beta": "0.4", "r": "0.6", "s_range": ["0.2", "0.7m"]}], "studies[0].s_range[1]", "0.7m", "a number"),
    ([{"beta": "0.4", "r": "0.6"}, "beta=0.5"], "studies[1]", "beta=0.5", "a mapping of a study's keys"),
    ("[{beta: 0.4}", "studies", "[{beta: 0.4}", "a list of studies"),
])
def test_a_command_line_study_that_is_not_a_number_is_refused_naming_key_value_and_what_is_allowed(studies, key, value,
                                                                                                    allowed):
    from vibroimpact.outputs.workflow_config import coerce_studies

    with pytest.raises(ConfigError) as err:
        coerce_studies(studies)
    assert (err.value.key, err.value.value) == (key, value)
    text = str(err.value)
    assert text.startswith(f"config: {key} = {value!r} is not allowed; allowed: {allowed}"), text
    assert "studies=[{beta: 0.4, r: 0.6}]" in text or "{beta: 0.4, r: 0.6}" in text


def test_the_numbers_coerced_are_the_numbers_the_schema_asks_of_a_study():
    from vibroimpact.outputs.workflow_config import STUDY_NUMBERS

    schema = yaml.safe_load((ROOT / "config" / "schema.yaml").read_text())
    study = schema["properties"]["studies"]["items"]["properties"]
    numeric = {k for k, v in study.items() if v.get("type") == "number" or v.get("items", {}).get("type") == "number"}
    assert set(STUDY_NUMBERS) == numeric == set(study)
