"""A curve's acceleration as the forcing of a follower: normalised to one motion, in smooth cells.

The response of a follower (camcore.dynamics._response) is driven by the curve's
acceleration over one motion. Curves whose T does not run over 0..1 or whose S does not
run from 0 to 1 are normalised as :mod:`camcore.indexer.kinematics` does: u = (T − T0)/ΔT,
S' = (S − S0)/ΔS, so that A' = A·ΔT²/ΔS and V' = V·ΔT/ΔS. Where V' jumps at a break point
(a curve made of pieces that meet with a kink), the acceleration holds a Dirac impulse of
the jump's size there; before T0 and after T7 a curve continues at constant velocity
(Makino's sections 0 and VIII), so its ends hold none.

Each smooth piece is cut into *cells* on which A' is a polynomial of degree 16 to rounding:
the Chebyshev coefficients of its interpolant at 17 Chebyshev–Lobatto points fall below
:data:`RESOLVED` times the largest |A'| in their last three places (cells are halved until
they do). A polynomial law is one cell, a sine segment over a quarter wave one or two, a
spline piece one.

References
----------
.. [1] INDEXMAN technical guide, section 5 (s = h·S, a = (h/th²)·A), as normalised in
   camcore.indexer.kinematics.
.. [2] L. N. Trefethen, *Approximation Theory and Approximation Practice* (SIAM, 2013),
   ch. 3 and 8 (Chebyshev coefficients of smooth functions decay geometrically; chopping
   a series where they reach rounding level).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..curves.curve import Curve
from ..deadline import checkpoint
from ..errors import InvalidParameterError
from . import _chebyshev as cheb

FloatArray = NDArray[np.float64]
IndexArray = NDArray[np.intp]

#: a cell is resolved when its last three Chebyshev coefficients are below this times max |A'|:
#: rounding in A' itself is ~1e-16 of it, so this is reached, and the acceleration left out is
#: ~1e-13 of its size (its effect on the response: module camcore.dynamics._response)
RESOLVED = 1e-13
#: ... or below this many times the rounding of A' on the cell (eps·(|A'| + |dA'/du|), the
#: value and a shift of u by eps); their sum over the cells bounds what rounding leaves out
NOISE = 64.0
#: cells narrower than this (in u) are not halved again: a piece still unresolved there has a
#: singular acceleration (a near-vertical tangent of a Bezier lift), which no cell would resolve
MIN_CELL = 2.0**-30
#: at most this many cells (a 10 000-point spline has 9 999): more means the acceleration is
#: not smooth enough to integrate
MAX_CELLS = 40_000
#: what the errors are about: the curve argument (of residual_vibration, FollowerResponse)
FIELD = ("curve",)
#: a jump of S' at a break point larger than this is a step the follower cannot follow
MAX_STEP = 1e-9


class Forcing:
    """The normalised acceleration A'(u) of a curve over u ∈ [0, 1], its smooth cells and impulses.

    Parameters
    ----------
    curve : Curve
        Any camcore curve that moves (S7 ≠ S0).

    Raises
    ------
    InvalidParameterError
        The curve does not move, its displacement jumps, or its acceleration cannot be
        resolved into smooth cells.
    """

    def __init__(self, curve: Curve):
        self.curve = curve
        self.t0 = curve.t_start
        self.d_t = curve.t_end - curve.t_start
        self.d_s = curve.s_end - curve.s_start
        if not (math.isfinite(self.d_s) and self.d_s != 0 and self.d_t > 0):
            raise InvalidParameterError("the curve must move (S at T7 different from S at T0) to excite a follower.",
                                        field=FIELD)
        self.accel_factor = self.d_t**2 / self.d_s
        bounds = (curve.break_points - self.t0) / self.d_t
        bounds[0], bounds[-1] = 0.0, 1.0
        self.piece_start = bounds[:-1]
        self.piece_end = bounds[1:]
        self.impulse_u, self.impulse = self._impulses()
        self.cell_start, self.cell_end, self.cell_piece = self._cells()

    # ---------------------------------------------------------------- evaluation
    def acceleration(self, u: FloatArray, piece: IndexArray) -> FloatArray:
        """A'(u) with the formula of the given pieces (each u on or at an end of its piece)."""
        t = self.t0 + self.d_t * u
        values: FloatArray = self.curve.eval_pieces(t, piece, 2)[2] * self.accel_factor
        return values

    def _ends(self, u: FloatArray, piece: IndexArray) -> tuple[FloatArray, FloatArray]:
        s, v = self.curve.eval_pieces(self.t0 + self.d_t * u, piece, 1)[:2]
        return s / self.d_s, v * self.d_t / self.d_s

    def _impulses(self) -> tuple[FloatArray, FloatArray]:
        """Where V' jumps between pieces, and by how much (the impulse of A' there)."""
        n = len(self.piece_start)
        if n < 2:
            return np.zeros(0), np.zeros(0)
        u = self.piece_start[1:]
        s_left, v_left = self._ends(u, np.arange(n - 1))
        s_right, v_right = self._ends(u, np.arange(1, n))
        step = np.abs(s_right - s_left)
        if step.max() > MAX_STEP:
            i = int(np.argmax(step))
            raise InvalidParameterError(
                f"the curve's displacement jumps by {float(step[i]):.3g} of its stroke at T = "
                f"{self.t0 + self.d_t * float(u[i]):.6g}: a follower cannot follow a step.", field=FIELD)
        return u, v_right - v_left

    def _cells(self) -> tuple[FloatArray, FloatArray, IndexArray]:
        """Halve each piece until A' is a degree-16 polynomial to rounding on every cell."""
        lo, hi = self.piece_start.copy(), self.piece_end.copy()
        piece = np.arange(len(lo))
        keep = hi > lo
        lo, hi, piece = lo[keep], hi[keep], piece[keep]
        done: list[tuple[FloatArray, FloatArray, IndexArray]] = []
        scale = 0.0
        while lo.size:
            checkpoint()
            if sum(d[0].size for d in done) + lo.size > MAX_CELLS:
                raise InvalidParameterError(
                    f"the curve's acceleration is not smooth enough to integrate the follower's response: "
                    f"more than {MAX_CELLS} cells would be needed.", field=FIELD)
            u = lo[:, None] + (hi - lo)[:, None] * (1.0 + cheb.RESOLVE_LOBATTO) / 2.0
            t = self.t0 + self.d_t * u.ravel()
            _s, _v, a, j = self.curve.eval_pieces(t, np.repeat(piece, cheb.RESOLVE_NODES), 3)
            values = (a * self.accel_factor).reshape(u.shape)
            slopes = np.abs(j * (self.accel_factor * self.d_t)).reshape(u.shape)
            if not (np.isfinite(values).all() and np.isfinite(slopes).all()):
                raise InvalidParameterError("the curve's acceleration is not finite everywhere on the motion.",
                                            field=FIELD)
            scale = max(scale, float(np.abs(values).max()))  # the largest |A'| seen so far
            tail = np.abs(values @ cheb.RESOLVE_COEFFICIENTS.T)[:, -3:].max(axis=1)
            # rounding: A' is known to ~eps of itself, and u to ~eps, which moves A' by eps·|dA'/du|
            noise = NOISE * np.finfo(float).eps * (np.abs(values) + slopes).max(axis=1)
            resolved = tail <= np.maximum(RESOLVED * scale, noise)
            narrow = (hi - lo) <= MIN_CELL
            if (narrow & ~resolved).any():
                i = int(np.flatnonzero(narrow & ~resolved)[0])
                raise InvalidParameterError(
                    f"the curve's acceleration is not smooth near T = {self.t0 + self.d_t * float(lo[i]):.6g} "
                    f"(a near-vertical tangent?): the follower's response cannot be integrated there.", field=FIELD)
            done.append((lo[resolved], hi[resolved], piece[resolved]))
            split = ~resolved
            mid = (lo[split] + hi[split]) / 2.0
            lo, hi, piece = (np.concatenate([lo[split], mid]), np.concatenate([mid, hi[split]]),
                             np.concatenate([piece[split], piece[split]]))
        start = np.concatenate([d[0] for d in done])
        order = np.argsort(start, kind="stable")
        return start[order], np.concatenate([d[1] for d in done])[order], np.concatenate([d[2] for d in done])[order]

    @property
    def cells(self) -> int:
        """Number of smooth cells [-]."""
        return int(self.cell_start.size)
