"""Fitting a stretch of the exact cutter curve with biarcs within a tolerance.

The fit is greedy (longest first): from the start of a stretch, the end of each biarc is
pushed as far along a fine grid of cam angles as the tolerance allows (each next trial where
the distances of the last ones say it reaches the tolerance, within a bracket that keeps shrinking),
so the path has few elements. Each biarc is then measured against the exact curve both ways
(:mod:`.measure`), and a biarc that misses the tolerance is fitted again tighter.

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
from typing import TypeVar

import numpy as np

from ..curves.base import FloatArray
from ..deadline import checkpoint
from ..errors import GeometryError, LimitExceededError
from .geometry import Biarc, Element, biarc, biarc_of, pair_distance
from .measure import Span, measure
from .offset import OffsetCurve

#: the greedy search aims at this fraction of the tolerance, so the measurement between the
#: grid points (which the search does not see) rarely sends a biarc back
AIM = 0.8
#: what a trial of the greedy search fits (a biarc's numbers; anything in a test)
Fit = TypeVar("Fit")
#: a stretch narrower than this is closed with a line whatever it deviates (a cusp of a
#: gouging path, where the tangent turns back): 1e-10 rad moves a point by ~1e-8 mm
NARROWEST_RAD = 1e-10


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

    def trial(i: int, j: int) -> tuple[Biarc | None, float]:
        """The biarc over grid steps i … j and its largest distance from their points (inf: none); its
        elements are made only for the one kept (:meth:`Biarc.distance` measures without them)."""
        fit = biarc_of(pts[i], tan[i], pts[j], tan[j])
        if fit is None:
            return None, math.inf
        return fit, float(fit.distance(px[i:j + 1], py[i:j + 1]).max())

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
        pair = good_fit.elements(float(theta[i]), float(theta[good]))
        budget.add(len(pair))
        spans.append(Span(float(theta[i]), float(theta[good]), pair))
        guess = max(1, good - i)
        i = good
    return spans


def _farthest_fit(trial: Callable[[int, int], tuple[Fit | None, float]], i: int, n: int, guess: int,
                  aim_mm: float) -> tuple[int, Fit | None]:
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
        dist = pair_distance(pair, xs, ys)
        if float(dist.max()) <= aim_mm:
            budget.add(2)
            return [Span(theta0, theta1, pair)]
    mid = 0.5 * (theta0 + theta1)
    mx, my, mtx, mty, _ = curve.travel(np.array([mid]))
    middle = (np.array([mx[0], my[0]]), np.array([mtx[0], mty[0]]))
    return (_split(curve, theta0, mid, start, middle, aim_mm, budget)
            + _split(curve, mid, theta1, middle, end, aim_mm, budget))


