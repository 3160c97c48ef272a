# Shared helpers: config checks that a schema cannot express, and parameter lookups.
import math


def _fail(key, value, allowed):
    raise ValueError(f"config: {key} = {value!r} is not allowed; allowed: {allowed}")


CAPTIONS = config["captions"]
SCENES = list(config["scenes"])
QUALITY = config["quality"]
RESOLUTION = config["resolution"][QUALITY]

for _scene, _spec in config["scenes"].items():
    for _name in _spec["captions"]:
        if _name not in CAPTIONS:
            _fail(f"scenes.{_scene}.captions", _name, f"a caption defined under 'captions': {sorted(CAPTIONS)}")


wildcard_constraints:
    name="|".join(CAPTIONS),
    scene="|".join(SCENES),


def caption_params(name):
    """Everything a caption run needs, from the config (physics + the caption's own values)."""
    c = CAPTIONS[name]
    ph = config["physics"]
    return dict(
        name=name,
        d=c["d"],
        gbar=ph["M"] * ph["g"] * math.sin(c["beta"]) / ph["F"],
        beta=c["beta"],
        r=ph["r"],
        phi=c["phi"],
        v0=c["v0"],
        motion=c["motion"],
        tol=config["attractor"]["tol"],
        max_events=config["attractor"]["max_events"],
        samples_per_unit=RESOLUTION["samples_per_unit"],
        t_show=max(s["t_show"] for s in config["scenes"].values() if name in s["captions"])
        if any(name in s["captions"] for s in config["scenes"].values())
        else 4.0,
    )
