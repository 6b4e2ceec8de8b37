"""How far a fit of lines and arcs stands from the exact cutter curve, measured both ways.

* curve → path: the distance of the exact curve P(θ) from a span's elements (a biarc: the nearer
  of its two arcs) over its whole stretch of θ: sampled, and every sampled local maximum climbed to
  its top between the samples its slope falls through (Illinois steps on the slope, which is the
  curve's velocity along the unit vector from the elements' nearest point), so the largest distance
  between the sample points is found, not only at them;
* path → curve: the distance of the elements' points from the exact curve (each point's foot on the
  curve by Gauss-Newton from the nearest sample, later from the feet at the climb's bracket),
  sampled along each element and the largest climbed the same way along the element (the slope is
  the point's velocity along the curve's normal at its foot).

Both are one-sided Hausdorff distances; the larger is the span's deviation. Both directions run
side by side (:func:`_lockstep`): each round evaluates the curve once at every cam angle either
needs, since an evaluation costs mostly its fixed part (the README's toolpath measures with 11
evaluations where shrinking grids, one direction after the other, took 26).

References
----------
.. [1] J. Kiefer, "Sequential minimax search for a maximum", Proc. AMS 4 (1953) 502-506 (the
   maximum lies between the best evaluated point's neighbours).
.. [2] M. Dowell, P. Jarratt, "A modified regula falsi method for computing the root of an
   equation", BIT 11 (1971) 168-174 (the Illinois method).
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from dataclasses import dataclass
from itertools import accumulate
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..curves.base import FloatArray
from ..deadline import checkpoint
from .geometry import Element, ElementArrays
from .offset import LEFT_LIMIT_RAD, OffsetCurve

#: samples per biarc (over its stretch of θ) and per element (along it) for the measurement
MEASURE_SAMPLES = 32
#: Illinois steps of a climb to a sampled maximum, at most (they take 3-6)
CLIMB_STEPS = 16
#: a climb stops where its last slope times its bracket's width, what the value could still gain
#: below a concave top, is under this [mm]: the rounding of 100 mm coordinates is ~1e-14 mm, and a
#: foot's slope is noisy at ~1e-9 (the foot is found to 1e-10 rad), so the top's place is not
#: sought finer than its value needs
CLIMB_GAIN_MM = 1e-13
#: Gauss-Newton steps of a foot point, at most: each multiplies the error by ~|P − X|·κ ≤ 1e-2
FOOT_STEPS = 5
#: a foot whose next step is under this has converged [rad]: it lies within about that of the foot
#: (~1e-8 mm along a 100 mm cam), and the distance there is off by the square of that over the distance
#: (a foot is where the distance is least): ~5e-14 mm at a 1e-3 mm deviation, the rounding of the coordinates
FOOT_STEP_RAD = 1e-10


IntArray = NDArray[np.intp]


@dataclass(frozen=True)
class Span:
    """Elements that stand for the exact curve between two cam angles (equal for a corner arc)."""

    theta0: float
    theta1: float
    elements: tuple[Element, ...]


def measure(curve: OffsetCurve, spans: list[Span]) -> FloatArray:
    """The deviation of each span from the exact curve, both ways, refined between samples.

    Parameters
    ----------
    curve : OffsetCurve
        The exact curve.
    spans : list of Span
        Spans over stretches θ0 < θ1 of the curve (corner arcs, θ0 = θ1, are exact and get 0).

    Returns
    -------
    ndarray
        max(curve → span, span → curve) of each span [mm].

    References
    ----------
    Kiefer (1953), the maximum between the best point's neighbours; Dowell and Jarratt (1971), the
    Illinois method on the slope; the Gauss-Newton foot point of a point on a curve.
    """
    out = np.zeros(len(spans))
    live = [k for k, s in enumerate(spans) if s.theta1 > s.theta0]
    if not live:
        return out
    checkpoint()
    elements = [e for k in live for e in spans[k].elements]
    arrays = ElementArrays(elements)
    first = np.cumsum([0] + [len(spans[k].elements) for k in live])[:-1]
    last = first + np.array([len(spans[k].elements) - 1 for k in live])
    # one-sided: a span that ends at a corner sees the curve's limit there, not the next stretch
    lo = np.array([spans[k].theta0 for k in live]) + LEFT_LIMIT_RAD
    hi = np.array([spans[k].theta1 for k in live]) - LEFT_LIMIT_RAD
    theta = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, MEASURE_SAMPLES)[None, :]
    sampled = curve.sample(theta.reshape(-1))  # the curve at the samples, for both directions
    owner = np.repeat(np.arange(len(live)), [len(spans[k].elements) for k in live])
    forward, backward = _lockstep(curve, [_curve_to_path(arrays, first, last, theta, sampled),
                                          _path_to_curve(arrays, owner, theta, sampled, lo, hi)])
    per_span = np.zeros(len(live))
    np.maximum.at(per_span, owner, backward)
    out[live] = np.maximum(forward, per_span)
    return out


#: a walk of the measurement: it yields the cam angles it needs the curve at, is sent the curve's
#: sample there (x, y, tx, ty, stretch) and returns its result
Sampled = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]
Walk = Generator[FloatArray, Sampled, Any]


def _lockstep(curve: OffsetCurve, walks: list[Walk]) -> list[Any]:
    """Run walks side by side, one evaluation of the curve per round for all their cam angles
    (a curve evaluation costs mostly its fixed part): their results, in order."""
    results: list[Any] = [None] * len(walks)
    asked: dict[int, FloatArray] = {}

    def advance(k: int, sent: Sampled | None) -> None:
        try:
            asked[k] = next(walks[k]) if sent is None else walks[k].send(sent)
        except StopIteration as done:
            results[k] = done.value

    for k in range(len(walks)):
        advance(k, None)
    while asked:
        checkpoint()
        keys = list(asked)
        shapes = [asked[k].shape for k in keys]
        sample = curve.sample(np.concatenate([asked[k].reshape(-1) for k in keys]))
        ends = list(accumulate(asked[k].size for k in keys))
        asked = {}
        for k, shape, lo, hi in zip(keys, shapes, [0, *ends], ends):  # each walk's slice (np.split's, without its cost)
            advance(k, tuple(column[lo:hi].reshape(shape) for column in sample))  # type: ignore[arg-type]
    return results


def _curve_to_path(arrays: ElementArrays, first: IntArray, last: IntArray, theta: FloatArray,
                   sampled: Sampled) -> Walk:
    """curve → path: each span's largest distance of the curve from its elements (a biarc: the
    nearer of its two arcs), the sampled local maxima climbed to the top (:func:`_climb`)."""
    spans, m = theta.shape

    def deviation(span: IntArray, sample: Sampled) -> tuple[FloatArray, FloatArray]:
        x, y, tx, ty, stretch = sample
        vx, vy = stretch * tx, stretch * ty  # dP/dθ
        # both elements in one pass: row 0 the first, row 1 the last (their operations broadcast)
        (d0, d1), (s0, s1) = arrays.distance_slope(np.stack([first[span], last[span]]), x, y, vx, vy)
        nearer = d1 < d0
        return np.where(nearer, d1, d0), np.where(nearer, s1, s0)

    value, slope = deviation(np.repeat(np.arange(spans), m), sampled)
    samples = value.reshape(spans, m)
    result = samples.max(axis=1)
    rows, a_col, b_col, slope_lo, slope_hi = _brackets(theta, samples, slope.reshape(spans, m))
    lo, hi = theta[rows, a_col], theta[rows, b_col]

    def probe(t: FloatArray, lanes: IntArray, *_: FloatArray) -> Generator[FloatArray, Sampled,
                                                                          tuple[FloatArray, FloatArray, FloatArray]]:
        v, s = deviation(rows[lanes], (yield t))
        return v, s, t

    top = yield from _climb(lo, hi, slope_lo, slope_hi, lo, hi, probe)
    np.maximum.at(result, rows, top)
    return result


def _path_to_curve(arrays: ElementArrays, owner: IntArray, theta: FloatArray, sampled: Sampled,
                   lo: FloatArray, hi: FloatArray) -> Walk:
    """path → curve: each element's largest distance from the curve within its span (each point's
    foot on the curve by Gauss-Newton, :func:`_foot`), the sampled local maxima climbed to the top."""
    count, m = owner.size, theta.shape[1]
    frac = np.linspace(0.0, 1.0, m)
    lane = np.repeat(np.arange(count), m)
    u = np.tile(frac, count)
    px, py, pvx, pvy = arrays.along(lane, u)
    near = _nearest_sample(theta, sampled[0], sampled[1], owner, px, py)
    # the first Gauss-Newton step from the nearest sample reads the sample itself: no new evaluation
    x, y, tx, ty, stretch = (column.reshape(theta.shape)[owner[lane], near] for column in sampled)
    t0 = theta[owner[lane], near]
    lo_e, hi_e = lo[owner[lane]], hi[owner[lane]]
    distance, feet, toward = yield from _foot(px, py, _foot_step(t0, px, py, (x, y, tx, ty, stretch), lo_e, hi_e),
                                              lo_e, hi_e)
    slope = _away_slope(toward, pvx, pvy)
    samples = distance.reshape(count, m)
    result = samples.max(axis=1)
    rows, a_col, b_col, slope_a, slope_b = _brackets(np.tile(frac, (count, 1)), samples, slope.reshape(count, m))
    a, b = frac[a_col], frac[b_col]
    # the feet at the brackets' ends, whose interpolation starts each next foot (a step or two from it)
    foot_a, foot_b = feet.reshape(count, m)[rows, a_col], feet.reshape(count, m)[rows, b_col]
    lane_lo, lane_hi = lo[owner[rows]], hi[owner[rows]]  # each climbing lane's span

    def probe(uu: FloatArray, lanes: IntArray, ua: FloatArray, ub: FloatArray, fa: FloatArray, fb: FloatArray
              ) -> Generator[FloatArray, Sampled, tuple[FloatArray, FloatArray, FloatArray]]:
        qx, qy, qvx, qvy = arrays.along(rows[lanes], uu)
        w = np.divide(uu - ua, ub - ua, out=np.zeros(uu.shape), where=ub > ua)
        span_lo, span_hi = lane_lo[lanes], lane_hi[lanes]
        start = np.clip(fa + w * (fb - fa), span_lo, span_hi)
        d, foot, toward = yield from _foot(qx, qy, start, span_lo, span_hi)
        return d, _away_slope(toward, qvx, qvy), foot

    top = yield from _climb(a, b, slope_a, slope_b, foot_a, foot_b, probe)
    np.maximum.at(result, rows, top)
    return result


def _away_slope(toward: tuple[FloatArray, FloatArray], vx: FloatArray, vy: FloatArray) -> FloatArray:
    """d|X − P|/du of a point X moving at (vx, vy) from its foot P, ``toward`` the unit normal of the
    curve at P pointing from X to P (the foot's own motion is second order, it being the nearest point).

    The normal, not (P − X)/|P − X|: X' runs nearly along the curve, and a foot found to 1e-10 rad
    turns P − X of a few µm by ~1e-6 rad, which would swamp the slope near a top."""
    nx, ny = toward
    return -(nx * vx + ny * vy)


def _brackets(x: FloatArray, samples: FloatArray, slopes: FloatArray
              ) -> tuple[IntArray, IntArray, IntArray, FloatArray, FloatArray]:
    """Each sampled local maximum (rows of x, its samples and their slopes) as the pair of
    samples its slope falls through from + to −: (row, column a, column b, slope_a, slope_b).

    A maximum at an end whose slope points out of the row is that end itself (nothing to climb);
    one whose neighbours' slopes do not fall through zero (a kink, where the nearer element changes)
    is bracketed by its two neighbours with the slopes of a parabola through the three samples,
    so the climb still keeps within them."""
    rows, cols = _local_maxima(samples)
    n = samples.shape[1]
    left, right = np.maximum(cols - 1, 0), np.minimum(cols + 1, n - 1)
    here = slopes[rows, cols]
    # from the best sample, the side its slope points to
    to_right = here > 0
    a_col = np.where(to_right, cols, left)
    b_col = np.where(to_right, right, cols)
    sa, sb = slopes[rows, a_col], slopes[rows, b_col]
    climb = (a_col < b_col) & (sa > 0) & (sb < 0) & (here != 0)
    # a kink: the parabola through the three samples (its slope at the outer two) brackets its vertex
    kink = ~climb & (left < cols) & (cols < right)
    if kink.any():
        k, r, lc, mc, rc = np.flatnonzero(kink), rows[kink], left[kink], cols[kink], right[kink]
        xl, xm, xr = x[r, lc], x[r, mc], x[r, rc]
        fl, fm, fr = samples[r, lc], samples[r, mc], samples[r, rc]
        # the divided differences of the parabola: its slope at xl and xr
        d1, d2 = (fm - fl) / (xm - xl), (fr - fm) / (xr - xm)
        curv = (d2 - d1) / (xr - xl)
        sa, sb = sa.copy(), sb.copy()
        sa[k], sb[k] = d1 + curv * (xl - xm), d2 + curv * (xr - xm)
        a_col, b_col = a_col.copy(), b_col.copy()
        a_col[k], b_col[k] = lc, rc
        kink &= (sa > 0) & (sb < 0)
    keep = climb | kink
    return rows[keep], a_col[keep], b_col[keep], sa[keep], sb[keep]


def _climb(a: FloatArray, b: FloatArray, slope_a: FloatArray, slope_b: FloatArray, aux_a: FloatArray,
           aux_b: FloatArray, probe: Callable[..., Generator[FloatArray, Sampled, tuple[FloatArray, FloatArray,
                                                                                        FloatArray]]]
           ) -> Generator[FloatArray, Sampled, FloatArray]:
    """The tops of smooth functions, one per lane, each between a and b where its slope falls from
    + to −: Illinois steps on the slope (regula falsi, the end kept twice running has its slope
    halved), every lane in one probe per step, until the value could gain no more than CLIMB_GAIN_MM
    (the last slope times the bracket's width).

    ``probe(x, lanes, a, b, aux_a, aux_b)`` answers the value, slope and an aux value (a foot's cam
    angle) at x of those lanes; aux is kept at the brackets' ends. The answer is the best value probed
    per lane (−inf: none)."""
    a, b, sa, sb, aux_a, aux_b = (np.array(v, dtype=np.float64) for v in (a, b, slope_a, slope_b, aux_a, aux_b))
    best = np.full(a.size, -np.inf)
    active = np.arange(a.size)
    # the state of the lanes still climbing, in the order of ``active`` (no gathers and scatters of the
    # whole state per step): the end kept last (−1 a, +1 b) and the best value probed
    kept = np.zeros(a.size, dtype=np.int8)
    top = best.copy()
    for _ in range(CLIMB_STEPS):
        if not active.size:
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            x = b - sb * (b - a) / (sb - sa)
        # a step outside the bracket (rounding at its ends) bisects it
        x = np.where((x > a) & (x < b), x, 0.5 * (a + b))
        value, slope, aux = yield from probe(x, active, a, b, aux_a, aux_b)
        top = np.fmax(top, value)
        down = slope < 0  # x is past the top: the new b
        up = slope > 0
        # Illinois: an end kept twice running has its slope halved, so the other end moves next
        sa = np.where(down & (kept == -1), 0.5 * sa, np.where(up, slope, sa))
        sb = np.where(up & (kept == 1), 0.5 * sb, np.where(down, slope, sb))
        a, b = np.where(up, x, a), np.where(down, x, b)
        aux_a, aux_b = np.where(up, aux, aux_a), np.where(down, aux, aux_b)
        kept = np.where(down, -1, np.where(up, 1, 0))
        going = np.abs(slope) * (b - a) > CLIMB_GAIN_MM  # a NaN slope stops too
        if not going.all():
            best[active[~going]] = top[~going]
            active, kept = active[going], kept[going]
            a, b, sa, sb, aux_a, aux_b, top = (v[going] for v in (a, b, sa, sb, aux_a, aux_b, top))
    best[active] = top
    return best


def _foot_step(t: FloatArray, px: FloatArray, py: FloatArray, sample: Sampled, lo: FloatArray, hi: FloatArray
               ) -> FloatArray:
    """One Gauss-Newton step of the feet of points (px, py) from cam angles t, the curve's sample there given."""
    x, y, tx, ty, stretch = sample
    dx, dy = x - px, y - py
    speed2 = stretch * stretch
    step = np.where(speed2 > 0, (dx * tx + dy * ty) * stretch / np.where(speed2 > 0, speed2, 1.0), 0.0)
    return np.clip(t - step, lo, hi)


def _foot(px: FloatArray, py: FloatArray, theta: FloatArray, lo: FloatArray, hi: FloatArray
          ) -> Generator[FloatArray, Sampled, tuple[FloatArray, FloatArray, tuple[FloatArray, FloatArray]]]:
    """Distance of each point from the curve near θ, the foot's θ and the curve's unit normal there
    pointing from the point to its foot: Gauss-Newton on (P(θ) − X)·P'(θ) = 0, kept within [lo, hi],
    until no step would move a foot by more than FOOT_STEP_RAD (at most FOOT_STEPS); any curve point
    bounds the distance from above, so a foot that stops at an end still gives an upper bound."""
    t = theta.copy()
    for _ in range(FOOT_STEPS):
        sample = yield t
        moved = _foot_step(t, px, py, sample, lo, hi)
        # every lane converged, or held at an end of its stretch (a NaN lane does not hold the rest): the
        # distance here is the foot's to within (stretch·FOOT_STEP_RAD)²/(2·distance), below rounding
        if not (np.abs(moved - t) > FOOT_STEP_RAD).any():
            break
        t = moved
    else:
        sample = yield t
    x, y, tx, ty, _ = sample
    dx, dy = x - px, y - py
    side = np.where(ty * dx - tx * dy >= 0, 1.0, -1.0)  # N = (ty, −tx) or its opposite, towards P
    return np.hypot(dx, dy), t, (side * ty, -side * tx)


def _local_maxima(samples: FloatArray) -> tuple[np.ndarray, np.ndarray]:
    """Row and column of every sample not below its neighbours (the ends included)."""
    # as against neighbours padded with −inf (each end has one neighbour; a NaN is no peak), without np.pad
    peak = samples >= -np.inf
    peak[:, 1:] &= samples[:, 1:] >= samples[:, :-1]
    peak[:, :-1] &= samples[:, :-1] >= samples[:, 1:]
    rows, cols = np.nonzero(peak)
    return rows, cols


def _nearest_sample(theta: FloatArray, cx: FloatArray, cy: FloatArray, owner: IntArray, px: FloatArray,
                    py: FloatArray) -> IntArray:
    """For each element's points (``px``, ``py``: a row of them per element, flattened), the column of
    the nearest of its span's curve samples (``theta``: a row per span; ``cx``, ``cy`` the curve there)."""
    m = theta.shape[1]
    sx, sy = cx.reshape(-1, m)[owner], cy.reshape(-1, m)[owner]  # each element's span's samples
    ex, ey = px.reshape(owner.size, -1), py.reshape(owner.size, -1)
    dx, dy = sx[:, None, :] - ex[:, :, None], sy[:, None, :] - ey[:, :, None]
    # the squares order as the distances do, at a third of hypot's cost; in place: the arrays are large
    np.multiply(dx, dx, out=dx)
    np.multiply(dy, dy, out=dy)
    k: IntArray = np.argmin(np.add(dx, dy, out=dx), axis=2)
    return k.reshape(-1)
