"""Datasets for phase portraits and time series of single runs (paper Figures 3, 4, 7 and 8)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import xarray as xr

from ..analysis.continuation import continue_orbit
from ..analysis.motions import identify_attractor
from ..analysis.orbits import OrbitError, find_orbit, orbit_from_vector, orbit_run, parse_word, solve_orbit
from ..datasets import annotate
from ..dynamics.params import Params
from ..dynamics.runs import simulate, trajectory
from .paper import caption_figure, printed_unit

__all__ = ["add_located_grazing", "bistability_dataset", "caption_summary", "orbit_dataset", "summary_markdown"]


def orbit_dataset(
    params: Params,
    phi: float,
    v0: float,
    *,
    t_show: float,
    samples_per_unit: int,
    name: str = "",
    max_events: int = 200_000,
    tol: float = 1e-9,
) -> xr.Dataset:
    """A run from a bottom impact (paper convention) shown over ``0 <= t <= t_show``, with its attractor.

    The dense time series (``Z``, ``Zdot``, ``X``, ``x`` on dimension ``time``) and the events in
    the window (dimension ``impact``) start at the caption's initial condition, as the paper's
    figures do.  A separate run, stopped as soon as the motion repeats, identifies the attractor;
    its impacts on one period are on dimension ``cycle`` and its name (e.g. ``2:1 period-2``) in
    the attribute ``motion``.  ``v_attractor``/``phase_attractor`` are the bottom impact of the
    cycle closest to ``(v0, phi)``, and ``dv``/``dphase`` their differences from them.
    """
    run = simulate(params, phi, v0, t_end=t_show)
    times = np.linspace(0.0, t_show, int(round(samples_per_unit * t_show)) + 1)
    ds = trajectory(run, times)
    for var in ("t", "wall", "v_minus", "phase", "kind"):
        ds[var] = run[var]
    long = simulate(params, phi, v0, n_impacts=max_events, stop_when_periodic=True, tol=tol)
    att = identify_attractor(long, tol=tol)
    ds.attrs.update(run.attrs)
    ds.attrs.update(name=name, motion=att.label, periodic=int(att.periodic), period=att.period,
                    n_bottom=att.n_bottom, n_top=att.n_top, t_settled=att.t_settled,
                    events_to_identify=int(long.sizes["impact"]))
    if att.periodic:
        cyc = att.cycle.rename(impact="cycle")
        for var in ("t", "wall", "v_minus", "phase", "dt"):
            ds[f"cycle_{var}"] = cyc[var].reset_coords(drop=True)
            ds[f"cycle_{var}"].attrs = dict(cyc[var].attrs, long_name=f"attractor cycle: {cyc[var].attrs.get('long_name', var)}")
        bottom = cyc.where(cyc.wall == 1, drop=True)
        dphase = (bottom.phase.values - phi + np.pi) % (2 * np.pi) - np.pi
        j = int(np.argmin(np.abs(bottom.v_minus.values - v0) + np.abs(dphase)))
        ds.attrs.update(v_attractor=float(bottom.v_minus.values[j]), phase_attractor=float(bottom.phase.values[j]),
                        dv=float(bottom.v_minus.values[j] - v0), dphase=float(dphase[j]))
        # the same impact on the periodic orbit solved by Newton's method (independent of the run)

        walls = cyc.wall.values
        start = int(np.flatnonzero(walls == 1)[j])
        word = "".join("B" if w == 1 else "T" for w in np.roll(walls, -start))
        try:
            o = find_orbit(params, word, float(bottom.phase.values[j]), float(bottom.v_minus.values[j]), k=att.period)
            dev = max(abs(float(o.v_minus[0]) - ds.attrs["v_attractor"]),
                      abs((float(o.phase[0]) - ds.attrs["phase_attractor"] + np.pi) % (2 * np.pi) - np.pi))
            ds.attrs.update(orbit_word=word, v_orbit=float(o.v_minus[0]), phase_orbit=float(o.phase[0]),
                            orbit_deviation=dev, orbit_status="solved", orbit_clearance=float(o.clearance))
            # how much the printed d's rounding moves that impact: the orbit at d -+ half a unit
            h = 0.5 * printed_unit(params.d)
            vs, ps = [], []
            for dd in (params.d - h, params.d + h):
                try:
                    o2 = find_orbit(replace(params, d=dd), word, float(o.phase[0]), float(o.v_minus[0]), k=att.period)
                    ok = o2.admissible
                except OrbitError:
                    ok = False
                vs.append(float(o2.v_minus[0]) if ok else np.nan)
                ps.append(float(o2.phase[0]) if ok else np.nan)
            ds.attrs.update(d_rounding=h, v_orbit_at_d_rounding=vs, phase_orbit_at_d_rounding=ps)
        except OrbitError as err:
            ds.attrs.update(orbit_word=word, v_orbit=np.nan, phase_orbit=np.nan, orbit_deviation=np.nan,
                            orbit_status=f"failed: {err}", d_rounding=np.nan, v_orbit_at_d_rounding=[np.nan, np.nan],
                            phase_orbit_at_d_rounding=[np.nan, np.nan])
    return annotate(ds)


#: the located grazing d is refined to this (the continuation's ``xtol``): the margin to grazing there is zero to
#: this times its slope in d, and below that rounding, which differs between machines
GRAZING_XTOL = 1e-13


def add_located_grazing(ds: xr.Dataset, params: Params, *, window: float = 0.01, step: float = 2e-4,
                        samples_per_unit: int = 400) -> xr.Dataset:
    """For a caption that shows "grazing behaviour": the same orbit at its located grazing point.

    The Newton orbit of the caption's attractor (``orbit_word``, period ``period``) is continued in d
    (gbar fixed: the length varies at fixed force) over ``d +- window``; the admissible grazing point
    nearest to the caption's d is the d where the orbit's loop touches a wall.  Added: ``grazing_d``,
    ``grazing_clearance`` (of the orbit solved there) and ``grazing_Z``, ``grazing_Zdot`` over one
    period from its first bottom impact, or ``grazing_status`` with the reason none was found."""

    if ds.attrs.get("orbit_status") != "solved":
        ds.attrs["grazing_status"] = f"no Newton orbit to continue ({ds.attrs.get('orbit_status')})"
        return ds
    k, word = int(ds.attrs["period"]), ds.attrs["orbit_word"]
    try:
        o = find_orbit(params, word, ds.attrs["phase_orbit"], ds.attrs["v_orbit"], k=k)
        br = continue_orbit(o, vary="d", d_range=(params.d - window, params.d + window), step=step,
                            xtol=GRAZING_XTOL)
    except OrbitError as err:
        ds.attrs["grazing_status"] = f"continuation failed: {err}"
        return ds
    kinds, crit, adm = br.critical_kind.values.astype(str), br.critical_d.values, br.critical_admissible.values
    cand = crit[(kinds == "grazing") & adm]
    if not cand.size:
        ds.attrs["grazing_status"] = f"no grazing point within d +- {window:g}"
        return ds
    dg = float(cand[np.argmin(np.abs(cand - params.d))])
    near = int(np.argmin(np.abs(br.d.values - dg)))
    pg = replace(params, d=dg)
    # Newton from the nearest branch point (not from a simulated guess: at grazing the loop's touch of
    # the wall makes the simulated word ambiguous)
    z0 = np.concatenate([[br.phase.values[near, 0]], np.roll(br.dt.values[near], -1), br.v_minus.values[near]])
    try:
        og = orbit_from_vector(pg, word, k, solve_orbit(z0, parse_word(word), dg, pg.gbar, pg.r, k))
    except OrbitError as err:
        ds.attrs["grazing_status"] = f"Newton failed at the located grazing d={dg:.8g}: {err}"
        return ds
    # drawn from the Newton orbit's own flights: at the grazing d a simulator's run of it registers the
    # loop's touch of the wall as an impact or not as rounding decides, and the two runs part there
    run = orbit_run(og)
    times = np.linspace(0.0, 2.0 * k, int(round(samples_per_unit * 2 * k)) + 1)
    tr = trajectory(run, times)
    ds["grazing_Z"] = ("grazing_time", tr.Z.values, {"long_name": "Z of the orbit at the located grazing d", "units": "1"})
    ds["grazing_Zdot"] = ("grazing_time", tr.Zdot.values,
                          {"long_name": "Zdot of the orbit at the located grazing d", "units": "1"})
    ds = ds.assign_coords(grazing_time=("grazing_time", times, {"long_name": "time from its first bottom impact",
                                                                "units": "1"}))
    ds.attrs.update(grazing_status="located", grazing_d=dg, grazing_clearance=float(og.clearance), grazing_xtol=GRAZING_XTOL,
                    grazing_phi=float(og.phase[0]), grazing_v0=float(og.v_minus[0]))
    return ds


def caption_summary(datasets: dict[str, xr.Dataset], expected: dict[str, str]) -> xr.Dataset:
    """One row per caption orbit: stated and found motion, and how far the caption lies from the attractor."""
    names = list(datasets)
    get = lambda key: [datasets[n].attrs.get(key, np.nan) for n in names]
    pair = lambda key: np.array([np.broadcast_to(np.asarray(datasets[n].attrs.get(key, np.nan), float), (2,))
                                 for n in names]).reshape(-1, 2)
    out = xr.Dataset(
        {
            "d": ("caption", get("d")),
            "gbar": ("caption", get("gbar")),
            "v0": ("caption", get("v0")),
            "phi": ("caption", get("phi")),
            "motion_stated": ("caption", [expected[n] for n in names]),
            "motion_found": ("caption", get("motion")),
            "v_attractor": ("caption", get("v_attractor")),
            "phase_attractor": ("caption", get("phase_attractor")),
            "dv": ("caption", get("dv")),
            "dphase": ("caption", get("dphase")),
            "v_orbit": ("caption", get("v_orbit"), {"long_name": "that impact on the Newton-solved periodic orbit"}),
            "phase_orbit": ("caption", get("phase_orbit"), {"units": "rad"}),
            "orbit_deviation": ("caption", get("orbit_deviation"),
                                {"long_name": "largest difference attractor - Newton orbit (velocity, phase)"}),
            "orbit_status": ("caption", [str(x) for x in get("orbit_status")]),
            "v_orbit_at_d_rounding": (("caption", "end"), pair("v_orbit_at_d_rounding"),
                                      {"long_name": "the orbit's velocity at d -+ half a unit of the printed d (NaN: no admissible orbit)"}),
            "phase_orbit_at_d_rounding": (("caption", "end"), pair("phase_orbit_at_d_rounding"),
                                          {"units": "rad", "long_name": "the orbit's phase at d -+ half a unit of the printed d"}),
        },
        coords={"caption": names},
    )
    out["reproduced"] = ("caption", [f == s or f.startswith(s + " ") for s, f in
                                     zip(out.motion_stated.values, out.motion_found.values, strict=True)])
    return annotate(out)


def summary_markdown(table: xr.Dataset) -> str:
    """The caption table as Markdown (for README.md): each orbit by its printed figure and panel and its
    config key."""
    rows = ["| figure | caption | d | stated | found | Zdot- caption → attractor | phase caption → attractor |",
            "|---|---|---|---|---|---|---|"]
    for i, name in enumerate(table.caption.values):
        r = table.isel(caption=i)
        rows.append(
            f"| {caption_figure(str(name)) or ''} | {name} | {float(r.d):.4g} | {str(r.motion_stated.values)} | {str(r.motion_found.values)} | "
            f"{float(r.v0):.4g} → {float(r.v_attractor):.6f} ({float(r.dv):+.1e}) | "
            f"{float(r.phi):.4g} → {float(r.phase_attractor):.6f} ({float(r.dphase):+.1e}) |"
        )
    return "\n".join(rows) + "\n"


def bistability_dataset(branch21: xr.Dataset, branch31: xr.Dataset, g1: float, g2: float, *, d_mid: float,
                        samples_per_unit: int = 400, offset: float = 1e-6, missing: str = "") -> xr.Dataset:
    """Phase portraits of the bistable 2:1 and 3:1 motions (paper Figure 8 (d)-(g)): the 2:1 orbit just
    above G1, both orbits at ``d_mid``, and the 3:1 orbit just below G2, each over one period.

    A panel that cannot be drawn is NaN and its ``status`` says why: G1 or G2 not found (NaN ``g1``, ``g2``;
    ``missing`` says why; attribute ``G_missing``), a failed branch, no admissible orbit of its branch, Newton failing, or an orbit
    that crosses a wall (not a motion of the device).  The others are drawn (``status`` ``"drawn"``).
    """

    ref = next((b for b in (branch21, branch31) if b.sizes.get("point", 0)), None)
    gbar = float(ref.gbar.values[0]) if ref is not None else np.nan
    slope = float(ref.attrs.get("gbar_slope", 0.0)) if ref is not None else 0.0
    r = float(ref.attrs["r"]) if ref is not None else np.nan
    d_ref = float(ref.d.values[0]) if ref is not None else np.nan
    panels = [("G1", branch21, g1 + offset), (f"d={d_mid:g} (2:1)", branch21, d_mid),
              (f"d={d_mid:g} (3:1)", branch31, d_mid), ("G2", branch31, g2 - offset)]
    n_t = int(round(2.0 * samples_per_unit)) + 1
    Z = np.full((len(panels), n_t), np.nan)
    V = np.full((len(panels), n_t), np.nan)
    v0s, phis, closure = (np.full(len(panels), np.nan) for _ in range(3))
    status, ds_attrs = [], {}
    for k, (name, br, d) in enumerate(panels):
        try:
            o = _panel_orbit(br, name, d, gbar + slope * (d - d_ref), r, missing)
        except OrbitError as err:
            status.append(f"not drawn: {err}")
            continue
        run = simulate(o.params, o.phi, float(o.v_minus[0]), t_end=2.0 * o.k + 1.0)
        tr = trajectory(run, np.linspace(0.0, 2.0 * o.k, n_t))
        Z[k], V[k] = tr.Z.values, tr.Zdot.values
        # closes: the state one period later is the same, compared between impacts (at an impact
        # instant rounding decides whether the pre- or post-impact velocity is sampled)
        probe = np.linspace(0.05, 0.95, 19)
        both = trajectory(run, np.concatenate([probe, probe + 2.0 * o.k]))
        z, v = (both[x].values.reshape(2, -1) for x in ("Z", "Zdot"))
        closure[k] = max(float(np.max(np.abs(z[1] - z[0]))), float(np.max(np.abs(v[1] - v[0]))))
        v0s[k], phis[k] = float(o.v_minus[0]), float(o.phi)
        ds_attrs[f"panel{k}_stable"] = int(o.stable)
        status.append("drawn")
    ds = xr.Dataset(
        {"Z": (("panel", "sample"), Z), "Zdot": (("panel", "sample"), V),
         "word": ("panel", np.array([str(p_[1].attrs.get("word", "")) for p_ in panels], dtype=object).astype(str)),
         "d": ("panel", np.array([p_[2] for p_ in panels], dtype=float)),
         "v0": ("panel", v0s, {"units": "1", "long_name": "pre-impact velocity of the bottom impact at t0"}),
         "phi": ("panel", phis, {"units": "rad", "long_name": "forcing phase of the bottom impact at t0"}),
         "closure": ("panel", closure, {"units": "1", "long_name": "largest change of Z or Zdot over one period, between impacts (0: the portrait closes)"}),
         "status": ("panel", np.array(status, dtype=object).astype(str),
                    {"long_name": "drawn, or not drawn and why"})},
        coords={"panel": [p_[0] for p_ in panels]},
    )
    ds.attrs.update(G1=g1, G2=g2, gbar=gbar, r=r, G_missing=missing, **ds_attrs)
    return annotate(ds)


def _panel_orbit(br: xr.Dataset, name: str, d: float, gbar: float, r: float, missing: str):
    """The admissible orbit of branch ``br`` at ``d`` for the portrait ``name``; ``OrbitError`` says why none."""

    word = str(br.attrs.get("word", "?"))
    if br.attrs.get("status") == "failed":
        raise OrbitError(f"no {word} branch ({br.attrs.get('reason', '')})")
    if not np.isfinite(d):
        raise OrbitError(f"no {name} ({missing or 'not located'})")
    # start from the physical (admissible, preferably stable) stretch of the branch: the branch also
    # passes these d on its unstable and wall-crossing stretches
    good = (br.admissible & br.stable).values if br.sizes.get("point", 0) else np.zeros(0, bool)
    good = good if good.any() else br.admissible.values if good.size else good
    cand = np.flatnonzero(good)
    if not cand.size:
        raise OrbitError(f"the {word} branch has no admissible orbit")
    i = int(cand[np.argmin(np.abs(br.d.values[cand] - d))])
    o = find_orbit(Params(d=float(d), gbar=gbar, r=r), word, float(br.phase[i, 0]), float(br.v_minus[i, 0]))
    if not o.admissible:
        raise OrbitError(f"the {word} orbit at d={d:.6g} is not a motion ({o.reason})")
    return o
