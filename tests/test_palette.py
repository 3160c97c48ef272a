"""One motion, one colour: the palette of every map, basin plot and sweep figure, read back from the figures."""

import json
import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from conftest import ROOT
from matplotlib.colors import to_hex

from vibroimpact.analysis.motions import NO_PERIOD_LABELS, Motion, orbit_motion
from vibroimpact.outputs.plots import fig_basins, fig_bis, fig_regime_map
from vibroimpact.outputs.plots._common import (
    BOTTOM,
    EXTRA_COLORS,
    MOTION_COLORS,
    OTHER,
    OTHER_COLOR,
    STICKING_COLORS,
    TOP,
    motion_color,
    sticking_motions,
)
from vibroimpact.outputs.plots.sweeps import BIS_MARKERS, BIS_POINTS, STICKING_KEY

GBAR = 0.12201  # beta = pi/6 at the physics' force (Fig BiS)


def legend_colours(fig):
    """Motion -> colour of every legend entry of a map figure (patches)."""
    out = {}
    for leg in [*fig.legends, *(ax.get_legend() for ax in fig.axes if ax.get_legend())]:
        for h, t in zip(leg.legend_handles, leg.get_texts(), strict=True):
            if hasattr(h, "get_facecolor") and not hasattr(h, "get_marker"):
                out[t.get_text()] = to_hex(h.get_facecolor())
    return out


def regime(labels, sticking=()):
    labels = np.asarray(labels, dtype=str)
    ny, nx = labels.shape
    return xr.Dataset({"label": (("beta", "s"), labels), "sticking": (("beta", "s"), np.isin(labels, list(sticking)))},
                      coords={"beta": ("beta", np.linspace(0.1, 1.5, ny), {"units": "rad"}),
                              "s": ("s", np.linspace(0.2, 0.7, nx), {"units": "m"})},
                      attrs={"phi": 0.42, "v0": 0.87, "F": 5.0})


def basins_set(labels):
    labels = np.asarray(labels, dtype=str)
    legend = list(dict.fromkeys(sorted(labels.ravel().tolist(), key=lambda x: -np.sum(labels == x))))
    code = np.vectorize(legend.index)(labels)
    return xr.Dataset({"attractor": (("phi", "v0"), code), "label": (("phi", "v0"), labels),
                       "sticking": (("phi", "v0"), np.zeros(labels.shape, bool))},
                      coords={"phi": np.linspace(0, 6.2, labels.shape[0]), "v0": np.linspace(0.02, 1.2, labels.shape[1])},
                      attrs={"d": 0.14, "gbar": GBAR, "r": 0.5, "beta": np.pi / 6, "s": 0.2249, "F": 5.0, "M": 0.1245,
                             "omega": 5 * np.pi, "legend": json.dumps(legend)})


def bis_inputs(n=60):
    """A synthetic Fig BiS: a sweep over d in [0.136, 0.144] whose down sweep finds 2:1 above G1 = 0.1376
    and 3:1 below, the up sweep 3:1 below G2 = 0.1419 and 2:1 above; portraits of the caption orbits of
    Fig BiS (e), (f); analytic branches, the 3:1 one with a fold at G2 (multiplier crossing +1, slowest
    impact 0.03)."""
    d = np.linspace(0.136, 0.144, n)
    g1, g2 = 0.1376, 0.1419
    lab = np.where(np.stack([d < g2, d < g1]), "3:1 period-2", "2:1 period-2")  # up, down
    nev = np.where(lab == "3:1 period-2", 4, 3)
    t = np.full((2, n, 8), np.nan)
    v = np.full((2, n, 8), np.nan)
    for k in range(2):
        for i in range(n):
            t[k, i, :2 * nev[k, i]] = np.cumsum(np.full(2 * nev[k, i], 2.0 / nev[k, i]))
            v[k, i, :2 * nev[k, i]] = np.tile(np.linspace(0.05, 0.45, nev[k, i]), 2)
    sw = xr.Dataset({"label": (("direction", "point"), lab), "sticking": (("direction", "point"), np.zeros(lab.shape, bool)),
                     "t": (("direction", "point", "event"), t),
                     "v_minus": (("direction", "point", "event"), v), "phase": (("direction", "point", "event"), v * 10),
                     "period_events": (("direction", "point"), nev)},
                    coords={"direction": ["up", "down"], "d": ("point", d)})
    m = 4
    portraits = xr.Dataset({"Z": (("panel", "sample"), np.zeros((m, 5))), "Zdot": (("panel", "sample"), np.zeros((m, 5))),
                            "word": ("panel", ["BBT", "BBT", "BBBT", "BBBT"]), "d": ("panel", [0.14] * 4),
                            "v0": ("panel", [0.41860685] * 2 + [0.39663633] * 2), "phi": ("panel", [5.85479958] * 2 + [5.88049505] * 2)},
                           coords={"panel": ["G1", "d=0.14 (2:1)", "d=0.14 (3:1)", "G2"]},
                           attrs={"G1": g1, "G2": g2, "gbar": GBAR, "r": 0.5})

    def branch(word, d, lam, slow):
        p = d.size
        n_imp = word.count("B") + word.count("T")
        vm = np.column_stack([slow] + [np.full(p, 0.2 * (j + 1)) for j in range(n_imp - 1)])
        return xr.Dataset({"admissible": ("point", np.ones(p, bool)), "stable": ("point", lam < 1),
                           "v_minus": (("point", "impact"), vm), "phase": (("point", "impact"), vm),
                           "dt": (("point", "impact"), vm), "eig_real": (("point", "eig"), np.column_stack([lam, lam / 3])),
                           "eig_imag": (("point", "eig"), np.zeros((p, 2))),
                           "critical_kind": ("critical", ["fold"]), "critical_d": ("critical", [g2])},
                          coords={"d": ("point", d)}, attrs={"word": word, "k": 1})

    u = np.linspace(-1, 1, 40)
    b21 = branch("BBT", np.linspace(g1, 0.144, 41), np.full(41, 0.5), np.full(41, 0.19))
    b31 = branch("BBBT", g2 - 0.004 * u**2, 1 + 0.5 * u, 0.03 - 0.01 * u)  # fold at u = 0
    return sw, None, portraits, [b21, b31]


def bis_lines(fig):
    """Per plotted motion of Fig BiS's panels (a)-(c) and (h): its markers and colours."""
    out = {}
    for ax in fig.axes:
        for line in ax.get_lines():
            name = line.get_label().lstrip("_")
            if name.endswith(("d decreasing", "d increasing")):
                out.setdefault(name.split(",")[0], set()).add((line.get_marker(), to_hex(line.get_color())))
    return out


def test_one_motion_has_one_colour_in_every_figure():
    """3:1 period-2 is the rarest motion of a regime map and the most frequent of a basin plot (and drawn
    in Fig BiS): the regime map, the basins and Fig BiS give it and every other motion one colour, the
    palette's, whatever the order of frequency."""
    regime_labels = np.repeat(["1:1 period-2", "2:1 period-2", "chaotic", "1:1 period-4", "3:1 period-2"],
                              [300, 150, 80, 50, 20]).reshape(30, 20)
    basin_labels = np.repeat(["3:1 period-2", "2:1 period-2"], [2000, 1000]).reshape(60, 50)
    figs = {"regime map": fig_regime_map([regime(regime_labels)]), "basins": fig_basins(basins_set(basin_labels))}
    colours = {name: legend_colours(f) for name, f in figs.items()}
    bis = fig_bis(*bis_inputs())
    colours["Fig BiS"] = {m: c for m, s in bis_lines(bis).items() for _, c in s}
    for f in [*figs.values(), bis]:
        plt.close(f)
    assert {"3:1 period-2", "2:1 period-2"} <= set(colours["regime map"]) & set(colours["basins"]) & set(colours["Fig BiS"])
    colours["regime map"].pop("the paper's sweeps (config names)", None)
    for motion in set().union(*colours.values()):
        seen = {name: table[motion] for name, table in colours.items() if motion in table}
        assert len(set(seen.values())) == 1, (motion, seen)  # the same in every figure that draws it
        assert set(seen.values()) == {to_hex(motion_color(motion))}  # and the palette's


def test_fig_bis_marker_says_the_motion_and_the_points_are_thinned():
    """Paper: 2:1 open circles, 3:1 crosses, in both sweep directions; every direction at most
    BIS_POINTS points a panel (200 merge into bands), the up sweep's between the down sweep's."""
    fig = fig_bis(*bis_inputs(n=200))
    lines = bis_lines(fig)
    assert lines == {"2:1 period-2": {("o", to_hex(motion_color("2:1 period-2")))},
                     "3:1 period-2": {("+", to_hex(motion_color("3:1 period-2")))}}
    ax = fig.axes[0]
    d = {k: np.unique(np.concatenate([ln.get_xdata() for ln in ax.get_lines() if ln.get_label().endswith(k)]))
         for k in ("d decreasing", "d increasing")}
    plt.close(fig)
    assert all(0 < x.size <= BIS_POINTS for x in d.values())
    assert not set(d["d decreasing"]) & set(d["d increasing"])  # interleaved, not on top of each other
    assert BIS_MARKERS == {"2:1 period-2": "o", "3:1 period-2": "+"}


def test_fig_bis_names_the_motions_as_the_paper_does_and_marks_the_portraits_impacts():
    fig = fig_bis(*bis_inputs())
    titles = [ax.get_title() for ax in fig.axes]
    marks = [[ln for ln in ax.get_lines() if ln.get_label().startswith("_impacts of")] for ax in fig.axes[-4:]]
    plt.close(fig)
    assert not any("BBT" in t or "BBBT" in t for t in titles)
    assert [len(m) for m in marks] == [1, 1, 1, 1]
    assert [m[0].get_marker() for m in marks] == ["o", "o", "+", "+"]
    # the 2:1 orbit hits the bottom twice and the top once per period, the 3:1 orbit the bottom three times
    assert [m[0].get_xdata().size for m in marks] == [3, 3, 4, 4]
    assert "G2, fold of 3:1" in titles[-1] and "multiplier\n0.987 to 1.013, d turns back" in titles[-1]
    assert "slowest impact" in titles[-1] and "=0.030 > 0" in titles[-1]


def test_fig_bis_draws_what_another_device_has_and_says_what_is_missing():
    """No G1, G2 (the sweep finds no 2:1 -> 3:1), a failed 2:1 branch: the sweep, the 3:1 branch and the two
    portraits that exist are drawn, the figure says on its panels what is not drawn and why."""
    sw, tr, portraits, (b21, b31) = bis_inputs()
    why = "the sweep over d in [0.136, 0.144] finds no interval"
    portraits.attrs.update(G1=np.nan, G2=np.nan, G_missing=why)
    portraits["status"] = ("panel", [f"not drawn: no G1 ({why})", "drawn", "drawn", f"not drawn: no G2 ({why})"])
    b21 = xr.Dataset(attrs=dict(status="failed", reason="the attractor at d=0.18 is 1:1 period-2", word="BBT"))
    fig = fig_bis(sw, tr, portraits, [b21, b31])
    texts = " ".join(t.get_text().replace("\n", " ") for ax in fig.axes for t in ax.texts)
    titles = [ax.get_title() for ax in fig.axes]
    analytic = {to_hex(ln.get_color()) for ln in fig.axes[0].get_lines() if ln.get_linestyle() in ("-", "--")}
    drawn = [bool(ax.get_lines()) for ax in fig.axes[-4:]]
    plt.close(fig)
    assert "not drawn: analytic 2:1: the attractor at d=0.18 is 1:1 period-2" in texts
    assert f"not drawn: G1, G2: {why}" in texts and f"not drawn: no G2 ({why})" in texts
    assert drawn == [False, True, True, False] and titles[-1] == "(g) G2, fold of 3:1"
    assert analytic == {to_hex(motion_color("3:1 period-2"))}


def test_a_map_names_the_more_frequent_of_two_motions_with_one_colour():
    """Two motions without a colour of their own can draw the same one: the map names the more frequent,
    the other is "other"; no two named motions share a colour."""
    rule = [f"{n}:{m} period-2" for n in range(5, 12) for m in range(0, 3)]
    by_colour = {}
    for lab in rule:
        by_colour.setdefault(motion_color(lab), []).append(lab)
    a, b = next(v for v in by_colour.values() if len(v) > 1)[:2]
    labels = np.repeat(["1:1 period-2", a, b], [500, 60, 40]).reshape(30, 20)
    fig = fig_regime_map([regime(labels)])
    names = legend_colours(fig)
    plt.close(fig)
    assert a in names and b not in names and "other" in names
    shown = [c for n, c in names.items() if n != "the paper's sweeps (config names)"]
    assert len(shown) == len(set(shown))


@pytest.mark.parametrize("label", sorted([m.label for m in MOTION_COLORS] + [OTHER]))
def test_the_palette_is_fixed_and_keeps_greys_for_no_period_and_beige_for_other(label):
    from matplotlib.colors import to_rgb

    r, g, b = to_rgb(motion_color(label))
    grey = max(r, g, b) - min(r, g, b) < 1e-9
    assert grey == (label in NO_PERIOD_LABELS)
    assert motion_color(label) not in (to_hex(BOTTOM), to_hex(TOP))


def test_the_table_gives_each_motion_one_colour_by_the_motion_or_by_its_name():
    """The table is keyed by motions; a figure asks by the motion or by its label (as the datasets hold it) and
    gets the same colour; no two motions of the table share one, nor share a name."""
    assert all(isinstance(m, Motion) for m in MOTION_COLORS)
    assert {m.label: motion_color(m) for m in MOTION_COLORS} == {m.label: motion_color(m.label) for m in MOTION_COLORS}
    assert {m.label: motion_color(m) for m in MOTION_COLORS} == {m.label: c for m, c in MOTION_COLORS.items()}
    assert len(set(MOTION_COLORS.values()) | {OTHER_COLOR}) == len(MOTION_COLORS) + 1
    assert len({m.label for m in MOTION_COLORS} | {OTHER}) == len(MOTION_COLORS) + 1
    assert {m.label for m in MOTION_COLORS if not m.periodic} == set(NO_PERIOD_LABELS)
    two_one = Motion(period=1, bottom=2, top=1)
    assert motion_color(orbit_motion("BBT")) == motion_color("2:1 period-2") == MOTION_COLORS[two_one]


def test_motions_the_table_does_not_list_get_one_colour_everywhere():
    assert motion_color("5:3 period-2") == motion_color("5:3 period-2")
    assert motion_color("1:4 period-2 with sticking", sticking=True) in STICKING_COLORS
    assert motion_color("1:4 period-2 with sticking") in EXTRA_COLORS  # the flag decides, not the label
    assert motion_color("7:2 over 3 forcing periods") not in [motion_color(n) for n in NO_PERIOD_LABELS]


def test_basins_name_the_incline_and_the_device():
    fig = fig_basins(basins_set(np.repeat(["3:1 period-2", "2:1 period-2"], [20, 10]).reshape(6, 5)))
    title = fig.axes[0].get_title()
    plt.close(fig)
    assert r"$\beta=\pi/6$" in title and "s = 0.2249 m" in title and "N" in title and "d = 0.14" in title


def test_a_motion_with_sticking_is_drawn_in_brown_by_its_flag_with_the_key_that_says_so():
    """A regime map's motion whose ``sticking`` flag is set gets a brown and the legend says what sticking means;
    the same cells without the flag get neither (the figure reads the flag, never the label)."""
    labels = np.repeat(["3:1 period-2", "1:3 over 2 forcing periods with sticking"], [20, 10]).reshape(6, 5)
    sticky = regime(labels, sticking={"1:3 over 2 forcing periods with sticking"})
    assert sticking_motions(sticky) == {"1:3 over 2 forcing periods with sticking"}
    got = {}
    for name, m in (("flag", sticky), ("none", regime(labels))):
        fig = fig_regime_map([m])
        got[name] = legend_colours(fig)["1:3 over 2 forcing periods with sticking"], fig.legends[0].get_title().get_text()
        plt.close(fig)
    assert got["flag"][0] in [c.lower() for c in STICKING_COLORS] and got["none"][0] in [c.lower() for c in EXTRA_COLORS]
    first = STICKING_KEY.split("\n")[0]
    assert first in got["flag"][1] and first not in got["none"][1]


def _flat(path):
    return " ".join((ROOT / path).read_text().split())


def test_captions_and_pages_name_the_colours_and_styles_things_are_drawn_in():
    """Fig BiS's caption and the sweeps page name 2:1 and 3:1 by the colours the figure draws them in (the page
    said black for a vermillion 2:1); the captions of Figures 2 and 9, the lambda_1 figure and the bifurcation sets,
    and the energy page, name d_graz and the 1:1 exit by their colour and line style in every figure."""
    from vibroimpact.outputs.plots._common import COLOR_NAMES, MARKS, STYLE_NAMES

    name = {m: COLOR_NAMES[motion_color(m)] for m in ("2:1 period-2", "3:1 period-2")}
    for path in ("workflow/report/figBiS.rst", "docs/guide/sweeps.md"):
        assert f"2:1 {name['2:1 period-2']}, 3:1 {name['3:1 period-2']}" in _flat(path), path
    d_graz = f"({COLOR_NAMES[MARKS['d_graz'][0]]}, {STYLE_NAMES[MARKS['d_graz'][1]]})"
    exit_ = f"1:1 exit ({COLOR_NAMES[MARKS['1:1 exit: grazing'][0]]})"
    assert MARKS["1:1 exit: grazing"][0] == MARKS["1:1 exit: jump"][0]
    styles = [rf'"{re.escape(k)}" \(?{STYLE_NAMES[MARKS[k][1]]}\b' for k in ("1:1 exit: grazing", "1:1 exit: jump")]
    for path in ("workflow/report/energy.rst", "workflow/report/lyapunov.rst", "docs/guide/energy.md"):
        text = _flat(path)
        assert f"d_graz {d_graz}" in text and exit_ in text, path
        assert all(re.search(s, text) for s in styles), path
    assert f"The 2:1 fold {d_graz} is the paper's d_graz" in _flat("workflow/report/bifurcation_set.rst")
    assert "The 2:1 fold" in _flat("workflow/report/bifurcation_set.rst") and MARKS["d_graz"][1] == ":"


def test_the_captions_say_how_few_points_go_unnamed():
    """The names over the sweep panels leave gaps where fewer than MIN_POINTS points hold one motion; the captions
    and the figures' own notes say how many."""
    from vibroimpact.outputs.plots._common import MIN_POINTS, RUNS_NOTE

    words = {3: "three", 4: "four", 5: "five", 6: "six", 8: "eight", 10: "ten"}
    for path in ("workflow/report/energy.rst", "workflow/report/lyapunov.rst"):
        assert f"fewer than {words[MIN_POINTS]} points of one motion" in _flat(path), path
    assert f"fewer than {MIN_POINTS} points of one motion" in RUNS_NOTE
