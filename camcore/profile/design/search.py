"""The bounded search over the design's remaining variables (offset, roller radius, and the spring
rate where it trades against the contact stress).

:func:`nested_minimum` (the offset and the roller radius): one variable at a time, nested. For each
value of the outer variable the inner one is minimised first: a coarse grid over its range brackets
the best point between its neighbours, and golden section closes the bracket to
:data:`LOCATION_TOLERANCE` of the range; the outer variable is searched the same way over the inner
minima. Every inner search of one outer round runs side by side (one evaluation of all of them per
step). A search along one variable is exact for a function unimodal along it (Kiefer), which the
design's base radius is along the roller radius (the pressure limit's radius falls as the roller
grows, the curvature limit's rises) and along the offset; unlike a grid over both at once it cannot
stall on the ridge where two limits trade (the minimum of a maximum of two functions lies on a curve
that no grid direction follows).

:func:`grid_minimum`: a grid over the whole box (the coarse screening of a 422's limits), optionally refined
by shrinking local grids around its best points.

Each round evaluates a local grid of :data:`LOCAL_POINTS` points per variable over a box around a
start's best point and keeps the best point ever evaluated; the next box is that point ± one local
step, so the box halves every round, until it is narrower than :data:`LOCATION_TOLERANCE` of each
variable's range. A local grid samples diagonal directions too, so the ridge of a maximum of two
limits (where the pressure angle and the curvature trade) does not stall it as a search along one
variable at a time would. The :data:`STARTS` best local minima of the coarse grid are refined side by
side, so a second basin is not lost to a slightly better first grid point.

References
----------
.. [1] Kiefer (1953): a unimodal function's minimum lies between the neighbours of the best of any
   set of evaluated points (the local grids).
.. [2] Hooke and Jeeves, "Direct search solution of numerical and statistical problems", J. ACM 8
   (1961) 212-229 (pattern search on shrinking steps).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...curves.base import FloatArray
from ...deadline import checkpoint

#: points per variable of the coarse grid, by the number of variables searched
COARSE_POINTS = {1: 33, 2: 13, 3: 7}
#: points per variable of each local grid (5: the next box, ± one step, is half the last)
LOCAL_POINTS = 5
#: the search stops when every box is narrower than this share of its variable's range
LOCATION_TOLERANCE = 1e-5
#: best local minima of the coarse grid refined side by side
STARTS = 2
#: points of the coarse grid of each variable of a nested search: the outer one, the inner ones
NESTED_OUTER_POINTS = 13
NESTED_INNER_POINTS = 9
#: the golden section's ratio
GOLDEN = (5**0.5 - 1) / 2


@dataclass(frozen=True)
class SearchOutcome:
    """Where the search settled: the point (None: no candidate met the limits), its value, how many
    candidates it evaluated and in how many rounds."""

    point: FloatArray | None
    value: float
    evaluations: int
    rounds: int
    coarse_points: int


def _local_minima(values: FloatArray) -> list[tuple[int, ...]]:
    """Grid indices whose finite value is at most every neighbour's along each axis, best first (ties in
    index order)."""
    finite = np.isfinite(values)
    is_min = finite.copy()
    for axis in range(values.ndim):
        for shift in (1, -1):
            neighbour = np.roll(values, shift, axis=axis)
            edge = [slice(None)] * values.ndim
            edge[axis] = slice(0, 1) if shift == 1 else slice(-1, None)
            neighbour[tuple(edge)] = np.inf  # no wrap-around: a bound has no neighbour beyond it
            is_min &= values <= neighbour
    flat = np.flatnonzero(is_min.ravel())
    order = flat[np.lexsort((flat, values.ravel()[flat]))]
    return [tuple(int(i) for i in np.unravel_index(k, values.shape)) for k in order]


def grid_minimum(objective: Callable[[FloatArray], FloatArray], lo: FloatArray, hi: FloatArray,
                 refine: bool = True) -> SearchOutcome:
    """The smallest value of ``objective`` over the box [lo, hi] (coarse grid, then local grids).

    Parameters
    ----------
    objective : callable
        ``points (m, d) -> values (m,)``; +inf where a point is infeasible [mm].
    lo, hi : ndarray
        The box, lo < hi in every variable [mm, N/mm or N·m/rad].
    refine : bool
        Refine the coarse grid's best points (else the best coarse point is the answer).

    Returns
    -------
    SearchOutcome
        The best point found (None when every coarse point is infeasible) and its value [mm], the
        evaluations and rounds [-].

    References
    ----------
    Hooke and Jeeves (1961), pattern search; Kiefer (1953), the best of a grid's points.
    """
    d = lo.size
    if d == 0:
        value = float(objective(np.zeros((1, 0)))[0])
        return SearchOutcome(np.zeros(0) if np.isfinite(value) else None, value, 1, 0, 1)
    n = COARSE_POINTS[d]
    axes = [np.linspace(lo[i], hi[i], n) for i in range(d)]
    mesh = np.stack([g.ravel() for g in np.meshgrid(*axes, indexing="ij")], axis=1)
    values = objective(mesh).reshape((n,) * d)
    evaluations = mesh.shape[0]
    starts = _local_minima(values)[:STARTS]
    if not starts:
        return SearchOutcome(None, float("inf"), evaluations, 0, evaluations)
    span = hi - lo
    step = span / (n - 1)
    best = [np.array([axes[i][k[i]] for i in range(d)]) for k in starts]
    best_value = [float(values[k]) for k in starts]
    boxes = [(np.maximum(lo, b - step), np.minimum(hi, b + step)) for b in best]
    frac = np.linspace(0.0, 1.0, LOCAL_POINTS)
    rounds = 0
    while refine and any(np.any(b_hi - b_lo > LOCATION_TOLERANCE * span) for b_lo, b_hi in boxes):
        checkpoint()
        rounds += 1
        grids = []
        for b_lo, b_hi in boxes:
            grids.append(np.array([b_lo + (b_hi - b_lo) * np.array(c) for c in itertools.product(frac, repeat=d)]))
        found = objective(np.concatenate(grids))
        evaluations += found.size
        per = LOCAL_POINTS**d
        for s, grid in enumerate(grids):
            local = found[s * per:(s + 1) * per]
            j = int(np.argmin(local))
            if local[j] < best_value[s]:
                best[s], best_value[s] = grid[j], float(local[j])
            width = (boxes[s][1] - boxes[s][0]) / (LOCAL_POINTS - 1)
            boxes[s] = (np.maximum(lo, best[s] - width), np.minimum(hi, best[s] + width))
    s = int(np.argmin(best_value))
    return SearchOutcome(best[s], best_value[s], evaluations, rounds, n**d)


def golden_steps(points: int) -> int:
    """Golden-section steps that close a bracket of two coarse cells of ``points`` to the tolerance.

    Parameters
    ----------
    points : int
        Points of the coarse grid over the variable's range [-].

    Returns
    -------
    int
        Steps, each shrinking the bracket by the golden ratio 0.618 [-].

    References
    ----------
    Kiefer (1953), golden-section search.
    """
    return int(np.ceil(np.log(LOCATION_TOLERANCE * (points - 1) / 2.0) / np.log(GOLDEN)))


def _nested(objective: Callable[[FloatArray], FloatArray], lo: FloatArray, hi: FloatArray, prefix: FloatArray,
            counter: list[int]) -> tuple[FloatArray, FloatArray]:
    """For every row of ``prefix`` (values of the first k variables), the best values of the remaining
    ones and the objective there: the next variable by coarse grid and golden section, the rest nested."""
    m, k = prefix.shape
    d = lo.size
    n = NESTED_OUTER_POINTS if k == 0 else NESTED_INNER_POINTS

    def deeper(x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The best of the rest (and the value) for each row of prefixes extended by one variable."""
        if x.shape[1] == d:
            counter[0] += x.shape[0]
            return x, objective(x)
        return _nested(objective, lo, hi, x, counter)

    checkpoint()
    axis = np.linspace(lo[k], hi[k], n)
    rows = np.column_stack([np.repeat(prefix, n, axis=0), np.tile(axis, m)])
    points, values = deeper(rows)
    points, values = points.reshape(m, n, d), values.reshape(m, n)
    j = np.argmin(values, axis=1)
    lanes = np.arange(m)
    best_x, best_v = points[lanes, j], values[lanes, j]
    a = axis[np.maximum(j - 1, 0)]
    b = axis[np.minimum(j + 1, n - 1)]
    x1, x2 = b - GOLDEN * (b - a), a + GOLDEN * (b - a)

    def at(x: FloatArray) -> tuple[FloatArray, FloatArray]:
        return deeper(np.column_stack([prefix, x]))

    p1, f1 = at(x1)
    p2, f2 = at(x2)
    for _ in range(golden_steps(n)):
        checkpoint()
        right = f2 < f1  # the minimum lies in [x1, b]: drop [a, x1); else in [a, x2]: drop (x2, b]
        a, b = np.where(right, x1, a), np.where(right, b, x2)
        x_new = np.where(right, a + GOLDEN * (b - a), b - GOLDEN * (b - a))
        p_new, f_new = at(x_new)
        keep = right[:, None]
        x1, x2 = np.where(right, x2, x_new), np.where(right, x_new, x1)
        p1, p2 = np.where(keep, p2, p_new), np.where(keep, p_new, p1)
        f1, f2 = np.where(right, f2, f_new), np.where(right, f_new, f1)
    for p, f in ((p1, f1), (p2, f2)):
        better = f < best_v
        best_x, best_v = np.where(better[:, None], p, best_x), np.where(better, f, best_v)
    return best_x, best_v


def nested_minimum(objective: Callable[[FloatArray], FloatArray], lo: FloatArray, hi: FloatArray) -> SearchOutcome:
    """The smallest value of ``objective`` over the box [lo, hi], one variable at a time, nested.

    Parameters
    ----------
    objective : callable
        ``points (m, d) -> values (m,)``; +inf where a point is infeasible [mm].
    lo, hi : ndarray
        The box, lo < hi in every variable [mm].

    Returns
    -------
    SearchOutcome
        The best point (None when none is feasible) and its value [mm], the evaluations [-]
        (``rounds``: the golden-section steps of each variable's search).

    References
    ----------
    Kiefer (1953), golden-section search (exact for a function unimodal within its bracket).
    """
    d = lo.size
    if d == 0:
        return grid_minimum(objective, lo, hi)
    counter = [0]
    points, values = _nested(objective, lo, hi, np.zeros((1, 0)), counter)
    value = float(values[0])
    coarse = NESTED_OUTER_POINTS * NESTED_INNER_POINTS ** (d - 1)
    return SearchOutcome(points[0] if np.isfinite(value) else None, value, counter[0],
                         golden_steps(NESTED_OUTER_POINTS), coarse)
