"""The registry of figures: one row per figure the workflow draws, the one place that names them.

Each row gives the figure's file stem (for the paper's figures its LaTeX label: ``fig0`` for Figure 2),
the number the published paper prints for it (None for the project's own figures), the plot function that
draws it, the Snakemake rule that runs it, its caption in ``workflow/report/`` and the rule that checks its
arrays against the committed reference.  The workflow's target lists, the report's captions, the
documentation's figures page and the tests read these rows; :data:`vibroimpact.outputs.paper.FIGURE_NUMBERS`
is derived from them.

A figure is found by its printed number or its stem::

    >>> figure(5).stem, figure(5).plot
    ('fig2', 'vibroimpact.outputs.plots.branches:fig2')
    >>> figure("fig5").number
    9

To add a figure, write its plot function (it returns a matplotlib figure drawn from the datasets it is given)
and its caption (``workflow/report/<stem>.rst``), and add one row below with ``rule="registry_figure"``: the
workflow's generic rule draws it from the row's ``inputs``, the default target and ``check`` include it and
the documentation shows it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from types import SimpleNamespace

import jinja2

__all__ = ["Figure", "REGISTRY", "RegistryError", "figure", "figures", "figure_numbers", "latex_label",
           "render_caption", "PAPER", "OWN"]

#: the report's category of the paper's figures and of the project's own
PAPER, OWN = "Paper figures", "Beyond the paper"


class RegistryError(KeyError):
    """A figure the registry does not hold."""

    def __str__(self):
        return str(self.args[0])


@dataclass(frozen=True)
class Figure:
    """One figure of the registry.

    Attributes
    ----------
    stem : str
        The file stem: ``results/figures/<stem>.png``, its arrays ``results/figures/data/<stem>.nc`` and its
        reference ``reference/figures/<stem>.nc``.  A family of figures, one per entry of a config section,
        writes the entry as a wildcard (``bifurcation_set_{map}``).
    number : int or None
        The number the published paper prints; None for the project's own figures.
    plot : str
        The plot function, ``module:function`` (resolved where it is called, so that reading the registry
        imports neither matplotlib nor the plot modules).
    rule : str
        The Snakemake rule that draws it; ``registry_figure`` is the generic rule, which calls :attr:`plot`
        on the datasets :attr:`inputs` names.
    caption : str
        The caption template in ``workflow/report/``.
    title : str
        What it shows, the documentation's heading (after the printed number for a paper figure).
    check : str or None
        The rule that compares its arrays with the committed reference (None: not compared).
    caption_wildcard : str or None
        The wildcard the caption template tells figures apart by (``scene``, ``efig``, ...), valued with the stem
        (for a family: with its entry).
    configured : str or None
        The config section whose keys name the figures drawn (``scenes``: a scene of the config is drawn);
        for a family, the sections whose keys it is drawn for, joined by ``+``.  None: always drawn.
    target : str
        The Snakemake target that draws it: ``all`` (the default target), ``bench``, ``bifurcation`` or
        ``design_maps``.
    category : str
        The report's category (the generic rule files its figures under "Registered figures").
    paper_device_only : bool
        Drawn by the default target only for the paper's device: the speed-and-accuracy figures are measured on
        it whatever the config (the analytics' accuracy against the paper's G1 and G2).
    inputs : tuple of str
        For :attr:`rule` ``registry_figure``: the files (relative to the results' root) whose datasets the plot
        function is called with, in order.
    member : str or None
        For a figure of a family, its entry (set by :func:`figure` and :func:`figures`).
    """

    stem: str
    number: int | None
    plot: str
    rule: str
    caption: str
    title: str
    check: str | None = "check_figure"
    caption_wildcard: str | None = None
    configured: str | None = None
    target: str = "all"
    category: str = OWN
    paper_device_only: bool = False
    inputs: tuple = ()
    member: str | None = field(default=None, compare=False)

    @property
    def family(self) -> bool:
        """Whether the row stands for one figure per entry of a config section."""
        return "{" in self.stem

    def caption_wildcards(self) -> dict:
        """The wildcards its caption template is rendered with (the report's and the documentation's)."""
        if self.caption_wildcard is None:
            return {}
        return {self.caption_wildcard: self.member or self.stem}

    def named(self, member: str) -> Figure:
        """The figure of a family for one entry of its config section."""
        return replace(self, stem=self.stem.format(**{self.caption_wildcard or "member": member}), member=member)

    def heading(self) -> str:
        """Its heading in the documentation: a paper figure by its printed number with its LaTeX label beside it
        and what it shows (``Figure 5 (Fig 2): the 2:1 branches``), a figure of a family with its plane."""
        if self.number is not None:
            return f"Figure {self.number} ({latex_label(self.stem)}): {self.title}"
        if self.member is not None:
            plane = ", ".join(AXIS_SYMBOLS.get(a, a) for a in self.member.split("_"))
            return self.title.format(**{self.caption_wildcard or "member": plane})
        return self.title


_PLOTS = "vibroimpact.outputs.plots"

#: how a family's headings write the axes of a plane named ``<x>_<y>`` in the config (``s_beta``: "s, β")
AXIS_SYMBOLS = {"beta": "β", "F": "‖F̂‖", "gbar": "ḡ"}


def _scene(stem, number, plot, title):
    return Figure(stem, number, f"{_PLOTS}.orbits:{plot}", "scene_figure", "scene.rst", title,
                  caption_wildcard="scene", configured="scenes", category=PAPER)


def _branches(stem, number, title):
    return Figure(stem, number, f"{_PLOTS}.branches:{stem}", stem, f"{stem}.rst", title,
                  configured="branch_scenes", category=PAPER)


def _energy(stem, number, title):
    return Figure(stem, number, f"{_PLOTS}.energy:fig_energy", "energy_figure", "energy.rst", title,
                  caption_wildcard="efig", configured="energy.figures", category=PAPER)


def _bench(stem, title, target="all"):
    return Figure(stem, None, f"{_PLOTS}.bench:fig_{stem}", "bench_figure", "bench.rst", title,
                  caption_wildcard="bench", category="Speed and accuracy", paper_device_only=True, target=target)


#: every figure, in the order the workflow lists them (the paper's are shown in the order of their numbers)
REGISTRY: tuple[Figure, ...] = (
    _scene("fig0b", 4, "fig0b", "time series of the 1:1, 2:1 and 3:1 motions"),
    _scene("fig4", 7, "fig4", "phase portraits near grazing, β = π/6"),
    _scene("figFN2", 3, "figFN2", "phase portraits from 1:1 through grazing to 2:1, β = π/2 and π/6"),
    _branches("fig2", 5, "the 2:1 branches"),
    _branches("fig3", 6, "stability of the 2:1 branches"),
    Figure("figBiS", 8, f"{_PLOTS}.sweeps:fig_bis", "figBiS", "figBiS.rst",
           "bistable 2:1 and 3:1 motions near grazing, β = π/6", category=PAPER),
    Figure("basins", None, f"{_PLOTS}.sweeps:fig_basins", "fig_basins", "basins.rst", "Basins of attraction"),
    Figure("regime_map", None, f"{_PLOTS}.sweeps:fig_regime_map", "fig_regime_map", "regime_map.rst",
           "Regime maps"),
    _energy("fig0", 2, "impact speeds and output voltages, β = π/3"),
    _energy("fig5", 9, "output voltages for four inclines"),
    Figure("lyapunov", None, f"{_PLOTS}.chaos:fig_lyapunov", "lyapunov_figure", "lyapunov.rst",
           "Largest Lyapunov exponent"),
    Figure("design", None, f"{_PLOTS}.energy:fig_design", "design", "design.rst", "Design guidance"),
    Figure("knocks", None, f"{_PLOTS}.design:fig_knocks", "registry_figure", "knocks.rst",
           "Output against critical shock", inputs=("results/knocks/map.nc",)),
    Figure("knock_section", None, f"{_PLOTS}.sweeps:fig_knock_section", "registry_figure", "knock_section.rst",
           "The basins a knock crosses", inputs=("results/knocks/section.nc",)),
    _bench("work_precision", "Work-precision"),
    _bench("failure_map", "Failure map"),
    _bench("analytics_accuracy", "Accuracy of the analytics"),
    # its timed job runs for a minute alone: drawn by the bench target, not the default one
    _bench("lyapunov_precision", "Speed against accuracy for λ₁", target="bench"),
    Figure("bifurcation_set_{map}", None, f"{_PLOTS}.sweeps:fig_bifurcation_set", "fig_bifurcation_set",
           "bifurcation_set.rst", "Bifurcation set over ({map})", caption_wildcard="map",
           configured="maps+bifurcation.maps", target="bifurcation"),
    Figure("design_map_{dmap}", None, f"{_PLOTS}.design:fig_design_map", "fig_design_map", "design_map.rst",
           "Design map over ({dmap})", caption_wildcard="dmap", configured="design.maps", target="design_maps"),
)


def _section(config: dict, dotted: str) -> list[str]:
    """The keys (or items) of the config section ``dotted`` (``energy.figures``), [] where it is absent."""
    node = config
    for key in dotted.split("."):
        node = node.get(key) if isinstance(node, dict) else None
        if node is None:
            return []
    return list(node)


def _members(row: Figure, config: dict) -> list[str]:
    return [m for part in row.configured.split("+") for m in _section(config, part)]


def figures(config: dict, *, target: str | None = None, paper_device: bool = True) -> list[Figure]:
    """The figures a config draws, each family expanded over its config section, in the registry's order.

    Parameters
    ----------
    config : dict
        The workflow's config (its sections ``scenes``, ``branch_scenes``, ``energy.figures``, ``maps``, ...).
    target : str, optional
        Only the figures this Snakemake target draws (``all``, ``bifurcation``, ``design_maps``).
    paper_device : bool, optional
        Whether the config's device is the paper's: the default target leaves out the figures measured on the
        paper's device only for another.

    Returns
    -------
    list of Figure
    """
    out = []
    for row in REGISTRY:
        if target is not None and (row.target != target or (row.paper_device_only and not paper_device)):
            continue
        if row.family:
            out += [row.named(m) for m in _members(row, config)]
        elif row.configured is None or row.stem in _section(config, row.configured):
            out.append(row)
    return out


def figure(key: int | str) -> Figure:
    """The row of a figure, by the number the paper prints (``figure(5)``) or by its stem (``"fig2"``, or a
    family's figure such as ``"bifurcation_set_s_F"``).

    Raises
    ------
    RegistryError
        No figure has this number or stem; the message lists those that do.
    """
    if isinstance(key, int) and not isinstance(key, bool):
        for row in REGISTRY:
            if row.number == key:
                return row
        raise RegistryError(f"no figure printed as Figure {key}: the paper's figures are "
                            f"{sorted(figure_numbers().values())} (Figure 1, the device, is not regenerated)")
    for row in REGISTRY:
        if row.stem == key:
            return row
        if row.family:
            wildcard = row.caption_wildcard or "member"
            pattern = re.escape(row.stem).replace(re.escape("{" + wildcard + "}"), "(?P<m>.+)")
            if (m := re.fullmatch(pattern, str(key))):
                return row.named(m["m"])
    raise RegistryError(f"no figure {key!r} in the registry: one of {[r.stem for r in REGISTRY]}")


def latex_label(stem: str) -> str:
    """The LaTeX label of a paper figure as the text writes it.

    Parameters
    ----------
    stem : str
        The figure's file stem.

    Returns
    -------
    str
        ``"Fig 0"`` for ``"fig0"``, ``"Fig FN2"`` for ``"figFN2"``.
    """
    return "Fig " + stem.removeprefix("fig")


def figure_numbers() -> dict[str, int]:
    """The paper's figures: stem -> printed number, in the paper's order."""
    return {r.stem: r.number for r in sorted((r for r in REGISTRY if r.number is not None), key=lambda r: r.number)}


def render_caption(report_dir, fig: Figure, checks: dict) -> str:
    """A figure's caption as the report and the documentation show it: its template in ``report_dir``
    (``workflow/report``) rendered with its wildcards, the check results and the printed numbers.

    Parameters
    ----------
    report_dir : path-like
        The folder of the caption templates.
    fig : Figure
        The figure (a family's with its entry: :func:`figure`).
    checks : dict
        Each figure's check result (:func:`vibroimpact.outputs.checks.check_summaries`), ``{}`` before a check.

    Returns
    -------
    str
    """
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(report_dir)), undefined=jinja2.StrictUndefined)
    snakemake = SimpleNamespace(wildcards=SimpleNamespace(**fig.caption_wildcards()),
                                config={"_check_results": checks, "_figure_numbers": figure_numbers()})
    return env.get_template(fig.caption).render(snakemake=snakemake).strip()
