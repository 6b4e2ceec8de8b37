"""Targets on a curve's stroke: monotonicity, range checks, the robust inverse and the
catalog's table method.

References
----------
.. [1] INDEXMAN technical guide, worked example before the characteristic-value table:
   S = 0.1833 between rows T = 0.30 and 0.31 of the MS table gives T = 0.304, V = 1.339.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .._solvers import bracketed_newton
from ..errors import NonMonotoneError, StrokeRangeError
from .base import CurveValues, FloatArray, PiecewiseCurve
from .extrema import Characteristics

#: samples of S(T) between the break points that bracket the robust inverse's targets
_INVERSE_NODES = 1025


def monotone_direction(curve: PiecewiseCurve, ch: Characteristics) -> int:
    """+1 if S never decreases over [T0, T7], -1 if it never increases, 0 otherwise.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.
    ch : Characteristics
        Its characteristic values (the extremes of V decide).

    Returns
    -------
    int
        +1, −1 or 0 [-]; V within 1e-12 of its peak below (or above) zero counts as zero
        (rounding at a dwell end).

    References
    ----------
    Makino (1977), characteristic values (the extremes of V over the curve); INDEXMAN
    technical guide, worked example before the characteristic-value table (an S → T lookup
    needs S to determine T).
    """
    # V may dip below zero by rounding at a dwell end; 1e-12 of the peak is rounding.
    slack = 1e-12 * max(ch.vm.value, 1.0)
    if curve.s_end >= curve.s_start and ch.v_min.value >= -slack:
        return 1
    if curve.s_end <= curve.s_start and ch.v_max.value <= slack:
        return -1
    return 0


def require_monotone(curve: PiecewiseCurve, ch: Characteristics) -> int:
    """The monotone direction (+1 or −1), or :class:`NonMonotoneError`.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.
    ch : Characteristics
        Its characteristic values (the extremes of V decide).

    Returns
    -------
    int
        +1 for a rising curve, −1 for a falling one [-].

    Raises
    ------
    NonMonotoneError
        S is not monotone over [T0, T7], or S7 = S0.

    References
    ----------
    INDEXMAN technical guide, worked example before the characteristic-value table (the
    inverse lookup, defined for a curve that only rises or only falls).
    """
    direction = monotone_direction(curve, ch)
    if direction == 0 or curve.s_end == curve.s_start:
        raise NonMonotoneError(
            "This curve's displacement S is not monotone over its stroke, so S does "
            "not determine T; an inverse lookup needs a curve that only rises or only falls."
        )
    return direction


def stroke_tolerance(curve: PiecewiseCurve) -> float:
    """Distance from an end of the stroke within which a target is that end.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.

    Returns
    -------
    float
        8 ulp of max(|S0|, |S7|, 1) [-]: S(T7) is summed section by section and may miss
        the nominal end by an ulp or two.

    References
    ----------
    IEEE 754-2019 binary64 (the spacing of floating-point numbers, ``numpy.spacing``);
    Makino (1977), eqs. (1)-(9) (S at the section starts, summed by exact integration).
    """
    # S(T7) is summed section by section and may miss the nominal end by an ulp or two;
    # a target within a few ulps of an end is that end
    return 8 * float(np.spacing(max(abs(curve.s_start), abs(curve.s_end), 1.0)))


def validate_stroke(curve: PiecewiseCurve, s: FloatArray) -> None:
    """Raise StrokeRangeError, naming the first offender, if any s is off the stroke.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.
    s : ndarray
        Displacements to look up [-]; NaN and infinities are off the stroke.

    Raises
    ------
    StrokeRangeError
        Some s lies outside [min(S0, S7), max(S0, S7)] by more than :func:`stroke_tolerance`.

    References
    ----------
    INDEXMAN technical guide, worked example before the characteristic-value table (the
    output angle is a fraction S of the index, 0 ≤ S ≤ 1).
    """
    lo, hi = sorted((curve.s_start, curve.s_end))
    tol = stroke_tolerance(curve)
    if s.size and not (lo - tol <= s.min() and s.max() <= hi + tol):  # NaN fails both
        bad = ~np.isfinite(s) | (s < lo - tol) | (s > hi + tol)
        i = int(np.nonzero(bad)[0][0])
        raise StrokeRangeError(
            f"s[{i}] = {float(s.reshape(-1)[i])!r} is outside the stroke of this curve, "
            f"which runs from S = {curve.s_start!r} to S = {curve.s_end!r}.",
            field=("s", i),
        )


def clamp_to_stroke(curve: PiecewiseCurve, s: FloatArray) -> FloatArray:
    """Validated targets onto [S0, S7]; a target within rounding of an end is that end.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.
    s : ndarray
        Displacements already accepted by :func:`validate_stroke` [-].

    Returns
    -------
    ndarray
        The targets clipped onto the stroke, those within :func:`stroke_tolerance` of an end
        set to that end [-]; ``s`` itself when no target is near an end (two reductions, no copy).

    References
    ----------
    IEEE 754-2019 binary64 (targets within a few ulp of an end are that end); INDEXMAN
    technical guide, worked example before the characteristic-value table.
    """
    lo, hi = sorted((curve.s_start, curve.s_end))
    tol = stroke_tolerance(curve)
    if s.size == 0 or (s.min() > lo + tol and s.max() < hi - tol):
        return s
    clamped = np.clip(s, lo, hi)
    for end in (curve.s_start, curve.s_end):
        near = np.abs(s - end) <= tol
        if near.any():
            clamped[near] = end
    return clamped


def robust_inverse(curve: PiecewiseCurve, target: FloatArray, direction: int) -> FloatArray:
    """First T with S(T) = target (validated, flat), bracketed on a node table.

    Robust and slow (a binary search and a bracketed Newton iteration per target): it
    builds the start tables of the fast inverse (:mod:`.inverse`).

    Parameters
    ----------
    curve : PiecewiseCurve
        A monotone curve.
    target : ndarray
        Displacements S, flat and on the stroke [-].
    direction : int
        +1 for a rising curve, −1 for a falling one [-].

    Returns
    -------
    ndarray
        The first T with S(T) = target, one per target [-].

    References
    ----------
    W. H. Press et al., Numerical Recipes, 3rd ed., §9.4 (Newton's method safeguarded by
    bisection); INDEXMAN technical guide, worked example before the characteristic-value table.
    """
    grid = np.linspace(curve.t_start, curve.t_end, _INVERSE_NODES)
    t_nodes = np.unique(np.concatenate([grid, curve.break_points]))
    key = curve.derivatives(t_nodes, 0)[0] * direction
    goal = target * direction
    # first node whose S reaches the target: bracket (node-1, node]
    k = np.clip(np.searchsorted(key, goal, side="left"), 1, len(t_nodes) - 1)
    lo, hi = t_nodes[k - 1].copy(), t_nodes[k].copy()
    f_lo, f_hi = key[k - 1] - goal, key[k] - goal
    exact_lo = f_lo >= 0  # target at or below the bracket start: the start is the answer
    span = np.where(f_hi > f_lo, f_hi - f_lo, 1.0)
    t = np.where(exact_lo, lo, lo + (hi - lo) * np.clip(-f_lo / span, 0.0, 1.0))
    t = np.where(f_hi == 0, np.where(exact_lo, lo, hi), t)
    active = np.flatnonzero(~exact_lo & (f_hi != 0))
    if active.size:
        def s_and_v(x: FloatArray) -> tuple[FloatArray, FloatArray]:
            s, v = curve.derivatives(x, 1)
            return s * direction, v * direction

        t[active] = bracketed_newton(s_and_v, goal[active], t[active], lo[active], hi[active])
    return t


def inverse_table(curve: PiecewiseCurve, values: CurveValues, s: ArrayLike, direction: int,
                  decimals: int | None = None) -> CurveValues:
    """The catalog's method: proportional interpolation between the rows of a table.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve whose table it is (its stroke bounds the targets).
    values : CurveValues
        The table's rows (T increasing).
    s : array_like
        Displacements to look up, on the stroke [-].
    direction : int
        The curve's monotone direction (+1 rising, −1 falling) [-].
    decimals : int, optional
        Round the table to this many decimals first, as printed (the catalog prints 5) [-].

    Returns
    -------
    CurveValues
        T, V, A, J, Q interpolated linearly between the rows whose S bracket each s.

    References
    ----------
    INDEXMAN technical guide, worked example before the characteristic-value table:
    S = 0.1833 between rows T = 0.30 and 0.31 of the MS table gives T = 0.304, V = 1.339.
    """
    s_arr = np.asarray(s, dtype=np.float64)
    validate_stroke(curve, s_arr.reshape(-1))
    target = clamp_to_stroke(curve, s_arr.reshape(-1))
    cols = [values.t, values.s, values.v, values.a, values.j, values.q, values.q_raw]
    if decimals is not None:
        cols = [np.round(c, decimals) for c in cols]
    t_r, s_r, v_r, a_r, j_r, q_r, qr_r = cols
    key = s_r * direction
    goal = target * direction
    k = np.clip(np.searchsorted(key, goal, side="left"), 1, len(key) - 1)
    ds = key[k] - key[k - 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(ds > 0, (goal - key[k - 1]) / ds, 0.0)
    frac = np.clip(frac, 0.0, 1.0)
    # a target at or below the first row's S sits on that row
    frac = np.where(goal <= key[0], 0.0, frac)

    def lerp(c: FloatArray) -> FloatArray:
        return (c[k - 1] + (c[k] - c[k - 1]) * frac).reshape(s_arr.shape)

    return CurveValues(
        t=lerp(t_r), s=s_arr, v=lerp(v_r), a=lerp(a_r), j=lerp(j_r), q=lerp(q_r), q_raw=lerp(qr_r)
    )


def table_rows(curve: PiecewiseCurve, step: float) -> FloatArray:
    """T = T0, T0 + step, …, T7 (the last row at T7): the rows of a catalog table.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.
    step : float
        Row spacing in T (> 0) [-]; the catalog's tables use 0.01.

    Returns
    -------
    ndarray
        The rows' T [-]; a last, shorter step ends exactly at T7.

    References
    ----------
    INDEXMAN technical guide, section 5 (the curve tables in steps of 0.01).
    """
    n = int(np.floor((curve.t_end - curve.t_start) / step + 1e-9))
    t_rows = curve.t_start + step * np.arange(n + 1)
    if t_rows[-1] < curve.t_end - 1e-12 * step:
        t_rows = np.append(t_rows, curve.t_end)
    else:
        t_rows[-1] = curve.t_end
    return np.asarray(t_rows, dtype=np.float64)
