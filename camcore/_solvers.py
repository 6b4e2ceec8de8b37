"""The numerical solvers every part of camcore shares, each with its guarantees.

- :func:`illinois_roots`: roots of many bracketed functions at once (vectorised Illinois
  regula falsi); used for the extrema of curves and of the indexer's power balance.
- :func:`bracketed_newton`: an increasing function inverted at many targets at once
  (vectorised safeguarded Newton); used for the inverse's start tables and for Bezier
  parameters. :func:`newton_roots` is the same for bracketed roots with exact
  derivatives; used for the extrema of curves and of the indexer's power balance.
- :func:`smallest_feasible`: the smallest x where a margin that grows with x reaches 0
  (scalar Illinois regula falsi after a doubling bracket); used for base-circle sizing.
- maxima of unimodal and periodic functions (golden section, local grids): :mod:`camcore._maxima`.

The exact inverse of a curve (:mod:`camcore.curves.inverse`) has its own Newton loop,
specialised for speed (per-cell start tables, block-wise evaluation); it is not repeated
here.

References
----------
.. [1] M. Dowell, P. Jarratt, "A modified regula falsi method for computing the root of an
   equation", BIT 11 (1971) 168-174 (the Illinois method).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from .deadline import checkpoint

FloatArray = NDArray[np.float64]

#: iterations of the vectorised Illinois method; a 1/256-wide bracket closes in ~10, and
#: no bracket of a float64 interval needs more than ~2100 bisections' worth of halvings
ILLINOIS_MAX_ITERATIONS = 200

#: iterations of bracketed Newton: bisection alone halves a unit bracket 52 times
NEWTON_MAX_ITERATIONS = 100



def illinois_roots(f: Callable[[FloatArray, NDArray[np.intp]], FloatArray], lo: FloatArray, hi: FloatArray,
                   f_lo: FloatArray, f_hi: FloatArray, piece: NDArray[np.intp]) -> None:
    """Shrink brackets [lo, hi] (f changes sign inside) around the roots of f, in place.

    Parameters
    ----------
    f : callable
        ``f(t, piece)`` evaluates every function at its own t; ``piece`` is passed
        through (the smooth piece of a curve that holds the bracket).
    lo, hi, f_lo, f_hi : ndarray
        Brackets and the function's values at their ends (signs differ), updated in place.
    piece : ndarray of int
        One label per bracket, handed to ``f``.

    Notes
    -----
    Illinois regula falsi: the chord's zero, and the value kept at an end that stays put
    twice is halved so both ends move in. Each trial point keeps 2 ulp from both ends, so
    once one lies that close to the root the next lands on its far side and the bracket
    closes. A bracket stops at a root (f = 0) or at 4 ulp wide: about 10 evaluations from
    a 1/256-wide cell, where bisection needs 45. At most ``ILLINOIS_MAX_ITERATIONS`` rounds.

    References
    ----------
    Dowell and Jarratt (1971), the Illinois method.
    """
    active = np.arange(lo.size)
    kept = np.zeros(lo.size, dtype=np.int8)  # +1: lo moved last time, −1: hi moved last time
    for _ in range(ILLINOIS_MAX_ITERATIONS):
        checkpoint()
        a, b = lo[active], hi[active]
        tol = 2 * np.spacing(np.maximum(np.abs(a), np.abs(b)))
        open_ = b - a > 2 * tol
        if not open_.all():
            active, a, b, tol = active[open_], a[open_], b[open_], tol[open_]
        if active.size == 0:
            return
        fa, fb = f_lo[active], f_hi[active]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            chord = a - fa * ((b - a) / (fb - fa))
        # the chord's zero lies in [a, b] (fa, fb differ in sign) up to rounding; the clip
        # also keeps it 2 ulp inside, so a zero found next to an end is checked from the far side
        mid = np.clip(np.where(np.isfinite(chord), chord, 0.5 * (a + b)), a + tol, b - tol)
        f_mid = f(mid, piece[active])
        root = f_mid == 0
        moves_lo = (np.sign(f_mid) == np.sign(fa)) & ~root
        moves_hi = ~moves_lo & ~root
        # Illinois: the end that stays put for a second time has its value halved
        halve_hi = moves_lo & (kept[active] == 1)
        halve_lo = moves_hi & (kept[active] == -1)
        lo[active] = np.where(moves_lo | root, mid, a)
        hi[active] = np.where(moves_hi | root, mid, b)
        f_lo[active] = np.where(moves_lo, f_mid, np.where(halve_lo, 0.5 * fa, fa))
        f_hi[active] = np.where(moves_hi, f_mid, np.where(halve_hi, 0.5 * fb, fb))
        kept[active] = np.where(moves_lo, 1, np.where(moves_hi, -1, 0))
        active = active[~root]


def bracketed_newton(value_and_slope: Callable[[FloatArray], tuple[FloatArray, FloatArray]], goal: FloatArray,
                     start: FloatArray, lo: FloatArray, hi: FloatArray, noise: float = 0.0) -> FloatArray:
    """x with g(x) = goal for an increasing g, many goals at once, each inside its bracket.

    Parameters
    ----------
    value_and_slope : callable
        ``x -> (g(x), g'(x))``.
    goal : ndarray
        Targets, one per bracket.
    start, lo, hi : ndarray
        Starting points inside the brackets [lo, hi] (g(lo) ≤ goal ≤ g(hi)); ``lo`` and
        ``hi`` are overwritten.
    noise : float
        A residual |g − goal| at or below this is rounding: that x is final.

    Returns
    -------
    ndarray
        The solutions, to 4 ulp of max(|x|, 1).

    Notes
    -----
    Each step shrinks the bracket with the residual's sign; a Newton step that would
    leave the bracket (or is not finite) bisects instead, so every target converges.
    A target stops at an exact hit, a residual at the noise level, a step or a bracket
    of 4 ulp, after at most ``NEWTON_MAX_ITERATIONS`` steps.
    """
    return _newton(lambda x, _which: value_and_slope(x), goal, start, lo, hi, noise)


def _newton(value_and_slope: Callable[[FloatArray, NDArray[np.intp]], tuple[FloatArray, FloatArray]],
            goal: FloatArray, start: FloatArray, lo: FloatArray, hi: FloatArray, noise: float) -> FloatArray:
    """The loop of :func:`bracketed_newton`; ``value_and_slope(x, which)`` also gets the indices
    of the targets still moving."""
    x = start.copy()
    active = np.ones(goal.shape, dtype=bool)
    for _ in range(NEWTON_MAX_ITERATIONS):
        checkpoint()
        if not active.any():
            break
        ia = np.nonzero(active)[0]
        xa = x[ia]
        value, slope = value_and_slope(xa, ia)
        f = value - goal[ia]
        lo_a = np.where(f < 0, xa, lo[ia])
        hi_a = np.where(f > 0, xa, hi[ia])
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = xa - f / slope
        ok = np.isfinite(newton) & (newton >= lo_a) & (newton <= hi_a)
        x_new = np.where(ok, newton, 0.5 * (lo_a + hi_a))
        tiny = 4 * np.spacing(np.maximum(np.abs(xa), 1.0))
        done = (np.abs(f) <= noise) | (np.abs(x_new - xa) <= tiny) | (hi_a - lo_a <= tiny)
        x[ia] = np.where(f == 0, xa, x_new)
        lo[ia] = lo_a
        hi[ia] = hi_a
        active[ia[done]] = False
    return x


def newton_roots(value_and_slope: Callable[[FloatArray, NDArray[np.intp]], tuple[FloatArray, FloatArray]],
                 lo: FloatArray, hi: FloatArray, f_lo: FloatArray, f_hi: FloatArray,
                 label: NDArray[np.intp]) -> FloatArray:
    """Roots of many bracketed functions with exact derivatives, all refined together.

    Parameters
    ----------
    value_and_slope : callable
        ``(t, label) -> (f, f')``: every function and its derivative at its own t; ``label``
        is passed through (which function, on which smooth piece).
    lo, hi, f_lo, f_hi : ndarray
        Brackets and the function's values at their ends (signs differ); ``lo`` and ``hi``
        are overwritten.
    label : ndarray of int
        One label per bracket.

    Returns
    -------
    ndarray
        One root per bracket, to 4 ulp of max(|t|, 1).

    Notes
    -----
    Safeguarded Newton (:func:`bracketed_newton` on f oriented to increase across its
    bracket) from the chord's zero: three or four evaluations from a grid cell where the
    Illinois method takes five to ten.

    References
    ----------
    Press et al., Numerical Recipes, 3rd ed. (2007), §9.4 (Newton-Raphson with bisection
    safeguard, rtsafe).
    """
    orient = np.where(f_hi > f_lo, 1.0, -1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        chord = lo - f_lo * ((hi - lo) / (f_hi - f_lo))
    start = np.clip(np.where(np.isfinite(chord), chord, 0.5 * (lo + hi)), lo, hi)

    def oriented(t: FloatArray, which: NDArray[np.intp]) -> tuple[FloatArray, FloatArray]:
        value, slope = value_and_slope(t, label[which])
        return orient[which] * value, orient[which] * slope

    return _newton(oriented, np.zeros(lo.shape), start, lo, hi, 0.0)


def newton_root(value_and_slope: Callable[[float], tuple[float, float]], lo: float, hi: float,
                f_lo: float, f_hi: float) -> float:
    """One bracketed root: the steps of :func:`newton_roots` for a single bracket, in Python floats.

    Parameters
    ----------
    value_and_slope : callable
        ``t -> (f, f')`` at one t, as Python floats.
    lo, hi, f_lo, f_hi : float
        The bracket and the function's values at its ends (signs differ).

    Returns
    -------
    float
        The root, to 4 ulp of max(|t|, 1): the same number :func:`newton_roots` gives for
        this bracket when ``value_and_slope`` gives the same numbers as its array version.

    Notes
    -----
    Every step is the array loop's IEEE operation, in the same order, on one element: a
    float's + − × ÷ round exactly as numpy's do, so the two agree to the bit. It exists
    for the few roots of one curve, where each array operation's fixed cost (about 1 µs)
    is most of the work: three steps of two roots take 30 µs here against 250 µs.

    References
    ----------
    Press et al., Numerical Recipes, 3rd ed. (2007), §9.4 (rtsafe).
    """
    orient = 1.0 if f_hi > f_lo else -1.0
    width, rise = hi - lo, f_hi - f_lo
    chord = lo - f_lo * (width / rise) if rise != 0.0 else math.nan
    x = min(max(chord if math.isfinite(chord) else 0.5 * (lo + hi), lo), hi)
    for _ in range(NEWTON_MAX_ITERATIONS):
        checkpoint()
        value, slope = value_and_slope(x)
        f = orient * value - 0.0  # the array loop's ``value - goal``: −0 stays −0
        slope = orient * slope
        lo_x = x if f < 0 else lo
        hi_x = x if f > 0 else hi
        # a zero slope: the array loop's f/0 is ±inf or nan, not finite, so it bisects
        step = x - f / slope if slope != 0.0 else math.nan
        x_new = step if math.isfinite(step) and lo_x <= step <= hi_x else 0.5 * (lo_x + hi_x)
        tiny = 4 * math.ulp(max(abs(x), 1.0))
        done = abs(f) <= 0.0 or abs(x_new - x) <= tiny or hi_x - lo_x <= tiny
        x = x if f == 0 else x_new
        lo, hi = lo_x, hi_x
        if done:
            break
    return x


class NoFeasiblePointError(ValueError):
    """The margin stayed negative up to the largest x tried."""

    def __init__(self, largest_tried: float):
        self.largest_tried = largest_tried
        super().__init__(f"no x up to {largest_tried!r} has a margin ≥ 0")


def smallest_feasible(margin: Callable[[float], float], lo: float, start: float, rel_tol: float = 1e-10) -> float:
    """Smallest x ≥ lo with margin(x) ≥ 0, for a margin that grows with x.

    Parameters
    ----------
    margin : callable
        ``x -> margin``; −inf where x is not feasible at all (the step then bisects).
    lo : float
        The smallest x worth trying (the margin is taken as negative there).
    start : float
        First upper bound tried; doubled (2x + 1) up to 60 times until the margin is ≥ 0.
    rel_tol : float
        The bracket is closed at this width relative to max(1, x).

    Returns
    -------
    float
        The bracket's feasible end (margin ≥ 0 there).

    Raises
    ------
    NoFeasiblePointError
        When no tried x has a margin ≥ 0.

    Notes
    -----
    Illinois regula falsi on the bracket (superlinear on smooth margins, never leaving the
    bracket), at most 200 steps; it stops early when a trial meets the margin exactly.

    References
    ----------
    Dowell and Jarratt (1971), the Illinois method.
    """
    hi = start
    for _ in range(60):
        checkpoint()
        f_hi = margin(hi)
        if f_hi >= 0:
            break
        hi = 2 * hi + 1.0
    else:
        raise NoFeasiblePointError(hi)
    a, b = lo, hi
    f_a, f_b = margin(a) if a > 0 else -math.inf, f_hi
    side = 0
    for _ in range(ILLINOIS_MAX_ITERATIONS):
        checkpoint()
        if b - a <= rel_tol * max(1.0, b) or f_b == 0:  # f_b = 0: the margin is met exactly at b
            break
        if math.isfinite(f_a) and f_b > f_a:
            m = b - f_b * (b - a) / (f_b - f_a)
            if not a < m < b:
                m = 0.5 * (a + b)
        else:
            m = 0.5 * (a + b)
        f_m = margin(m)
        if f_m >= 0:
            b, f_b = m, f_m
            if side == 1 and math.isfinite(f_a):
                f_a *= 0.5  # Illinois: halve the stale end so the bracket shrinks from both sides
            side = 1
        else:
            a, f_a = m, f_m
            if side == -1:
                f_b *= 0.5
            side = -1
    return b


def scan_roots(fun: Callable[[FloatArray], FloatArray], grid: FloatArray,
               values: FloatArray | None = None) -> tuple[list[float], FloatArray]:
    """Every root of a scalar function that a grid brackets, refined to machine precision.

    Parameters
    ----------
    fun : callable
        Vectorised function of x; a non-finite value (x where it is not defined) brackets nothing.
    grid : ndarray
        Sorted points x; the function is assumed to change sign at most once between neighbours.
    values : ndarray, optional
        ``fun(grid)``, when the caller has it.

    Returns
    -------
    (list of float, ndarray)
        The grid points where ``fun`` is exactly 0 and one root in each cell where it changes
        sign, sorted; and ``fun`` on the grid (for a caller that explains why there is none).

    Notes
    -----
    Each cell is refined by :func:`illinois_roots` (to 4 ulp, at most
    ``ILLINOIS_MAX_ITERATIONS`` rounds); the root is the cell's midpoint.

    References
    ----------
    Dowell and Jarratt (1971), the Illinois method.
    """
    values = np.asarray(fun(grid) if values is None else values, dtype=np.float64)
    roots = [float(x) for x in grid[values == 0]]
    cells = np.flatnonzero(np.isfinite(values[:-1]) & np.isfinite(values[1:]) & (values[:-1] * values[1:] < 0))
    if cells.size:
        lo, hi = grid[cells].astype(np.float64), grid[cells + 1].astype(np.float64)
        illinois_roots(lambda x, _cell: np.asarray(fun(x), dtype=np.float64), lo, hi, values[cells].copy(),
                       values[cells + 1].copy(), np.zeros(cells.size, dtype=np.intp))
        roots += [float(x) for x in 0.5 * (lo + hi)]
    return sorted(roots), values
