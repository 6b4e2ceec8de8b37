"""Characteristic values of a curve from its closed form (section-wise extrema).

The candidates for an extreme of any function of the motion are each piece's two ends
(one-sided limits) and every interior root of the function's derivative, bracketed on a
grid of all pieces at once and refined to machine precision (:func:`illinois_roots`).

References
----------
.. [1] Makino (1977), characteristic values Vm, Am, Jm, Qm (AV) of the universal curve.
.. [2] INDEXMAN technical guide, section 5, characteristic table (Q = A·V/Am).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._solvers import illinois_roots, newton_root, newton_roots
from ..deadline import checkpoint
from ..results import Extremum, doc
from .base import FloatArray, PiecewiseCurve
from .jumps import AccelerationJump, acceleration_jumps

#: functions of [S, V, A, J, dJ/dT] (arrays, or floats at one time) to rows (a sequence, or one array)
Rows = Callable[[list[Any]], Any]
#: the same to each row's own derivative, None for a row without one
RowSlopes = Callable[[list[Any]], list[Any]]

#: samples per piece used to bracket the roots of a derivative before refining them;
#: every piece of every curve we build has at most a few extrema, far fewer than this.
_BRACKET_SAMPLES = 257

#: roots refined one by one on a curve's scalar formulas (:meth:`PiecewiseCurve.eval_point`)
#: up to this many, where the array loop's fixed cost per operation is most of its work;
#: both give the same numbers (tests/camcore/curves/test_batch.py)
_POINT_NEWTON_MAX = 16


@dataclass(frozen=True)
class Characteristics:
    """Characteristic values of a curve over [T0, T7], from its closed form.

    ``vm`` is the largest |V|; ``am`` the largest |A| (the Am that normalises Q), and
    ``am_abs`` the same value with the T where it occurs, like every other extreme. Negative extremes (``am_neg``, ``jm_neg``,
    ``qm_neg``) are signed (≤ 0 for the standard curves), as Makino's AJKMM and QMM are.
    """

    vm: Extremum = field(metadata=doc("largest |V|"))
    am: float = field(metadata=doc("largest |A|, the Am that normalises Q"))
    am_abs: Extremum = field(metadata=doc("largest |A| (= am) and where it occurs"))
    am_pos: Extremum = field(metadata=doc("largest A"))
    am_neg: Extremum = field(metadata=doc("smallest A (signed)"))
    jm_pos: Extremum = field(metadata=doc("largest J"))
    jm_neg: Extremum = field(metadata=doc("smallest J (signed)"))
    qm_pos: Extremum = field(metadata=doc("largest Q = A·V/Am (indexer catalog)"))
    qm_neg: Extremum = field(metadata=doc("smallest Q = A·V/Am (signed)"))
    qm_raw_pos: Extremum = field(metadata=doc("largest A·V (Makino's QMP)"))
    qm_raw_neg: Extremum = field(metadata=doc("smallest A·V (Makino's QMM)"))
    v_max: Extremum = field(metadata=doc("largest V"))
    v_min: Extremum = field(metadata=doc("smallest V"))
    s_max: Extremum = field(metadata=doc("largest S"))
    s_min: Extremum = field(metadata=doc("smallest S"))
    a_jumps: tuple[AccelerationJump, ...] = field(default=(), metadata=doc(
        "where A jumps (the jerk is unbounded there, beyond jm_pos and jm_neg): T, A before, A after; T0 and "
        "T7 against the dwells (A = 0)"))


def _characteristic_rows(d: list[Any]) -> list[Any]:
    """V, A, J, dJ/dT and d(A·V)/dT = J·V + A² (arrays, or floats at one time): the functions
    whose roots are the peaks of S, V, A, J and A·V."""
    return [d[1], d[2], d[3], d[4], d[3] * d[1] + d[2] * d[2]]


def _characteristic_row_slopes(d: list[Any]) -> list[Any]:
    """Each row's own derivative; J's has none here (it would need d²J/dT²), so its roots are
    refined by the Illinois method, the others' by Newton."""
    return [d[2], d[3], d[4], None, d[4] * d[1] + 3.0 * d[2] * d[3]]


def characteristic_candidates(curve: PiecewiseCurve) -> tuple[FloatArray, NDArray[np.intp]]:
    """Where S, V, A, J and A·V may peak: the candidates every characteristic value is taken from.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve (one alone, or many curves' sections stacked side by side).

    Returns
    -------
    (ndarray, ndarray)
        Candidate times T [-] and their pieces [-] (:func:`critical_points` of the roots of V,
        A, J, dJ/dT and J·V + A²).

    References
    ----------
    Makino (1977), characteristic values Vm, Am, Jm, Qm taken section by section.
    """
    return critical_points(curve, _characteristic_rows, _characteristic_row_slopes)


def critical_points(curve: PiecewiseCurve, slopes: Rows,
                    slope_derivatives: RowSlopes | None = None,
                    ) -> tuple[FloatArray, NDArray[np.intp]]:
    """Times, with their pieces, where functions of the motion may peak over [T0, T7].

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve, evaluated piece by piece with its closed-form formulas.
    slopes : callable
        Maps [S, V, A, J, dJ/dT] at some times to the rows (one per function) of the
        functions' derivatives with respect to T.
    slope_derivatives : callable, optional
        Maps the same to each row's own derivative (None for a row without one). Both are
        also called with floats (one time) where the curve has scalar formulas
        (:attr:`PiecewiseCurve.has_point_formulas`): they must then return a list of rows.

    Returns
    -------
    (ndarray, ndarray)
        Candidate times T [-] and their pieces (indices) [-]: each piece's two ends
        (one-sided limits) and every interior root of every row, bracketed on a grid of all
        pieces at once and refined to machine precision: all rows with a derivative by
        safeguarded Newton (together on arrays, or one by one on the curve's scalar formulas
        when they are few: the same numbers), the others by the Illinois method.

    References
    ----------
    Makino (1977), characteristic values Vm, Am, Jm, Qm taken section by section;
    Dowell and Jarratt (1971), the Illinois method (:func:`camcore._solvers.illinois_roots`);
    Press et al. (2007), §9.4 (:func:`camcore._solvers.newton_roots`).
    """
    starts, ends = curve.piece_starts, curve.piece_ends
    n = curve.n_pieces
    grid = _bracket_grid(curve)

    def rows(t: FloatArray, piece: NDArray[np.intp]) -> FloatArray:
        return np.atleast_2d(np.asarray(slopes(curve.eval_pieces(t, piece, 4)), dtype=np.float64))

    derivs = np.asarray(slopes(curve.eval_grid(grid, 4)), dtype=np.float64)
    if derivs.ndim == 2:  # one function: one row
        derivs = derivs[None]
    n_rows = derivs.shape[0]
    has_slope = [False] * n_rows
    if slope_derivatives is not None:  # which rows have one: ask with floats (no evaluation)
        has_slope = [d is not None for d in slope_derivatives([0.0] * 5)]
    times = [starts, ends]
    pieces = [np.arange(n, dtype=np.intp), np.arange(n, dtype=np.intp)]
    # every row's sign changes and exact zeros at once, then row by row (sorted by row)
    # (a sign change: one end > 0 and the other < 0; boolean passes, and the indices from the
    # flat positions: several times faster than products of signs and a 3-D nonzero)
    above, below = derivs > 0.0, derivs < 0.0
    change = above[:, :, :-1] & below[:, :, 1:]
    change |= below[:, :, :-1] & above[:, :, 1:]
    q_all, k_all, i_all = _grid_indices(change)
    # a grid point where a row is exactly 0 is a candidate, unless the row is 0 over its whole
    # piece: a closed form with fewer roots than the grid has points is then 0 throughout, its
    # function constant there, and the piece's ends (candidates already) hold its value
    zero = derivs == 0.0
    zero &= ~zero.all(axis=2, keepdims=True)
    q_zero, k_zero, i_zero = _grid_indices(zero)
    cuts, zero_cuts = np.searchsorted(q_all, np.arange(n_rows + 1)), np.searchsorted(q_zero, np.arange(n_rows + 1))
    newton: list[tuple[FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.intp]]] = []
    for q in range(n_rows):
        k_idx, i_idx = k_all[cuts[q]:cuts[q + 1]], i_all[cuts[q]:cuts[q + 1]]
        if k_idx.size:
            d = derivs[q]
            lo, hi = grid[k_idx, i_idx], grid[k_idx, i_idx + 1]
            f_lo, f_hi = d[k_idx, i_idx], d[k_idx, i_idx + 1]
            if has_slope[q]:
                newton.append((lo, hi, f_lo, f_hi, q * n + k_idx))
            else:
                def row_q(t: FloatArray, k: NDArray[np.intp], row: int = q) -> FloatArray:
                    return rows(t, k)[row]

                illinois_roots(row_q, lo, hi, f_lo, f_hi, k_idx)
                times.append(0.5 * (lo + hi))
                pieces.append(k_idx)
        if zero_cuts[q + 1] > zero_cuts[q]:
            times.append(grid[k_zero[zero_cuts[q]:zero_cuts[q + 1]], i_zero[zero_cuts[q]:zero_cuts[q + 1]]])
            pieces.append(k_zero[zero_cuts[q]:zero_cuts[q + 1]])
    if newton:
        assert slope_derivatives is not None
        lo, hi, f_lo, f_hi, label = (np.concatenate([b[i] for b in newton]) for i in range(5))
        times.append(_newton_refined(curve, slopes, slope_derivatives, lo, hi, f_lo, f_hi, label))
        pieces.append(label % n)
    return np.concatenate(times), np.concatenate(pieces)


def _grid_indices(mask: NDArray[np.bool_]) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.intp]]:
    """np.nonzero of a 3-D mask (row, piece, grid point), in its order, from the flat positions."""
    _, pieces, points = mask.shape
    row, rest = np.divmod(np.flatnonzero(mask), pieces * points)
    return (row, *np.divmod(rest, points))


def _bracket_grid(curve: PiecewiseCurve) -> FloatArray:
    """The grid the roots are bracketed on: row k evenly over piece k, both ends included;
    fewer points per piece when there are many small pieces (splines of many points: cubic
    pieces whose derivatives have at most a few roots)."""
    per_piece = min(max(2**18 // max(curve.n_pieces, 1), 17), _BRACKET_SAMPLES)
    starts, ends = curve.piece_starts, curve.piece_ends
    return starts[:, None] + (ends - starts)[:, None] * _fractions(per_piece)[None, :]


@functools.cache
def _fractions(samples: int) -> FloatArray:
    """``samples`` evenly spaced fractions of a piece, 0 to 1 (read-only: shared)."""
    frac = np.linspace(0.0, 1.0, samples)
    frac.flags.writeable = False
    return frac


def _newton_refined(curve: PiecewiseCurve, slopes: Rows,
                    slope_derivatives: RowSlopes, lo: FloatArray,
                    hi: FloatArray, f_lo: FloatArray, f_hi: FloatArray, label: NDArray[np.intp]) -> FloatArray:
    """The roots in the brackets (``label``: row × n_pieces + piece) by safeguarded Newton: one by
    one on the curve's scalar formulas when they are few, else all together on arrays."""
    n = curve.n_pieces
    if curve.has_point_formulas and label.size <= _POINT_NEWTON_MAX:
        return np.array([_point_root(curve, slopes, slope_derivatives, *divmod(lab, n), *bracket)
                         for lab, *bracket in zip(label.tolist(), lo.tolist(), hi.tolist(), f_lo.tolist(),
                                                  f_hi.tolist())], dtype=np.float64)

    def value_and_slope(t: FloatArray, lab: NDArray[np.intp]) -> tuple[FloatArray, FloatArray]:
        row, piece = np.divmod(lab, n)
        d = curve.eval_pieces(t, piece, 4)  # once: the rows and their slopes both read it
        values, slopes_of = np.atleast_2d(np.asarray(slopes(d), dtype=np.float64)), slope_derivatives(d)
        take = np.arange(t.size)
        slope_rows = np.vstack([np.broadcast_to(np.nan if r is None else r, t.shape) for r in slopes_of])
        return values[row, take], slope_rows[row, take]

    return newton_roots(value_and_slope, lo, hi, f_lo, f_hi, label)


def _point_root(curve: PiecewiseCurve, slopes: Rows,
                slope_derivatives: RowSlopes, row: int, piece: int,
                lo: float, hi: float, f_lo: float, f_hi: float) -> float:
    """One row's root on one piece by :func:`newton_root` on the curve's scalar formulas: the
    number the array refinement gives (the rows are the same expressions on floats)."""
    def value_and_slope(t: float) -> tuple[float, float]:
        d = curve.eval_point(t, piece)
        return slopes(d)[row], slope_derivatives(d)[row]

    return newton_root(value_and_slope, lo, hi, f_lo, f_hi)


def peaks_of(times: FloatArray, values: FloatArray) -> tuple[Extremum, Extremum]:
    """(max, min) of values at candidate times; ties go to the earliest T.

    Parameters
    ----------
    times : ndarray
        Candidate times T, in any order [-].
    values : ndarray
        The function at each candidate [-] (any unit; the extremes keep it).

    Returns
    -------
    (Extremum, Extremum)
        The largest and the smallest value, each with the earliest T where it occurs.

    References
    ----------
    Makino (1977), characteristic values (the first T of each peak, as his tables give it);
    INDEXMAN technical guide, section 5, characteristic table.
    """
    order = np.argsort(times, kind="stable")
    return _sorted_peaks(times[order], values[order])


def _sorted_peaks(t_sorted: FloatArray, v_sorted: FloatArray) -> tuple[Extremum, Extremum]:
    """:func:`peaks_of` for candidates already in order of T."""
    i_max, i_min = int(np.argmax(v_sorted)), int(np.argmin(v_sorted))
    return Extremum(float(v_sorted[i_max]), float(t_sorted[i_max])), Extremum(float(v_sorted[i_min]),
                                                                              float(t_sorted[i_min]))


def characteristics(curve: PiecewiseCurve) -> Characteristics:
    """Exact characteristic values over [T0, T7] (section-wise extrema).

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve, evaluated with its closed-form formulas.

    Returns
    -------
    Characteristics
        Peaks of S, V, A, J, A·V and Q = A·V/Am with the T of each (all dimensionless).

    References
    ----------
    Makino (1977), characteristic values; INDEXMAN technical guide, section 5
    (characteristic table, Q = A·V/Am).
    """
    t_all, k_all = characteristic_candidates(curve)
    order = np.argsort(t_all, kind="stable")  # once for every peak (peaks_of's order)
    t_all = t_all[order]
    s_, v, acc, j = curve.eval_pieces(t_all, k_all[order], 3)
    s_max, s_min = _sorted_peaks(t_all, s_)
    v_max, v_min = _sorted_peaks(t_all, v)
    am_pos, am_neg = _sorted_peaks(t_all, acc)
    jm_pos, jm_neg = _sorted_peaks(t_all, j)
    q_pos, q_neg = _sorted_peaks(t_all, acc * v)
    vm = v_max if abs(v_max.value) >= abs(v_min.value) else v_min
    am = max(abs(am_pos.value), abs(am_neg.value))
    # the T of the largest |A|; the earlier of the two peaks when they tie, and they tie
    # within a few ulps: Amp and Amm solved from eq. (11) differ by an ulp or two where
    # the law makes them equal (m = 1: TR's Amp is 1 ulp below its Amm)
    t_am = min(x.t for x in (am_pos, am_neg) if am - abs(x.value) <= 4 * float(np.spacing(am)))
    scale = 1.0 / am if am > 0 else 0.0
    return Characteristics(
        vm=Extremum(abs(vm.value), vm.t),
        am=am,
        am_abs=Extremum(am, t_am),
        am_pos=am_pos,
        am_neg=am_neg,
        jm_pos=jm_pos,
        jm_neg=jm_neg,
        qm_pos=Extremum(q_pos.value * scale, q_pos.t),
        qm_neg=Extremum(q_neg.value * scale, q_neg.t),
        qm_raw_pos=q_pos,
        qm_raw_neg=q_neg,
        v_max=v_max,
        v_min=v_min,
        s_max=s_max,
        s_min=s_min,
        a_jumps=acceleration_jumps(curve, am),
    )


def power_balance_peaks(curve: PiecewiseCurve, c1: ArrayLike, c2: ArrayLike
                        ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Exact max and min over [T0, T7] of f(T) = c1·V·A + c2·V, for many (c1, c2) at once.

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.
    c1, c2 : array_like
        One pair of coefficients per row (same shape, 1-D) [N·m] (or any unit: f takes it).

    Returns
    -------
    (ndarray, ndarray, ndarray, ndarray)
        Per row: the largest f [f's unit] and its T [-], the smallest f and its T (ties: the earliest T).

    Notes
    -----
    Candidates are each piece's ends (one-sided) and every root of
    f′ = c1·(J·V + A²) + c2·A, bracketed on one grid of the curve (evaluated once for all
    rows) and refined together by safeguarded Newton on f″ = c1·(dJ·V + 3·A·J) + c2·J, as
    :func:`critical_points` does for one function.

    References
    ----------
    Power balance of a lossless cam drive, T_in = (dθout/dθin)·T_out; Makino (1977),
    characteristic values taken section by section; Dowell and Jarratt (1971).
    """
    k1 = np.atleast_1d(np.asarray(c1, dtype=np.float64))
    k2 = np.atleast_1d(np.asarray(c2, dtype=np.float64))
    rows = k1.size
    starts, ends = curve.piece_starts, curve.piece_ends
    n = curve.n_pieces
    grid = _bracket_grid(curve)
    _, v, a, j = curve.eval_grid(grid, 3)
    inertia_slope, friction_slope = j * v + a * a, a
    # each piece's ends (one-sided), the same times for every row: evaluated once
    end_t = np.concatenate([starts, ends])
    _, end_v, end_a = curve.eval_pieces(end_t, np.concatenate([np.arange(n), np.arange(n)]), 2)
    top, top_t = np.empty(rows), np.empty(rows)
    bottom, bottom_t = np.empty(rows), np.empty(rows)
    # rows in blocks: the grid of one block of rows stays below a few MB, and so do its
    # candidates (a 10 000-point curve has 20 000 ends a row); a deadline is checked each block
    block = max(1, 2**19 // grid.size)
    for first in range(0, rows, block):
        checkpoint()
        r = np.arange(first, min(first + block, rows))
        cand_t = [np.tile(end_t, r.size)]
        cand_f = [(k1[r, None] * end_v[None] * end_a[None] + k2[r, None] * end_v[None]).reshape(-1)]
        cand_r = [np.repeat(r, 2 * n)]
        g = k1[r, None, None] * inertia_slope[None] + k2[r, None, None] * friction_slope[None]
        sign = np.sign(g)
        r_idx, k_idx, i_idx = np.nonzero(sign[:, :, :-1] * sign[:, :, 1:] < 0)
        if r_idx.size:
            lo, hi = grid[k_idx, i_idx].copy(), grid[k_idx, i_idx + 1].copy()
            f_lo, f_hi = g[r_idx, k_idx, i_idx].copy(), g[r_idx, k_idx, i_idx + 1].copy()
            row_of = r[r_idx]

            def slope(t: FloatArray, label: NDArray[np.intp]) -> tuple[FloatArray, FloatArray]:
                row, piece = np.divmod(label, n)
                _, vv, aa, jj, dj = curve.eval_pieces(t, piece, 4)
                # f′ = c1·(J·V + A²) + c2·A and its derivative f″ = c1·(dJ·V + 3·A·J) + c2·J
                return (k1[row] * (jj * vv + aa * aa) + k2[row] * aa,
                        k1[row] * (dj * vv + 3.0 * aa * jj) + k2[row] * jj)

            roots = newton_roots(slope, lo, hi, f_lo, f_hi, row_of * n + k_idx)
            _, v_r, a_r = curve.eval_pieces(roots, k_idx, 2)
            cand_t.append(roots)
            cand_f.append(k1[row_of] * v_r * a_r + k2[row_of] * v_r)
            cand_r.append(row_of)
        zr, zk, zi = np.nonzero(g == 0.0)
        if zr.size:
            _, v_z, a_z = curve.eval_pieces(grid[zk, zi], zk, 2)
            cand_t.append(grid[zk, zi])
            cand_f.append(k1[r[zr]] * v_z * a_z + k2[r[zr]] * v_z)
            cand_r.append(r[zr])
        t_all, f_all, r_all = np.concatenate(cand_t), np.concatenate(cand_f), np.concatenate(cand_r)
        order = np.argsort(r_all, kind="stable")
        t_s, f_s, r_s = t_all[order], f_all[order], r_all[order]
        bounds = np.searchsorted(r_s, r)
        top[r] = np.maximum.reduceat(f_s, bounds)
        bottom[r] = np.minimum.reduceat(f_s, bounds)
        # the earliest T of each extreme; a row whose f is not finite everywhere (inputs past
        # float range) has no extreme to find: its earliest candidate stands in (the answer
        # refuses the non-finite values)
        earliest = np.minimum.reduceat(t_s, bounds)
        at_top = np.minimum.reduceat(np.where(f_s == top[r_s], t_s, np.inf), bounds)
        at_bottom = np.minimum.reduceat(np.where(f_s == bottom[r_s], t_s, np.inf), bounds)
        top_t[r] = np.where(np.isfinite(at_top), at_top, earliest)
        bottom_t[r] = np.where(np.isfinite(at_bottom), at_bottom, earliest)
    return top, top_t, bottom, bottom_t
