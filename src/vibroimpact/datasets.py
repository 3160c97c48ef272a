"""One place for every variable's units and descriptions; datasets are built through it."""

from __future__ import annotations

import datetime as _dt
import json
import os
import tempfile
from pathlib import Path

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
    "v0": ("1", "pre-impact velocity of the initial bottom impact", "paper convention, docs/guide/model.md"),
    "n_events": ("1", "number of recorded events", ""),
    "status": ("1", "run status", "see flag_values and flag_meanings"),
    "period_events": ("1", "events per period of the attractor", "0 when no period was identified"),
    # energy (docs/guide/model.md, paper eq. V1)
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
    "caption": ("", "caption orbit (config name)", ""),
    "orbit_status": ("", "the caption's analytic orbit: found, or why not", ""),
    "orbit_deviation": ("1", "largest distance of the attractor's impacts from the analytic orbit's", ""),
    "v_orbit": ("1", "analytic orbit's bottom impact velocity Zdot- nearest the caption's", ""),
    "phase_orbit": ("rad", "analytic orbit's bottom impact phase nearest the caption's", ""),
    "v_orbit_at_d_rounding": ("1", "the same at the caption's d moved by its rounding", ""),
    # physical parameters
    "s": ("m", "cylinder length s", ""),
    "F": ("N", "forcing amplitude ||F||", ""),
    "beta": ("rad", "incline beta", ""),
    "omega": ("rad/s", "forcing angular frequency omega", ""),
    # branches and their stability (docs/guide/model.md)
    "eig_real": ("1", "real part of an eigenvalue of the monodromy matrix DP", ""),
    "eig_imag": ("1", "imaginary part of an eigenvalue of DP", ""),
    "eig_abs": ("1", "modulus of an eigenvalue of DP", ""),
    "trace": ("1", "trace Tr(DP) of the monodromy matrix (eq. Tr)", ""),
    "det": ("1", "determinant Det(DP) of the monodromy matrix", ""),
    "discriminant": ("1", "Delta = Tr^2 - 4 Det (eq. Lambda)", ""),
    "stable": ("1", "the orbit is linearly stable (every |eigenvalue| < 1)", ""),
    "stability": ("", "stability class (paper Table 1)", ""),
    "admissible": ("1", "every flight of the orbit stays between the walls", ""),
    "clearance": ("1", "smallest distance of a flight's interior extremum to a wall (negative: through it)", ""),
    "reason": ("", "why the orbit is not admissible (empty when it is)", ""),
    "motion": ("", "motion n:m of the word", ""),
    "critical_kind": ("", "critical point: B (eigenvalue -1), fold (+1), A (Delta = 0), NS, grazing", ""),
    "critical_admissible": ("1", "the orbit at the critical point is admissible", ""),
    "critical_refined": ("1", "located to xtol (else: linear estimate between branch points)", ""),
    "critical_note": ("", "why a critical point could not be refined (empty when it was)", ""),
    # sweeps, transitions, bistability
    "direction": ("", "sweep direction (up: d increasing, down: d decreasing)", ""),
    "label": ("", "motion of the attractor (n:m, period)", ""),
    "label_up": ("", "motion followed by the up sweep", ""),
    "label_down": ("", "motion followed by the down sweep", ""),
    "before": ("", "motion before the transition", ""),
    "after": ("", "motion after the transition", ""),
    "found_by": ("", "how the interval was found", ""),
    "lo_source": ("", "what bounds the interval below", ""),
    "hi_source": ("", "what bounds the interval above", ""),
    "panel": ("", "panel of the figure", ""),
    "word": ("", "orbit word (walls met over one period)", ""),
    # bifurcation set
    "curve_index": ("1", "the curve a point belongs to (index along curve)", ""),
    "curve_kind": ("", "kind of the point the curve follows (B, fold, A, grazing)", ""),
    "curve_word": ("", "word of the orbit the curve belongs to", ""),
    "curve_status": ("", "ok, or failed (see curve_reason)", ""),
    "curve_reason": ("", "why the point could not be followed (empty when it was)", ""),
    "curve_stop": ("", "why the curve ends, each way", ""),
    "event_kind": ("", "what the curve meets: another test function's zero, or a cusp", ""),
    "event_curve": ("1", "the curve of the event (index along curve)", ""),
    "curve_a": ("1", "first curve of the crossing (index along curve)", ""),
    "curve_b": ("1", "second curve of the crossing (index along curve)", ""),
    "name_a": ("", "first curve of the crossing (word and kind)", ""),
    "name_b": ("", "second curve of the crossing (word and kind)", ""),
    "label_a": ("", "attractor on the lower side of the boundary", ""),
    "label_b": ("", "attractor on the upper side of the boundary", ""),
    "on_curve": ("1", "a bifurcation curve passes within the tolerance of the boundary", ""),
    "cause": ("", "on a curve; else aperiodic (one side has no period) or jump (two periodic motions)", ""),
    "distance": ("1", "distance to the nearest curve, in grid cells", ""),
    # benchmarks
    "solver": ("", "method and its setting", ""),
    "family": ("", "method family", ""),
    "setting": ("1", "tolerance (solve_ivp, heyoka, Siconos event-driven) or step h (RK4, Moreau-Jean)", ""),
    "scene": ("", "benchmark scene", ""),
    "case": ("", "hard case of the failure map", ""),
    "outcome": ("", "outcome of the method on the case", ""),
    "detail": ("", "what the method did on the case", ""),
    "reached": ("1", "the method reaches the matched accuracy", ""),
    "stage": ("", "stage timed", ""),
    "step": ("1", "continuation arclength step", ""),
    "points": ("1", "sweep points per direction", ""),
    "point_kind": ("", "kind of located point", ""),
    "grazing": ("", "grazing point (G1, G2)", ""),
    # the paper's d_graz: where the 1:1 attractor, followed with decreasing d, leaves the 1:1 family
    # (vibroimpact.analysis.family_exit)
    "d_graz": ("1", "d_graz: d where the 1:1 attractor followed down leaves the 1:1 family",
               "middle of the final bracket; a grazing where d_graz_kind says so"),
    "d_graz_width": ("1", "width of d_graz's final bracket", ""),
    "d_graz_clearance": ("1", "smallest clearance of the last 1:1 attractor (bracket's upper end)",
                         "distance of its flights' interior extrema to a wall; tends to 0 at a grazing"),
    "d_graz_slowest_after": ("1", "slowest impact speed |Zdot-| of the motion beyond d_graz", ""),
    "d_graz_kind": ("", "grazing (clearance below GRAZING_CLEARANCE d) or no grazing", ""),
    "d_graz_after": ("", "motion beyond d_graz (bracket's lower end)", ""),
    "d_graz_status": ("", "located, or why not", ""),
    "d_graz_sampled": ("1", "d_graz's clearance is a sample's least (the last 1:1 motion has no period)", ""),
    "d_graz_s": ("m", "cylinder length s at d_graz", ""),
    "d_graz_F": ("N", "forcing amplitude ||F|| at d_graz", ""),
}

#: index dimensions: name -> what one index is
INDEX = {
    "point": "point (of the branch or curve, by arclength; of the sweep, by d)", "impact": "impact of one period",
    "event": "event", "critical": "critical or grazing point", "curve": "curve of the set",
    "crossing": "crossing of two curves", "boundary": "simulated boundary of the map", "transition": "located transition",
    "interval": "bistable interval", "eig": "eigenvalue of DP", "sim": "simulated point", "run": "run",
    "line": "line of the plane followed with d decreasing",
}
#: prefixes whose variable is another variable at a located place: prefix -> where
AT = {"critical_": "at the critical point", "event_": "where the curve meets another set",
      "crossing_": "where the two curves cross"}


def annotate(ds: xr.Dataset) -> xr.Dataset:
    """Attach units (where numeric), long_name and description to every known variable and coordinate
    (CF style: strings and labels get a long_name only), to the index dimensions, and to a variable
    named ``<prefix><known name>`` (:data:`AT`) from the known one; what a builder set stays."""
    for name in list(ds.variables):
        attrs = ds[name].attrs
        entry = VARIABLES.get(name)
        if entry is None and name in INDEX:
            entry = ("1", f"index of the {INDEX[name]}", "")
        if entry is None:
            for prefix, where in AT.items():
                base = VARIABLES.get(name[len(prefix):]) if name.startswith(prefix) else None
                if base is not None:
                    entry = (base[0], f"{base[1]} {where}", "")
                    break
        if entry is None:
            continue
        units, long_name, description = entry
        if units and ds[name].dtype.kind in "fiub":
            attrs.setdefault("units", units)
        attrs.setdefault("long_name", long_name)
        if description:
            attrs.setdefault("description", description)
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
    """Write atomically (temporary file then rename): never a partial file; annotated first
    (:func:`annotate`).  ``fmt="NETCDF3_64BIT"`` suits many small float variables (a figure's data: a
    third of the size); it is written by scipy's engine, which writes the header once, where the netCDF4
    library rewrites it for every variable (the difference grows with the number of variables; the same
    dataset read back).  NETCDF4 files are written by the netCDF4 engine.  A dataset with more than one
    empty dimension (a figure that draws nothing in some panels) is written as NETCDF4: the classic format
    reads a zero length as its one unlimited dimension, and the netCDF library refuses a file with several."""

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    annotate(ds)  # every dataset written carries units and long names (CF style)
    if fmt.startswith("NETCDF3") and sum(size == 0 for size in ds.sizes.values()) > 1:
        fmt = "NETCDF4"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".part")
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="scipy" if fmt.startswith("NETCDF3") else "netcdf4", format=fmt)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def _codes(labels: np.ndarray):
    """Integer codes for labels, most frequent first; returns (codes, legend)."""
    uniq, counts = np.unique(labels, return_counts=True)
    legend = list(uniq[np.argsort(-counts, kind="stable")])
    lookup = {lab: i for i, lab in enumerate(legend)}
    return np.vectorize(lookup.__getitem__, otypes=[np.int16])(labels), legend


def attractor_codes(ds: xr.Dataset, dims) -> xr.Dataset:
    """``ds`` with the integer ``attractor`` of each cell on ``dims``: an index into its labels, most frequent
    first, listed in the variable's ``legend`` attribute and as JSON in the dataset's."""
    codes, legend = _codes(ds["label"].values)
    ds["attractor"] = (dims, codes, {"units": "1", "long_name": "attractor class (index into the legend)",
                                      "legend": "; ".join(f"{i}: {lab}" for i, lab in enumerate(legend))})
    ds.attrs["legend"] = json_list(legend)
    return ds


def json_list(items):
    """The items as a JSON list of strings (a netCDF attribute)."""
    return json.dumps([str(x) for x in items])
