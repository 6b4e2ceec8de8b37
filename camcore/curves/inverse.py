"""The exact inverse S → T of a monotone curve, vectorised and blocked.

For each target S the answer is the first T in [T0, T7] with S(T) = target, found by
safeguarded Newton iteration on the closed form. What makes it fast:

* a start table (:class:`InverseGrid`, built once per curve): the first T reaching each of
  4096 + 1 evenly spaced S levels. A target finds its cell by arithmetic, and its start
  is the cubic Hermite interpolant of T(S) in the cell (slopes dT/dS = 1/V): close enough
  that one Newton step reaches the rounding level, and the step's predicted error
  |A/2V|·δ² says so without another evaluation;
* at a dwell end (V = 0 at T0 or T7), S − S_end ≈ c·τ^k, k the order of the first
  non-zero derivative there, and T(S) is not smooth: in the 32 cells next to the end the
  start comes from a second table, evenly spaced in z = (S − S_end)^(1/k), in which T is
  smooth (:class:`EndTable`);
* targets go through that first step in blocks (temporaries stay in cache), evaluating the
  curve piece by piece with scalar coefficients (:meth:`PiecewiseCurve.eval_grouped`); the few
  left over (break points inside a cell, S at its rounding noise) iterate together
  afterwards, with Newton on (S − S_end)^(1/k) in the end cells.

Every step is kept inside a bracket that shrinks with the sign of the residual; a step
that would leave it bisects instead, so the iteration converges for any monotone curve.
Measured (bench/README.md): 1e6 targets in about 3 times a forward table of 1e6 points.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..deadline import checkpoint
from .base import WORK_ROWS, FloatArray, PiecewiseCurve
from .extrema import Characteristics
from .stroke import clamp_to_stroke, robust_inverse

#: S levels of the start table (8 + 16 + 4 bytes a level: 115 kB cached per curve)
CELLS = 4096

#: targets per block: the block's dozen temporaries stay in the CPU's cache
BLOCK = 8192

#: Hermite start only where V changes by less than this factor across the cell (elsewhere,
#: near V = 0, the cubic can leave the cell: a linear start, then Newton or bisection)
HERMITE_MAX_V_RATIO = 4.0

#: near a dwell end (the first and last END_CELLS cells) the start comes from a table of
#: END_LEVELS levels evenly spaced in z = (distance from the end)^(1/k), where T(z) is
#: smooth, instead of in S, where T ∝ (S − S_end)^(1/k) is not
END_CELLS = 32
END_LEVELS = 512

#: a residual below 2 eps of |S| is rounding (between 2 and 4 ulp of S)
EPS2 = 2 * float(np.finfo(np.float64).eps)

#: iterations never needed in practice (bisection alone halves a cell 52 times)
MAX_ITERATIONS = 100


@dataclass(frozen=True)
class EndTable:
    """Start table next to a dwell end: T where the distance from the end is END_CELLS/CELLS
    of the stroke times z^k, for z = j/END_LEVELS."""

    k: int
    t: FloatArray        # END_LEVELS + 1 times, first = the end itself
    hermite: FloatArray  # (2, END_LEVELS), as InverseGrid.hermite but with slopes dT/dz


@dataclass(frozen=True)
class InverseGrid:
    """Start table of the inverse: T where S reaches S0 + (S7 − S0)·i/CELLS, per cell."""

    direction: int                  # +1 rising, −1 falling
    s_start: float
    s_end: float
    t_levels: FloatArray            # CELLS + 1 times, first = T0, last = T7
    hermite: FloatArray             # (2, CELLS): ΔS/V − ΔT at both ends of a cell, 0 = linear start
    cell_piece: NDArray[np.int32]   # the piece holding each cell, −1 where a break point is inside
    end_order: tuple[int, int]      # order k of the first non-zero derivative at T0 and at T7
    end_tables: tuple[EndTable | None, EndTable | None]  # at T0 and T7 (None: not a dwell end)


def dwell_order(values: list[float], peaks: list[float]) -> int:
    """Order (1..4) of the first derivative that is not zero; 4 if V, A, J all vanish.

    Near the end S − S_end ≈ S⁽ᵏ⁾(T_end)·τᵏ/k! (Taylor), so k decides how T(S) behaves there.

    Parameters
    ----------
    values : list of float
        V, A, J, dJ/dT at the end [-].
    peaks : list of float
        Each derivative's peak |value| over the curve [-] (0 = unknown): a value below
        1e-9 of its peak is rounding noise from the sections' sums.

    Returns
    -------
    int
        k [-]: 1 when V ≠ 0 (no dwell), else the order of the first non-zero derivative.

    References
    ----------
    Makino (1977), eqs. (1)-(9): the sections whose end values are tested (a dwell end
    has V = 0, a quarter-sine start also A = 0).
    """
    for k, (value, peak) in enumerate(zip(values, peaks), start=1):
        if abs(value) > 1e-9 * peak:
            return k
    return len(values)


def build_grid(curve: PiecewiseCurve, ch: Characteristics, direction: int) -> InverseGrid:
    """The start table of a curve's inverse (built once per curve, then cached by it).

    Parameters
    ----------
    curve : PiecewiseCurve
        A monotone curve.
    ch : Characteristics
        Its characteristic values (the peaks tell rounding noise from a non-zero end derivative).
    direction : int
        +1 for a rising curve, −1 for a falling one [-].

    Returns
    -------
    InverseGrid
        T at 4096 + 1 evenly spaced S levels (from :func:`~camcore.curves.stroke.robust_inverse`),
        Hermite corrections per cell, the piece of each cell and the end tables at dwell ends.

    References
    ----------
    INDEXMAN technical guide, worked example before the characteristic-value table (the S → T
    lookup this table serves); C. de Boor, A Practical Guide to Splines (2001), ch. IV (cubic
    Hermite interpolation: the start, with slopes dT/dS = 1/V, where V varies by less than a
    factor 4 over a cell).
    """
    i = np.arange(CELLS + 1)
    s_start, s_end = curve.s_start, curve.s_end
    levels = s_start + (s_end - s_start) * (i / CELLS)
    levels[-1] = s_end
    t_levels = robust_inverse(curve, levels, direction)
    t_levels[0], t_levels[-1] = curve.t_start, curve.t_end
    v_levels = curve.derivatives(t_levels, 1)[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        hermite = _hermite(t_levels, np.diff(levels) / v_levels[:-1], np.diff(levels) / v_levels[1:])
    first = np.searchsorted(curve.piece_starts, t_levels[:-1], side="right") - 1
    last = np.searchsorted(curve.piece_starts, t_levels[1:], side="left") - 1
    first = np.clip(first, 0, curve.n_pieces - 1)
    last = np.clip(last, 0, curve.n_pieces - 1)
    cell_piece = np.where(first == last, first, -1).astype(np.int32)
    peaks = [ch.vm.value, ch.am, max(ch.jm_pos.value, -ch.jm_neg.value), 0.0]
    at_start = [float(d[0]) for d in curve.derivatives(np.array([curve.t_start]), 4)[1:]]
    # T7 belongs to the last piece: its left limit, the end of the motion
    at_end = [float(d[0]) for d in curve.derivatives(np.array([curve.t_end]), 4)[1:]]
    orders = (dwell_order(at_start, peaks), dwell_order(at_end, peaks))
    tables = tuple(_end_table(curve, direction, k, at_t7) if k > 1 else None
                   for k, at_t7 in zip(orders, (False, True)))
    return InverseGrid(direction, s_start, s_end, t_levels, hermite, cell_piece, orders, tables)  # type: ignore[arg-type]


def _hermite(t: FloatArray, step_lo: FloatArray, step_hi: FloatArray) -> FloatArray:
    """Cubic Hermite corrections per cell of a table t: the start inside a cell is the chord
    plus f(1 − f)·((1 − f)·c0 − f·c1), with c = (slope × cell width) − ΔT at each end.

    ``step_lo``, ``step_hi`` are slope × cell width at the cell's two ends. Only where the
    slope changes by less than HERMITE_MAX_V_RATIO over the cell (0: a linear start).
    """
    width = np.diff(t)
    ratio = step_lo / step_hi
    smooth = (ratio > 0) & (ratio <= HERMITE_MAX_V_RATIO) & (ratio >= 1 / HERMITE_MAX_V_RATIO)
    return np.where(smooth, [step_lo - width, step_hi - width], 0.0)


def _end_table(curve: PiecewiseCurve, direction: int, k: int, at_t7: bool) -> EndTable:
    z = np.arange(END_LEVELS + 1) / END_LEVELS
    reach = END_CELLS / CELLS * z**k  # distance from the end, as a fraction of the stroke
    span = curve.s_end - curve.s_start
    levels = curve.s_end - span * reach if at_t7 else curve.s_start + span * reach
    t = robust_inverse(curve, levels, direction)
    t[0] = curve.t_end if at_t7 else curve.t_start
    v = curve.derivatives(t, 1)[1]
    # dT/dz = (dS/dz) / V, dS/dz = ±span·(END_CELLS/CELLS)·k·z^(k−1): times the step 1/END_LEVELS
    ds_dz = (-span if at_t7 else span) * (END_CELLS / CELLS) * k * z ** (k - 1) / END_LEVELS
    with np.errstate(divide="ignore", invalid="ignore"):
        slope_step = ds_dz / v  # 0/0 at the end itself: no Hermite in the first sub-cell
        hermite = _hermite(t, slope_step[:-1], slope_step[1:])
    return EndTable(k, t, hermite)


def solve(curve: PiecewiseCurve, grid: InverseGrid, target: FloatArray,
          rates: tuple[FloatArray, FloatArray] | None = None) -> FloatArray:
    """T for each target (flat, validated: on the stroke within rounding).

    A first pass takes every target through one Newton step, block by block; most are
    then final. The rest (dwell-end cells, break points, S at the rounding noise) are
    gathered from all blocks and iterated together.

    Parameters
    ----------
    curve : PiecewiseCurve
        The monotone curve of ``grid``.
    grid : InverseGrid
        Its start table (:func:`build_grid`).
    target : ndarray
        Displacements S, one-dimensional, each on the stroke within rounding [-]
        (:func:`~camcore.curves.stroke.validate_stroke`).
    rates : (ndarray, ndarray), optional
        Arrays the size of ``target`` that receive V and A at each answer [-]: from the last
        Newton evaluation, carried over the last step δ by Taylor (V + A·δ + J·δ²/2, A + J·δ;
        the terms left out, dJ·δ³/6 and dJ·δ²/2, are below rounding for |δ| ≤ RATES_STEP),
        evaluated afresh for the few answers whose last step was longer.

    Returns
    -------
    ndarray
        For each target the first T in [T0, T7] with S(T) = target [-], to a few ulp.

    References
    ----------
    INDEXMAN technical guide, worked example before the characteristic-value table (S = 0.1833
    on MS gives T = 0.304); W. H. Press et al., Numerical Recipes, 3rd ed., §9.4 (Newton's
    method kept inside a bracket, bisecting when a step leaves it); Makino (1977), eqs. (1)-(9)
    (the closed form that is iterated on).
    """
    result = np.empty_like(target)
    pending: list[_Targets] = []
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for lo in range(0, target.size, BLOCK):
            hi = min(lo + BLOCK, target.size)
            first = _Targets.start(curve, grid, clamp_to_stroke(curve, target[lo:hi]), lo)
            rest = _first_step(curve, grid, first, result, rates)
            if rest is not None:
                pending.append(rest)
        if pending:
            rest = _Targets.concat(pending)
            rest.mark_end_cells(grid)
            for lo in range(0, rest.size, BLOCK):
                _iterate(curve, grid, rest.take(np.arange(lo, min(lo + BLOCK, rest.size))), result, MAX_ITERATIONS,
                         rates)
    if rates is not None:
        # NaN marks an answer whose last step was too long for the Taylor carry
        again = np.flatnonzero(np.isnan(rates[0]))
        if again.size:
            _s, rates[0][again], rates[1][again] = curve.derivatives(result[again], 2)
    return result


#: longest last Newton step [-] over which V and A are carried by Taylor: with |dJ| up to 1e4
#: (the catalog's steepest laws are near 2e3) the left-out terms stay below 1e-15
RATES_STEP = 1e-9


def _carry(rates: tuple[FloatArray, FloatArray] | None, idx: NDArray[np.intp] | slice, delta: FloatArray,
           v: FloatArray, a: FloatArray, j: FloatArray, sign: int) -> None:
    """V and A at t + δ from V, A, J at t (oriented by ``sign``) into ``rates`` at ``idx``;
    NaN where |δ| > RATES_STEP (evaluated afresh by :func:`solve`)."""
    if rates is None:
        return
    near = np.abs(delta) <= RATES_STEP
    rates[0][idx] = np.where(near, sign * (v + delta * (a + 0.5 * delta * j)), np.nan)
    rates[1][idx] = np.where(near, sign * (a + delta * j), np.nan)


def _start(grid: InverseGrid, target: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
    """Start, bracket [lo, hi] and cell of each target."""
    x = target - grid.s_start
    x *= CELLS / (grid.s_end - grid.s_start)  # ∈ [0, CELLS]: targets are clamped onto the stroke
    cell = x.astype(np.intp)
    np.minimum(cell, CELLS - 1, out=cell)
    f = x
    f -= cell  # position in the cell, 0..1
    lo = grid.t_levels[cell]
    hi = grid.t_levels[1:][cell]  # t_levels[cell + 1], without computing cell + 1
    c0 = grid.hermite[0][cell]
    c1 = grid.hermite[1][cell]
    g = 1.0 - f
    c0 *= g
    c1 *= f
    c0 -= c1
    c0 *= f
    c0 *= g                    # f(1 − f)·((1 − f)·c0 − f·c1)
    t = hi - lo
    t *= f
    t += lo
    t += c0
    np.maximum(t, lo, out=t)
    np.minimum(t, hi, out=t)
    return t, lo, hi, cell


def _start_near_end(table: EndTable, reach: FloatArray, at_t7: bool, at: NDArray[np.intp],
                    t: FloatArray, low: FloatArray, high: FloatArray) -> None:
    """Start and bracket of the targets ``at``, whose distance from a dwell end is ``reach``
    (a fraction of the stroke, < END_CELLS/CELLS), from the end's table in z."""
    z = (np.maximum(reach, 0.0) * (CELLS / END_CELLS)) ** (1.0 / table.k) * END_LEVELS
    j = np.minimum(z.astype(np.intp), END_LEVELS - 1)
    f = z - j
    t_j, t_next = table.t[j], table.t[1:][j]
    g = 1.0 - f
    start = t_j + f * (t_next - t_j) + f * g * (g * table.hermite[0][j] - f * table.hermite[1][j])
    lo, hi = (t_next, t_j) if at_t7 else (t_j, t_next)  # at T7, T falls as z grows
    t[at] = np.minimum(np.maximum(start, lo), hi)
    low[at], high[at] = lo, hi


@dataclass
class _Targets:
    """Targets still iterating: where their answers go, iterate t, bracket, goal, piece.

    ``piece`` −1 means a break point lies in the target's cell (looked up each step). In a
    dwell-end cell (``side`` +1 at T0, −1 at T7, else 0) Newton runs on the k-th root of
    the distance from the end (``power`` = 1/k, ``base`` = S at the end, ``reach`` = the
    target's distance from it).
    """

    idx: NDArray[np.intp] | slice
    t: FloatArray
    low: FloatArray
    high: FloatArray
    goal: FloatArray
    piece: NDArray[np.signedinteger[Any]]
    side: FloatArray | None = None
    power: FloatArray | None = None
    base: FloatArray | None = None
    reach: FloatArray | None = None

    @property
    def size(self) -> int:
        return int(self.t.size)

    @classmethod
    def start(cls, curve: PiecewiseCurve, grid: InverseGrid, target: FloatArray, offset: int) -> _Targets:
        t, low, high, cell = _start(grid, target)
        goal = target * grid.direction if grid.direction < 0 else target
        table_start, table_end = grid.end_tables
        span = grid.s_end - grid.s_start
        if table_start is not None and cell.min() < END_CELLS:
            at = np.flatnonzero(cell < END_CELLS)
            _start_near_end(table_start, (target[at] - grid.s_start) / span, False, at, t, low, high)
        if table_end is not None and cell.max() >= CELLS - END_CELLS:
            at = np.flatnonzero(cell >= CELLS - END_CELLS)
            _start_near_end(table_end, (grid.s_end - target[at]) / span, True, at, t, low, high)
        return cls(slice(offset, offset + target.size), t, low, high, goal, grid.cell_piece[cell])

    def mark_end_cells(self, grid: InverseGrid) -> None:
        """Switch the targets in a dwell-end cell to Newton on the k-th root (see the class)."""
        k0, k7 = grid.end_order
        d = grid.direction
        x = (self.goal * d - grid.s_start) * (CELLS / (grid.s_end - grid.s_start))  # the cell, as in _start
        n = self.size
        side, power, base = np.zeros(n), np.ones(n), np.zeros(n)
        for k, sd, mask in ((k0, 1.0, x < 1.0), (k7, -1.0, x >= CELLS - 1)):
            if k > 1 and mask.any():
                side[mask], power[mask] = sd, 1.0 / k
                base[mask] = (grid.s_start if sd > 0 else grid.s_end) * d
        if side.any():
            self.side, self.power, self.base = side, power, base
            self.reach = (self.goal - base) * side

    def take(self, keep: NDArray[np.intp]) -> _Targets:
        idx = keep + self.idx.start if isinstance(self.idx, slice) else self.idx[keep]
        ends = [None if x is None else x[keep] for x in (self.side, self.power, self.base, self.reach)]
        return _Targets(idx, self.t[keep], self.low[keep], self.high[keep], self.goal[keep], self.piece[keep], *ends)

    @staticmethod
    def concat(parts: list[_Targets]) -> _Targets:
        def cat(name: str, fill: float) -> FloatArray | None:
            if all(getattr(p, name) is None for p in parts):
                return None
            return np.concatenate([getattr(p, name) if getattr(p, name) is not None else np.full(p.size, fill)
                                   for p in parts])

        def joined(name: str) -> FloatArray:
            return np.concatenate([getattr(p, name) for p in parts])

        idx = np.concatenate([np.arange(p.idx.start, p.idx.stop) if isinstance(p.idx, slice) else p.idx
                              for p in parts])
        return _Targets(idx, joined("t"), joined("low"), joined("high"), joined("goal"),
                        np.concatenate([p.piece for p in parts]),
                        cat("side", 0.0), cat("power", 1.0), cat("base", 0.0), cat("reach", 0.0))


def _first_step(curve: PiecewiseCurve, grid: InverseGrid, x: _Targets, result: FloatArray,
                rates: tuple[FloatArray, FloatArray] | None = None) -> _Targets | None:
    """One Newton step for a fresh block, with only the test that finishes most targets.

    A step that stays inside the cell and whose predicted error |A/2V|·δ² is below an ulp
    is final. Everything else (exact hits on a cell's end, dwell-end cells, break points,
    S at its rounding noise) goes on to :func:`_iterate` from its start, which has every
    test. Returns those targets, or None.
    """
    pe = x.piece
    mixed = pe < 0
    if mixed.any():
        pe = pe.copy()
        pe[mixed] = np.clip(curve.piece_index(x.t[mixed]), 0, curve.n_pieces - 1)
    values = curve.eval_grouped(x.t, pe, 2 if rates is None else 3)
    s_now, v_now, a_now = values[:3]
    if grid.direction < 0:
        s_now, v_now, a_now = -s_now, -v_now, -a_now
    step = s_now - x.goal
    step /= v_now
    t_new = x.t - step
    if rates is not None:  # before a_now is overwritten below
        _carry(rates, x.idx, -step, values[1], values[2], values[3], 1)
    done = t_new > x.low
    done &= t_new < x.high
    tiny = 4 * float(np.spacing(max(abs(curve.t_start), abs(curve.t_end), 1.0)))
    a_now /= v_now
    step *= step
    step *= np.abs(a_now, out=a_now)
    done &= step <= 0.5 * tiny
    result[x.idx] = t_new
    rest = np.flatnonzero(~done)
    return x.take(rest) if rest.size else None


def _iterate(curve: PiecewiseCurve, grid: InverseGrid, x: _Targets, result: FloatArray, iterations: int,
             rates: tuple[FloatArray, FloatArray] | None = None) -> _Targets:
    """Up to ``iterations`` safeguarded Newton steps; answers go into ``result`` as they come.

    Returns the targets not yet final (call under np.errstate: inf/nan steps are expected).
    """
    direction = grid.direction
    # ulp-level tolerance: T within 4 ulp of the curve's largest |T|
    tiny = 4 * float(np.spacing(max(abs(curve.t_start), abs(curve.t_end), 1.0)))
    work = np.empty((WORK_ROWS, x.size))
    for _ in range(iterations):
        checkpoint()
        if x.size == 0:
            break
        pe = x.piece
        mixed = pe < 0
        if mixed.any():
            pe = pe.copy()
            pe[mixed] = np.clip(curve.piece_index(x.t[mixed]), 0, curve.n_pieces - 1)
        values = curve.eval_grouped(x.t, pe, 2 if rates is None else 3, work)
        s_now, v_now, a_now = values[:3]
        if direction < 0:
            s_now, v_now, a_now = -s_now, -v_now, -a_now
        f = s_now - x.goal
        step = f / v_now
        ends = None
        if x.side is not None:
            ends = np.flatnonzero(x.side)
            # Newton on g = p^(1/k) − reach^(1/k), p = (S − S_end)·side:
            # step = k·p·(1 − (reach/p)^(1/k)) / (dp/dT)
            p = (s_now[ends] - x.base[ends]) * x.side[ends]  # type: ignore[index]
            power = x.power[ends]  # type: ignore[index]
            step[ends] = (p - p * (x.reach[ends] / p) ** power) / (power * v_now[ends] * x.side[ends])  # type: ignore[index]
        t_new = x.t - step
        ok = t_new > x.low
        ok &= t_new < x.high  # false for nan and inf too
        # a residual at the rounding level of S cannot be improved (dT = dS / V): keep t
        at_rounding = np.abs(f) <= EPS2 * np.abs(s_now)
        np.copyto(t_new, x.t, where=at_rounding)
        np.abs(step, out=step)
        # Newton's error after a step δ is about |A / 2V|·δ²: below an ulp, the step is final
        done = np.abs(a_now / v_now) * (step * step) <= 0.5 * tiny
        if ends is not None:
            done[ends] = False
        done |= step <= tiny
        done &= ok
        done |= at_rounding
        # where S is noise (cancellation near a dwell end) only the bracket can close
        done |= (x.high - x.low) <= tiny
        result[x.idx] = t_new
        if rates is not None:
            _carry(rates, x.idx, t_new - x.t, values[1], values[2], values[3], 1)
        rest = np.flatnonzero(~done)
        # the rest: shrink the bracket with the residual's sign; a step leaving it bisects
        f, t_new, ok, t = f[rest], t_new[rest], ok[rest], x.t[rest]
        x = x.take(rest)
        np.copyto(x.low, t, where=f < 0)
        np.copyto(x.high, t, where=f > 0)
        ok &= t_new > x.low
        ok &= t_new < x.high
        np.copyto(t_new, 0.5 * (x.low + x.high), where=~ok)
        x.t = t_new
        work = work[:, : x.size]
    return x
