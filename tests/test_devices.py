"""Devices drawn at random: each runs the default target end to end (the smoke preset), or is refused before any
job with the key, the value and what is allowed.  No numerical failure reaches the user as a traceback.

A draw is a device file as a user writes one (only what differs from config/config.yaml): the cylinder's mass,
the force, the frequency, the restitution, the membrane's constants, and the four inclines of the paper's scenes
(pi/2, pi/3, pi/4, pi/6: every scene at one of them moves to the drawn one).  Each value is drawn within the
schema's bounds where the schema has them (r, h; the inclines within the (s, beta) map's range, where the design
table's must lie); where it has none (no physical bound exists for a mass, a force, a frequency, a stiffness, a
radius or a voltage on its own), within a factor of 10 of the paper's, the membrane's radius above the ball's.
Two draws, the same on every run (derandomized, not shrunk: a failing draw is reported as drawn): the first
(hypothesis' simplest: a 1 kg cylinder at 1 N) is refused, the second runs end to end, ~2 min on 2 cores.
The example device (config/example_device.yaml) runs the whole default target at the smoke preset in
tests/test_readme.py, by README's line for a device of one's own.
"""

import hashlib
import json
import math
import re
import subprocess
import sys

import pytest
import yaml
from conftest import ROOT, scratch_clone
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

_SCHEMA = yaml.safe_load((ROOT / "config" / "schema.yaml").read_text())
SCHEMA = _SCHEMA["properties"]
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
#: the paper's four inclines; a draw moves every scene at one of them to its own
INCLINES = (math.pi / 2, math.pi / 3, math.pi / 4, math.pi / 6)
#: what the default target writes for any device, under results/devices/<name>/
WRITTEN = [f"results/figures/{f}.png" for f in ("fig0b", "fig4", "figFN2", "fig2", "fig3", "figBiS", "basins",
                                                "regime_map", "fig0", "fig5", "design", "lyapunov")]
WRITTEN += [f"results/tables/{t}" for t in ("table1.md", "captions.md", "transitions.md", "design.md", "chaos.md",
                                            "workflow_cost.md")] + ["results/checks/paper_values.csv"]


def schema_floats(section, key):
    """Floats within the schema's bounds of ``section.key`` (finite ones)."""
    spec = SCHEMA[section]["properties"][key]
    lo = spec.get("minimum", spec.get("exclusiveMinimum"))
    hi = spec.get("maximum", spec.get("exclusiveMaximum"))
    return st.floats(lo, hi, exclude_min="exclusiveMinimum" in spec, exclude_max="exclusiveMaximum" in spec)


def around(value):
    """Log-uniform within a factor of 10 of ``value`` (the paper's)."""
    return st.floats(math.log(value / 10), math.log(value * 10)).map(lambda x: float(f"{math.exp(x):.6g}"))


#: the bounds of a scene's incline
BETA = _SCHEMA["definitions"]["sweep_scene"]["properties"]["beta"]
devices = st.fixed_dictionaries({
    "physics": st.fixed_dictionaries({"M": around(CONFIG["physics"]["M"]), "F": around(CONFIG["physics"]["F"]),
                                      "omega": around(CONFIG["physics"]["omega"]), "r": schema_floats("physics", "r")}),
    "membrane": st.fixed_dictionaries({"h": schema_floats("membrane", "h"),
                                       **{k: around(CONFIG["membrane"][k]) for k in ("K", "r_b", "U_in", "m")},
                                       "R_over_r_b": st.floats(1.0, 10.0, exclude_min=True)}),  # R > r_b
    # the design table's inclines lie in the (s, beta) map's range, which starts above the schema's 0
    "inclines": st.lists(st.floats(CONFIG["maps"]["s_beta"]["y_range"][0], BETA["maximum"]), min_size=4,
                         max_size=4, unique_by=lambda b: f"{b:.4f}"),
})


def device_file(draw) -> dict:
    """The device file of a draw: its physics, membrane and every scene's incline moved to the drawn one."""
    move = lambda b: next((new for old, new in zip(INCLINES, draw["inclines"], strict=True)
                           if abs(b - old) < 1e-9), b)
    c = CONFIG
    mem = dict(draw["membrane"])
    mem["R"] = mem["r_b"] * mem.pop("R_over_r_b")
    out = {"physics": draw["physics"], "membrane": mem,
           "captions": {n: {"beta": move(x["beta"])} for n, x in c["captions"].items()},
           "branch_scenes": {n: {"betas": [move(b) for b in x["betas"]],
                                 **({"grazing": {**x["grazing"], "beta": move(x["grazing"]["beta"])}}
                                    if "grazing" in x else {})} for n, x in c["branch_scenes"].items()},
           "sweeps": {"scenes": {n: {"beta": move(x["beta"])} for n, x in c["sweeps"]["scenes"].items()}},
           "basins": {n: {"beta": move(x["beta"])} for n, x in c["basins"].items()},
           "maps": {n: {"beta": move(x["beta"])} for n, x in c["maps"].items() if "beta" in x},
           "bifurcation": {"beta": move(c["bifurcation"]["beta"])},
           "design": {"table_betas": [move(b) for b in c["design"]["table_betas"]]}}
    out["device"] = "draw-" + hashlib.sha1(json.dumps(out, sort_keys=True).encode()).hexdigest()[:8]
    return out


def run_device(clone, draw, timeout=900):
    """Write the draw's device file in ``clone`` and run the default target at the smoke preset."""
    spec = device_file(draw)
    path = clone / f"{spec['device']}.yaml"
    path.write_text(yaml.safe_dump(spec))
    res = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", "--keep-going", "--configfile", path.name,
                          "--config", "quality=smoke"], cwd=clone, capture_output=True, text=True, timeout=timeout)
    return spec, res


def assert_ran_or_refused(clone, spec, res):
    """Exit 0 with every figure and table written, or refused before any job: no results folder, the message
    naming the key, the value and what is allowed; and refused only for what a device can lack, a scene where
    the forcing cannot lift the ball (M g sin(beta) / F >= 1 at the incline and force it names)."""
    out = res.stdout + res.stderr
    folder = clone / "results" / "devices" / spec["device"]
    if res.returncode == 0:
        missing = [f for f in WRITTEN if not (folder / f).is_file() or not (folder / f).stat().st_size]
        assert not missing, (spec, missing)
        return "ran"
    failed = sorted(set(re.findall(r"Error in rule (\w+):", out)))
    assert not failed, f"{spec['device']}: jobs failed: {failed}\n{yaml.safe_dump(spec)}\n{out[-4000:]}"
    assert not folder.exists() and "localrule" not in out, (spec, "a refused device ran jobs")
    refusal = re.search(r"config: (\S+\.beta\S*) = (\S+) is not allowed; allowed: an incline where the forcing can lift "
                        r"the ball .*? at F = (\S+) N", out)
    assert refusal, f"refused for something else than lifting the ball:\n{out[-3000:]}"
    beta, F = float(refusal.group(2)), float(refusal.group(3))
    assert spec["physics"]["M"] * CONFIG["physics"]["g"] * math.sin(beta) / F >= 1, refusal.group(0)
    return "refused"


@pytest.fixture(scope="module")
def clone(tmp_path_factory):
    return scratch_clone(tmp_path_factory.mktemp("devices"))


@pytest.mark.slow
@settings(max_examples=2, deadline=None, derandomize=True, database=None, phases=[Phase.explicit, Phase.generate],
          suppress_health_check=list(HealthCheck))
@given(draw=devices)
def test_a_device_drawn_at_random_runs_end_to_end_or_is_refused_before_any_job(clone, draw):
    spec, res = run_device(clone, draw)
    outcome = assert_ran_or_refused(clone, spec, res)
    print(spec["device"], outcome, json.dumps(draw))


@pytest.mark.slow  # ~15 s: two branch jobs of a device at the smoke preset, in a scratch copy of the workflow
def test_a_lighter_device_driven_faster_has_its_branches_as_far_as_its_sweeps(tmp_path):
    """A lighter cylinder driven faster (M = 0.1 kg, omega = 8 pi) spans d = s M omega^2 / (F pi^2) up to 0.9216
    over the paper's lengths (its Figure 9 sweeps of s end at 0.72 m), twice the paper's branch range: its 1:1
    branch at pi/3, drawn with those sweeps, is continued until it leaves that d, not the paper's 0.46; its 2:1
    branch still ends at its fold, below."""
    from conftest import _copy_workflow

    _copy_workflow(tmp_path)
    (tmp_path / "light.yaml").write_text("device: light\nphysics: {M: 0.1, omega: 25.132741228718345}\n")
    branch = "results/branches/beta-1.0472_r-0.5000/orbit-{}_vary-s.nc"
    res = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", branch.format("BT"), branch.format("BBT"),
                          "--configfile", "light.yaml", "--config", "quality=smoke"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=900)
    assert res.returncode == 0, res.stderr[-3000:]
    import xarray as xr

    d_max = 0.72 * 0.1 * (8 * math.pi) ** 2 / (5.0 * math.pi ** 2)  # the sweeps' largest d
    one = xr.load_dataset(tmp_path / "results" / "devices" / "light" / branch.format("BT"))
    left = re.fullmatch(r"left d_range at d = (\S+)", one.attrs["stop_increasing"])
    assert one.attrs["status"] == "ok" and left and float(left.group(1)) > d_max, one.attrs["stop_increasing"]
    step = CONFIG["resolution"]["smoke"]["branch_step"]
    assert d_max - step < float(one.d.max()) <= d_max
    two = xr.load_dataset(tmp_path / "results" / "devices" / "light" / branch.format("BBT"))
    assert two.attrs["status"] == "ok" and "fold" in two.critical_kind.values and float(two.d.max()) < 0.46
