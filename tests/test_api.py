"""The package's top level: the documented entry points, with numpydoc docstrings that run."""

import doctest
import inspect

import pytest

import vibroimpact as vi

ENTRY_POINTS = ["find_orbit", "continue_orbit", "sweep", "locate_transitions", "bistable_intervals", "basins",
                "regime_map", "Membrane", "voltage_gain", "speed_si", "averages", "orbit_energy", "branch_energy",
                "sweep_energy", "simulate", "trajectory", "basin_stability", "critical_shock", "knock_map",
                "knock_section"]


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
    from vibroimpact.analysis import orbits

    assert doctest.testmod(orbits, raise_on_error=False).failed == 0


def test_the_top_level_imports_lazily_and_every_public_name_resolves():
    """``import vibroimpact`` loads neither numba, scipy nor xarray (a workflow job pays only for what
    it uses); every name in ``__all__`` then resolves to the object of the module that defines it."""
    import subprocess
    import sys

    code = ("import sys, vibroimpact; "
            "print(sorted(m for m in ('numba', 'scipy', 'xarray', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"
    for name in vi.__all__:
        obj = getattr(vi, name)
        if name in vi._WHERE:
            import importlib

            assert obj is getattr(importlib.import_module(f"vibroimpact.{vi._WHERE[name]}"), name)
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        vi.nonexistent  # noqa: B018
