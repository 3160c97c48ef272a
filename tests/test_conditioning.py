"""Each figure array's measured conditioning (vibroimpact.outputs.conditioning), and accepting references with it."""

import math
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml
from conftest import ROOT, _copy_workflow, readme_command

from vibroimpact.outputs.conditioning import LIBM_SWITCH, PERTURBATIONS, perturbed_config, regenerate, spreads


def _ds(**arrays):
    return xr.Dataset({k: (f"{k}_dim0", np.asarray(v, float), {"axis_label": "x", "label": "", "axes_title": ""})
                       for k, v in arrays.items()})


def test_an_array_is_ill_conditioned_when_any_perturbation_moves_it_beyond_the_strict_tolerance():
    ref = _ds(a=[1.0, 2.0], b=[1.0, 2.0], c=[1.0, 2.0], d=[1.0, np.nan])
    near = _ds(a=[1.0 + 1e-12, 2.0], b=[1.0, 2.0 + 1e-6], c=[1.0, 2.0, 3.0], d=[1.0, np.nan])
    same = _ds(a=[1.0, 2.0], b=[1.0, 2.0], c=[1.0, 2.0], d=[1.0, 5.0])
    df = spreads(ref, {"p": near, "q": same}, rtol=1e-9, atol=1e-12).set_index("variable")
    assert df.loc["a", "conditioning"] == "strict" and df.loc["a", "spread"] == pytest.approx(1e-12, rel=1e-3)
    assert df.loc["a", "ratio"] == pytest.approx(1e-12 / (1e-12 + 1e-9), rel=1e-3)  # a fraction of the tolerance
    assert df.loc["b", "conditioning"] == "ill-conditioned" and df.loc["b", "moved_by"] == "p"
    assert df.loc["b", "ratio"] == pytest.approx(1e-6 / (1e-12 + 2e-9), rel=1e-6)
    assert df.loc["c", "spread"] == math.inf and df.loc["c", "moved_by"] == "p"  # changed shape
    assert df.loc["d", "conditioning"] == "ill-conditioned" and df.loc["d", "moved_by"] == "q"  # NaN moved


def test_optional_peers_are_excluded_and_each_array_is_judged_by_its_declared_rule():
    """An optional peer is excluded as in the check; a timing moves (it is ill-conditioned) but its declared rule
    passes every copy; an array declaring no rule that moves fails under the perturbation that moved it."""
    ref = xr.Dataset({"t": ("n", [1.0], {"axis_label": "time (s)", "label": "", "axes_title": "", "wellposed": "timing",
                                         "provenance": "timing"}),
                      "s": ("n", [1.0], {"axis_label": "x", "label": "Siconos", "axes_title": ""}),
                      "e": ("n", [1.0], {"axis_label": "x", "label": "", "axes_title": ""})})
    df = spreads(ref, {"p": ref * 2, "q": ref}, rtol=1e-9, atol=1e-12, optional=["Siconos"]).set_index("variable")
    assert df.conditioning["s"] == "excluded" and df.judged["s"] == "excluded"
    assert df.conditioning["t"] == "ill-conditioned" and df.judged["t"] == "pass" and df.rule["t"] == "timing"
    assert df.judged["e"] == "fail under p" and df.rule["e"] == "strict" and df.provenance["e"] == "exact"
    assert df.by_perturbation["e"].startswith("p: ") and df.by_perturbation["e"].endswith("q: 0")


def test_the_mass_moves_by_the_given_number_of_ulps_and_nothing_else():
    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    for k in (2, -2, 1, -1, 0):
        out = perturbed_config(cfg, k)
        m0, m1 = cfg["physics"]["M"], out["physics"]["M"]
        assert (m1 - m0) == pytest.approx(k * math.ulp(m0), abs=0.5 * math.ulp(m0))
        out["physics"]["M"] = m0
        assert out == cfg
    # each perturbation: the other libm, the inputs moved, both (the other way), and OpenBLAS's kernels of
    # three CPU generations
    assert PERTURBATIONS == {"libm": (LIBM_SWITCH, 0), "mass +2 ulp": ({}, 2), "libm, mass -2 ulp": (LIBM_SWITCH, -2),
                             **{f"OpenBLAS {c}": ({"OPENBLAS_CORETYPE": c}, 0)
                                for c in ("Haswell", "Sandybridge", "Nehalem")}}
    assert LIBM_SWITCH == {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA"}


def test_the_openblas_kernel_sets_are_read_from_openblas_and_the_machine_s_own_is_left_out():
    """numpy's OpenBLAS reports the kernel set it picked; OPENBLAS_CORETYPE picks another in a fresh process (here
    any x86-64 CPU runs Sandybridge's), and the perturbations leave out the set the machine picks anyway."""
    from vibroimpact.outputs.conditioning import openblas_core, perturbations

    blas = np.__config__.CONFIG["Build Dependencies"]["blas"]["name"]
    if "openblas" not in blas:
        pytest.skip(f"numpy's BLAS here is {blas}, not an OpenBLAS that reports its kernel set")
    own = openblas_core()
    assert own, "numpy's OpenBLAS names no kernel set"
    assert openblas_core(env={"OPENBLAS_CORETYPE": "Sandybridge"}) == "Sandybridge"
    chosen = perturbations()
    assert f"OpenBLAS {own}" not in chosen and {"libm", "mass +2 ulp", "libm, mass -2 ulp"} <= set(chosen)
    assert "OpenBLAS Sandybridge" in chosen or own == "Sandybridge"


def test_a_move_between_one_and_two_tolerances_is_a_move():
    ref = _ds(a=[1.0], b=[2.0])
    new = _ds(a=[1.0 + 1.5 * (1e-12 + 1e-9)], b=[2.0 + 1.0e-12])
    df = spreads(ref, {"p": new}, rtol=1e-9, atol=1e-12).set_index("variable")
    assert df.loc["a", "conditioning"] == "ill-conditioned" and df.loc["b", "conditioning"] == "strict"
    empty = spreads(_ds(e=[]), {"p": _ds(e=[])}, rtol=1e-9, atol=1e-12)
    assert list(empty.conditioning) == ["strict"] and list(empty.moved_by) == [""]


def test_the_image_spread_and_the_ill_conditioned_variables_of_a_figure():
    from vibroimpact.outputs.conditioning import ill_conditioned, image_spread

    ref = _ds(a=[1.0])
    ref.attrs["png_phash"] = "f" * 64
    copies = {"p": ref.copy(), "q": ref.copy()}
    copies["p"].attrs["png_phash"] = "e" + "f" * 63  # one hex digit: 1 bit
    copies["q"].attrs["png_phash"] = "0" + "f" * 63  # 4 bits
    assert image_spread(ref, copies) == 4
    assert image_spread(_ds(a=[1.0]), copies) == 0  # no hash in the reference
    table = pd.DataFrame([dict(figure="f", variable="a", conditioning="ill-conditioned"),
                          dict(figure="f", variable="b", conditioning="strict"),
                          dict(figure="g", variable="c", conditioning="ill-conditioned")])
    assert ill_conditioned(table, "f") == {"a"} and ill_conditioned(None, "f") == set()


def test_a_perturbed_regeneration_runs_the_workflow_in_a_copy_with_the_switch_and_the_moved_mass(tmp_path):
    """regenerate() on a workflow of one rule that writes what it was run with: the libm switch in its
    environment, the config's mass moved by -2 ulps, in the scratch copy, the original untouched."""
    root = tmp_path / "root"
    (root / "config").mkdir(parents=True)
    (root / "config" / "config.yaml").write_text("physics: {M: 0.1245}\n")
    (root / "Snakefile").write_text(
        'configfile: "config/config.yaml"\n\n\nrule probe:\n    output:\n        "out.txt",\n    run:\n'
        '        import os\n\n        with open(output[0], "w") as fh:\n'
        '            fh.write(f"{os.environ.get(\'GLIBC_TUNABLES\', \'\')} {config[\'physics\'][\'M\']!r}")\n')
    out = regenerate(root, tmp_path / "scratch", "libm, mass -2 ulp", ["out.txt"], cores=1)
    env, mass = (out / "out.txt").read_text().split()
    assert env == LIBM_SWITCH["GLIBC_TUNABLES"]
    assert float(mass) == math.nextafter(math.nextafter(0.1245, 0), 0)
    assert not (root / "out.txt").exists() and "0.1245" in (root / "config" / "config.yaml").read_text()
    with pytest.raises(RuntimeError, match="(?s)under perturbation 'libm' failed.*no-such-target"):
        regenerate(root, tmp_path / "scratch", "libm", ["no-such-target"], cores=1)


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


def test_the_testing_page_s_table_counts_per_figure_and_perturbation_in_the_paper_s_order():
    """summary() counts, per figure and perturbation, the arrays moved beyond the strict tolerance and those
    their declared rule fails; conditioning_markdown() lists the paper's figures by printed number first, then
    every array that moved with how far each perturbation moved it."""
    from vibroimpact.outputs.conditioning import conditioning_markdown, summary

    table = pd.DataFrame([
        dict(figure="basins", variable="a", rule="motions", provenance="simulation", conditioning="ill-conditioned",
             spread=1.0, ratio=9.0, moved_by="p", judged="pass", by_perturbation="p: 9; q: 0.5"),
        dict(figure="fig5", variable="b", rule="strict", provenance="exact", conditioning="strict", spread=0.0,
             ratio=0.25, moved_by="", judged="pass", by_perturbation="p: 0.25; q: 0"),
        dict(figure="fig5", variable="c", rule="magnitude", provenance="method error", conditioning="ill-conditioned",
             spread=1.0, ratio=3.0, moved_by="p; q", judged="fail under q", by_perturbation="p: 3; q: 2")])
    per = summary(table, ["p", "q"]).assign(machine_openblas="Haswell")
    got = per.set_index(["figure", "perturbation"])
    assert got.loc[("fig5", "p"), "moved"] == 1 and got.loc[("fig5", "q"), "failed"] == 1
    assert got.loc[("fig5", "p"), "failed"] == 0 and got.loc[("fig5", "p"), "largest_pointwise_ratio"] == 0.25
    assert got.loc[("basins", "q"), "moved"] == 0 and got.loc[("basins", "p"), "arrays"] == 1
    md = conditioning_markdown(table, per)
    assert "OpenBLAS picks its Haswell kernels" in md
    assert md.index("Figure 9 (Fig 5)") < md.index("| basins")  # the paper's figure first
    row = md.split("| Figure 9 (Fig 5)")[1].split("\n")[0]
    assert [c.strip() for c in row.split("|")[1:4]] == ["2", "1 (0)", "1 (1)"]
    assert "p: 3; q: 2" in md and "fail under q" in md and "| b " not in md  # only the arrays that moved


def test_a_probe_of_the_libm_switch_that_cannot_run_is_an_error_not_a_no(tmp_path):
    """An interpreter that cannot run the probe (here one that fails as a Python without numpy would) is an error:
    it must not read as 'the switch changes nothing here', which the workflow and the tests would take for a CPU
    whose glibc takes one path anyway (and skip the other libm)."""
    from vibroimpact.outputs.conditioning import libm_switch_works

    broken = tmp_path / "python"
    broken.write_text("#!/bin/sh\necho \"ModuleNotFoundError: No module named 'numpy'\" >&2\nexit 1\n")
    broken.chmod(0o755)
    with pytest.raises(subprocess.CalledProcessError):
        libm_switch_works(str(broken))


def _table():
    """A conditioning table as figure_conditioning writes it, counted by hand: figure f has four arrays compared
    (an optional peer's excluded, the image row apart): a strict array moved 3 tolerances by libm (and failing
    there), a cloud that libm moved (NaN elsewhere) and mass +2 ulp by 40 tolerances (its rule passing both), a
    strict array that moved by neither, and a strict array that mass +2 ulp changed in shape (failing there);
    figure g (first, as the workflow's figures come in no sorted order) one strict array that moved by neither;
    figure h one timing, moved by both, no strict array."""
    from vibroimpact.outputs.checks import IMAGE_ROW

    rows = [("g", "d", "strict", "strict", "", "pass", "libm: 0.7; mass +2 ulp: 0.9"),
            ("f", "a", "strict", "ill-conditioned", "libm", "fail under libm", "libm: 3; mass +2 ulp: 0.5"),
            ("f", "b", "motions", "ill-conditioned", "libm; mass +2 ulp", "pass", "libm: moved; mass +2 ulp: 40"),
            ("f", "c", "strict", "strict", "", "pass", "libm: 0.2; mass +2 ulp: 0"),
            ("f", "e", "strict", "ill-conditioned", "mass +2 ulp", "fail under mass +2 ulp", "libm: 0; mass +2 ulp: moved"),
            ("f", "s", "strict", "excluded", "", "excluded", ""),
            ("f", IMAGE_ROW, "", "ill-conditioned", "", "", ""),
            ("h", "t", "timing", "ill-conditioned", "libm; mass +2 ulp", "pass", "libm: 5; mass +2 ulp: 7")]
    return pd.DataFrame(rows, columns=["figure", "variable", "rule", "conditioning", "moved_by", "judged",
                                       "by_perturbation"]).assign(provenance="exact")


def _cells(text, first):
    line = next(x for x in text.splitlines() if x.startswith(f"| {first} "))
    return [c.strip() for c in line.strip("|").split("|")]


def test_the_summary_and_the_testing_page_count_each_figure_s_moved_and_failed_arrays():
    from vibroimpact.outputs.conditioning import conditioning_markdown, summary

    table = _table()
    per = summary(table, ["libm", "mass +2 ulp"])
    record = lambda fig, name, *counts: dict(zip(per.columns, (fig, name, *counts), strict=True))
    assert per.to_dict("records") == [record("g", "libm", 1, 0, 0, 0.7, 0), record("g", "mass +2 ulp", 1, 0, 0, 0.9, 0),
                                      record("f", "libm", 4, 2, 1, 3.0, 1), record("f", "mass +2 ulp", 4, 2, 1, 0.5, 1),
                                      record("h", "libm", 1, 1, 0, 0.0, 0), record("h", "mass +2 ulp", 1, 1, 0, 0.0, 0)]
    md = conditioning_markdown(table, per.assign(machine_openblas="Haswell"))
    assert md.startswith("Measured on a machine whose OpenBLAS picks its Haswell kernels, under 2 perturbations "
                         "(libm, mass +2 ulp).")
    assert _cells(md, "figure") == ["figure", "arrays", "libm", "mass +2 ulp"]
    assert _cells(md, "f") == ["f", "4", "2 (1)", "2 (1)"] and _cells(md, "g") == ["g", "1", "0 (0)", "0 (0)"]
    assert _cells(md, "h") == ["h", "1", "1 (0)", "1 (0)"]
    moved = md.split("The arrays that moved, and by how much:")[1]
    rows = [[c.strip() for c in x.strip("|").split("|")] for x in moved.splitlines() if x.startswith("| f ")]
    assert [r[:4] for r in rows] == [["f", "a", "strict", "exact"], ["f", "b", "motions", "exact"],
                                     ["f", "e", "strict", "exact"]]
    assert rows[0][4:] == ["libm: 3; mass +2 ulp: 0.5", "fail under libm"] and "| g " not in moved
    # measured under one perturbation, with no kernel set reported
    one = conditioning_markdown(table, summary(table, ["mass +2 ulp"]))
    assert one.startswith("Measured on a machine whose OpenBLAS picks its unreported kernels, under 1 "
                          "perturbations (mass +2 ulp).")
    assert _cells(one, "f") == ["f", "4", "2 (1)"] and _cells(one, "g") == ["g", "1", "0 (0)"]
