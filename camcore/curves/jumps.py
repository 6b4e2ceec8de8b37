"""Where a curve's acceleration jumps: its jerk is unbounded there, so a finite ``jm`` is not
the whole story (constant acceleration, simple harmonic, the trapezoid's corners).

References
----------
.. [1] Makino (1977), section 2: the curves are joined at their break points with continuous
   S and V; A is continuous only where the law makes it so.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..results import doc
from .base import PiecewiseCurve

#: a jump smaller than this fraction of max(1, Am) is rounding, not a jump
JUMP_TOLERANCE = 1e-9


@dataclass(frozen=True)
class AccelerationJump:
    """A jump of the acceleration at T: its value just before and just after."""

    t: float = field(metadata=doc("T of the jump"))
    before: float = field(metadata=doc("A just before T (0 before T0: the dwell)"))
    after: float = field(metadata=doc("A just after T (0 after T7: the dwell)"))


def acceleration_jumps(curve: PiecewiseCurve, am: float) -> tuple[AccelerationJump, ...]:
    """The acceleration's jumps: at the curve's pieces' joins, and at T0 and T7 against the dwells
    before and after (A = 0 there).

    Parameters
    ----------
    curve : PiecewiseCurve
        The curve.
    am : float
        Its largest |A| (the scale of a jump worth reporting) [-].

    Returns
    -------
    tuple of AccelerationJump
        In order of T; a jump is reported where |after − before| > 1e-9·max(1, Am) [-].

    References
    ----------
    Makino (1977), section 2 (continuity at the break points).
    """
    starts = curve.piece_starts
    n = curve.n_pieces
    at = np.append(starts, curve.t_end)
    # one-sided limits: piece k−1 at its end, piece k at its start (the dwells outside give 0)
    left_pieces, right_pieces = np.arange(-1, n), np.arange(0, n + 1)
    inside_left, inside_right = left_pieces >= 0, right_pieces < n
    before = np.zeros(at.size)
    after = np.zeros(at.size)
    # both sides in one evaluation: n pieces' ends, then their starts
    sides = curve.eval_pieces(np.concatenate([at[inside_left], at[inside_right]]),
                              np.concatenate([left_pieces[inside_left], right_pieces[inside_right]]), 2)[2]
    before[inside_left], after[inside_right] = sides[:n], sides[n:]
    jump = np.abs(after - before) > JUMP_TOLERANCE * max(1.0, am)
    return tuple(AccelerationJump(float(t), float(b), float(a)) for t, b, a in zip(at[jump], before[jump], after[jump]))
