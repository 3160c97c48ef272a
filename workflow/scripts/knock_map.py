"""The knock map: a design map over the configured plane (the design maps' start states, the knock preset's grid)
and the critical shock of every attractor of every point (vibroimpact.analysis.robust.knock_map)."""
import vibroimpact.outputs.job  # noqa: F401  (first: the job's garbage collector, before the heavy imports)

# isort: split
import logging

import numba

from vibroimpact.analysis.design import design_map, grid_axes, start_states
from vibroimpact.analysis.robust import knock_map, mark_choices
from vibroimpact.datasets import provenance, write_netcdf
from vibroimpact.dynamics.device import Device

logging.basicConfig(filename=snakemake.log[0], level=logging.INFO)
numba.set_num_threads(max(1, min(snakemake.threads, numba.config.NUMBA_NUM_THREADS)))
sp, kn, de, pre = snakemake.params.spec, snakemake.params.knocks, snakemake.params.design, snakemake.params.preset
device = Device.from_config(**snakemake.params.device)
xs, ys = grid_axes(sp, pre["grid"], de["table_betas"])  # the design table's inclines get rows of their own
st = de["starts"]
phi, v0 = start_states(pre["starts"], distribution=st["distribution"], seed=st["seed"], phi_range=st["phi_range"],
                       v0_range=st["v0_range"])
dm = design_map(sp["x"], xs, sp["y"], ys, phi=phi, v0=v0, device=device, max_periods=snakemake.params.max_periods,
                tol=snakemake.params.tol, window=snakemake.params.window, window_time=snakemake.params.window_time,
                min_share=de["min_share"], confidence=de["confidence"], **{k: sp[k] for k in ("beta", "s", "F") if k in sp})
# the points shared among the job's threads, one numba thread each (the same shocks as on one thread)
workers = max(1, snakemake.threads)
km = mark_choices(knock_map(dm, kind=kn["kind"], device=device, workers=workers), float(kn["knock"]))
km.attrs.update(provenance(**dict(snakemake.params)), map=kn["map"],
                distribution=st["distribution"], seed=st["seed"], workers=workers)
write_netcdf(km, snakemake.output[0])
runs = km["shock_runs"].values
logging.info("%d points, %d attractors knocked, %d runs (at most %d per motion)", km["top"].size,
             int((runs > 0).sum()), int(runs.sum()), int(runs.max(initial=0)))
