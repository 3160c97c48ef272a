"""The figure regeneration check: data read back from a drawn figure and compared with a reference."""

import math

import numpy as np
import pytest

from vibroimpact.outputs import plots
from vibroimpact.outputs.figdata import compare, compare_image, figure_data, hash_distance, image_hash


def _figure(shift=0.0, extra=False):
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2)
    x = np.linspace(0, 1, 7)
    a.plot(x, x**2 + shift, label="parabola")
    a.plot(x, np.where(x > 0.5, np.nan, x), "--")
    a.scatter([0.1, 0.2], [1.0, 2.0], c=[3.0, 4.0])
    a.set_title("(a) test")
    a.set_xlabel("d")
    a.set_ylabel("U_T (V)")
    plots.wellposed(b.imshow(np.arange(6.0).reshape(2, 3)), "timing")  # declared a timing where it is drawn
    b.set_xlabel("cost per impact (µs)")
    if extra:
        a.plot([0, 1], [0, 1])
    return fig


def test_figure_data_is_what_is_drawn(tmp_path):
    fig = _figure()
    paths = plots.save(fig, tmp_path / "f", data=tmp_path / "data" / "f.nc", attrs={"config": "{}"})
    import xarray as xr

    ds = xr.load_dataset(paths[-1], engine="netcdf4")
    np.testing.assert_array_equal(ds["a0_line0_y"].values, np.linspace(0, 1, 7) ** 2)
    assert ds["a0_line0_y"].attrs["label"] == "parabola" and ds["a0_line0_y"].attrs["units"] == "V"
    assert ds["a0_line0_x"].attrs["units"] == "1" and ds["a0_line0_x"].attrs["axes_title"] == "(a) test"
    assert np.isnan(ds["a0_line1_y"].values[-1])
    np.testing.assert_array_equal(ds["a0_points0_c"].values, [3.0, 4.0])
    assert ds["a1_image0_z"].shape == (2, 3) and ds.attrs["config"] == "{}"


def test_each_artist_of_a_kind_is_numbered_in_drawing_order():
    """Two point sets in one axes are a0_points0 and a0_points1, in the order they were drawn (the names the
    documentation gives, which a regeneration's check pairs by)."""
    import matplotlib.pyplot as plt

    from vibroimpact.outputs.figdata import figure_data

    fig, ax = plt.subplots()
    ax.scatter([0.1, 0.2], [1.0, 2.0])
    ax.scatter([0.3], [5.0])
    ds = figure_data(fig)
    plt.close(fig)
    assert sorted(v for v in ds.data_vars if "points" in v) == ["a0_points0_x", "a0_points0_y", "a0_points1_x",
                                                                "a0_points1_y"]
    np.testing.assert_array_equal(ds["a0_points1_y"].values, [5.0])


def test_save_writes_the_formats_asked_for_and_refuses_a_figure_without_png(tmp_path):
    """PNG always (the report and the image check read it), other formats as the quality preset asks;
    the Snakemake helper takes them from the rule's named outputs."""
    from types import SimpleNamespace

    paths = plots.save(_figure(), tmp_path / "a", formats=("png",))
    assert [p.name for p in paths] == ["a.png"] and not (tmp_path / "a.pdf").exists()
    paths = plots.save(_figure(), tmp_path / "b", formats=("png", "pdf", "svg"))
    assert [p.suffix for p in paths] == [".png", ".pdf", ".svg"]
    assert (tmp_path / "b.pdf").read_bytes()[:4] == b"%PDF" and b"<svg" in (tmp_path / "b.svg").read_bytes()
    out = SimpleNamespace(png=str(tmp_path / "c.png"), pdf=str(tmp_path / "c.pdf"), data=str(tmp_path / "c.nc"))
    assert [p.name for p in plots.save_outputs(_figure(), out, data=out.data)] == ["c.png", "c.pdf", "c.nc"]
    for bad in (("pdf",), ("png", "eps")):
        with pytest.raises(ValueError, match="formats.*allowed: png"):
            plots.save(_figure(), tmp_path / "d", formats=bad)
    assert not (tmp_path / "d.pdf").exists()


def test_compare_passes_identical_data_and_names_every_difference():
    ref = figure_data(_figure())
    same = compare(figure_data(_figure()), ref, rtol=1e-9, atol=1e-12)
    assert set(same.status) == {"pass", "excluded"} and list(same.status).count("excluded") == 1  # the timing
    moved = compare(figure_data(_figure(shift=1e-6)), ref, rtol=1e-9, atol=1e-12)
    row = moved.set_index("variable").loc["a0_line0_y"]
    assert row.status == "fail" and row.max_difference == pytest.approx(1e-6, rel=1e-6)
    assert (moved.status == "pass").sum() == len(moved) - 2
    grown = compare(figure_data(_figure(extra=True)), ref, rtol=1e-9, atol=1e-12)
    assert grown.status.str.startswith("fail: new").sum() == 2
    lost = compare(ref, figure_data(_figure(extra=True)), rtol=1e-9, atol=1e-12)
    assert lost.status.str.startswith("fail: missing").sum() == 2


def test_compare_checks_nan_places_and_excludes_timings():
    """A timing is excluded because its figure declared it one where it drew it, not by its axis label: the
    same array declaring nothing is compared pointwise."""
    ref = figure_data(_figure())
    new = ref.copy(deep=True)
    new["a0_line1_y"].values[0] = math.nan
    new["a1_image0_z"].values[:] += 1.0
    df = compare(new, ref, rtol=1e-9, atol=1e-12).set_index("variable")
    assert df.loc["a0_line1_y", "status"].startswith("fail: NaN")
    assert df.loc["a1_image0_z", "status"] == "excluded" and df.loc["a1_image0_z", "provenance"] == "timing"
    for ds in (new, ref):
        ds["a1_image0_z"].attrs.pop("wellposed")
    assert compare(new, ref, rtol=1e-9, atol=1e-12).set_index("variable").loc["a1_image0_z", "status"] == "fail"


def test_a_redrawn_png_showing_the_same_image_keeps_its_committed_bytes(tmp_path):
    """In a git work tree, a figure redrawn with its data moved at rounding level (antialiased edges may move by
    a grey level) keeps the committed PNG, so the work tree stays clean; a figure that changed is written."""
    import subprocess

    from vibroimpact.outputs.plots._common import keep_committed_png, same_image

    git = ["git", "-C", str(tmp_path), "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run(git[:3] + ["init", "-q"], check=True)
    plots.save(_figure(), tmp_path / "f", formats=("png",))
    subprocess.run(git + ["add", "f.png"], check=True)
    subprocess.run(git + ["commit", "-q", "-m", "f"], check=True)
    committed = (tmp_path / "f.png").read_bytes()
    # a sub-pixel move (1e-6 of the axes) changes antialiased pixels by a grey level: another file, the same image
    plots.save(_figure(shift=1e-6), tmp_path / "h", formats=("png",))
    assert (tmp_path / "h.png").read_bytes() != committed and same_image(committed, tmp_path / "h.png")
    plots.save(_figure(shift=1e-6), tmp_path / "f", formats=("png",))
    assert (tmp_path / "f.png").read_bytes() == committed
    # drawn again as committed: the same bytes, kept
    plots.save(_figure(), tmp_path / "f", formats=("png",))
    assert (tmp_path / "f.png").read_bytes() == committed and keep_committed_png(tmp_path / "f.png")
    plots.save(_figure(shift=0.2), tmp_path / "f", formats=("png",))
    assert (tmp_path / "f.png").read_bytes() != committed and not same_image(committed, tmp_path / "f.png")
    # a file git does not track is written as drawn
    plots.save(_figure(), tmp_path / "g", formats=("png",))
    assert not keep_committed_png(tmp_path / "g.png")


def test_fig2_marks_and_names_every_admissible_critical_point():
    """Fig 2's data, read back from the drawn figure: a diamond at each located admissible critical
    point in range on each impact's curve, named once per panel (A1, A2, ... by increasing d)."""
    import vibroimpact as vi
    from vibroimpact.analysis.continuation import continue_orbit

    p = vi.Params.from_physical(s=0.14 / vi.Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    br = continue_orbit(vi.find_orbit(p, "BBT", 5.855, 0.4185), vary="s", d_range=(0.13, 0.21), step=2e-3)
    br.attrs["beta"] = math.pi / 6  # as the workflow records it
    lo, hi = 0.134, 0.205
    crit = {(str(k), round(float(d), 9)) for k, d, a in
            zip(br.critical_kind.values, br.critical_d.values, br.critical_admissible.values, strict=True)
            if a and lo <= d <= hi}
    assert {k for k, _ in crit} >= {"A", "grazing"}
    ds = figure_data(plots.fig2([br], [None], [(lo, hi)]))
    for col in range(3):
        xs = [float(ds[v].values[0]) for v in ds.data_vars
              if v.startswith(f"a{col}_line") and v.endswith("_x") and ds[v].attrs["marker"] == "D"]
        assert sorted(round(x, 9) for x in xs) == sorted(d for _, d in crit for _ in range(3))
        texts = sorted(ds[v].attrs["label"] for v in ds.data_vars if v.startswith(f"a{col}_text"))
        names = [s for s in texts if not s.startswith("P")]
        n_a = sum(k == "A" for k, _ in crit)
        assert names == sorted([f"A{i + 1}" for i in range(n_a)] + ["G"] * sum(k == "grazing" for k, _ in crit))
        # and each of the three curves its transition's name (BBT: P3 into the first bottom impact, P1, P2)
        assert [s for s in texts if s.startswith("P")] == ["P1", "P2", "P3"]


def test_branch_figures_draw_the_rows_that_exist_and_say_why_the_others_do_not():
    """Another device may have no 2:1 branch at an incline, or map a row's s range to d where its branch is not
    admissible: Figures 5 and 6 draw the other rows and say, in the row, what is missing and why."""
    import matplotlib.pyplot as plt
    import xarray as xr

    import vibroimpact as vi
    from vibroimpact.analysis.continuation import continue_orbit

    p = vi.Params.from_physical(s=0.14 / vi.Params.from_physical(s=1.0, beta=math.pi / 6).d, beta=math.pi / 6)
    br = continue_orbit(vi.find_orbit(p, "BBT", 5.855, 0.4185), vary="s", d_range=(0.13, 0.21), step=4e-3)
    br.attrs.update(beta=math.pi / 6, status="ok")
    failed = xr.Dataset(attrs=dict(beta=1.2, word="BBT", status="failed", reason="the attractor at d=0.18 is 1:1 period-2"))
    rows, ranges = [br, failed, br], [(0.134, 0.205), (0.134, 0.205), (0.3, 0.4)]
    for fig in (plots.fig2(rows, [None] * 3, ranges), plots.fig3(rows, ranges)):
        ncol = len(fig.axes) // 3
        texts = [" ".join(t.get_text().replace("\n", " ") for t in ax.texts) for ax in fig.axes[:3 * ncol]]
        drawn = [bool(ax.get_lines()) for ax in fig.axes[:3 * ncol]]
        titles = [ax.get_title() for ax in fig.axes[:3 * ncol]]
        plt.close(fig)
        assert drawn == [True] * ncol + [False] * 2 * ncol
        assert "not drawn: no 2:1 branch (the attractor at d=0.18 is 1:1 period-2)" in texts[ncol + ncol // 2]
        assert texts[2 * ncol + ncol // 2].startswith("not drawn: the 2:1 branch has no admissible point in this row's "
                                                      "d range [0.3, 0.4]")
        assert titles[ncol].startswith(f"({'abcdefghi'[ncol]}) ")  # the rows keep their letters
    # no G1 (the 2:1 branch's stable stretch does not end by grazing): only G2's line, and only G2 named
    fig = plots.fig2([br], [None], [(0.134, 0.205)], {"beta": math.pi / 6, "G1": np.nan, "G2": 0.1419})
    named = {t.get_text() for ax in fig.axes for t in ax.texts} & {"G1", "G2"}
    lines = [ln.get_xdata()[0] for ax in fig.axes for ln in ax.get_lines() if ln.get_linestyle() == "-."]
    plt.close(fig)
    assert named == {"G2"} and lines == [0.1419] * 3


def test_image_layer_sees_a_change_the_same_figure_does_not(tmp_path):
    """The same figure rendered twice hashes identically (Agg is deterministic); one added line or a
    moved curve changes the hash; a figure with timings is reported as excluded, not passed."""
    import xarray as xr

    hashes = []
    for k, kw in enumerate([{}, {}, {"extra": True}, {"shift": 0.3}]):
        paths = plots.save(_figure(**kw), tmp_path / f"f{k}", data=tmp_path / f"f{k}.nc")
        ds = xr.load_dataset(paths[-1], engine="netcdf4")
        assert ds.attrs["png_phash"] == image_hash(paths[0])
        hashes.append(ds)
    assert hash_distance(hashes[0].attrs["png_phash"], hashes[1].attrs["png_phash"]) == 0
    assert compare_image(hashes[1], hashes[0], max_distance=0)["status"] == "pass"
    for changed in hashes[2:]:
        row = compare_image(changed, hashes[0], max_distance=0)
        assert row["status"] == "fail" and row["max_difference"] > 0
    assert compare_image(hashes[2], hashes[0], max_distance=0, draws_timings=True)["status"] == "excluded"
    no_hash = hashes[0].copy()
    del no_hash.attrs["png_phash"]
    assert compare_image(no_hash, hashes[0], max_distance=0)["status"].startswith("fail: no image hash")


def test_methods_needing_a_system_package_are_excluded_present_or_absent():
    """Siconos' rows are drawn where it is installed: the check excludes them whether only the
    reference or only the new data has them, and still compares everything else."""
    import xarray as xr

    def ds(with_peer, y=1.0):
        v = {"a0_line0_y": xr.Variable(("n",), [y, 2.0], {"label": "heyoka", "axes_title": "2:1", "axis_label": "err"})}
        if with_peer:
            v["a0_line1_y"] = xr.Variable(("n",), [5.0, 6.0], {"label": "Siconos event-driven", "axes_title": "2:1",
                                                                  "axis_label": "err"})
            v["a1_image0_z"] = xr.Variable(("r", "c"), [[1.0]], {"label": "", "axes_title": "Siconos (system package)",
                                                                   "axis_label": "image"})
        return xr.Dataset(v)

    for new, ref in ((ds(False), ds(True)), (ds(True), ds(False))):
        df = compare(new, ref, rtol=1e-9, atol=0.0, optional=["Siconos"])
        assert set(df.status) == {"pass", "excluded"} and (df.status == "excluded").sum() == 2
    df = compare(ds(False, y=1.5), ds(True), rtol=1e-9, atol=0.0, optional=["Siconos"])
    assert df.set_index("variable").status["a0_line0_y"] == "fail"
    assert (compare(ds(False), ds(True), rtol=1e-9, atol=0.0).status == "fail: missing").sum() == 2
