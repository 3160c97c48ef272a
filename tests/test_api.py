"""The package's top level: the documented entry points, with numpydoc docstrings that run."""

import doctest
import inspect

import pytest

import vibroimpact as vi

ENTRY_POINTS = ["find_orbit", "continue_orbit", "sweep", "locate_transitions", "bistable_intervals", "basins",
                "regime_map", "Membrane", "voltage_gain", "speed_si", "averages", "orbit_energy", "branch_energy",
                "sweep_energy", "simulate", "trajectory"]


@pytest.mark.parametrize("name", ENTRY_POINTS)
def test_entry_point_is_importable_from_the_top_level_with_a_numpydoc_docstring(name):
    obj = getattr(vi, name)
    assert name in vi.__all__
    doc = inspect.getdoc(obj)
    assert "Parameters\n----------" in doc
    if inspect.isfunction(obj):
        assert "Returns\n-------" in doc
        documented = doc.split("Parameters\n----------")[1].split("\n\n")[0]
        for p in inspect.signature(obj).parameters.values():
            if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL) and p.name not in ("tol", "window", "max_events"):
                assert p.name in documented, f"{name}: parameter {p.name!r} undocumented"


def test_docstring_examples_run():
    from vibroimpact import orbits

    assert doctest.testmod(orbits, raise_on_error=False).failed == 0
