"""Curves derived from other curves: Makino's symmetrical return stroke.

References
----------
H. Makino, "Universal Cam Curve and Its Application" (1977), subroutine CURVE,
lines 147-151 and 223-226 (INIT = 2): T → T0 + T7 − T, V and J change sign.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .base import FloatArray
from .curve import Curve


class ReturnCurve(Curve):
    """The return stroke of a rise: the rise played backwards in time.

    S_ret(T) = S(T0 + T7 − T), V_ret = −V(…), A_ret = A(…), J_ret = −J(…). For a
    standard rise (S: 0 → 1) the return falls from 1 to 0; the drop from the top,
    1 − S_ret(T) = 1 − S(1 − T), is the mirrored rise. At a break point the return
    takes the piece that starts there in its own time (the same right-limit rule as
    every table).
    """

    def __init__(self, rise: Curve):
        self.rise = rise
        ends = rise.break_points
        mirror = ends[0] + ends[-1]
        self._mirror = float(mirror)
        # piece k of the return is piece n-1-k of the rise
        self.piece_starts = np.sort(mirror - ends[1:])
        self.piece_starts[0] = ends[0]
        self.t_end = float(ends[-1])
        self.scale = getattr(rise, "scale", None)
        self.has_point_formulas = rise.has_point_formulas

    def eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        vals = self.rise.eval_pieces(self._mirror - t, self.rise.n_pieces - 1 - piece, order)
        # 0 − x, not −x: a rise at rest (V = +0) gives a return at rest, not at −0
        return [v if i % 2 == 0 else 0.0 - v for i, v in enumerate(vals)]

    def eval_point(self, t: float, k: int) -> list[float]:
        # the rise's scalar formulas at the same mirrored time and piece as eval_pieces: the same bits
        vals = self.rise.eval_point(self._mirror - t, self.rise.n_pieces - 1 - k)
        return [v if i % 2 == 0 else 0.0 - v for i, v in enumerate(vals)]
