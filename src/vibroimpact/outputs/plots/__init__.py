"""Figures drawn from saved datasets, one module per family of figures.  The paper's figures are named by the
numbers the published paper prints (the function names keep the paper's LaTeX labels: ``fig2`` draws Figure 5);
the registry of figures (:mod:`vibroimpact.outputs.registry`, ``figure(5)``) says which function draws which:

- :mod:`.orbits`: single trajectories (Figures 3, 4 and 7);
- :mod:`.branches`: analytic branches and their stability (Figures 5 and 6);
- :mod:`.sweeps`: sweeps and bistability (Figure 8), basins, regime maps, bifurcation sets;
- :mod:`.energy`: voltages (Figures 2 and 9) and design guidance;
- :mod:`.chaos`: the largest Lyapunov exponent under the bifurcation diagrams of Figures 2 and 9;
- :mod:`.design`: design maps under multistability;
- :mod:`.bench`: speed against accuracy.

All share one style file (``vibroimpact.mplstyle``) and :func:`save`, which writes the PDF, the PNG
and the arrays the figure draws.
"""

from ._common import STYLE_FILE, save, save_outputs, use_style, wellposed
from .bench import fig_analytics_accuracy, fig_failure_map, fig_lyapunov_precision, fig_work_precision
from .branches import critical_markers, fig2, fig3
from .chaos import fig_lyapunov
from .design import fig_design_map
from .energy import fig_design, fig_energy
from .orbits import NEAR_GRAZING, fig0b, fig4, figFN2, phase_portrait, time_series
from .sweeps import fig_basins, fig_bifurcation_set, fig_bis, fig_regime_map

__all__ = ["NEAR_GRAZING", "STYLE_FILE", "critical_markers", "fig0b", "fig2", "fig3", "fig4", "figFN2",
           "fig_analytics_accuracy", "fig_basins", "fig_bis", "fig_design", "fig_design_map", "fig_energy", "fig_failure_map", "fig_lyapunov",
           "fig_bifurcation_set", "fig_regime_map", "fig_lyapunov_precision", "fig_work_precision", "phase_portrait", "save", "save_outputs", "time_series", "use_style", "wellposed"]
