"""Evaluation of a piecewise-smooth dimensionless cam motion curve.

A curve is dimensionless: time T runs over [T0, T7] (0..1 for the standard curves),
displacement S, velocity V = dS/dT, acceleration A, jerk J = d³S/dT³.
Every curve is made of *pieces* on which it is smooth (analytic); between pieces A or J
may jump. Evaluation at a break point takes the piece that starts there (right limit);
at T7 it takes the last piece. This is the convention of the INDEXMAN tables and of
Makino's subroutine CURVE.

This module only evaluates; characteristic values are in :mod:`.extrema`, the inverse
in :mod:`.inverse` and :mod:`.stroke`, and :class:`camcore.curves.curve.Curve` puts them
together.

References
----------
.. [1] Makino (1977), eqs. (1)-(12) and subroutine CURVE (right-limit convention).
.. [2] INDEXMAN technical guide, section 5 (cam curves, 0.01-step tables).
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: curves with at most this many pieces evaluate sorted T piece by piece, on contiguous
#: slices (no per-point piece index or gathers); longer ones (measured points) gather.
_SLICED_PIECES = 16

#: ... and only for at least this many points per piece: slicing costs ~25 µs of fixed
#: work per piece, gathering ~60 ns more per point (measured: MS, MT, cycloid cross
#: over between 2 000 and 3 000 points).
_SLICED_MIN_POINTS_PER_PIECE = 512

#: sorted T is evaluated in blocks of this many points (a few per piece for a large
#: table), so that the temporaries stay in cache; they live in one workspace of
#: ``WORK_ROWS`` rows allocated per call, not in fresh arrays per block and operation
#: (allocating costs as much as a multiplication pass: freshly mapped, zeroed pages).
_BLOCK = 16384
WORK_ROWS = 5

#: at most this many points are evaluated one by one in Python floats, here where the curve has scalar
#: formulas (:meth:`PiecewiseCurve.eval_point`) and by the lifts and the turret built on curves: a call on
#: arrays costs ~30 µs whatever its size, one point ~3 µs (a tracing or fitting solver asks for one or
#: two points at a time, hundreds of times)
FEW_POINTS = 8



@dataclass(frozen=True)
class CurveValues:
    """Columns of a curve table, all dimensionless.

    ``q`` is the catalog's torque coefficient A·V/Am; ``q_raw`` is Makino's A·V.
    """

    t: FloatArray
    s: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray
    q: FloatArray
    q_raw: FloatArray

    def columns(self) -> dict[str, FloatArray]:
        return {"t": self.t, "s": self.s, "v": self.v, "a": self.a, "j": self.j, "q": self.q}

@dataclass(frozen=True)
class Piece:
    """A smooth stretch [start, end] of a curve, by its index in the curve."""

    index: int
    start: float
    end: float


class PiecewiseCurve:
    """Base class: a dimensionless cam motion curve made of smooth pieces (evaluation only).

    Subclasses provide :attr:`piece_starts` (sorted start times of the non-empty
    pieces, first = T0), :attr:`t_end` (T7) and :meth:`eval_pieces`, which evaluates
    S and its derivatives up to ``order`` (≤ 4) with the formulas of given pieces.
    Outside [T0, T7] the curve continues as Makino's sections 0 and VIII: constant
    S0/V0 before T0, constant velocity V7 after T7.
    """

    piece_starts: FloatArray
    t_end: float
    #: whether :meth:`eval_point` is there (scalar formulas giving eval_pieces' numbers)
    has_point_formulas: bool = False
    #: whether :meth:`eval_piece` is a faster path of its own (a section curve's scalar coefficients);
    #: without one, a table piece by piece is eval_pieces block by block, slower than one gather
    #: (a return of the cycloid, 3604 angles: 173 against 111 µs)
    has_piece_path: bool = False

    # ---------------------------------------------------------------- subclasses
    def eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        """Return [S, V, A, J, dJ/dT][: order + 1] of the given pieces at t."""
        raise NotImplementedError

    def eval_grid(self, grid: FloatArray, order: int) -> list[FloatArray]:
        """[S, V, A, J, dJ/dT][: order + 1] on a grid of shape (n_pieces, m), row k on piece k:
        :meth:`eval_pieces`' numbers, shaped like the grid (a subclass may use that each piece's
        points are together)."""
        n, m = grid.shape
        values = self.eval_pieces(grid.reshape(-1), np.repeat(np.arange(n, dtype=np.intp), m), order)
        return [v.reshape(n, m) for v in values]

    def eval_point(self, t: float, k: int) -> list[float]:
        """[S, V, A, J, dJ/dT] of piece k at one t, as Python floats: the numbers
        :meth:`eval_pieces` gives there, to the bit (only where :attr:`has_point_formulas`)."""
        raise NotImplementedError

    def eval_piece(self, t: FloatArray, k: int, order: int, out: list[FloatArray],
                    work: FloatArray | None = None) -> None:
        """Write [S, V, A, J, dJ/dT][: order + 1] of piece k at sorted t (all on it) into out.

        ``work`` is scratch space the caller reuses from block to block (rows of at least
        ``len(t)``; ``WORK_ROWS`` of them). The default uses :meth:`eval_pieces`;
        subclasses may override it with a version that uses the piece's coefficients
        directly (same numbers, less work).
        """
        vals = self.eval_pieces(t, np.full(t.shape, k, dtype=np.intp), order)
        for o, v in zip(out, vals):
            o[...] = v

    # ---------------------------------------------------------------- geometry
    @property
    def t_start(self) -> float:
        """T0, where the curve starts [-]."""
        return float(self.piece_starts[0])

    @property
    def n_pieces(self) -> int:
        """Number of smooth pieces (non-empty sections) [-]."""
        return len(self.piece_starts)

    @cached_property
    def piece_ends(self) -> FloatArray:
        """End T of each piece: the next piece's start, T7 for the last [-]."""
        return np.append(self.piece_starts[1:], self.t_end)

    @cached_property
    def pieces(self) -> list[Piece]:
        """The smooth pieces in order, each with its start and end T."""
        return [Piece(i, float(a), float(b)) for i, (a, b) in enumerate(zip(self.piece_starts, self.piece_ends))]

    @cached_property
    def break_points(self) -> FloatArray:
        """T0, the starts of the pieces, and T7."""
        return np.append(self.piece_starts, self.t_end)

    def piece_index(self, t: FloatArray) -> NDArray[np.intp]:
        """Index of the piece whose formula applies at t (right limit; last piece at T7).

        -1 means before T0, ``n_pieces`` after T7.
        """
        return np.searchsorted(self._piece_index_bounds, t, side="right") - 1

    @cached_property
    def _piece_index_bounds(self) -> FloatArray:
        # piece starts, then the float just above T7: T7 itself falls in the last piece
        return np.append(self.piece_starts, np.nextafter(self.t_end, np.inf))

    @cached_property
    def _ends(self) -> tuple[list[float], list[float]]:
        """S, V at T0 (right limit) and at T7 (left limit)."""
        t0 = np.array([self.t_start])
        t7 = np.array([self.t_end])
        first = self.eval_pieces(t0, np.array([0]), 1)
        last = self.eval_pieces(t7, np.array([self.n_pieces - 1]), 1)
        return [float(first[0][0]), float(first[1][0])], [float(last[0][0]), float(last[1][0])]

    @property
    def s_start(self) -> float:
        """S0, the displacement at T0 (right limit) [-]."""
        return self._ends[0][0]

    @property
    def s_end(self) -> float:
        """S7, the displacement at T7 (left limit) [-]."""
        return self._ends[1][0]

    @property
    def v_start(self) -> float:
        """V0, the velocity at T0 (right limit) [-]."""
        return self._ends[0][1]

    @property
    def v_end(self) -> float:
        """V7, the velocity at T7 (left limit) [-]."""
        return self._ends[1][1]

    # ---------------------------------------------------------------- evaluation
    def derivatives(self, t: ArrayLike, order: int = 3) -> list[FloatArray]:
        """S and its derivatives up to ``order`` (0..4) at the times t.

        Parameters
        ----------
        t : array_like
            Dimensionless time T; any shape.
        order : int
            Highest derivative: 0 → [S], 3 → [S, V, A, J], 4 adds dJ/dT.

        Returns
        -------
        list of ndarray
            [S, V, A, J, dJ/dT][: order + 1], each shaped like ``t`` [-]; outside [T0, T7]
            Makino's sections 0 and VIII (S0, V0 before T0; constant V7 after T7).
        """
        t_arr = np.asarray(t, dtype=np.float64)
        flat = t_arr.reshape(-1)
        if flat.size <= FEW_POINTS and self.has_point_formulas:
            points = self._derivatives_pointwise(flat, order)
            if points is not None:
                return [o.reshape(t_arr.shape) for o in points]
        sliced = (self.has_piece_path and self.n_pieces <= _SLICED_PIECES
                  and flat.size >= _SLICED_MIN_POINTS_PER_PIECE * self.n_pieces)
        if sliced and bool(np.all(flat[1:] >= flat[:-1])):
            out = self._derivatives_sorted(flat, order)
        else:
            out = self._derivatives_gathered(flat, order)
        return [o.reshape(t_arr.shape) for o in out]

    def _derivatives_pointwise(self, flat: FloatArray, order: int) -> list[FloatArray] | None:
        """A few T inside [T0, T7], each by :meth:`point_derivatives` (the gathered numbers to the bit,
        without the arrays' fixed cost); None when one lies outside (the general path fills sections 0
        and VIII)."""
        rows = []
        for t in flat.tolist():
            row = self.point_derivatives(t)
            if row is None:
                return None
            rows.append(row)
        return [np.array([row[o] for row in rows], dtype=np.float64) for o in range(order + 1)]

    def point_derivatives(self, t: float) -> list[float] | None:
        """S, V, A, J, dJ/dT at one T inside [T0, T7] as Python floats.

        Parameters
        ----------
        t : float
            Dimensionless time [-].

        Returns
        -------
        list of float or None
            [S, V, A, J, dJ/dT] by :meth:`eval_point`, the arrays' numbers to the bit [-]; None outside
            [T0, T7] (Makino's sections 0 and VIII) or for a curve without point formulas.

        References
        ----------
        Makino (1977), subroutine CURVE: one T, its section, its formulas.
        """
        if not self.has_point_formulas:
            return None
        k = bisect_right(self._piece_index_bounds_list, t) - 1  # :meth:`piece_index`: searchsorted(…, "right") − 1
        if not 0 <= k < self.n_pieces:
            return None
        return self.eval_point(t, k)

    @cached_property
    def _piece_index_bounds_list(self) -> list[float]:
        return [float(b) for b in self._piece_index_bounds]

    def _derivatives_sorted(self, flat: FloatArray, order: int) -> list[FloatArray]:
        """Sorted T (a table): each piece evaluates its contiguous slice of T, block by block."""
        out = list(np.empty((order + 1, flat.size)))
        work = np.empty((WORK_ROWS, min(_BLOCK, flat.size)))
        # piece k holds T in [start_k, start_k+1); T7 itself belongs to the last piece
        bounds = np.searchsorted(flat, self.piece_starts, side="left").tolist()
        bounds.append(int(np.searchsorted(flat, self.t_end, side="right")))
        for k in range(self.n_pieces):
            for lo in range(bounds[k], bounds[k + 1], _BLOCK):
                hi = min(lo + _BLOCK, bounds[k + 1])
                self.eval_piece(flat[lo:hi], k, order, [o[lo:hi] for o in out], work)
        self._fill_outside(flat, out, slice(0, bounds[0]), slice(bounds[-1], None))
        return out

    def _derivatives_gathered(self, flat: FloatArray, order: int) -> list[FloatArray]:
        """Any T: a piece index per T, the piece coefficients gathered."""
        idx = self.piece_index(flat)
        inside = (idx >= 0) & (idx < self.n_pieces)
        if inside.all():
            vals = self.eval_pieces(flat, idx, order)
            return [np.asarray(v, dtype=np.float64) for v in vals]
        out = [np.empty_like(flat) for _ in range(order + 1)]
        if inside.any():
            vals = self.eval_pieces(flat[inside], idx[inside], order)
            for o, v in zip(out, vals):
                o[inside] = v
        self._fill_outside(flat, out, idx < 0, idx >= self.n_pieces)
        return out

    def eval_grouped(self, t: FloatArray, piece: NDArray[np.intp], order: int,
                      work: FloatArray | None = None) -> list[FloatArray]:
        """[S, V, …][: order + 1] at t in any order, each t on its (valid) piece.

        Piece by piece with the piece's scalar coefficients (:meth:`eval_piece`) when
        that pays; the same numbers as :meth:`eval_pieces`, which it falls back to for
        few points or many pieces.
        """
        if (not self.has_piece_path or self.n_pieces > _SLICED_PIECES
                or t.size < _SLICED_MIN_POINTS_PER_PIECE * self.n_pieces):
            return self.eval_pieces(t, piece, order)
        out = np.empty((order + 1, t.size))
        first, last = int(piece.min()), int(piece.max())
        if first == last:  # one piece (a block of sorted targets, mostly)
            self.eval_piece(t, first, order, list(out), work)
            return list(out)
        for k in range(first, last + 1):
            sel = np.flatnonzero(piece == k)
            if sel.size:
                part = np.empty((order + 1, sel.size))
                self.eval_piece(t[sel], k, order, list(part), work)
                out[:, sel] = part
        return list(out)

    def _fill_outside(self, flat: FloatArray, out: list[FloatArray], before: Any, after: Any) -> None:
        """Sections 0 and VIII: S0, V0 before T0; S7 + V7·(T − T7), V7 after T7; A = J = 0."""
        (s0, v0), (s7, v7) = self._ends
        out[0][before] = s0
        out[0][after] = s7 + v7 * (flat[after] - self.t_end)
        if len(out) > 1:
            out[1][before] = v0
            out[1][after] = v7
        for o in out[2:]:
            o[before] = 0.0
            o[after] = 0.0


@dataclass(frozen=True)
class Scale:
    """How a user curve's dimensionless T, S map back to its own units.

    theta = theta_start + theta_span · T;  h = h_min + h_span · S.
    """

    theta_start: float
    theta_span: float
    h_min: float
    h_span: float
    units: dict[str, str] = field(default_factory=dict)
