"""Maxima of functions the solvers of camcore share, each with its guarantees.

- :func:`golden_max`: the maximum of a unimodal function on an interval (one new point per
  step); used where each evaluation is a lane of its own (toolpath fitting, dynamics).
- :func:`polished_grid_max`: the maximum of a smooth function to within rounding, shrinking grids
  to a small width, then one parabolic step.
- :func:`local_grid_max`: the same maxima by shrinking local grids (a few calls of many
  points each); :func:`periodic_grid_maxima` refines several quantities of one grid this way,
  all in one call per round (a profile's checks); :func:`periodic_grid_max` one quantity.

References
----------
.. [1] J. Kiefer, "Sequential minimax search for a maximum", Proc. AMS 4 (1953) 502-506
   (golden-section search).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ._solvers import FloatArray
from .deadline import checkpoint

#: golden-section steps: 0.618^80 ≈ 2e-17 of the starting interval
GOLDEN_ITERATIONS = 80

#: width [rad] to which :func:`periodic_grid_max` refines an extreme of a function of the cam angle
PERIODIC_WIDTH = 1e-9

#: width of :func:`polished_grid_max`'s grids before its parabolic step, for a function of the cam angle
#: [rad] (the vertex then lies within about |f‴/f″|·1e-10 of the maximum, the value within rounding)
POLISH_WIDTH = 1e-5

#: points of each local grid of :func:`polished_grid_max`: a call narrows an interval 4-fold
POLISH_GRID_POINTS = 9

#: points of each local grid of :func:`local_grid_max`: a round narrows an interval 16-fold,
#: so a 7200-point grid's cell (8.7e-4 rad) reaches PERIODIC_WIDTH in 5 rounds
LOCAL_GRID_POINTS = 33

#: rounds of :func:`local_grid_max`: 16^13 ≈ 4.5e15 narrows any interval of one period to an ulp
LOCAL_GRID_ROUNDS = 13


def golden_max(fun: Callable[[FloatArray], FloatArray], a: float | FloatArray, b: float | FloatArray,
               iterations: int = GOLDEN_ITERATIONS, width: float = 1e-13) -> tuple[FloatArray, FloatArray]:
    """Maxima of unimodal functions on intervals [a, b] by golden-section search, all
    intervals refined together (one call of ``fun`` per step for all of them).

    Parameters
    ----------
    fun : callable
        Vectorised function, evaluated elementwise (lane i only ever sees points of
        interval i, so each lane is the scalar search it replaces).
    a, b : float or ndarray
        The intervals' ends [-].
    iterations : int
        At most this many steps [-].
    width : float
        A lane stops shrinking once its interval is narrower than this [-].

    Returns
    -------
    (ndarray, ndarray)
        The best point of each interval and the value there [-].

    References
    ----------
    Kiefer (1953), golden-section search.
    """
    checkpoint()
    g = (math.sqrt(5.0) - 1.0) / 2.0
    lo = np.atleast_1d(np.asarray(a, dtype=np.float64)).copy()
    hi = np.atleast_1d(np.asarray(b, dtype=np.float64)).copy()
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = fun(x1), fun(x2)
    for _ in range(iterations):
        active = hi - lo >= width
        if not active.any():
            break
        right = active & (f1 < f2)  # the maximum lies in [x1, hi]: drop [lo, x1)
        left = active & ~right
        lo, hi = np.where(right, x1, lo), np.where(left, x2, hi)
        x1, f1, x2, f2 = np.where(right, x2, x1), np.where(right, f2, f1), np.where(left, x1, x2), np.where(left, f1, f2)
        new = np.where(right, lo + g * (hi - lo), hi - g * (hi - lo))
        f_new = fun(new)
        x2, f2 = np.where(right, new, x2), np.where(right, f_new, f2)
        x1, f1 = np.where(left, new, x1), np.where(left, f_new, f1)
    better_first = f1 >= f2
    return np.where(better_first, x1, x2), np.where(better_first, f1, f2)


def polished_grid_max(fun: Callable[[FloatArray], FloatArray], a: float | FloatArray, b: float | FloatArray,
                      width: float, points: int = POLISH_GRID_POINTS) -> tuple[FloatArray, FloatArray]:
    """Maxima of smooth unimodal functions on intervals [a, b]: shrinking local grids
    (:func:`local_grid_max`) to ``width``, then one parabolic step, all intervals together.

    The best grid point lies within ``width`` of its maximum; the parabola through it and two points a
    quarter of that width either side (the end of [a, b] instead where the point lies within ``width``
    of it) puts its vertex within about |f‴/f″|·width² of the maximum, where the value is within
    rounding of the extreme. The answer is the best point evaluated, and a maximum at an end of [a, b]
    (a kink there) is evaluated at the end itself. For a function whose every call costs far more than
    its points (a curve evaluated afresh), ``points`` = 9 narrows an interval 4-fold per call where
    golden section narrows it 1.6-fold.

    Parameters
    ----------
    fun : callable
        Vectorised function of a 2-D array (one row of points per interval), answering an array of
        the same shape; row i only ever holds points of interval i; non-finite values count as −inf.
    a, b : float or ndarray
        The intervals' ends [-].
    width : float
        Width of the last local grid's interval before the parabolic step [-].
    points : int
        Points of each local grid (≥ 3) [-].

    Returns
    -------
    (ndarray, ndarray)
        The best point of each interval and the value there [-].

    References
    ----------
    Kiefer (1953), the maximum between the best point's neighbours; Brent (1973), ch. 5 (the
    parabolic step through three points).
    """
    lo = np.atleast_1d(np.asarray(a, dtype=np.float64))
    hi = np.atleast_1d(np.asarray(b, dtype=np.float64))
    x, f = local_grid_max(fun, lo, hi, width=width, points=points)
    # two points a quarter of the width either side, or the interval's end where the best point lies
    # within the width of it (a maximum at an end, a kink there, is then evaluated at the end itself)
    step = 0.25 * width
    xm = np.where(x - lo < width, lo, x - step)
    xp = np.where(hi - x < width, hi, x + step)
    fm, fp = np.asarray(fun(np.column_stack([xm, xp])), dtype=np.float64).T  # both in one call
    # the vertex of the parabola through (xm, fm), (x, f), (xp, fp); a lane with an infinite value has none
    dm, dp = x - xm, x - xp
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        num = dm * dm * (f - fp) - dp * dp * (f - fm)
        den = dm * (f - fp) - dp * (f - fm)
        vertex = x - 0.5 * num / den
    vertex = np.clip(np.where(np.isfinite(vertex), vertex, x), xm, xp)
    fv = np.asarray(fun(vertex[:, None]), dtype=np.float64)[:, 0]
    best_x, best_f = x, f
    for xs, fs in ((xm, fm), (xp, fp), (vertex, fv)):
        better = fs > best_f
        best_x, best_f = np.where(better, xs, best_x), np.where(better, fs, best_f)
    return best_x, best_f


def local_grid_max(fun: Callable[[FloatArray], FloatArray], a: float | FloatArray, b: float | FloatArray,
                   width: float, points: int = LOCAL_GRID_POINTS) -> tuple[FloatArray, FloatArray]:
    """Maxima of unimodal functions on intervals [a, b] by shrinking local grids, all
    intervals refined together (one call of ``fun`` per round for all of them).

    Each round evaluates ``points`` evenly spaced points of every interval and keeps the
    best point's two neighbours as the next interval, until every interval is narrower than
    ``width``. The answer is the best point ever evaluated, so it is never worse than the
    interval's ends.

    Parameters
    ----------
    fun : callable
        Vectorised function of a 2-D array (one row of points per interval), answering an
        array of the same shape; non-finite values count as −inf.
    a, b : float or ndarray
        The intervals' ends [-].
    width : float
        An interval stops shrinking once it is narrower than this [-].
    points : int
        Points of each local grid (≥ 3) [-].

    Returns
    -------
    (ndarray, ndarray)
        The best point of each interval and the value there [-].

    References
    ----------
    Kiefer (1953): a unimodal function's maximum lies between the neighbours of the best of
    any set of evaluated points (here a uniform grid rather than the golden section).
    """
    lo = np.atleast_1d(np.asarray(a, dtype=np.float64)).copy()
    hi = np.atleast_1d(np.asarray(b, dtype=np.float64)).copy()
    rows = np.arange(lo.size)
    frac = np.linspace(0.0, 1.0, points)
    best_t, best_v = lo.copy(), np.full(lo.size, -np.inf)
    for _ in range(LOCAL_GRID_ROUNDS):
        checkpoint()
        x = lo[:, None] + (hi - lo)[:, None] * frac
        v = np.asarray(fun(x), dtype=np.float64)
        v = np.where(np.isfinite(v), v, -np.inf)
        j = np.argmax(v, axis=1)
        better = v[rows, j] > best_v
        best_t, best_v = np.where(better, x[rows, j], best_t), np.where(better, v[rows, j], best_v)
        active = hi - lo >= width
        if not active.any():
            break
        lo = np.where(active, x[rows, np.maximum(j - 1, 0)], lo)
        hi = np.where(active, x[rows, np.minimum(j + 1, points - 1)], hi)
    return best_t, best_v


def periodic_grid_maxima(fun: Callable[[FloatArray], FloatArray], grid: FloatArray, grid_values: FloatArray,
                         period: float = 2 * math.pi) -> list[tuple[float, float]]:
    """Maxima of several periodic functions of one variable: the best grid point of each,
    refined between its neighbours by :func:`local_grid_max`, all functions in one call of
    ``fun`` per round.

    Parameters
    ----------
    fun : callable
        ``fun(x)`` for a 1-D array of angles answers a (k, len(x)) array: the k functions at
        every angle [rad]; non-finite values count as −inf.
    grid : ndarray
        Sorted points over one period; it must hold every point where a function may jump
        and that point's left neighbour, so no jump lies inside a refined interval.
    grid_values : ndarray
        ``fun(grid)``, shape (k, len(grid)) (a caller that already has it saves the call).
    period : float
        The period [rad].

    Returns
    -------
    list of (float, float)
        For each function, the angle of its maximum (in [0, period)) and the maximum.
    """
    vals = np.where(np.isfinite(grid_values), grid_values, -np.inf)
    k = vals.shape[0]
    i = np.argmax(vals, axis=1)
    best_t, best_v = grid[i], vals[np.arange(k), i]
    lo = np.where(i > 0, grid[i - 1], grid[-1] - period)
    hi = np.where(i + 1 < grid.size, grid[np.minimum(i + 1, grid.size - 1)], grid[0] + period)
    # both neighbouring intervals of each function: lane 2q is [lo, best], 2q + 1 [best, hi]
    which = np.repeat(np.arange(k), 2)
    starts, ends = np.ravel(np.column_stack([lo, best_t])), np.ravel(np.column_stack([best_t, hi]))

    def lanes(x: FloatArray) -> FloatArray:
        every = fun(x.ravel()).reshape(k, *x.shape)
        return every[which, np.arange(x.shape[0])]

    # an angle to 1e-9 rad puts the value within ½|f''|·1e-18 of the maximum, below the
    # rounding of f itself
    t, v = local_grid_max(lanes, starts, ends, width=PERIODIC_WIDTH)
    out = []
    for q in range(k):
        tq, vq = float(best_t[q]), float(best_v[q])
        for lane in (2 * q, 2 * q + 1):
            if v[lane] > vq:
                tq, vq = float(t[lane]), float(v[lane])
        out.append((float(np.mod(tq, period)), vq))
    return out


def periodic_grid_max(fun: Callable[[FloatArray], FloatArray], grid: FloatArray, breaks: FloatArray,
                      period: float = 2 * math.pi) -> tuple[float, float]:
    """Maximum of a periodic function: the best grid point, refined between its neighbours
    (:func:`periodic_grid_maxima` with one function).

    Parameters
    ----------
    fun : callable
        Vectorised function of the angle [rad]; non-finite values count as −inf.
    grid : ndarray
        Sorted points over one period; it must hold every point where ``fun`` may jump
        and that point's left neighbour, so no jump lies inside a refined interval.
    breaks : ndarray
        The jump points (documentation of the grid's contract; not used otherwise).
    period : float
        The period [rad].

    Returns
    -------
    (float, float)
        The angle of the maximum (in [0, period)) and the maximum.
    """
    def one(x: FloatArray) -> FloatArray:
        return np.asarray(fun(x), dtype=np.float64)[None, :]

    return periodic_grid_maxima(one, grid, one(grid), period)[0]
