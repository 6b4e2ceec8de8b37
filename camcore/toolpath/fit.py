"""Fitting a stretch of the exact cutter curve with biarcs, and measuring how far apart they are.

The fit is greedy (longest first): from the start of a stretch, the end of each biarc is
pushed as far along a fine grid of cam angles as the tolerance allows (each next trial where
the distances of the last ones say it reaches the tolerance, within a bracket that keeps shrinking),
so the path has few elements. Each biarc is then *measured* against the
exact curve both ways, and a biarc that misses the tolerance is fitted again tighter:

* curve → path: the distance of the exact curve P(θ) from the biarc over its whole stretch
  of θ: sampled, and every sampled local maximum refined by shrinking local grids in θ and a
  parabolic step (so the largest distance between the sample points is found, not only at them);
* path → curve: the distance of the biarc's points from the exact curve (each point's foot
  on the curve by Gauss-Newton from the nearest sample, later from the feet already found),
  sampled along each element and the largest refined the same way along the element.

Both are one-sided Hausdorff distances; the larger is the biarc's deviation.

References
----------
.. [1] D. S. Meek, D. J. Walton, "Approximation of discrete data by G1 arc splines",
   Computer-Aided Design 24 (1992) 301-306 (biarcs fitted to data within a tolerance).
.. [2] J. Kiefer, "Sequential minimax search for a maximum", Proc. AMS 4 (1953) 502-506 (the
   maximum lies between the best evaluated point's neighbours).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._maxima import POLISH_WIDTH, polished_grid_max
from ..curves.base import FloatArray
from ..deadline import checkpoint
from ..errors import GeometryError, LimitExceededError
from .geometry import Element, ElementArrays, biarc
from .offset import LEFT_LIMIT_RAD, OffsetCurve

#: samples per biarc (over its stretch of θ) and per element (along it) for the measurement
MEASURE_SAMPLES = 32
MEASURE_GRID_POINTS = 9
#: the greedy search aims at this fraction of the tolerance, so the measurement between the
#: grid points (which the search does not see) rarely sends a biarc back
AIM = 0.8
#: a stretch narrower than this is closed with a line whatever it deviates (a cusp of a
#: gouging path, where the tangent turns back): 1e-10 rad moves a point by ~1e-8 mm
NARROWEST_RAD = 1e-10
#: the local grids' last width along an element (its parameter u runs 0 … 1) before the parabolic
#: step: the deviation is smooth along an arc, so the vertex lies within ~1e-8 of its maximum
ELEMENT_POLISH_WIDTH = 1e-4
#: Gauss-Newton steps of a foot point, at most: each multiplies the error by ~|P − X|·κ ≤ 1e-2
FOOT_STEPS = 5
#: a foot whose next step is under this has converged [rad]: it lies within about that of the foot
#: (~1e-8 mm along a 100 mm cam), and the distance there is off by the square of that over the distance
#: (a foot is where the distance is least): ~5e-14 mm at a 1e-3 mm deviation, the rounding of the coordinates
FOOT_STEP_RAD = 1e-10


@dataclass(frozen=True)
class Span:
    """Elements that stand for the exact curve between two cam angles (equal for a corner arc)."""

    theta0: float
    theta1: float
    elements: tuple[Element, ...]


class Budget:
    """Counts the elements made and stops the fit over ``limit`` (413)."""

    def __init__(self, limit: int):
        self.limit = limit
        self.count = 0

    def add(self, n: int) -> None:
        self.count += n
        if self.count > self.limit:
            raise LimitExceededError("toolpath elements", self.count, self.limit, field=("tolerance_mm",))


def fit_stretch(curve: OffsetCurve, theta0: float, theta1: float, start: tuple[FloatArray, FloatArray],
                end: tuple[FloatArray, FloatArray], tolerance_mm: float, step_rad: float,
                budget: Budget) -> tuple[list[Span], float]:
    """Biarcs within ``tolerance_mm`` of a regular stretch θ0 … θ1 of the exact curve.

    Parameters
    ----------
    curve : OffsetCurve
        The exact curve.
    theta0, theta1 : float
        The stretch, θ0 < θ1, with no corner or cusp inside [rad].
    start, end : (ndarray, ndarray)
        The point [mm] and the unit travel tangent [-] at each end (their one-sided limits).
    tolerance_mm : float
        Largest deviation allowed, measured both ways [mm].
    step_rad : float
        Spacing of the grid the greedy search picks biarc ends from [rad].
    budget : Budget
        The element count and its limit.

    Returns
    -------
    (list of Span, float)
        Consecutive biarcs (or lines) from θ0 to θ1, each measured within the tolerance, and
        the largest deviation measured [mm].

    References
    ----------
    Meek and Walton (1992), arc splines within a tolerance; Kiefer (1953), golden section.
    """
    spans = _greedy(curve, theta0, theta1, start, end, AIM * tolerance_mm, step_rad, budget)
    for tighter in range(1, 8):
        deviation = measure(curve, spans)
        if float(deviation.max(initial=0.0)) <= tolerance_mm:
            return spans, float(deviation.max(initial=0.0))
        checkpoint()
        refitted: list[Span] = []
        for span, dev in zip(spans, deviation):
            if dev <= tolerance_mm:
                refitted.append(span)
                continue
            # fitted again over its own stretch, aiming lower, from a grid 8 times finer
            budget.add(-len(span.elements))
            a = (np.asarray(span.elements[0].start), _tangent_from(curve, span.theta0, 1.0))
            b = (np.asarray(span.elements[-1].end), _tangent_from(curve, span.theta1, -1.0))
            refitted += _greedy(curve, span.theta0, span.theta1, a, b, AIM * tolerance_mm * 0.5 ** tighter,
                                (span.theta1 - span.theta0) / 8, budget)
        spans = refitted
    raise GeometryError(f"the path could not be fitted within {tolerance_mm!r} mm between cam angles "
                        f"{math.degrees(theta0)!r}° and {math.degrees(theta1)!r}°.", field=("tolerance_mm",))


def _tangent_from(curve: OffsetCurve, theta: float, side: float) -> FloatArray:
    """The unit travel tangent at θ, taken just inside the stretch (side +1: after θ, −1: before)."""
    _, _, tx, ty, _ = curve.travel(np.array([theta + side * 1e3 * NARROWEST_RAD]))
    return np.array([tx[0], ty[0]])


def _greedy(curve: OffsetCurve, theta0: float, theta1: float, start: tuple[FloatArray, FloatArray],
            end: tuple[FloatArray, FloatArray], aim_mm: float, step_rad: float, budget: Budget) -> list[Span]:
    n = max(2, math.ceil((theta1 - theta0) / step_rad))
    theta = np.linspace(theta0, theta1, n + 1)
    x, y, tx, ty, _ = curve.travel(theta)
    px, py = x.copy(), y.copy()
    px[0], py[0], px[-1], py[-1] = start[0][0], start[0][1], end[0][0], end[0][1]
    tx[0], ty[0], tx[-1], ty[-1] = start[1][0], start[1][1], end[1][0], end[1][1]
    pts = np.column_stack([px, py])
    tan = np.column_stack([tx, ty])

    def trial(i: int, j: int) -> tuple[tuple[Element, ...] | None, float]:
        """The biarc over grid steps i … j and its largest distance from their points (inf: none)."""
        pair = biarc(pts[i], tan[i], pts[j], tan[j], float(theta[i]), float(theta[j]))
        if pair is None:
            return None, math.inf
        xs, ys = px[i:j + 1], py[i:j + 1]
        return pair, float(np.minimum(pair[0].distance(xs, ys), pair[1].distance(xs, ys)).max())

    spans: list[Span] = []
    i, guess = 0, 8
    while i < n:
        checkpoint()
        good, good_fit = _farthest_fit(trial, i, n, guess, aim_mm)
        if good_fit is None:  # not even one grid step: split that step in θ
            spans += _split(curve, float(theta[i]), float(theta[i + 1]), (pts[i], tan[i]), (pts[i + 1], tan[i + 1]),
                            aim_mm, budget)
            i += 1
            continue
        budget.add(len(good_fit))
        spans.append(Span(float(theta[i]), float(theta[good]), good_fit))
        guess = max(1, good - i)
        i = good
    return spans


def _farthest_fit(trial: Callable[[int, int], tuple[tuple[Element, ...] | None, float]], i: int, n: int, guess: int,
                  aim_mm: float) -> tuple[int, tuple[Element, ...] | None]:
    """The farthest grid point j ≤ n whose biarc from i keeps within ``aim_mm``, where a biarc's distance
    grows with its length: j and its biarc (i and None when not even i + 1 fits).

    Each next trial is where a power law through the last two (the distance of a biarc fitted to a smooth
    curve grows as about the cube of its length) crosses the aim, kept inside the bracket; a trial on
    the same side as the last two bisects instead, so the bracket at least halves every third trial. A
    few trials (3–4) find the point bisection finds in 8.
    """
    good, good_fit, good_d, bad, bad_d = i, None, 0.0, n + 1, math.inf
    j, sides = min(n, i + guess), ""
    while True:
        fit, d = trial(i, j)
        fits = fit is not None and d <= aim_mm
        if fits:
            good, good_fit, good_d = j, fit, d
        else:
            bad, bad_d = j, d
        sides = (sides + ("g" if fits else "b"))[-3:]
        if bad - good <= 1 or good == n:
            return good, good_fit
        if sides in ("ggg", "bbb"):  # the prediction keeps landing on one side: halve the bracket
            j = (good + bad) // 2
            continue
        # the power law d ∝ (j − i)^p through the known points (p = 3 with only one)
        if good > i and good_d > 0 and bad <= n and math.isfinite(bad_d) and bad_d > good_d:
            power = math.log(bad_d / good_d) / math.log((bad - i) / (good - i))
            ref, ref_d = good, good_d
        elif good > i and good_d > 0:
            power, ref, ref_d = 3.0, good, good_d
        elif bad <= n and math.isfinite(bad_d) and bad_d > 0:
            power, ref, ref_d = 3.0, bad, bad_d
        else:
            j = (good + bad) // 2 if bad <= n else min(n, i + 2 * (good - i))
            continue
        reach = i + (ref - i) * (aim_mm / ref_d) ** (1.0 / power)
        # beyond a good point the law extrapolates, so at most 4 times as far; below a bad one it
        # interpolates (a first guess just too long: the next trial is just short of it, not 4 steps)
        most = i + 4 * max(1, good - i) if ref == good else bad - 1
        j = int(min(max(math.floor(reach), good + 1), bad - 1, n, most))


def _split(curve: OffsetCurve, theta0: float, theta1: float, start: tuple[FloatArray, FloatArray],
           end: tuple[FloatArray, FloatArray], aim_mm: float, budget: Budget) -> list[Span]:
    """Biarcs over one grid step that no single biarc fits, by halving it (near a cusp)."""
    checkpoint()
    if theta1 - theta0 <= NARROWEST_RAD:
        budget.add(1)
        line = Element((float(start[0][0]), float(start[0][1])), (float(end[0][0]), float(end[0][1])), None, True,
                       theta0, theta1)
        return [Span(theta0, theta1, (line,))]
    inside = np.linspace(theta0, theta1, 17)[1:-1]
    xs, ys = curve.points(inside)
    pair = biarc(start[0], start[1], end[0], end[1], theta0, theta1)
    if pair is not None:
        dist = np.minimum(pair[0].distance(xs, ys), pair[1].distance(xs, ys))
        if float(dist.max()) <= aim_mm:
            budget.add(2)
            return [Span(theta0, theta1, pair)]
    mid = 0.5 * (theta0 + theta1)
    mx, my, mtx, mty, _ = curve.travel(np.array([mid]))
    middle = (np.array([mx[0], my[0]]), np.array([mtx[0], mty[0]]))
    return (_split(curve, theta0, mid, start, middle, aim_mm, budget)
            + _split(curve, mid, theta1, middle, end, aim_mm, budget))


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
    Kiefer (1953), the maximum between the best point's neighbours; Brent (1973), the parabolic step;
    the Gauss-Newton foot point of a point on a curve.
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
    m = MEASURE_SAMPLES
    # curve → path: the distance from the span's elements (a biarc: the nearer of its two arcs)
    frac = np.linspace(0.0, 1.0, m)
    theta = lo[:, None] + (hi - lo)[:, None] * frac[None, :]
    lanes = np.repeat(np.arange(len(live)), m)

    def from_path(lane: np.ndarray, x: FloatArray, y: FloatArray) -> FloatArray:
        return np.minimum(arrays.distance(first[lane], x, y), arrays.distance(last[lane], x, y))

    def to_path(lane: np.ndarray, t: FloatArray) -> FloatArray:
        return from_path(lane, *curve.points(t))

    cx, cy = curve.points(theta.reshape(-1))  # the curve at the samples, for both directions
    samples = from_path(lanes, cx, cy).reshape(len(live), m)
    forward = samples.max(axis=1)
    rows, cols = _local_maxima(samples)
    if rows.size:
        a = theta[rows, np.maximum(cols - 1, 0)]
        b = theta[rows, np.minimum(cols + 1, m - 1)]

        def to_path_rows(t: FloatArray) -> FloatArray:
            return to_path(np.repeat(rows, t.shape[1]), t.reshape(-1)).reshape(t.shape)

        _, refined = polished_grid_max(to_path_rows, a, b, width=POLISH_WIDTH, points=MEASURE_GRID_POINTS)
        np.maximum.at(forward, rows, refined)
    # path → curve: each element's points, their feet on the curve (within the span's θ)
    owner = np.repeat(np.arange(len(live)), [len(spans[k].elements) for k in live])
    count = len(elements)
    u = np.tile(frac, count)
    lane_e = np.repeat(np.arange(count), m)
    px, py = arrays.point(lane_e, u)
    guess = _nearest_sample(theta, cx, cy, owner, px, py)
    lo_e, hi_e = lo[owner[lane_e]], hi[owner[lane_e]]
    back_distance, back_foot = _foot(curve, px, py, guess, lo_e, hi_e)
    back_samples = back_distance.reshape(count, m)
    backward = back_samples.max(axis=1)
    best = np.argmax(back_samples, axis=1)
    ua = frac[np.maximum(best - 1, 0)]
    ub = frac[np.minimum(best + 1, m - 1)]
    # the feet last found along each element (sorted by u): each new point's foot starts from their
    # interpolation, within the square of the grid's spacing of the answer (a Gauss-Newton step or two)
    known_u: FloatArray = np.tile(frac, (count, 1))
    known_foot: FloatArray = back_foot.reshape(count, m)

    def to_curve(uu: FloatArray) -> FloatArray:
        nonlocal known_u, known_foot
        lane = np.repeat(np.arange(count), uu.shape[1])
        x, y = arrays.point(lane, uu.reshape(-1))
        start = _interpolated(known_u, known_foot, uu).reshape(-1)
        distance, feet = _foot(curve, x, y, start, lo[owner[lane]], hi[owner[lane]])
        if uu.shape[1] > 1:
            known_u, known_foot = uu, feet.reshape(uu.shape)
        return distance.reshape(uu.shape)

    _, refined_back = polished_grid_max(to_curve, ua, ub, width=ELEMENT_POLISH_WIDTH, points=MEASURE_GRID_POINTS)
    backward = np.maximum(backward, refined_back)
    per_span = np.zeros(len(live))
    np.maximum.at(per_span, owner, backward)
    out[live] = np.maximum(forward, per_span)
    return out


def _local_maxima(samples: FloatArray) -> tuple[np.ndarray, np.ndarray]:
    """Row and column of every sample not below its neighbours (the ends included)."""
    padded = np.pad(samples, ((0, 0), (1, 1)), constant_values=-np.inf)
    peak = (samples >= padded[:, :-2]) & (samples >= padded[:, 2:])
    rows, cols = np.nonzero(peak)
    return rows, cols


def _interpolated(known_u: FloatArray, known: FloatArray, u: FloatArray) -> FloatArray:
    """Row by row, the linear interpolation at ``u`` of values ``known`` at sorted ``known_u``
    (extended linearly beyond the row's ends)."""
    k = np.clip(np.sum(known_u[:, None, :] <= u[:, :, None], axis=2) - 1, 0, known_u.shape[1] - 2)
    u0, u1 = np.take_along_axis(known_u, k, axis=1), np.take_along_axis(known_u, k + 1, axis=1)
    f0, f1 = np.take_along_axis(known, k, axis=1), np.take_along_axis(known, k + 1, axis=1)
    span = u1 - u0
    w = np.divide(u - u0, span, out=np.zeros_like(u), where=span > 0)
    return f0 + w * (f1 - f0)


def _nearest_sample(theta: FloatArray, cx: FloatArray, cy: FloatArray, owner: np.ndarray, px: FloatArray,
                    py: FloatArray) -> FloatArray:
    """For each element's points (``px``, ``py``: a row of them per element, flattened), the θ of the
    nearest of its span's curve samples (``theta``: a row per span; ``cx``, ``cy`` the curve there)."""
    m = theta.shape[1]
    sx, sy = cx.reshape(-1, m)[owner], cy.reshape(-1, m)[owner]  # each element's span's samples
    ex, ey = px.reshape(owner.size, -1), py.reshape(owner.size, -1)
    k = np.argmin(np.hypot(sx[:, None, :] - ex[:, :, None], sy[:, None, :] - ey[:, :, None]), axis=2)
    return np.take_along_axis(theta[owner], k, axis=1).reshape(-1)


def _foot(curve: OffsetCurve, px: FloatArray, py: FloatArray, theta: FloatArray, lo: FloatArray,
          hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Distance of each point from the curve near θ, and the foot's θ: Gauss-Newton on
    (P(θ) − X)·P'(θ) = 0, kept within [lo, hi], until no step would move a foot by more than
    FOOT_STEP_RAD (at most FOOT_STEPS); any curve point bounds the distance from above, so a foot that
    stops at an end still gives an upper bound."""
    t = theta.copy()
    for _ in range(FOOT_STEPS):
        x, y, tx, ty, stretch = curve.sample(t)
        dx, dy = x - px, y - py
        speed2 = stretch * stretch
        step = np.where(speed2 > 0, (dx * tx + dy * ty) * stretch / np.where(speed2 > 0, speed2, 1.0), 0.0)
        moved = np.clip(t - step, lo, hi)
        # every lane converged, or held at an end of its stretch (a NaN lane does not hold the rest): the
        # distance here is the foot's to within (stretch·FOOT_STEP_RAD)²/(2·distance), below rounding
        if not (np.abs(moved - t) > FOOT_STEP_RAD).any():
            return np.hypot(dx, dy), t
        t = moved
    x, y = curve.points(t)
    return np.hypot(x - px, y - py), t
