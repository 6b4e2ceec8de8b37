"""A lift schedule's segments evaluated together: every section of every segment's curve in one
coefficient table, so the lift at many cam angles is one gather and one pass of the section
formulas, whatever the number of segments.

Each step is the one :meth:`camcore.profile.lift.LiftSchedule.derivatives` takes segment by
segment, in the same order on the same numbers (the segment's T from the angle, the section
from T by the curve's right-limit rule, a return's mirrored time and signs, the chain rule's
factors), only with each segment's constants gathered per angle: the same values to the bit
(tests/camcore/profile/test_lift_stack.py compares them over every kind of segment). Per call
this costs one set of array operations where segment by segment cost one per segment and curve;
the toolpath, the barrel cam and the dynamics ask for a few dozen to a few hundred angles at a
time, dozens of times per request.

References
----------
.. [1] Makino (1977), eqs. (1)-(9) (the section formulas) and subroutine CURVE, INIT = 2 (a
   return plays the rise backwards: T → T0 + T7 − T, V and J change sign).
.. [2] Bezier valve-cam notes, eq. (12) (the chain rule over the cam angle).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ..curves.base import FloatArray
from ..curves.curve import Curve
from ..curves.reverse import ReturnCurve
from ..curves.sections import SectionCurve, eval_sections


class _Segment(Protocol):
    """A schedule's segment as :class:`camcore.profile.lift.LiftSchedule` keeps it."""

    @property
    def start(self) -> float: ...
    @property
    def span(self) -> float: ...
    @property
    def level(self) -> float: ...
    @property
    def amount(self) -> float: ...
    @property
    def curve(self) -> Curve | None: ...
    @property
    def s0(self) -> float: ...
    @property
    def s1(self) -> float: ...


#: the rows of :attr:`StackedLift.constants`: a column's segment, in the order the steps use them
ROWS = ("start", "span", "t_start", "t_span", "mirror", "level", "s0", "column", "dwell", "back",
        "f0", "f1", "f2", "f3", "f4")
#: the highest derivative the section formulas give (dJ/dT)
MOST_ORDER = 4
#: float steps from a bound's estimated angle to its exact one, at most: it takes 0-2 (2 000 random
#: schedules, spans from 1e-6° to 360°); past this the schedule is evaluated segment by segment, so
#: a schedule of many segments cannot make the stack costly to build
MOST_STEPS = 64


class StackedLift:
    """A schedule's pieces as columns over the cam angle, with each column's constants.

    Column c holds the angles from ``thresholds[c]`` to the next: one section of one segment's
    curve (or a dwell), found with one ``np.searchsorted`` of the angles. The thresholds are exact:
    the segment's time T(θ) = T0 + (T7 − T0)·min(max((θ − θa)/β, 0), 1) rises with θ in floating
    point too (each operation is monotonic), so a bound of the curve's pieces is passed at one float
    angle, found by stepping from its estimate; the angle's section is then the one the curve's own
    ``np.searchsorted`` of T gives.

    Parameters
    ----------
    segments : sequence
        The schedule's segments in order (start [rad], span [rad], level, amount, curve or None
        for a dwell, S0, S7 of the curve), as :class:`camcore.profile.lift.LiftSchedule` keeps them;
        every curve a section curve or its return (:meth:`of`).
    starts : ndarray
        The segments' starts [rad] (the first is 0).
    """

    def __init__(self, segments: Sequence[_Segment], starts: FloatArray):
        sections = [_sections(s.curve) for s in segments]
        used = [x for x in sections if x is not None]
        self.coefficients = np.concatenate([x.coefficients for x in used], axis=1)
        ends = [*starts[1:].tolist(), math.inf]
        thresholds: list[float] = []
        columns: list[list[float]] = []
        self.exact = True
        offset = 0
        for k, (s, x) in enumerate(zip(segments, sections)):
            base = [s.start, s.span, 0.0, 0.0, 0.0, s.level, s.s0, -1.0, 1.0, 0.0] + [0.0] * (MOST_ORDER + 1)
            if s.curve is None or x is None:
                thresholds.append(float(starts[k]))
                columns.append(base)
                continue
            c = s.curve
            back = isinstance(c, ReturnCurve)
            mirror = c._mirror if isinstance(c, ReturnCurve) else 0.0
            gain, rate = s.amount / (s.s1 - s.s0), (c.t_end - c.t_start) / s.span
            factors = [gain, *(gain * rate**o for o in range(1, MOST_ORDER + 1))]
            bounds = c._piece_index_bounds.tolist()
            for j in range(len(bounds)):
                at = float(starts[k]) if j == 0 else self._passed(s.start, s.span, c.t_start, c.t_end - c.t_start,
                                                                   bounds[j])
                if at >= ends[k]:
                    break
                piece = x.n_pieces - 1 - j if back else j
                # past the last bound: T beyond T7 (Makino's section VIII), left to the segment's own curve
                column = float(offset + piece) if j < x.n_pieces else -2.0
                thresholds.append(at)
                columns.append([s.start, s.span, c.t_start, c.t_end - c.t_start, mirror,
                                s.level, s.s0, column, 0.0, float(back), *factors])
            offset += x.n_pieces
        thresholds.append(math.inf)  # a NaN angle sorts past every float: left to the segments one by one
        columns.append([0.0] * 7 + [-2.0] + [0.0] * (len(ROWS) - 8))
        self.thresholds = np.array(thresholds)
        self.constants = np.array(columns).T
        self.back = bool(self.constants[ROWS.index("back")].any())

    def _passed(self, start: float, span: float, t_start: float, t_span: float, bound: float) -> float:
        """The least float angle whose T is at least ``bound`` (monotonic in θ: step from the estimate)."""
        def time(theta: float) -> float:
            return t_start + t_span * min(max((theta - start) / span, 0.0), 1.0)

        if time(math.inf) < bound:  # T stops at T0 + (T7 − T0) at the segment's end, short of the bound
            return math.inf
        theta = start + span * (bound - t_start) / t_span
        for _ in range(MOST_STEPS):
            if time(theta) < bound:
                theta = math.nextafter(theta, math.inf)
            elif time(math.nextafter(theta, -math.inf)) >= bound:
                theta = math.nextafter(theta, -math.inf)
            else:
                return theta
        self.exact = False
        return theta

    @classmethod
    def of(cls, segments: Sequence[_Segment], starts: FloatArray) -> StackedLift | None:
        """The stack of a schedule whose curves are all section curves or their returns (None otherwise).

        Parameters
        ----------
        segments : sequence
            As the constructor's.
        starts : ndarray
            The segments' starts [rad].

        Returns
        -------
        StackedLift or None
            The stack; None when a curve has other formulas, no segment has a curve, or a bound
            was not pinned to its float angle.

        References
        ----------
        Makino (1977), eqs. (1)-(9).
        """
        sections = [_sections(s.curve) for s in segments]
        if any(x is None and s.curve is not None for x, s in zip(sections, segments)):
            return None
        if all(x is None for x in sections):
            return None
        stack = cls(segments, starts)
        return stack if stack.exact else None

    def derivatives(self, flat: FloatArray, order: int) -> list[FloatArray] | None:
        """[h, dh/dθ, …][: order + 1] at angles in [0, 2π), or None where an angle's time falls past its
        curve or is NaN (there segment by segment, which fills Makino's sections 0 and VIII).

        Parameters
        ----------
        flat : ndarray
            Cam angles reduced to [0, 2π), one dimension [rad].
        order : int
            Highest derivative (0..4) [-].

        Returns
        -------
        list of ndarray or None
            The lift [lift unit] and its derivatives [lift unit/radᵏ].

        References
        ----------
        Makino (1977), eqs. (1)-(9); Bezier valve-cam notes, eq. (12).
        """
        where = np.searchsorted(self.thresholds, flat, side="right") - 1
        # the constants of the columns, the factors only as far as the order (a row costs a gather)
        start, span, t_start, t_span, mirror, level, s0, column, dwell, back, *factor = self.constants[
            : len(ROWS) - MOST_ORDER + order].take(where, axis=1)
        if bool((column < -1.0).any()):
            return None
        live: NDArray[np.intp] | None = None
        if bool(dwell.any()):
            out = list(np.zeros((order + 1, flat.size)))
            on = dwell > 0.0
            out[0][on] = level[on]
            live = np.flatnonzero(~on)
            if not live.size:
                return out
            flat, start, span, t_start, t_span, mirror, level, s0, column, back = (
                v[live] for v in (flat, start, span, t_start, t_span, mirror, level, s0, column, back))
            factor = [f[live] for f in factor]
        u = np.minimum(np.maximum((flat - start) / span, 0.0), 1.0)
        t = t_start + t_span * u
        turned = back > 0.0 if self.back else None
        if turned is not None:  # a return: its rise at the mirrored time (the column counts from its end)
            t = np.where(turned, mirror - t, t)
        values = eval_sections(self.coefficients, t, column.astype(np.intp), order)
        found = [level + factor[0] * (values[0] - s0)]
        for o in range(1, order + 1):
            v = values[o]
            if turned is not None and o % 2 == 1:
                v = np.where(turned, 0.0 - v, v)  # 0 − x, as a return turns V and J: a rest stays +0
            found.append(factor[o] * v)
        if live is None:
            return found
        for target, value in zip(out, found):
            target[live] = value
        return out


def _sections(curve: Curve | None) -> SectionCurve | None:
    """The section curve a segment's curve evaluates with: itself, or the rise of a return."""
    if isinstance(curve, ReturnCurve):
        curve = curve.rise
    return curve if isinstance(curve, SectionCurve) else None
