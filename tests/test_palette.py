"""One motion, one colour: the palette of every map, basin plot and sweep figure, read back from the figures."""

import json

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.colors import to_hex

from vibroimpact.analysis.sweeps import NO_PERIOD_LABELS
from vibroimpact.outputs.plots import fig_basins, fig_regime_map
from vibroimpact.outputs.plots._common import BOTTOM, MOTION_COLORS, TOP, motion_color

GBAR = 0.12201  # beta = pi/6 at the physics' force (Fig BiS)


def legend_colours(fig):
    """Motion -> colour of every legend entry of a map figure (patches)."""
    out = {}
    for leg in [*fig.legends, *(ax.get_legend() for ax in fig.axes if ax.get_legend())]:
        for h, t in zip(leg.legend_handles, leg.get_texts(), strict=True):
            if hasattr(h, "get_facecolor") and not hasattr(h, "get_marker"):
                out[t.get_text()] = to_hex(h.get_facecolor())
    return out


def regime(labels):
    labels = np.asarray(labels, dtype=str)
    ny, nx = labels.shape
    return xr.Dataset({"label": (("beta", "s"), labels)},
                      coords={"beta": ("beta", np.linspace(0.1, 1.5, ny), {"units": "rad"}),
                              "s": ("s", np.linspace(0.2, 0.7, nx), {"units": "m"})},
                      attrs={"phi": 0.42, "v0": 0.87, "F": 5.0})


def basins_set(labels):
    labels = np.asarray(labels, dtype=str)
    legend = list(dict.fromkeys(sorted(labels.ravel().tolist(), key=lambda x: -np.sum(labels == x))))
    code = np.vectorize(legend.index)(labels)
    return xr.Dataset({"attractor": (("phi", "v0"), code), "label": (("phi", "v0"), labels)},
                      coords={"phi": np.linspace(0, 6.2, labels.shape[0]), "v0": np.linspace(0.02, 1.2, labels.shape[1])},
                      attrs={"d": 0.14, "gbar": GBAR, "r": 0.5, "beta": np.pi / 6, "s": 0.2249, "F": 5.0, "M": 0.1245,
                             "omega": 5 * np.pi, "legend": json.dumps(legend)})


def test_one_motion_has_one_colour_in_every_figure():
    """3:1 period-2 is the rarest motion of a regime map and the most frequent of a basin plot: the regime
    map and the basins give it and every other motion one colour, the palette's, whatever the order of
    frequency."""
    regime_labels = np.repeat(["1:1 period-2", "2:1 period-2", "chaotic", "1:1 period-4", "3:1 period-2"],
                              [300, 150, 80, 50, 20]).reshape(30, 20)
    basin_labels = np.repeat(["3:1 period-2", "2:1 period-2"], [2000, 1000]).reshape(60, 50)
    figs = {"regime map": fig_regime_map([regime(regime_labels)]), "basins": fig_basins(basins_set(basin_labels))}
    colours = {name: legend_colours(f) for name, f in figs.items()}
    for f in figs.values():
        plt.close(f)
    assert {"3:1 period-2", "2:1 period-2"} <= set(colours["regime map"]) & set(colours["basins"])
    colours["regime map"].pop("the paper's sweeps (config names)", None)
    for motion in set().union(*colours.values()):
        seen = {name: table[motion] for name, table in colours.items() if motion in table}
        assert len(set(seen.values())) == 1, (motion, seen)  # the same in every figure that draws it
        assert set(seen.values()) == {to_hex(motion_color(motion))}  # and the palette's


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


@pytest.mark.parametrize("label", sorted(MOTION_COLORS))
def test_the_palette_is_fixed_and_keeps_greys_for_no_period_and_beige_for_other(label):
    from matplotlib.colors import to_rgb

    r, g, b = to_rgb(motion_color(label))
    grey = max(r, g, b) - min(r, g, b) < 1e-9
    assert grey == (label in NO_PERIOD_LABELS)
    assert motion_color(label) not in (to_hex(BOTTOM), to_hex(TOP))


def test_motions_the_table_does_not_list_get_one_colour_everywhere():
    assert motion_color("5:3 period-2") == motion_color("5:3 period-2")
    assert motion_color("1:4 period-2 with sticking") != motion_color("other")
    assert motion_color("7:2 over 3 forcing periods") not in [motion_color(n) for n in NO_PERIOD_LABELS]


def test_basins_name_the_incline_and_the_device():
    fig = fig_basins(basins_set(np.repeat(["3:1 period-2", "2:1 period-2"], [20, 10]).reshape(6, 5)))
    title = fig.axes[0].get_title()
    plt.close(fig)
    assert r"$\beta=\pi/6$" in title and "s = 0.2249 m" in title and "N" in title and "d = 0.14" in title
