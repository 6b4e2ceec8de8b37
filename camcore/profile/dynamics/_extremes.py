"""Exact extremes of several functions of the cam angle at once: grid, then local grids.

Every function is sampled on a grid that holds every break point of the lift and its left
neighbour (:func:`camcore.profile.checks.check_grid`), so no jump of the lift's derivatives
lies strictly inside a grid cell and each function is smooth there. The best local maxima of
each function on the grid (up to :data:`MAX_CANDIDATES` of them, so a second basin whose
sampled peak is a little lower than the first is refined too) are refined by shrinking local
grids in both neighbouring cells, all lanes of all functions in one search (one evaluation of the
state per round, however many functions and candidates). A cell is refined to 1e-5 rad and then
by one parabolic step (:func:`camcore._maxima.polished_grid_max`): the value is then within rounding
of the extreme.

References
----------
.. [1] Kiefer (1953): a unimodal function's maximum lies between the best evaluated point's neighbours.
.. [2] Brent (1973), *Algorithms for Minimization without Derivatives*, ch. 5: the parabolic step.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..._maxima import POLISH_WIDTH, polished_grid_max
from ...curves.base import FloatArray

#: local maxima of the sampled function refined per function (the best ones by sampled value)
MAX_CANDIDATES = 16


def _clean(values: FloatArray) -> FloatArray:
    """NaN counts as −inf (a point where the function is not defined never wins)."""
    return np.where(np.isnan(values), -np.inf, values)


def refine_maxima(evaluate: Callable[[FloatArray], FloatArray], grid: FloatArray,
                  period: float = 2 * math.pi) -> tuple[FloatArray, FloatArray]:
    """The maximum of each of k periodic functions of the angle, and where it lies.

    ``evaluate(x)`` returns a (k, len(x)) array: the k functions at the angles x [rad].
    Returns the angles of the maxima in [0, period) and the maxima, one per function.
    """
    values = _clean(np.atleast_2d(evaluate(grid)))
    k, n = values.shape
    best_i = np.argmax(values, axis=1)
    best_t = grid[best_i].astype(np.float64)
    best_v = values[np.arange(k), best_i]
    lo: list[float] = []
    hi: list[float] = []
    owner: list[int] = []
    for j in range(k):
        v = values[j]
        before, after = np.roll(v, 1), np.roll(v, -1)
        peaks = np.flatnonzero(((v > before) & (v >= after)) | ((v >= before) & (v > after)))
        if peaks.size == 0:  # constant: any point is the maximum
            continue
        peaks = peaks[np.argsort(-v[peaks], kind="stable")[:MAX_CANDIDATES]]
        for i in peaks.tolist():
            left = float(grid[i - 1]) if i > 0 else float(grid[-1]) - period
            right = float(grid[i + 1]) if i + 1 < n else float(grid[0]) + period
            lo += [left, float(grid[i])]
            hi += [float(grid[i]), right]
            owner += [j, j]
    if owner:
        lanes = np.asarray(owner, dtype=np.intp)

        def lane_values(x: FloatArray) -> FloatArray:  # row i: points of lane i, of its function's
            every = _clean(np.atleast_2d(evaluate(x.reshape(-1))))
            return every[np.repeat(lanes, x.shape[1]), np.arange(x.size)].reshape(x.shape)

        t, v = polished_grid_max(lane_values, np.asarray(lo), np.asarray(hi), width=POLISH_WIDTH)
        for lane in range(lanes.size):
            j = int(lanes[lane])
            if v[lane] > best_v[j]:
                best_t[j], best_v[j] = t[lane], v[lane]
    return np.mod(best_t, period), best_v
