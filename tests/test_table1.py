"""Paper Table 1: node or focus, stable or unstable, on each interval between the critical points B and A1, A2, ...
of the 2:1 branches, read from the branch data (vibroimpact.outputs.tables.stability_types)."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from vibroimpact.outputs.tables import stability_types, table1, table1_markdown

ROOT = Path(__file__).resolve().parents[1]

#: the paper's Table 1, by increasing d: d < d_B, d_B < d < d_A1, d_A1 < d < d_A2, d_A2 < d < d_A3, d > d_A3
PAPER_TABLE1 = ["unstable node", "stable node", "stable focus", "stable node", "stable focus"]


def synthetic_branch(crossings, b=0.13, fold=0.22, sign=1.0):
    """A branch up to a fold at ``fold`` and back: on the lower sheet Delta changes sign at each of ``crossings``
    (positive below the first, times ``sign``), the smaller eigenvalue crosses -1 at ``b``; the upper sheet is
    unstable with Delta > 0.  Critical points as the continuation records them (an A on the upper sheet too)."""
    up = np.linspace(0.11, fold, 221)
    down = up[::-1][1:]
    d = np.concatenate([up, down])
    lower = np.arange(d.size) < up.size
    disc = np.where(lower, sign * np.prod([c - d for c in crossings], axis=0), 0.5)
    lam = np.where(lower, -1.0 + 5 * (d - b), 2.0)
    stable = lower & (d > b)
    kinds = ["B", *["A"] * len(crossings), "fold", "A"]
    where = [b, *crossings, fold, 0.17]  # the last A lies on the upper sheet only
    return xr.Dataset(
        {"discriminant": ("point", disc), "eig_real": (("point", "eig"), np.column_stack([lam, np.full(d.size, 0.1)])),
         "stable": ("point", stable), "admissible": ("point", np.ones(d.size, bool)),
         "critical_kind": ("critical", kinds), "critical_d": ("critical", where)},
        coords={"d": ("point", d)}, attrs={"step": 1e-3, "beta": 0.5})


def test_each_interval_is_typed_from_the_data_at_its_middle():
    br = synthetic_branch([0.15, 0.19, 0.20])
    t = stability_types(br)
    assert list(t.type) == PAPER_TABLE1
    assert list(t.from_point) == ["branch end", "B", "A1", "A2", "A3"]
    assert list(t.to_point) == ["B", "A1", "A2", "A3", "fold"]
    assert t.d_to.iloc[0] == pytest.approx(0.13) and t.d_to.iloc[-1] == pytest.approx(0.22)


def test_the_other_sign_gives_the_other_types():
    """Nothing is typed by its place in the list: Delta of the opposite sign swaps every node and focus."""
    t = stability_types(synthetic_branch([0.15, 0.19, 0.20], sign=-1.0))
    assert list(t.type) == ["unstable focus", "stable focus", "stable node", "stable focus", "stable node"]


def test_table1_lists_the_types_as_the_paper_writes_its_intervals():
    df = table1([synthetic_branch([0.15, 0.19]).assign_attrs(status="ok")])
    assert df.types.iloc[0] == ("d < d_B: unstable node; d_B < d < d_A1: stable node; d_A1 < d < d_A2: stable focus; "
                                "d_A2 < d < d_fold: stable node")
    assert "| 0.5000 | d < d_B: unstable node;" in table1_markdown(df)


def test_an_incline_without_a_2to1_branch_is_a_row_saying_why():
    """Another device may have no 2:1 branch at an incline (its attractor there is another motion): the table has
    its row, with the reason, beside the inclines that have one; and a table of such rows only is still written,
    with every column the paper-value check reads (NaN: nothing to compare)."""
    failed = xr.Dataset(attrs={"beta": 1.2, "status": "failed", "reason": "the attractor at d=0.18 is 1:1 period-2"})
    for branches in ([failed], [synthetic_branch([0.15, 0.19]).assign_attrs(status="ok"), failed]):
        df = table1(branches)
        md = table1_markdown(df)
        assert np.isnan(df.d_fold.iloc[-1]) and np.isnan(df.stable_from.iloc[-1])  # what the check reads
        assert "| 1.2000 | no 2:1 branch: the attractor at d=0.18 is 1:1 period-2 | | | | | |" in md
        assert "| 1.2000 | no 2:1 branch |" in md and "- 1.2000: no 2:1 branch (the attractor at d=0.18" in md
        assert ("| 0.5000 | d < d_B: unstable node;" in md) == (len(branches) == 2)


def check_branch_types(results):
    """On every continued 2:1 branch in ``results``: each interval's type holds at every point of the sheet inside
    it (one sign of Delta, one stability: its ends are all the sign changes), and the types follow the paper's
    Table 1."""
    import yaml

    cfg = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    r = cfg["physics"]["r"]  # Table 1's branches: the physics' restitution at the inclines of Figure 6 (not studies')
    files = [f for b in cfg["branch_scenes"]["fig3"]["betas"]
             for f in [Path(results, "branches", f"beta-{b:.4f}_r-{r:.4f}", "orbit-BBT_vary-s.nc")] if f.exists()]
    if not files:
        pytest.skip(f"no 2:1 branches in {results}/branches")
    for f in files:
        br = xr.load_dataset(f, engine="netcdf4")
        t = stability_types(br)
        assert len(t) >= 4, (f, t)
        d, disc, stable = br.d.values, br.discriminant.values, br.stable.values
        # the stable sheet: the side of the fold with more stable, admissible points
        k = int(np.argmax(d))
        ok = stable & br.admissible.values
        on_sheet = np.arange(d.size) <= k if ok[: k + 1].sum() >= ok[k:].sum() else np.arange(d.size) >= k
        for r in t.itertuples():
            inside = np.flatnonzero(on_sheet & (d > r.d_from + 1e-9) & (d < r.d_to - 1e-9))
            assert inside.size, (f, r)
            node = r.type.endswith("node")
            assert np.all(disc[inside] > 0) if node else np.all(disc[inside] < 0), (f, r)
            assert np.all(stable[inside] == r.type.startswith("stable")), (f, r)
        n = min(len(t), len(PAPER_TABLE1))
        assert list(t.type[:n]) == PAPER_TABLE1[:n], (f, list(t.type))


def test_the_built_branches_have_the_paper_s_types():
    """The 2:1 branches built in this checkout's results/ (skipped where none are built)."""
    check_branch_types(ROOT / "results")


@pytest.mark.slow
def test_the_default_target_s_branches_have_the_paper_s_types(default_run):
    clone, _ = default_run
    check_branch_types(clone / "results")
