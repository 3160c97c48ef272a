"""Each figure array's measured conditioning (vibroimpact.conditioning), and accepting references with it."""

import math
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml
from conftest import ROOT, _copy_workflow, readme_command

from vibroimpact.conditioning import PERTURBATIONS, perturbed_config, spreads


def _ds(**arrays):
    return xr.Dataset({k: (f"{k}_dim0", np.asarray(v, float), {"axis_label": "x", "label": "", "axes_title": ""})
                       for k, v in arrays.items()})


def test_an_array_is_ill_conditioned_when_any_perturbation_moves_it_beyond_the_strict_tolerance():
    ref = _ds(a=[1.0, 2.0], b=[1.0, 2.0], c=[1.0, 2.0], d=[1.0, np.nan])
    near = _ds(a=[1.0 + 1e-12, 2.0], b=[1.0, 2.0 + 1e-6], c=[1.0, 2.0, 3.0], d=[1.0, np.nan])
    same = _ds(a=[1.0, 2.0], b=[1.0, 2.0], c=[1.0, 2.0], d=[1.0, 5.0])
    df = spreads(ref, {"p": near, "q": same}, rtol=1e-9, atol=1e-12).set_index("variable")
    assert df.loc["a", "conditioning"] == "strict" and df.loc["a", "spread"] == pytest.approx(1e-12, rel=1e-3)
    assert df.loc["b", "conditioning"] == "ill-conditioned" and df.loc["b", "moved_by"] == "p"
    assert df.loc["b", "ratio"] == pytest.approx(1e-6 / (1e-12 + 2e-9), rel=1e-6)
    assert df.loc["c", "spread"] == math.inf and df.loc["c", "moved_by"] == "p"  # changed shape
    assert df.loc["d", "conditioning"] == "ill-conditioned" and df.loc["d", "moved_by"] == "q"  # NaN moved


def test_timings_and_optional_peers_are_excluded_as_in_the_check():
    ref = xr.Dataset({"t": ("n", [1.0], {"axis_label": "time (s)", "label": "", "axes_title": ""}),
                      "s": ("n", [1.0], {"axis_label": "x", "label": "Siconos", "axes_title": ""})})
    df = spreads(ref, {"p": ref * 2}, rtol=1e-9, atol=1e-12, exclude=["time (s)"], optional=["Siconos"])
    assert set(df.conditioning) == {"excluded"}


def test_the_mass_moves_by_the_given_number_of_ulps_and_nothing_else():
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    for k in (2, -2, 0):
        out = perturbed_config(cfg, k)
        m0, m1 = cfg["physics"]["M"], out["physics"]["M"]
        assert (m1 - m0) == pytest.approx(k * math.ulp(m0), abs=0.5 * math.ulp(m0))
        out["physics"]["M"] = m0
        assert out == cfg
    assert set(PERTURBATIONS) == {"libm", "mass +2 ulp", "libm, mass -2 ulp"}


@pytest.mark.slow
def test_references_are_accepted_with_their_measured_conditioning(tmp_path):
    """README's command for accepting figures, at a smaller preset (figure_checks.figures: [fig4], fewer
    samples): the conditioning regenerates the figure under each perturbation, the update copies its data
    and merges its rows into the committed conditioning, and the check of that figure then passes."""
    cfg = _copy_workflow(tmp_path)
    cfg["figure_checks"]["figures"] = ["fig4"]
    cfg["resolution"]["draft"]["samples_per_unit"] = 60
    (tmp_path / "config" / "config.yaml").write_text(yaml.safe_dump(cfg))
    cmd = readme_command("tests/test_conditioning.py::test_references_are_accepted_with_their_measured_conditioning")
    args = cmd.split("#")[0].split()
    assert args[:3] == [".venv/bin/snakemake", "--cores", "2"]
    before = pd.read_csv(tmp_path / "reference" / "figures" / "conditioning.csv")
    res = subprocess.run([sys.executable, "-m", "snakemake", *args[1:]], cwd=tmp_path, capture_output=True, text=True,
                         timeout=1200)
    assert res.returncode == 0, res.stderr[-3000:]
    after = pd.read_csv(tmp_path / "reference" / "figures" / "conditioning.csv")
    measured = pd.read_csv(tmp_path / "results" / "checks" / "conditioning.csv")
    assert set(measured.figure) == {"fig4"}
    new_data = xr.load_dataset(tmp_path / "results" / "figures" / "data" / "fig4.nc")
    assert set(measured.variable) >= {v for v in new_data.data_vars if new_data[v].attrs.get("role") != "wellposed"}
    # the other figures' rows are kept, fig4's replaced
    others = before[before.figure != "fig4"].reset_index(drop=True)
    pd.testing.assert_frame_equal(after[after.figure != "fig4"].reset_index(drop=True), others)
    assert len(after[after.figure == "fig4"]) == len(measured)
    xr.testing.assert_identical(xr.load_dataset(tmp_path / "reference" / "figures" / "fig4.nc"), new_data)
    check = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", "results/checks/figures/fig4.csv"],
                           cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert check.returncode == 0, check.stderr[-3000:]
