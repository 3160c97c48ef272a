"""The benchmarks: the simulation methods compared (ours and the peers heyoka and Siconos),
work-precision, the failure map.  Built on :mod:`vibroimpact.dynamics` and :mod:`vibroimpact.analysis`."""
