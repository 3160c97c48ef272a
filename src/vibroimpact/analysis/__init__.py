"""The analysis: periodic orbits and their stability, continuation in one and two parameters,
grazing, settled attractors, sweeps, basins and maps, energy, design under multistability.  Built
on :mod:`vibroimpact.dynamics`."""
