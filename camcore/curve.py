"""The curve interface shared by every cam motion law.

A curve is dimensionless: time T runs over [T0, T7] (0..1 for the standard curves),
displacement S, velocity V = dS/dT, acceleration A, jerk J = d³S/dT³.
Every curve is made of *pieces* on which it is smooth (analytic); between pieces A or J
may jump. Evaluation at a break point takes the piece that starts there (right limit);
at T7 it takes the last piece. This is the convention of the INDEXMAN tables and of
Makino's subroutine CURVE.

References
----------
.. [1] H. Makino, "Universal Cam Curve and Its Application" (1977), eqs. (1)-(12).
.. [2] INDEXMAN technical guide, section 5 (cam curves, characteristic values).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import NonMonotoneError, StrokeRangeError

if TYPE_CHECKING:
    from .inverse import InverseGrid

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

#: samples per piece used to bracket the roots of a derivative before refining them;
#: every piece of every curve we build has at most a few extrema, far fewer than this.
_BRACKET_SAMPLES = 257


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
class Extremum:
    """A peak value and the T where it first occurs."""

    value: float
    t: float


@dataclass(frozen=True)
class Characteristics:
    """Characteristic values of a curve over [T0, T7], from its closed form.

    ``vm`` is the largest |V|; ``am`` the largest |A| (the Am that normalises Q), and
    ``am_abs`` the same value with the T where it occurs, like every other extreme.
    Negative extremes (``am_neg``, ``jm_neg``, ``qm_neg``) are signed (≤ 0 for the
    standard curves), as Makino's AJKMM and QMM are.
    """

    vm: Extremum
    v_max: Extremum
    v_min: Extremum
    am: float
    am_abs: Extremum
    am_pos: Extremum
    am_neg: Extremum
    jm_pos: Extremum
    jm_neg: Extremum
    qm_pos: Extremum
    qm_neg: Extremum
    qm_raw_pos: Extremum
    qm_raw_neg: Extremum
    s_max: Extremum
    s_min: Extremum

    def as_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"am": self.am}
        for name in (
            "vm", "v_max", "v_min", "am_abs", "am_pos", "am_neg", "jm_pos", "jm_neg",
            "qm_pos", "qm_neg", "qm_raw_pos", "qm_raw_neg", "s_max", "s_min",
        ):
            ext: Extremum = getattr(self, name)
            out[name] = ext.value
            out[f"t_{name}"] = ext.t
        return out


@dataclass(frozen=True)
class Piece:
    """A smooth stretch [start, end] of a curve, by its index in the curve."""

    index: int
    start: float
    end: float


class Curve:
    """Base class: a dimensionless cam motion curve made of smooth pieces.

    Subclasses provide :attr:`piece_starts` (sorted start times of the non-empty
    pieces, first = T0), :attr:`t_end` (T7) and :meth:`_eval_pieces`, which evaluates
    S and its derivatives up to ``order`` (≤ 4) with the formulas of given pieces.
    Outside [T0, T7] the curve continues as Makino's sections 0 and VIII: constant
    S0/V0 before T0, constant velocity V7 after T7.
    """

    piece_starts: FloatArray
    t_end: float

    # ---------------------------------------------------------------- subclasses
    def _eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        """Return [S, V, A, J, dJ/dT][: order + 1] of the given pieces at t."""
        raise NotImplementedError

    def _eval_piece(self, t: FloatArray, k: int, order: int, out: list[FloatArray],
                    work: FloatArray | None = None) -> None:
        """Write [S, V, A, J, dJ/dT][: order + 1] of piece k at sorted t (all on it) into out.

        ``work`` is scratch space the caller reuses from block to block (rows of at least
        ``len(t)``; ``WORK_ROWS`` of them). The default uses :meth:`_eval_pieces`;
        subclasses may override it with a version that uses the piece's coefficients
        directly (same numbers, less work).
        """
        vals = self._eval_pieces(t, np.full(t.shape, k, dtype=np.intp), order)
        for o, v in zip(out, vals):
            o[...] = v

    # ---------------------------------------------------------------- geometry
    @property
    def t_start(self) -> float:
        return float(self.piece_starts[0])

    @property
    def n_pieces(self) -> int:
        return len(self.piece_starts)

    @cached_property
    def pieces(self) -> list[Piece]:
        ends = np.append(self.piece_starts[1:], self.t_end)
        return [Piece(i, float(a), float(b)) for i, (a, b) in enumerate(zip(self.piece_starts, ends))]

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
        first = self._eval_pieces(t0, np.array([0]), 1)
        last = self._eval_pieces(t7, np.array([self.n_pieces - 1]), 1)
        return [float(first[0][0]), float(first[1][0])], [float(last[0][0]), float(last[1][0])]

    @property
    def s_start(self) -> float:
        return self._ends[0][0]

    @property
    def s_end(self) -> float:
        return self._ends[1][0]

    # ---------------------------------------------------------------- evaluation
    def derivatives(self, t: ArrayLike, order: int = 3) -> list[FloatArray]:
        """S and its derivatives up to ``order`` (0..4) at the times t.

        Parameters
        ----------
        t : array_like
            Dimensionless time T; any shape.
        order : int
            Highest derivative: 0 → [S], 3 → [S, V, A, J], 4 adds dJ/dT.
        """
        t_arr = np.asarray(t, dtype=np.float64)
        flat = t_arr.reshape(-1)
        sliced = self.n_pieces <= _SLICED_PIECES and flat.size >= _SLICED_MIN_POINTS_PER_PIECE * self.n_pieces
        if sliced and bool(np.all(flat[1:] >= flat[:-1])):
            out = self._derivatives_sorted(flat, order)
        else:
            out = self._derivatives_gathered(flat, order)
        return [o.reshape(t_arr.shape) for o in out]

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
                self._eval_piece(flat[lo:hi], k, order, [o[lo:hi] for o in out], work)
        self._fill_outside(flat, out, slice(0, bounds[0]), slice(bounds[-1], None))
        return out

    def _derivatives_gathered(self, flat: FloatArray, order: int) -> list[FloatArray]:
        """Any T: a piece index per T, the piece coefficients gathered."""
        idx = self.piece_index(flat)
        inside = (idx >= 0) & (idx < self.n_pieces)
        if inside.all():
            vals = self._eval_pieces(flat, idx, order)
            return [np.asarray(v, dtype=np.float64) for v in vals]
        out = [np.empty_like(flat) for _ in range(order + 1)]
        if inside.any():
            vals = self._eval_pieces(flat[inside], idx[inside], order)
            for o, v in zip(out, vals):
                o[inside] = v
        self._fill_outside(flat, out, idx < 0, idx >= self.n_pieces)
        return out

    def _eval_grouped(self, t: FloatArray, piece: NDArray[np.intp], order: int,
                      work: FloatArray | None = None) -> list[FloatArray]:
        """[S, V, …][: order + 1] at t in any order, each t on its (valid) piece.

        Piece by piece with the piece's scalar coefficients (:meth:`_eval_piece`) when
        that pays; the same numbers as :meth:`_eval_pieces`, which it falls back to for
        few points or many pieces.
        """
        if self.n_pieces > _SLICED_PIECES or t.size < _SLICED_MIN_POINTS_PER_PIECE * self.n_pieces:
            return self._eval_pieces(t, piece, order)
        out = np.empty((order + 1, t.size))
        first, last = int(piece.min()), int(piece.max())
        if first == last:  # one piece (a block of sorted targets, mostly)
            self._eval_piece(t, first, order, list(out), work)
            return list(out)
        for k in range(first, last + 1):
            sel = np.flatnonzero(piece == k)
            if sel.size:
                part = np.empty((order + 1, sel.size))
                self._eval_piece(t[sel], k, order, list(part), work)
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

    def evaluate(self, t: ArrayLike) -> CurveValues:
        """S, V, A, J, Q at the times t (a table's columns)."""
        t_arr = np.asarray(t, dtype=np.float64)
        s, v, a, j = self.derivatives(t_arr, 3)
        q_raw = a * v
        am = self.characteristics.am
        q = q_raw / am if am > 0 else np.zeros_like(q_raw)
        return CurveValues(t=t_arr, s=s, v=v, a=a, j=j, q=q, q_raw=q_raw)

    def sample_times(self, samples: int) -> FloatArray:
        """``samples`` evenly spaced times over [T0, T7], both ends included."""
        return np.linspace(self.t_start, self.t_end, samples)

    def table(self, samples: int) -> CurveValues:
        return self.evaluate(self.sample_times(samples))

    # ---------------------------------------------------------------- extrema
    def critical_points(
        self, slopes: Callable[[list[FloatArray]], FloatArray]
    ) -> tuple[FloatArray, NDArray[np.intp]]:
        """Times, with their pieces, where functions of the motion may peak over [T0, T7].

        ``slopes`` maps [S, V, A, J, dJ/dT] at some times to the rows (one per function) of
        the functions' derivatives with respect to T. The candidates are each piece's two
        ends (one-sided limits) and every interior root of every row, bracketed on a grid
        of all pieces at once and refined by bisection to machine precision. Evaluating a
        function at these times with the returned pieces gives its exact extremes.
        """
        starts = self.piece_starts
        ends = np.append(starts[1:], self.t_end)
        n = self.n_pieces
        # fewer grid points per piece when there are many small pieces (splines of many
        # points: cubic pieces whose derivatives have at most a few roots)
        per_piece = int(np.clip(2**18 // max(n, 1), 17, _BRACKET_SAMPLES))
        frac = np.linspace(0.0, 1.0, per_piece)
        grid = starts[:, None] + (ends - starts)[:, None] * frac[None, :]
        kk = np.repeat(np.arange(n, dtype=np.intp), per_piece)

        def rows(t: FloatArray, piece: NDArray[np.intp]) -> FloatArray:
            return np.atleast_2d(np.asarray(slopes(self._eval_pieces(t, piece, 4)), dtype=np.float64))

        derivs = rows(grid.reshape(-1), kk)
        derivs = derivs.reshape(derivs.shape[0], n, per_piece)
        times = [starts, ends]
        pieces = [np.arange(n, dtype=np.intp), np.arange(n, dtype=np.intp)]
        for q, d in enumerate(derivs):
            sign = np.sign(d)
            k_idx, i_idx = np.nonzero(sign[:, :-1] * sign[:, 1:] < 0)
            if k_idx.size:
                lo, hi = grid[k_idx, i_idx].copy(), grid[k_idx, i_idx + 1].copy()
                f_lo, f_hi = d[k_idx, i_idx].copy(), d[k_idx, i_idx + 1].copy()
                _refine_roots(lambda t, k, row=q: rows(t, k)[row], lo, hi, f_lo, f_hi, k_idx)
                times.append(0.5 * (lo + hi))
                pieces.append(k_idx)
            zk, zi = np.nonzero(d == 0.0)
            if zk.size and zk.size < d.size:
                times.append(grid[zk, zi])
                pieces.append(zk)
        return np.concatenate(times), np.concatenate(pieces)

    def _extremum_candidates(self) -> tuple[FloatArray, FloatArray]:
        """Candidate times and values (rows S, V, A, J, A·V) of the characteristic extrema."""
        t_all, k_all = self.critical_points(
            lambda d: np.vstack([d[1], d[2], d[3], d[4], d[3] * d[1] + d[2] * d[2]])
        )
        s_, v, acc, j = self._eval_pieces(t_all, k_all, 3)
        return t_all, np.vstack([s_, v, acc, j, acc * v])

    @cached_property
    def characteristics(self) -> Characteristics:
        """Exact characteristic values over [T0, T7] (section-wise extrema)."""
        t_all, v_all = self._extremum_candidates()
        # ties: the earliest T wins (np.argmax/argmin return the first occurrence)
        order = np.argsort(t_all, kind="stable")
        t_all = t_all[order]
        v_all = v_all[:, order]

        def ext(row: int, use_max: bool) -> Extremum:
            data = v_all[row]
            i = int(np.argmax(data) if use_max else np.argmin(data))
            return Extremum(float(data[i]), float(t_all[i]))

        v_max, v_min = ext(1, True), ext(1, False)
        vm = v_max if abs(v_max.value) >= abs(v_min.value) else v_min
        am_pos, am_neg = ext(2, True), ext(2, False)
        am = max(abs(am_pos.value), abs(am_neg.value))
        # the T of the largest |A|; the earlier of the two peaks when they tie, and they tie
        # within a few ulps: Amp and Amm solved from eq. (11) differ by an ulp or two where
        # the law makes them equal (m = 1: TR's Amp is 1 ulp below its Amm)
        t_am = min(x.t for x in (am_pos, am_neg) if am - abs(x.value) <= 4 * float(np.spacing(am)))
        q_pos, q_neg = ext(4, True), ext(4, False)
        scale = 1.0 / am if am > 0 else 0.0
        return Characteristics(
            vm=Extremum(abs(vm.value), vm.t),
            v_max=v_max,
            v_min=v_min,
            am=am,
            am_abs=Extremum(am, t_am),
            am_pos=am_pos,
            am_neg=am_neg,
            jm_pos=ext(3, True),
            jm_neg=ext(3, False),
            qm_pos=Extremum(q_pos.value * scale, q_pos.t),
            qm_neg=Extremum(q_neg.value * scale, q_neg.t),
            qm_raw_pos=q_pos,
            qm_raw_neg=q_neg,
            s_max=ext(0, True),
            s_min=ext(0, False),
        )

    # ---------------------------------------------------------------- inverse
    @cached_property
    def monotone_direction(self) -> int:
        """+1 if S never decreases over [T0, T7], -1 if it never increases, 0 otherwise."""
        ch = self.characteristics
        # V may dip below zero by rounding at a dwell end; 1e-12 of the peak is rounding.
        slack = 1e-12 * max(ch.vm.value, 1.0)
        if self.s_end >= self.s_start and ch.v_min.value >= -slack:
            return 1
        if self.s_end <= self.s_start and ch.v_max.value <= slack:
            return -1
        return 0

    def _require_monotone(self) -> int:
        direction = self.monotone_direction
        if direction == 0 or self.s_end == self.s_start:
            raise NonMonotoneError(
                "This curve's displacement S is not monotone over its stroke, so S does "
                "not determine T; an inverse lookup needs a curve that only rises or only falls."
            )
        return direction

    def _stroke_tolerance(self) -> float:
        # S(T7) is summed section by section and may miss the nominal end by an ulp or two;
        # a target within a few ulps of an end is that end
        return 8 * float(np.spacing(max(abs(self.s_start), abs(self.s_end), 1.0)))

    def _check_stroke(self, s: FloatArray) -> FloatArray:
        """Validate targets against the stroke; return them clamped onto [S0, S7]."""
        self._validate_stroke(s)
        return self._clamp_to_stroke(s)

    def _validate_stroke(self, s: FloatArray) -> None:
        """Raise StrokeRangeError, naming the first offender, if any s is off the stroke."""
        lo, hi = sorted((self.s_start, self.s_end))
        tol = self._stroke_tolerance()
        if s.size and not (lo - tol <= s.min() and s.max() <= hi + tol):  # NaN fails both
            bad = ~np.isfinite(s) | (s < lo - tol) | (s > hi + tol)
            i = int(np.nonzero(bad)[0][0])
            raise StrokeRangeError(
                f"s[{i}] = {float(s.reshape(-1)[i])!r} is outside the stroke of this curve, "
                f"which runs from S = {self.s_start!r} to S = {self.s_end!r}.",
                field=("s", i),
            )

    def _clamp_to_stroke(self, s: FloatArray) -> FloatArray:
        """Validated targets onto [S0, S7]; a target within rounding of an end is that end.

        Returns s itself when no target is near an end (two reductions, no copy).
        """
        lo, hi = sorted((self.s_start, self.s_end))
        tol = self._stroke_tolerance()
        if s.size == 0 or (s.min() > lo + tol and s.max() < hi - tol):
            return s
        clamped = np.clip(s, lo, hi)
        for end in (self.s_start, self.s_end):
            near = np.abs(s - end) <= tol
            if near.any():
                clamped[near] = end
        return clamped

    @cached_property
    def _inverse_nodes(self) -> tuple[FloatArray, FloatArray]:
        """Times and S at the break points and a fine grid: brackets for the inverse."""
        grid = np.linspace(self.t_start, self.t_end, 1025)
        t_nodes = np.unique(np.concatenate([grid, self.break_points]))
        s_nodes = self.derivatives(t_nodes, 0)[0]
        return t_nodes, s_nodes

    def _inverse_bracketed(self, target: FloatArray, direction: int) -> FloatArray:
        """First T with S(T) = target (validated, flat), by searching the node table.

        Robust and slow (a binary search per target): used to build :attr:`_inverse_grid`.
        """
        t_nodes, s_nodes = self._inverse_nodes
        key = s_nodes * direction
        goal = target * direction
        # first node whose S reaches the target: bracket (node-1, node]
        k = np.searchsorted(key, goal, side="left")
        k = np.clip(k, 1, len(t_nodes) - 1)
        lo = t_nodes[k - 1].copy()
        hi = t_nodes[k].copy()
        f_lo = key[k - 1] - goal
        f_hi = key[k] - goal
        exact_lo = f_lo >= 0  # target at or below the bracket start: the start is the answer
        span = np.where(f_hi > f_lo, f_hi - f_lo, 1.0)
        t = np.where(exact_lo, lo, lo + (hi - lo) * np.clip(-f_lo / span, 0.0, 1.0))
        active = ~exact_lo & (f_hi != 0)
        t = np.where(f_hi == 0, np.where(exact_lo, lo, hi), t)
        for _ in range(100):
            if not active.any():
                break
            ia = np.nonzero(active)[0]
            ta = t[ia]
            sv = self.derivatives(ta, 1)
            f = sv[0] * direction - goal[ia]
            dfdt = sv[1] * direction
            done = f == 0
            # shrink the bracket around the root
            lo_a = np.where(f < 0, ta, lo[ia])
            hi_a = np.where(f > 0, ta, hi[ia])
            with np.errstate(divide="ignore", invalid="ignore"):
                newton = ta - f / dfdt
            ok = np.isfinite(newton) & (newton > lo_a) & (newton < hi_a)
            t_new = np.where(ok, newton, 0.5 * (lo_a + hi_a))
            step = np.abs(t_new - ta)
            tiny = 4 * np.spacing(np.maximum(np.abs(ta), 1.0))
            done |= (step <= tiny) | (hi_a - lo_a <= tiny)
            t[ia] = np.where(f == 0, ta, t_new)
            lo[ia] = lo_a
            hi[ia] = hi_a
            active[ia[done]] = False
        return t

    @cached_property
    def _inverse_grid(self) -> InverseGrid:
        """The inverse's start table (built once per curve with the robust solver; cached)."""
        from .inverse import build_grid  # camcore.inverse imports this module

        return build_grid(self, self._require_monotone())

    @property
    def inverse_ready(self) -> bool:
        """Whether :meth:`inverse` has its start table (the first call on a curve builds
        it, a few milliseconds; every later call only solves)."""
        return "_inverse_grid" in self.__dict__

    def inverse(self, s: ArrayLike) -> FloatArray:
        """Exact inverse: for each displacement s, the first T in [T0, T7] with S(T) = s.

        Vectorised safeguarded Newton iteration on the closed form, started from a
        table of T at 4096 evenly spaced S levels (see :mod:`camcore.inverse`); it stops
        when the residual is at the rounding level of S, or when the Newton step, its
        predicted error |A/2V|·δ², or the bracket reach the spacing of floating-point
        numbers. Raises :class:`NonMonotoneError` for a curve that is not monotone and
        :class:`StrokeRangeError` for s outside the stroke.
        """
        from .inverse import solve  # here, not at the top: camcore.inverse imports this module

        self._require_monotone()
        s_arr = np.asarray(s, dtype=np.float64)
        flat = s_arr.reshape(-1)
        self._validate_stroke(flat)
        return solve(self, self._inverse_grid, flat).reshape(s_arr.shape)

    def inverse_table(self, s: ArrayLike, step: float, decimals: int | None = None) -> CurveValues:
        """The catalog's method: proportional interpolation between rows of a table.

        Builds the table T = T0, T0 + step, …, T7 (the last row at T7), optionally
        rounded to ``decimals`` as printed in a catalog, finds the rows whose S bracket
        each s and interpolates T, V and A linearly between them.

        References
        ----------
        INDEXMAN technical guide, worked example before the characteristic-value table:
        S = 0.1833 between rows T = 0.30 and 0.31 of the MS table gives T = 0.304,
        V = 1.339.
        """
        direction = self._require_monotone()
        s_arr = np.asarray(s, dtype=np.float64)
        target = self._check_stroke(s_arr.reshape(-1))
        n = int(np.floor((self.t_end - self.t_start) / step + 1e-9))
        t_rows = self.t_start + step * np.arange(n + 1)
        if t_rows[-1] < self.t_end - 1e-12 * step:
            t_rows = np.append(t_rows, self.t_end)
        else:
            t_rows[-1] = self.t_end
        rows = self.evaluate(t_rows)
        cols = [rows.t, rows.s, rows.v, rows.a, rows.j, rows.q, rows.q_raw]
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


def _refine_roots(f: Callable[[FloatArray, NDArray[np.intp]], FloatArray], lo: FloatArray, hi: FloatArray,
                  f_lo: FloatArray, f_hi: FloatArray, piece: NDArray[np.intp]) -> None:
    """Shrink brackets [lo, hi] (f changes sign inside) around the roots of f, in place.

    Illinois regula falsi: the chord's zero, and the value kept at an end that stays put
    twice is halved so both ends move in. Each trial point keeps 2 ulp from both ends, so
    once one lies that close to the root the next lands on its far side and the bracket
    closes. A bracket stops at a root (f = 0) or at 4 ulp
    wide: about 10 evaluations from a 1/256-wide cell, where bisection needs 45.
    """
    active = np.arange(lo.size)
    kept = np.zeros(lo.size, dtype=np.int8)  # +1: lo moved last time, −1: hi moved last time
    for _ in range(200):
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
