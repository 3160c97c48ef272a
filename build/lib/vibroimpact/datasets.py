"""One place for every variable's units and descriptions; datasets are built through it."""

from __future__ import annotations

import datetime as _dt
import json

import numpy as np
import xarray as xr

from ._version import __version__

#: name -> (units, long_name, description)
VARIABLES: dict[str, tuple[str, str, str]] = {
    "t": ("1", "impact time", "non-dimensional time t = omega tau / pi of the event (forcing period 2)"),
    "wall": ("1", "wall", "+1 bottom membrane (Z = d/2), -1 top membrane (Z = -d/2), 0 in flight"),
    "v_minus": ("1", "pre-impact relative velocity Zdot-",
                "signed: positive at the bottom wall, negative at the top wall; 0 for stick and release, NaN at a start in flight"),
    "v_plus": ("1", "post-event relative velocity Zdot+", "Zdot+ = -r Zdot- at an impact; 0 at stick and release"),
    "phase": ("rad", "impact phase", "phi_k = mod(pi t_k + phi, 2 pi)"),
    "z": ("1", "relative position Z at the event", "Z = X* - x*"),
    "dt": ("1", "time since the previous event", "Delta t_k = t_k - t_{k-1}"),
    "kind": ("1", "event kind", "see flag_values and flag_meanings"),
    "Z": ("1", "relative position Z = X* - x*", "cylinder centre minus ball, non-dimensional"),
    "Zdot": ("1", "relative velocity dZ/dt", ""),
    "X": ("1", "cylinder displacement X*", "X*(t) = -cos(pi t + phi) / pi^2 (zero-mean periodic cylinder motion)"),
    "x": ("1", "ball displacement x*", "x* = X* - Z"),
    "time": ("1", "time t", "non-dimensional time"),
    "d": ("1", "non-dimensional cylinder length d", "d = s M omega^2 / (F pi^2)"),
    "gbar": ("1", "non-dimensional gravity gbar", "gbar = M g sin(beta) / F"),
    "r": ("1", "coefficient of restitution r", ""),
    "phi": ("rad", "forcing phase at t0", ""),
    "v0": ("1", "pre-impact velocity of the initial bottom impact", "paper convention, docs/model.md"),
    "n_events": ("1", "number of recorded events", ""),
    "status": ("1", "run status", "see flag_values and flag_meanings"),
    "period_events": ("1", "events per period of the attractor", "0 when no period was identified"),
    # energy (docs/model.md, paper eq. V1)
    "gain": ("V", "output voltage U_k - U_in at each impact", ""),
    "U_I": ("V", "average output voltage per impact (eq. V1)", ""),
    "U_T": ("V", "average output voltage per unit of non-dimensional time (eq. V1)", ""),
    "speed": ("m/s", "dimensional impact speed", "|Zdot-| F pi / (M omega)"),
    "window_time": ("1", "non-dimensional time the averages are taken over", "inf where the ball rests on the bottom for good"),
    "window_impacts": ("1", "impacts the averages are taken over", ""),
    # caption orbits against the exact attractor
    "motion_stated": ("1", "motion stated in the caption (n:m)", ""),
    "motion_found": ("1", "attractor found by exact simulation", ""),
    "v_attractor": ("1", "attractor's bottom impact velocity Zdot- nearest the caption's", ""),
    "phase_attractor": ("rad", "attractor's bottom impact phase nearest the caption's", ""),
    "dv": ("1", "v_attractor minus the caption's Zdot(t0)", ""),
    "dphase": ("rad", "phase_attractor minus the caption's phi (wrapped)", ""),
    "reproduced": ("1", "the stated n:m motion is the attractor", ""),
}


def annotate(ds: xr.Dataset) -> xr.Dataset:
    """Attach units, long_name and description to every known variable and coordinate."""
    for name in list(ds.variables):
        if name in VARIABLES:
            units, long_name, description = VARIABLES[name]
            ds[name].attrs.update(units=units, long_name=long_name)
            if description:
                ds[name].attrs["description"] = description
    return ds


def provenance(**config) -> dict:
    """Global attributes: package version, creation time and the configuration that made the data."""
    return {
        "vibroimpact_version": __version__,
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "config": json.dumps(config, sort_keys=True, default=_jsonable),
    }


def _jsonable(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)


def write_netcdf(ds: xr.Dataset, path, *, fmt: str = "NETCDF4") -> None:
    """Write atomically (temporary file then rename) with the netCDF4 engine: never a partial file.
    ``fmt="NETCDF3_64BIT"`` suits many small float variables (a figure's data: a third of the size)."""
    import os
    import tempfile
    from pathlib import Path

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".part")
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="netcdf4", format=fmt)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
