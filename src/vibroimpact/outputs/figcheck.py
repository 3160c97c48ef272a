"""The rules the figure regeneration check compares a figure's arrays by.

One rule for tolerances, declared where an array is drawn, from what produced it (its provenance,
:data:`PROVENANCE`), and applied on every machine: an exact value (a closed form, a Newton-solved orbit) is
compared **pointwise** (``|new - ref| <= atol + rtol |ref|``, ``rtol`` the attractors' identification
tolerance 1e-9); a value that rides on bits no machine reproduces (a chaotic run, a long run's statistic, a
random draw, a method's error at its tolerance, a timing: :data:`NOT_POINTWISE`) never is, whatever one
machine measured.  It is compared by what is well-posed about it, which its figure recorded when drawing it
(:func:`vibroimpact.outputs.plots._common.wellposed`); :mod:`vibroimpact.outputs.conditioning` measures
what each rule tolerates (the figure data recomputed under another libm, other OpenBLAS kernels and inputs
moved by a few ulps):

``motions``
    values at simulated attractors (sweep points, map cells), grouped by the point they belong to.
    Where the motion is the same and settled (an exact cycle) in both, its values pointwise (a value
    computed from the cycle's monodromy matrix, its largest Lyapunov exponent, with ``|ref|`` replaced by
    its recorded ``sensitivity`` to the matrix's entries where that is larger: the strict tolerance on
    the entries, carried through the eigenvalue's condition number); where the
    value is a statistic (a motion with no period: the long run's batch mean; an expectation over
    random starts), the two estimates agree within :data:`Z_CRIT` combined standard errors; where the
    motion differs, only at a point on a boundary of its motion in the reference (a neighbouring point
    has another motion, or the new motion's region lies within :data:`REACH` points: coexisting motions'
    basins interleave) or where one of the two is a transient that outlasted the cap (on a map of
    motions only: no period within the cap on either side, whether chaotic, quasi-periodic or unsettled).
``run``
    a text naming a run of one motion, at its middle: the same text, within one sweep step (a name of merged
    short runs: within one sweep step).
``placed``
    a text the layout placed at one of several anchors: the coordinates the anchors share, within their step.
``located``
    values located between neighbouring points of a grid (a transition along a sweep, the 1:1 exit): each
    coordinate within the artist's recorded grid step along it (``step_x``, ``step_y``; none: pointwise); an
    element the artist marks ``sampled`` (a classification from a finite sample of a motion with no period:
    another run may draw it in the artist beside) may be present in one and missing in the other.
``curve``
    a curve sampled by continuation (where its points fall along it depends on the step control):
    every point of each lies on the other, within the other's chord error (``L theta / 4`` for a
    segment of length ``L`` turning by ``theta``), or within one segment of a piece's end.
``on curve``
    points located on sampled curves (events, crossings, linear between two curve points): within the
    nearest segment of the axes' curves.
``boundary``
    markers between grid cells whose motions differ: any marker in one and not the other lies beside
    a cell whose motion differs between the two.
``magnitude``
    errors against a reference, as orders of magnitude above their rounding floor (:func:`magnitude`).
``outcome``
    categorical outcomes, the same but in cells the producer found sensitive to the last bit (:func:`outcome`).
``timing``
    a wall-clock time: not compared.

An array with no rule recorded is compared pointwise; one whose values move on another machine must say
what is well-posed about it, and the conditioning's test finds any that does not.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.motion_names import no_period

__all__ = ["PROVENANCE", "NOT_POINTWISE", "DEFAULT_PROVENANCE", "Z_CRIT", "MAGNITUDE_DECADES", "RULES", "judge",
           "motion_flips", "strict_close", "artist_base"]


#: what produced an artist's arrays, which decides how the check may compare them.  The arrays of an artist
#: whose provenance is in :data:`NOT_POINTWISE` ride on bits no machine reproduces (another libm, another BLAS
#: kernel, another CPU's code path turns the last bit of a chaotic run, a step-size decision or a timing into a
#: visible difference): they are never compared pointwise, whatever one machine measures
PROVENANCE = {
    "exact": "a closed form, a Newton-solved orbit or a converged root: reproduced to rounding",
    "continuation": "a curve sampled by step control: where its points fall along it depends on the steps",
    "grid": "a value located between neighbouring points of a grid",
    "simulation": "values at simulated attractors: an exact cycle where the motion is periodic, a long-run "
                  "statistic where it is not, a motion that may differ where basins interleave",
    "chaotic run": "computed along a chaotic trajectory, which amplifies the last bit of every step",
    "method error": "the error of a method against a reference: at a tolerance or step, its truncation, set by "
                    "the steps it took (an adaptive method's turn on comparisons a last bit can flip); below, "
                    "rounding, a count of ulps",
    "random starts": "shares over a random sample of starts: a statistic with a binomial error",
    "timing": "a wall-clock time: the machine's speed, not a result",
    "layout": "a label's place, chosen among candidates to clear what is drawn (which may move)",
}
#: provenances whose arrays are never compared pointwise
NOT_POINTWISE = frozenset({"simulation", "chaotic run", "method error", "random starts", "timing", "layout"})
#: the provenance a rule is recorded with where the figure names none
DEFAULT_PROVENANCE = {"motions": "simulation", "run": "simulation", "boundary": "simulation", "located": "grid",
                      "curve": "continuation", "on curve": "continuation", "magnitude": "method error",
                      "outcome": "chaotic run", "timing": "timing", "placed": "layout"}



#: two estimates of one statistic differ by more than this many combined standard errors with
#: probability 1e-6 (Student's t with 19 degrees of freedom: the long runs' 20 batch means); a full
#: check makes about a thousand such comparisons, so a false alarm once in a thousand checks
Z_CRIT = 7.07


def artist_base(name: str) -> str:
    """``a1_line3_y`` -> ``a1_line3``: the artist a figure-data variable belongs to."""
    return name.rsplit("_", 1)[0]


def strict_close(a, b, rtol, atol) -> bool:
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape or np.any(np.isnan(a) != np.isnan(b)):
        return False
    ok = ~np.isnan(b)
    return bool(np.all(np.abs(a[ok] - b[ok]) <= atol + rtol * np.abs(b[ok])))


def _aux(ds, base, key, default=None):
    name = f"{base}_wp_{key}"
    return ds[name].values if name in ds else default


def _parts(ds, base):
    """Keys (one row per element: x, or x and y for a map) and values of an artist."""
    x, y, c = (ds[f"{base}_{p}"].values.astype(float) if f"{base}_{p}" in ds else None for p in ("x", "y", "c"))
    if c is not None:  # a scatter or a map: keys (x, y), values the colour
        n = c.size
        keys = np.column_stack([np.broadcast_to(x, n), np.broadcast_to(y, n)]) if x is not None and x.size == n \
            else np.arange(n, dtype=float)[:, None]
        return keys, c
    return x[:, None], y


def _unique_keys(keys, rtol, atol):
    """Unique rows of ``keys`` (equal within the strict tolerance) in sorted order, and each row's index."""
    order = np.lexsort(keys.T[::-1])
    rows = keys.tolist()  # Python floats: the same IEEE operations as NumPy's, without a call per row
    uniq, index = [], np.empty(len(keys), int)
    last = None
    for i in order.tolist():
        row = rows[i]
        if last is None or not all(abs(x - u) <= atol + rtol * abs(u) for x, u in zip(row, last, strict=True)):
            uniq.append(row)
            last = row
        index[i] = len(uniq) - 1
    return np.array(uniq, dtype=keys.dtype).reshape(-1, keys.shape[1]), index


#: how far (in grid steps) the region of a coexisting motion may reach into another's: a start in a
#: multistable region goes to whichever attractor's basin holds it, and basins interleave
REACH = 2


def _neighbours(uniq, reach=1):
    """For each unique key, the indices of the keys within ``reach`` grid steps: along a sweep (one
    coordinate), or on a map (two; ``reach = 1``: the four neighbours, more: the square around it)."""
    if uniq.shape[1] == 1:
        n = len(uniq)
        return [[j for j in range(i - reach, i + reach + 1) if j != i and 0 <= j < n] for i in range(n)]
    xs, ys = np.unique(uniq[:, 0]), np.unique(uniq[:, 1])
    cell = list(zip(np.searchsorted(xs, uniq[:, 0]).tolist(), np.searchsorted(ys, uniq[:, 1]).tolist(), strict=True))
    where = {c: i for i, c in enumerate(cell)}
    out = []
    for ix, iy in cell:
        cells = ([(ix - 1, iy), (ix + 1, iy), (ix, iy - 1), (ix, iy + 1)] if reach == 1 else
                 [(ix + a, iy + b) for a in range(-reach, reach + 1) for b in range(-reach, reach + 1) if a or b])
        out.append([where[c] for c in cells if c in where])
    return out


def _per_key(ds, base, index, n_keys, values):
    """Per unique key: motion, settled, unsettled, mean, se, sorted finite values."""
    n = len(index)
    motion = _aux(ds, base, "motion", np.full(n, "")).astype(str)
    settled = _aux(ds, base, "settled", np.zeros(n)).astype(bool)
    unsettled = _aux(ds, base, "unsettled", np.zeros(n)).astype(bool)
    mean = _aux(ds, base, "mean", np.full(n, np.nan)).astype(float)
    se = _aux(ds, base, "se", np.full(n, np.nan)).astype(float)
    sensitivity = _aux(ds, base, "sensitivity", np.zeros(n)).astype(float)
    labels_only = f"{base}_wp_settled" not in ds
    if labels_only:
        # a map of motions only: a motion with no period within the cap is chaos, quasi-periodic or a transient
        # longer than the cap (split by a statistic, its long run's exponent), and whether such a transient
        # ends within the cap is for rounding to decide
        unsettled = unsettled | no_period(motion)
    # the rows of each key in their order (a stable sort by key, cut where the key changes): per key its
    # first row's motion, mean and se, whether all rows settled and any did not, the largest sensitivity (NaN
    # ignored, at least 0) and the sorted finite values
    order = np.argsort(index, kind="stable")
    cuts = np.searchsorted(index[order], np.arange(n_keys + 1))
    first = order[cuts[:-1]]
    all_settled = np.logical_and.reduceat(settled[order], cuts[:-1]) if n_keys else np.zeros(0, bool)
    any_unsettled = np.logical_or.reduceat(unsettled[order], cuts[:-1]) if n_keys else np.zeros(0, bool)
    largest = (np.fmax(0.0, np.fmax.reduceat(sensitivity[order], cuts[:-1])) if n_keys else np.zeros(0)).tolist()
    vals = values[order]
    return [dict(motion=motion[first[u]], settled=bool(all_settled[u]) and not labels_only,
                 sensitivity=largest[u], unsettled=bool(any_unsettled[u]), mean=float(mean[first[u]]),
                 se=float(se[first[u]]), values=_sorted_finite(vals[cuts[u]:cuts[u + 1]]), labels_only=labels_only)
            for u in range(n_keys)]


def _sorted_finite(v):
    return np.sort(v[np.isfinite(v)])


def motions(new, ref, base, *, rtol, atol):
    """The ``motions`` rule for one artist: ``(ok, max_difference, detail, flipped_keys)``."""
    kr, vr = _parts(ref, base)
    kn, vn = _parts(new, base)
    ur, ir = _unique_keys(kr, rtol, atol)
    un, inn = _unique_keys(kn, rtol, atol)
    if ur.shape != un.shape or not strict_close(un, ur, rtol, atol):
        return False, math.nan, f"the points moved ({len(un)} points, reference {len(ur)})", np.zeros((0, kr.shape[1]))
    pr, pn = _per_key(ref, base, ir, len(ur), vr), _per_key(new, base, inn, len(un), vn)
    nb, near = _neighbours(ur), _neighbours(ur, REACH)
    counts = dict(exact=0, statistic=0, boundary=0, unsettled=0, motion=0)
    fails, flipped, worst, zmax = [], [], 0.0, 0.0
    for u, (a, b) in enumerate(zip(pr, pn, strict=True)):
        where = ", ".join(f"{x:.6g}" for x in ur[u])
        if a["motion"] == b["motion"] and a["settled"] and b["settled"]:
            counts["exact"] += 1
            # an exact value derived from a matrix (a cycle's lambda_1) is known to the strict tolerance of
            # its matrix's entries times its sensitivity to them
            scale = np.maximum(np.abs(a["values"]), a["sensitivity"]) if a["values"].shape == b["values"].shape else 0
            if a["values"].shape != b["values"].shape or not np.all(
                    (np.isnan(a["values"]) == np.isnan(b["values"]))
                    & ~(np.abs(b["values"] - a["values"]) > atol + rtol * scale)):
                fails.append(f"at ({where}) {a['motion']}: values differ")
            elif a["values"].size:
                worst = max(worst, float(np.max(np.abs(b["values"] - a["values"]))))
        elif all(math.isfinite(x) for x in (a["mean"], a["se"], b["mean"], b["se"])):
            counts["statistic"] += 1
            diff = abs(b["mean"] - a["mean"])
            scale = math.hypot(a["se"], b["se"])
            if diff > atol + rtol * abs(a["mean"]):
                z = diff / scale if scale > 0 else math.inf
                zmax = max(zmax, z)
                if z > Z_CRIT:
                    fails.append(f"at ({where}): {b['mean']:.6g} against {a['mean']:.6g} is {z:.1f} standard errors")
        elif a["motion"] != b["motion"]:
            flipped.append(ur[u])
            if a["unsettled"] or b["unsettled"]:
                counts["unsettled"] += 1
            elif any(pr[j]["motion"] != a["motion"] for j in nb[u]) or any(pr[j]["motion"] == b["motion"]
                                                                            for j in near[u]):
                counts["boundary"] += 1
            else:
                fails.append(f"at ({where}): {b['motion']!r} where the reference has {a['motion']!r} inside its region")
        else:
            counts["motion"] += 1
    detail = (f"{len(ur)} points: {counts['exact']} exact values, {counts['statistic']} statistics (largest "
              f"{zmax:.1f} SE), {counts['motion']} same motion, {counts['boundary']} motion changed at a boundary, "
              f"{counts['unsettled']} at a transient longer than the cap")
    if fails:
        detail += "; " + "; ".join(fails[:5]) + (f"; and {len(fails) - 5} more" if len(fails) > 5 else "")
    return not fails, worst, detail, np.array(flipped).reshape(-1, kr.shape[1])


def run_text(new, ref, name, *, rtol, atol):
    """The ``run`` rule for a text variable: within one sweep step along x (its row, y, is the layout's), and the
    same text where it names one motion (a name of merged short runs, ``merged``, lists motions that interleave
    where they meet, and is not compared)."""
    a, b = ref[name], new[name]
    step = float(a.attrs.get("wp_step", 0.0))
    merged = bool(a.attrs.get("wp_merged", False)) or bool(b.attrs.get("wp_merged", False))
    if not merged and a.attrs.get("label") != b.attrs.get("label"):
        return False, math.nan, f"text {b.attrs.get('label')!r} where the reference has {a.attrs.get('label')!r}"
    dx = abs(float(b.values[0]) - float(a.values[0]))
    ok = dx <= step + atol + rtol * abs(float(a.values[0]))
    return ok, dx, f"moved {dx:.3g} along the sweep (one step: {step:.3g})" + ("; merged runs" if merged else "")


def placed(new, ref, name, *, rtol, atol):
    """The ``placed`` rule for a text the layout placed at one of several anchors (a line's name beside it): the
    coordinates the candidates share (not in ``free``) within their recorded step (``wp_step_x``, ``wp_step_y``;
    none: pointwise); the ``free`` ones, the layout's choice, not compared."""
    a, b = np.asarray(ref[name].values, float), np.asarray(new[name].values, float)
    attrs = ref[name].attrs
    if a.shape != b.shape:
        return False, math.nan, f"shape {b.shape}, reference {a.shape}"
    free = str(attrs.get("wp_free", ""))
    keep = [k for k, axis in enumerate("xy") if axis not in free and k < a.size]
    step = np.array([float(attrs.get(f"wp_step_{'xy'[k]}", 0.0)) for k in keep])
    diff = np.abs(a[keep] - b[keep])
    good = bool(np.all(diff <= step + atol + rtol * np.abs(a[keep])))
    worst = float(diff.max(initial=0.0))
    return good, worst, f"moved {worst:.3g} along {', '.join('xy'[k] for k in keep) or 'nothing'} ({free or 'no'} " \
                        "coordinate the layout's choice)"


def located(new, ref, name, *, rtol, atol):
    """The ``located`` rule for a line's or points' coordinate: NaN where the reference has NaN, and every
    value within the recorded grid step along that coordinate (``wp_step_x`` or ``wp_step_y``)."""
    a, b = np.asarray(ref[name].values, float), np.asarray(new[name].values, float)
    part, attrs = name.rsplit("_", 1)[-1], ref[name].attrs
    # a text's anchor (x, y) takes the step along each; a line's or points' coordinate its own
    step = (np.array([float(attrs.get("wp_step_x", 0.0)), float(attrs.get("wp_step_y", 0.0))]) if part == "xy"
            else float(attrs.get(f"wp_step_{part}", 0.0)))
    if a.shape != b.shape:
        return False, math.nan, f"shape {b.shape}, reference {a.shape}"
    base = artist_base(name)
    sampled = np.zeros(a.shape, bool)
    for ds in (ref, new):  # a classification either run made from a sample
        if f"{base}_wp_sampled" in ds and ds[f"{base}_wp_sampled"].shape == a.shape:
            sampled |= ds[f"{base}_wp_sampled"].values.astype(bool)
    flips = np.isnan(a) != np.isnan(b)
    if np.any(flips & ~sampled):
        return False, math.nan, f"NaN at {int(np.sum(flips & ~sampled))} other places"
    ok = ~np.isnan(a) & ~np.isnan(b)
    step = np.broadcast_to(step, a.shape)[ok]
    diff = np.abs(a[ok] - b[ok])
    worst = float(diff.max(initial=0.0))
    good = bool(np.all(diff <= step + atol + rtol * np.abs(a[ok])))
    moved = f"moved at most {worst:.3g} (one grid step: {float(step.max(initial=0.0)):.3g})"
    return good, worst, moved + (f"; {int(flips.sum())} sampled classifications differ" if flips.any() else "")


def _pieces(x, y):
    """Finite runs of a polyline (NaN separates pieces)."""
    ok = np.isfinite(x) & np.isfinite(y)
    cuts = np.flatnonzero(np.diff(ok.astype(int)) != 0) + 1
    return [np.column_stack([x[s], y[s]]) for s in np.split(np.arange(x.size), cuts) if s.size and ok[s[0]]]


def _segments(pieces):
    """Segments of the pieces: start, end, length, chord error allowance, and which of its ends is a
    piece's end (-1 its start, 1 its end, 2 both, 0 neither)."""
    rows = []
    for p in pieces:
        if len(p) == 1:
            rows.append((p[0], p[0], 0.0, 0.0, 2))
            continue
        d = np.diff(p, axis=0)
        L = np.hypot(d[:, 0], d[:, 1])
        ang = np.zeros(len(p))
        if len(p) > 2:
            c = np.sum(d[:-1] * d[1:], axis=1) / np.maximum(L[:-1] * L[1:], 1e-300)
            ang[1:-1] = np.arccos(np.clip(c, -1.0, 1.0))
        for i in range(len(d)):
            theta = max(ang[i], ang[i + 1])
            end = 2 if len(d) == 1 else -1 if i == 0 else 1 if i == len(d) - 1 else 0
            # a piece of one segment shows no turning: its points are known to a step
            sag = L[i] if len(d) == 1 else L[i] * theta / 4.0
            rows.append((p[i], p[i + 1], L[i], sag, end))
    return rows


def _distance_ok(points, segs, atol):
    """Whether each point lies within the allowance of a segment: the chord error, or the segment's
    length beyond a piece's end (where the continuation stopped, known to one step).  Blocks of points
    against every segment at once (:data:`_BLOCK` pairs), the same operations on each pair as one point at
    a time."""
    if not segs:
        return np.zeros(len(points), bool), np.full(len(points), np.inf)
    a = np.array([s[0] for s in segs])
    b = np.array([s[1] for s in segs])
    L = np.array([s[2] for s in segs])
    sag = np.array([s[3] for s in segs])
    end = np.array([s[4] for s in segs])
    ab = b - a
    ab2 = np.maximum(ab[:, 0] * ab[:, 0] + ab[:, 1] * ab[:, 1], 1e-300)
    start_end, stop_end = (end == -1) | (end == 2), (end == 1) | (end == 2)
    ok = np.zeros(len(points), bool)
    dist = np.empty(len(points))
    step = max(1, _BLOCK // len(segs))
    for k in range(0, len(points), step):
        p = np.asarray(points[k:k + step], float)
        dx, dy = p[:, 0:1] - a[:, 0], p[:, 1:2] - a[:, 1]
        t = np.clip((dx * ab[:, 0] + dy * ab[:, 1]) / ab2, 0.0, 1.0)
        dd = np.hypot(p[:, 0:1] - (a[:, 0] + t * ab[:, 0]), p[:, 1:2] - (a[:, 1] + t * ab[:, 1]))
        beyond = (start_end & (t <= 0.0)) | (stop_end & (t >= 1.0))
        allow = sag + atol + np.where(beyond, L, 0.0)
        ok[k:k + step] = np.any(dd <= allow, axis=1)
        dist[k:k + step] = dd.min(axis=1)
    return ok, dist


#: point-segment pairs :func:`_distance_ok` takes at once (a few MB of temporaries)
_BLOCK = 1 << 18


def curve(new, ref, base, *, rtol, atol):
    """The ``curve`` rule: ``(ok, max distance, detail)`` in units of the reference's extent."""
    xr_, yr = ref[f"{base}_x"].values.astype(float), ref[f"{base}_y"].values.astype(float)
    xn, yn = new[f"{base}_x"].values.astype(float), new[f"{base}_y"].values.astype(float)
    fin = np.isfinite(xr_) & np.isfinite(yr)
    if not fin.any():
        same = not (np.isfinite(xn) & np.isfinite(yn)).any()
        return same, 0.0, "no finite point" if same else "points where the reference has none"
    scale = np.array([max(np.ptp(xr_[fin]), 1e-300), max(np.ptp(yr[fin]), 1e-300)])
    pr, pn = _pieces(xr_ / scale[0], yr / scale[1]), _pieces(xn / scale[0], yn / scale[1])
    tol = atol + rtol
    ok1, d1 = _distance_ok(np.concatenate(pn) if pn else np.zeros((0, 2)), _segments(pr), tol)
    ok2, d2 = _distance_ok(np.concatenate(pr), _segments(pn), tol)
    worst = float(max(d1.max(initial=0.0), d2.max(initial=0.0)))
    bad = int((~ok1).sum() + (~ok2).sum())
    return bad == 0, worst, (f"{bad} points off the other curve" if bad else
                             f"every point on the other curve (largest distance {worst:.2g} of its extent)")


def _nearest_length(p, segs):
    """Length of the segment nearest to the point ``p`` (0 without segments)."""
    if not segs:
        return 0.0
    a = np.array([s[0] for s in segs])
    ab = np.array([s[1] for s in segs]) - a
    t = np.clip(np.sum((p - a) * ab, axis=1) / np.maximum(np.sum(ab * ab, axis=1), 1e-300), 0.0, 1.0)
    return float(segs[int(np.argmin(np.hypot(*(p - (a + t[:, None] * ab)).T)))][2])


def on_curve(new, ref, base, curves, *, rtol, atol):
    """The ``on curve`` rule: each point within the nearest reference curve segment's length of its
    reference position (``curves``: the axes' curve artists)."""
    pr = np.column_stack([ref[f"{base}_x"].values, ref[f"{base}_y"].values]).astype(float)
    pn = np.column_stack([new[f"{base}_x"].values, new[f"{base}_y"].values]).astype(float)
    if pr.shape != pn.shape:
        return False, math.nan, f"{len(pn)} points, reference {len(pr)}"
    pts = [np.column_stack([ref[f"{c}_x"].values, ref[f"{c}_y"].values]).astype(float) for c in curves]
    allpts = np.concatenate(pts + [pr])
    fin = np.isfinite(allpts).all(axis=1)
    scale = np.maximum(np.ptp(allpts[fin], axis=0), 1e-300) if fin.any() else np.ones(2)
    segs = [s for c in pts for s in _segments(_pieces(c[:, 0] / scale[0], c[:, 1] / scale[1]))]
    worst, bad = 0.0, 0
    for p, q in zip(pr / scale, pn / scale, strict=True):
        if not np.all(np.isfinite(p)):
            bad += int(np.any(np.isfinite(q)))
            continue
        dist = np.hypot(*(q - p))
        worst = max(worst, float(dist))
        bad += int(dist > _nearest_length(p, segs) + atol + rtol)
    return bad == 0, worst, (f"{bad} points moved by more than their curve segment" if bad else
                             f"within their curve segments (largest move {worst:.2g} of the extent)")


def boundary(new, ref, base, flipped, spacing, *, rtol, atol):
    """The ``boundary`` rule: markers in one and not the other lie within one grid cell of a cell whose
    motion differs (``flipped``: those cells' keys; ``spacing``: the grid's steps)."""
    pr = np.column_stack([ref[f"{base}_x"].values, ref[f"{base}_y"].values]).astype(float)
    pn = np.column_stack([new[f"{base}_x"].values, new[f"{base}_y"].values]).astype(float)

    def unmatched(p, q):
        if not len(q):
            return p
        keep = [not np.any(np.all(np.abs(q - x) <= atol + rtol * np.abs(x), axis=1)) for x in p]
        return p[np.array(keep, bool)]

    odd = np.concatenate([unmatched(pn, pr), unmatched(pr, pn)])
    if not len(odd):
        return True, 0.0, f"the same {len(pr)} markers"
    if spacing is None or not len(flipped):
        return False, math.nan, f"{len(odd)} markers differ and no cell's motion changed"
    near = [bool(np.any(np.all(np.abs(flipped - x) <= 1.0001 * spacing, axis=1))) for x in odd]
    bad = len(near) - sum(near)
    return bad == 0, math.nan, (f"{len(odd)} markers differ, {bad} of them away from any cell whose motion changed"
                                if bad else f"{len(odd)} markers differ, each beside a cell whose motion changed")


def motion_flips(new, ref, axes, *, rtol, atol):
    """Cells whose motion differs on the map of ``axes`` (its artist recorded with the ``motions`` rule), and the
    map's grid steps (None where the axes hold no map)."""
    for name in ref.data_vars:
        if (name.startswith(axes + "_points") and ref[name].attrs.get("wellposed") == "motions"
                and name.endswith("_c") and (artist_base(name) + "_c") in new):
            base = artist_base(name)
            flipped = motions(new, ref, base, rtol=rtol, atol=atol)[3]
            keys = np.column_stack([ref[base + "_x"].values, ref[base + "_y"].values])
            steps = [np.min(np.diff(np.unique(k))) if np.unique(k).size > 1 else 0.0 for k in keys.T]
            return flipped, np.array(steps)
    return np.zeros((0, 2)), None


def _on_curve(new, ref, name, *, rtol, atol):
    axes = name.split("_", 1)[0]
    curves = sorted({artist_base(v) for v in ref.data_vars
                     if v.startswith(axes + "_") and ref[v].attrs.get("wellposed") == "curve"})
    return on_curve(new, ref, artist_base(name), curves, rtol=rtol, atol=atol)


def _boundary(new, ref, name, *, rtol, atol):
    flipped, steps = motion_flips(new, ref, name.split("_", 1)[0], rtol=rtol, atol=atol)
    return boundary(new, ref, artist_base(name), flipped, steps, rtol=rtol, atol=atol)[:3]


#: an error against a reference is read off a work-precision chart in decades: two runs' errors agree when
#: they are the same order of magnitude, within one decade of each other.  Above its rounding floor an
#: integrator's error moves under another machine's libm or BLAS kernels by far less (its step sequence
#: moves, the truncation error it leaves does not: measured in the conditioning table); a method made ten
#: times less accurate fails
MAGNITUDE_DECADES = 1.0


def magnitude(new, ref, name, *, rtol, atol):
    """The ``magnitude`` rule for errors against a reference (the y of an error-against-cost line, or a text's
    anchor on it): each error within :data:`MAGNITUDE_DECADES` of the reference's, both read as at least the
    artist's recorded ``floor`` (the rounding level of the quantity whose error it is: below it an error is
    a count of ulps that any machine may change); NaN where the reference has NaN, an infinite error (wrong
    walls) where the reference has one.  A text's x (a cost) is a timing and not compared."""
    a, b = np.asarray(ref[name].values, float), np.asarray(new[name].values, float)
    if a.shape != b.shape:
        return False, math.nan, f"shape {b.shape}, reference {a.shape}"
    if name.endswith("_xy"):  # a label placed on the line: its error coordinate only
        a, b = a[1:], b[1:]
    floor = float(ref[name].attrs.get("wp_floor", 0.0))
    if np.any(np.isnan(a) != np.isnan(b)) or np.any(np.isinf(a) != np.isinf(b)):
        return False, math.nan, "NaN or infinite errors at other places"
    ok = np.isfinite(a)
    with np.errstate(divide="ignore"):
        da = np.log10(np.maximum(np.abs(a[ok]), floor))
        db = np.log10(np.maximum(np.abs(b[ok]), floor))
    diff = np.abs(db - da)
    if np.any(~np.isfinite(diff)):
        return False, math.nan, "a zero error with no rounding floor recorded"
    worst = float(diff.max(initial=0.0))
    good = worst <= MAGNITUDE_DECADES
    return good, worst, (f"largest change {worst:.2g} decades (allowed {MAGNITUDE_DECADES:g}; errors below "
                         f"{floor:.1e} count as {floor:.1e})")


def outcome(new, ref, name, *, rtol, atol):
    """The ``outcome`` rule for a map of categorical outcomes (an image of codes): the same code in every
    cell, but in cells either run marks ``sensitive`` (an outcome its producer saw change when the start
    moved by one ulp: a chaotic run's, decided by when two trajectories part)."""
    a, b = np.asarray(ref[name].values, float), np.asarray(new[name].values, float)
    if a.shape != b.shape:
        return False, math.nan, f"shape {b.shape}, reference {a.shape}"
    base = artist_base(name)
    sensitive = np.zeros(a.shape, bool)
    for ds in (ref, new):
        key = f"{base}_wp_sensitive"
        if key in ds and ds[key].size == a.size:
            sensitive |= ds[key].values.astype(bool).reshape(a.shape)
    differ = ~((a == b) | (np.isnan(a) & np.isnan(b)))
    bad = int(np.sum(differ & ~sensitive))
    detail = f"{int(differ.sum())} cells differ, {int((differ & sensitive).sum())} of them sensitive to the last bit"
    return bad == 0, float(differ.sum()), detail + (f"; {bad} others" if bad else "")


def timing(new, ref, name, *, rtol, atol):
    """The ``timing`` rule: a wall-clock time is the machine's speed, not a result, and is not compared (its
    presence is: a missing timing fails as a missing variable)."""
    return True, math.nan, "a timing: not compared"


#: every rule but ``strict`` (pointwise, :func:`strict_close`), the one place a rule's name meets its
#: comparison: ``(new, ref, name, *, rtol, atol) -> (ok, max difference, detail)`` for a variable ``name``
#: of the reference; all but those of :data:`PER_VARIABLE` judge the variable's whole artist at once
RULES = {
    "motions": lambda new, ref, name, **kw: motions(new, ref, artist_base(name), **kw)[:3],
    "run": run_text,
    "located": located,
    "curve": lambda new, ref, name, **kw: curve(new, ref, artist_base(name), **kw),
    "on curve": _on_curve,
    "boundary": _boundary,
    "placed": placed,
    "magnitude": magnitude,
    "outcome": outcome,
    "timing": timing,
}
#: the rules that judge one variable, not its whole artist
PER_VARIABLE = frozenset({"located", "placed", "magnitude", "outcome", "timing"})


def judge(rule, new, ref, name, *, rtol, atol, cache=None):
    """``(ok, max difference, detail)`` of the variable ``name`` by its recorded ``rule`` (:data:`RULES`); a
    variable or artist missing from ``new`` fails, naming it.  ``cache``: a dict the results of one comparison
    of two figures share (a rule judging a whole artist runs once for its variables)."""
    key = (rule, name if rule in PER_VARIABLE else artist_base(name))
    if cache is not None and key in cache:
        return cache[key]
    if rule not in RULES:
        out = (False, math.nan, f"unknown rule {rule!r}; allowed: strict, {', '.join(RULES)}")
    else:
        try:
            out = RULES[rule](new, ref, name, rtol=rtol, atol=atol)
        except KeyError as err:
            out = (False, math.nan, f"missing {err}")
    if cache is not None:
        cache[key] = out
    return out
