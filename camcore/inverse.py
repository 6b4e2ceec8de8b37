"""The exact inverse S → T of a monotone curve, vectorised and blocked.

For each target S the answer is the first T in [T0, T7] with S(T) = target, found by
safeguarded Newton iteration on the closed form. What makes it fast:

* a start table (:class:`InverseGrid`, built once per curve): the first T reaching each of
  M + 1 evenly spaced S levels, with V there. A target finds its cell by arithmetic, and
  the start inside the cell is the cubic Hermite interpolant of T(S) (slopes dT/dS = 1/V),
  within ~1e-15 of the root where V does not vary much over the cell; one Newton step
  then reaches the rounding level, and the step's predicted error |A/2V|·δ² says so
  without another evaluation;
* at a dwell end (V = 0 at T0 or T7), S − S_end ≈ c·τ^k, where k is the order of the
  first non-zero derivative there: Newton runs on (S − S_end)^(1/k), which is nearly
  linear in τ, instead of on S, where it would crawl;
* targets are processed in blocks (temporaries stay in cache), and each block evaluates
  the curve piece by piece with scalar coefficients (:meth:`Curve._eval_grouped`).

Every step is kept inside a bracket that shrinks with the sign of the residual; a step
that would leave it bisects instead, so the iteration converges for any monotone curve.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .curve import WORK_ROWS

if TYPE_CHECKING:
    from .curve import Curve, FloatArray

#: S levels of the start table (8 + 16 + 4 bytes a level, cached per curve)
CELLS = 8192

#: targets per block: the block's dozen temporaries stay in the CPU's cache
BLOCK = 8192

#: Hermite start only where V changes by less than this factor across the cell (elsewhere,
#: near V = 0, the cubic can leave the cell: a linear start, then Newton or bisection)
HERMITE_MAX_V_RATIO = 4.0

#: a residual below 2 eps of |S| is rounding (between 2 and 4 ulp of S)
EPS2 = 2 * float(np.finfo(np.float64).eps)

#: iterations never needed in practice (bisection alone halves a cell 52 times)
MAX_ITERATIONS = 100


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


def dwell_order(values: list[float], peaks: list[float]) -> int:
    """Order (1..4) of the first derivative that is not zero; 4 if V, A, J all vanish.

    ``values`` are V, A, J, dJ/dT at the end; a value below 1e-9 of its peak over the
    curve (``peaks``, 0 = unknown) is rounding noise from the sections' sums.
    """
    for k, (value, peak) in enumerate(zip(values, peaks), start=1):
        if abs(value) > 1e-9 * peak:
            return k
    return len(values)


def build_grid(curve: Curve, direction: int) -> InverseGrid:
    i = np.arange(CELLS + 1)
    s_start, s_end = curve.s_start, curve.s_end
    levels = s_start + (s_end - s_start) * (i / CELLS)
    levels[-1] = s_end
    t_levels = curve._inverse_bracketed(levels, direction)
    t_levels[0], t_levels[-1] = curve.t_start, curve.t_end
    v_levels = curve.derivatives(t_levels, 1)[1]
    # cubic Hermite start in a cell: the chord plus f(1 − f)·((1 − f)·c0 − f·c1), where
    # c = ΔS/V − ΔT at each end
    ds = np.diff(levels)
    width = np.diff(t_levels)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = v_levels[:-1] / v_levels[1:]
        smooth = (ratio > 0) & (ratio <= HERMITE_MAX_V_RATIO) & (ratio >= 1 / HERMITE_MAX_V_RATIO)
        hermite = np.where(smooth, [ds / v_levels[:-1] - width, ds / v_levels[1:] - width], 0.0)
    first = np.searchsorted(curve.piece_starts, t_levels[:-1], side="right") - 1
    last = np.searchsorted(curve.piece_starts, t_levels[1:], side="left") - 1
    first = np.clip(first, 0, curve.n_pieces - 1)
    last = np.clip(last, 0, curve.n_pieces - 1)
    cell_piece = np.where(first == last, first, -1).astype(np.int32)
    ch = curve.characteristics
    peaks = [ch.vm.value, ch.am, max(ch.jm_pos.value, -ch.jm_neg.value), 0.0]
    at_start = [float(d[0]) for d in curve.derivatives(np.array([curve.t_start]), 4)[1:]]
    # T7 belongs to the last piece: its left limit, the end of the motion
    at_end = [float(d[0]) for d in curve.derivatives(np.array([curve.t_end]), 4)[1:]]
    return InverseGrid(direction, s_start, s_end, t_levels, hermite, cell_piece,
                       (dwell_order(at_start, peaks), dwell_order(at_end, peaks)))


def solve(curve: Curve, grid: InverseGrid, target: FloatArray) -> FloatArray:
    """T for each target (flat, validated: on the stroke within rounding)."""
    out = np.empty_like(target)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for lo in range(0, target.size, BLOCK):
            hi = min(lo + BLOCK, target.size)
            out[lo:hi] = _solve_block(curve, grid, curve._clamp_to_stroke(target[lo:hi]))
    return out


def _start(grid: InverseGrid, target: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
    """Start, bracket [lo, hi] and cell of each target."""
    x = target - grid.s_start
    x *= CELLS / (grid.s_end - grid.s_start)  # ∈ [0, CELLS]: targets are clamped onto the stroke
    cell = x.astype(np.intp)
    np.minimum(cell, CELLS - 1, out=cell)
    f = x
    f -= cell  # position in the cell, 0..1
    lo = grid.t_levels[cell]
    hi = grid.t_levels[cell + 1]
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


class _EndCells:
    """Targets in a dwell-end cell: Newton on the k-th root of the distance from the end."""

    def __init__(self, grid: InverseGrid, cell: NDArray[np.intp], goal: FloatArray, t: FloatArray):
        k0, k7 = grid.end_order
        d = grid.direction
        self.at = np.zeros(t.size, dtype=bool)
        self.side = np.zeros(t.size)   # +1 at T0, −1 at T7
        self.power = np.ones(t.size)   # 1/k
        self.base = np.zeros(t.size)   # S at the end (times direction)
        for k, side, i_end in ((k0, 1.0, 0), (k7, -1.0, CELLS)):
            if k <= 1:
                continue
            mask = cell == (0 if side > 0 else CELLS - 1)
            if not mask.any():
                continue
            s_end = (grid.s_start if side > 0 else grid.s_end) * d
            self.at |= mask
            self.side[mask], self.power[mask], self.base[mask] = side, 1.0 / k, s_end
            # start: the pure power law S − S_end ∝ τ^k through the cell's far corner
            i_far = i_end + (1 if side > 0 else -1)
            s_far = (grid.s_start + (grid.s_end - grid.s_start) * (i_far / CELLS)) * d
            t_end, t_far = grid.t_levels[i_end], grid.t_levels[i_far]
            frac = np.clip((goal[mask] - s_end) / (s_far - s_end), 0.0, 1.0) ** (1.0 / k)
            t[mask] = t_end + (t_far - t_end) * frac
        self.reach = (goal - self.base) * self.side  # the target's distance from its end, ≥ 0
        self.any = bool(self.at.any())

    def newton_steps(self, step: FloatArray, s_now: FloatArray, v_now: FloatArray) -> None:
        """Replace the plain Newton step by the k-th-root one in the end cells.

        g = p^(1/k) − reach^(1/k) with p = (S − S_end)·side: step = k·p·(1 − (reach/p)^(1/k)) / (dp/dT).
        """
        ea = np.flatnonzero(self.at)
        p = (s_now[ea] - self.base[ea]) * self.side[ea]
        power = self.power[ea]
        step[ea] = (p - p * (self.reach[ea] / p) ** power) / (power * v_now[ea] * self.side[ea])

    def keep(self, rest: NDArray[np.intp]) -> None:
        self.at, self.side, self.power, self.base, self.reach = (
            self.at[rest], self.side[rest], self.power[rest], self.base[rest], self.reach[rest])
        self.any = bool(self.at.any())


def _solve_block(curve: Curve, grid: InverseGrid, target: FloatArray) -> FloatArray:
    """T for one block of clamped targets (call under np.errstate: inf/nan steps are expected)."""
    direction = grid.direction
    t, low, high, cell = _start(grid, target)
    piece = grid.cell_piece[cell].astype(np.intp)
    goal = target * direction if direction < 0 else target
    ends = None
    if (grid.end_order[0] > 1 and cell.min() == 0) or (grid.end_order[1] > 1 and cell.max() == CELLS - 1):
        ends = _EndCells(grid, cell, goal, t)
    result = np.empty_like(t)
    # ulp-level tolerance: T within 4 ulp of the curve's largest |T|
    tiny = 4 * float(np.spacing(max(abs(curve.t_start), abs(curve.t_end), 1.0)))
    idx = None  # None: the whole block; else the positions in result still iterating
    mixed = piece < 0
    any_mixed = bool(mixed.any())
    work = np.empty((WORK_ROWS, t.size))
    for _ in range(MAX_ITERATIONS):
        pe = piece
        if any_mixed:
            pe = piece.copy()
            pe[mixed] = np.clip(curve.piece_index(t[mixed]), 0, curve.n_pieces - 1)
        s_now, v_now, a_now = curve._eval_grouped(t, pe, 2, work)
        if direction < 0:
            s_now, v_now, a_now = -s_now, -v_now, -a_now
        f = s_now - goal
        step = f / v_now
        if ends is not None:
            ends.newton_steps(step, s_now, v_now)
        t_new = t - step
        ok = t_new > low
        ok &= t_new < high  # false for nan and inf too
        # a residual at the rounding level of S cannot be improved (dT = dS / V): keep t
        at_rounding = np.abs(f) <= EPS2 * np.abs(s_now)
        np.copyto(t_new, t, where=at_rounding)
        np.abs(step, out=step)
        # Newton's error after a step δ is about |A / 2V|·δ²: below an ulp, the step is final
        done = np.abs(a_now / v_now) * (step * step) <= 0.5 * tiny
        if ends is not None:
            done &= ~ends.at
        done |= step <= tiny
        done &= ok
        done |= at_rounding
        if idx is not None:
            # where S is noise (cancellation near a dwell end) only the bracket can close
            done |= (high - low) <= tiny
        if idx is None:
            result[:] = t_new
        else:
            result[idx] = t_new
        rest = np.flatnonzero(~done)
        if rest.size == 0:
            break
        # the rest: shrink the bracket with the residual's sign; a step leaving it bisects
        t, t_new, f, ok = t[rest], t_new[rest], f[rest], ok[rest]
        low, high, goal, piece, mixed = low[rest], high[rest], goal[rest], piece[rest], mixed[rest]
        idx = rest if idx is None else idx[rest]
        any_mixed = bool(mixed.any())
        if ends is not None:
            ends.keep(rest)
            if not ends.any:
                ends = None
        np.copyto(low, t, where=f < 0)
        np.copyto(high, t, where=f > 0)
        ok &= t_new > low
        ok &= t_new < high
        np.copyto(t_new, 0.5 * (low + high), where=~ok)
        t = t_new
        work = work[:, : t.size]
    return result
