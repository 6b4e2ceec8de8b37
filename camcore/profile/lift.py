"""The lift over one cam turn: rise / dwell / return segments, one user curve over the
drive angle, or a motion program, with the rotation ratio between drive shaft and cam shaft.

References
----------
.. [1] Bezier valve-cam notes: rotation ratio γ = ω_cam/ω_dr, θcam = γ θdr,
   dh/dθcam = (1/γ) dh/dθdr (eq. 12).
.. [2] Makino (1977), subroutine CURVE (INIT = 2: a return plays the rise backwards).
"""

from __future__ import annotations

import math
from bisect import bisect_right
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..curves.base import FEW_POINTS, FloatArray
from ..curves.catalog import named_curve
from ..curves.curve import Curve
from ..curves.reverse import ReturnCurve
from ..errors import GeometryError, InvalidParameterError
from ..motion.program import CONTINUITY_TOLERANCE, MotionProgram
from .lift_stack import StackedLift

TWO_PI = 2.0 * math.pi
#: angles (degrees) of a lift schedule must add to 360 within this tolerance
ANGLE_TOLERANCE_DEG = 1e-9
#: a schedule "closes" when its final level equals its initial level within this (mm or deg)
CLOSURE_TOLERANCE = 1e-9
#: angles a schedule evaluates in one pass of its stacked segments, at most: beyond, segment by
#: segment, whose curves take a sorted table piece by piece; one pass's gathered coefficients
#: (19 rows) cost more from ~1700 angles on (measured on the README cam: 122 against 140 µs at 1600,
#: 293 against 152 µs at 2000)
STACKED_MOST = 1536
#: angles from which a call tests whether they already lie in [0, 2π) before reducing them (the test,
#: two passes and two reductions, costs more than np.mod's one pass on fewer)
MOD_TEST_LEAST = 256


# ============================================================================ lift
class Lift(Protocol):
    """Anything that gives the lift and its derivatives over the cam angle.

    ``derivatives(theta, order)`` returns [h, dh/dθ, d²h/dθ², d³h/dθ³][: order + 1]
    at cam angles θ (radians, any real value: the lift is periodic over 2π), in the
    lift's unit (mm, or degrees of swing for oscillating followers) per radian^k.
    ``breaks_rad`` lists cam angles in [0, 2π) where a derivative may jump.
    """

    unit: str

    def derivatives(self, theta: ArrayLike, order: int = 2) -> list[FloatArray]: ...

    @property
    def breaks_rad(self) -> FloatArray: ...


@dataclass(frozen=True)
class Segment:
    """One stretch of a lift schedule.

    type: ``"rise"``, ``"dwell"`` or ``"return"``; ``angle_deg``: its cam angle;
    ``lift_mm`` (translating followers) or ``swing_deg`` (oscillating): the rise or the
    drop; ``curve``: the motion law of a rise (a return plays it backwards with
    :class:`ReturnCurve`; pass a curve that rises, S: S0 → S7). ``None`` = cycloid.
    """

    type: Literal["rise", "dwell", "return"]
    angle_deg: float
    lift_mm: float = 0.0
    curve: Curve | None = None
    swing_deg: float | None = None

    @property
    def amount(self) -> float:
        return float(self.swing_deg if self.swing_deg is not None else self.lift_mm)


@dataclass(frozen=True)
class _Piece:
    start: float  # rad
    span: float  # rad
    level: float  # lift at the start of the segment
    amount: float  # signed change over the segment
    curve: Curve | None  # None: dwell
    s0: float
    s1: float


class LiftSchedule:
    """Lift over one cam turn from rise / dwell / return segments (angles add to 360°).

    Rise: h = level + lift·(S(T) − S0)/(S7 − S0); return: h = level − lift·(…) with the
    :class:`ReturnCurve` of the segment's curve; T = T0 + (T7 − T0)·(θ − θa)/β. By the
    chain rule dᵏh/dθᵏ = ±lift/(S7 − S0)·((T7 − T0)/β)ᵏ·dᵏS/dTᵏ (β in radians).
    """

    def __init__(self, segments: Sequence[Segment], initial: float = 0.0, unit: str = "mm"):
        if not segments:
            raise InvalidParameterError("A lift schedule needs at least one segment.", field=("segments",))
        total = 0.0
        for i, seg in enumerate(segments):
            if seg.type not in ("rise", "dwell", "return"):
                raise InvalidParameterError(
                    f"segments[{i}]: type must be 'rise', 'dwell' or 'return', not {seg.type!r}.", field=("segments", i))
            if not (math.isfinite(seg.angle_deg) and seg.angle_deg > 0):
                raise InvalidParameterError(f"segments[{i}]: angle_deg must be a positive number of degrees.",
                                            field=("segments", i, "angle_deg"))
            if seg.type != "dwell" and not (math.isfinite(seg.amount) and seg.amount >= 0):
                raise InvalidParameterError(
                    f"segments[{i}]: the {seg.type} must be a finite, non-negative lift (it is {seg.amount!r}).",
                    field=("segments", i))
            total += seg.angle_deg
        if abs(total - 360.0) > ANGLE_TOLERANCE_DEG:
            raise InvalidParameterError(
                f"The segment angles add to {total!r}°; they must add to 360° (one cam turn).", field=("segments",))
        pieces: list[_Piece] = []
        level = float(initial)
        start = 0.0
        for i, seg in enumerate(segments):
            span = math.radians(seg.angle_deg)
            if seg.type == "dwell":
                pieces.append(_Piece(start, span, level, 0.0, None, 0.0, 1.0))
            else:
                rise = seg.curve if seg.curve is not None else named_curve("cycloid")
                curve = rise if seg.type == "rise" else ReturnCurve(rise)
                s0, s1 = curve.s_start, curve.s_end
                if s1 == s0 or (seg.type == "rise") != (s1 > s0):
                    raise InvalidParameterError(
                        f"segments[{i}]: the curve of a {seg.type} must run from S0 to a different S7 "
                        "(give the rising curve; a return plays it backwards).", field=("segments", i, "curve"))
                amount = seg.amount if seg.type == "rise" else -seg.amount
                pieces.append(_Piece(start, span, level, amount, curve, s0, s1))
                level += amount
                if level < -CLOSURE_TOLERANCE:
                    raise GeometryError(
                        f"segments[{i}]: the return drops the follower {-level!r} below the base circle.",
                        field=("segments", i))
            start += span
        if abs(level - initial) > CLOSURE_TOLERANCE * max(1.0, abs(initial)):
            raise InvalidParameterError(
                f"The schedule does not close: it ends at {level!r} {unit} but starts at {initial!r} {unit}; "
                "the rises must equal the returns over one turn.", field=("segments",))
        self.segments = tuple(segments)
        self.unit = unit
        self.initial = float(initial)
        self._pieces = pieces
        self._starts = np.array([p.start for p in pieces])
        self._starts_list = [p.start for p in pieces]
        br: list[float] = []
        for p in pieces:
            br.append(p.start)
            if p.curve is not None:
                t0, t7 = p.curve.t_start, p.curve.t_end
                br.extend(p.start + p.span * (np.asarray(p.curve.break_points) - t0) / (t7 - t0))
        self._breaks = np.unique(np.mod(np.asarray(br, dtype=np.float64), TWO_PI))

    @property
    def breaks_rad(self) -> FloatArray:
        return self._breaks

    @cached_property
    def _stack(self) -> StackedLift | None:
        return StackedLift.of(self._pieces, self._starts)

    def derivatives(self, theta: ArrayLike, order: int = 2) -> list[FloatArray]:
        th = np.asarray(theta, dtype=np.float64)
        flat = th.reshape(-1)
        # np.mod costs ~10 ns an angle: a long array already in [+0, 2π) (a grid's, a fit's) is its own
        # remainder (fmod is exact there; −0 and NaN fail the test and are reduced)
        if flat.size < MOD_TEST_LEAST or not (bool((flat < TWO_PI).all()) and not bool(np.signbit(flat).any())):
            flat = np.mod(flat, TWO_PI)
        if FEW_POINTS < flat.size <= STACKED_MOST and self._stack is not None:  # one pass (lift_stack)
            stacked = self._stack.derivatives(flat, order)
            if stacked is not None:
                return [o.reshape(th.shape) for o in stacked]
        out = list(np.zeros((order + 1, flat.size)))
        # np.minimum/np.maximum, not np.clip: the same numbers without its Python wrappers (the solvers
        # ask for one to a few hundred angles at a time, hundreds of times per request)
        for k, sel in self._on_pieces(flat):
            p = self._pieces[k]
            if p.curve is None:
                out[0][sel] = p.level
                continue
            c = p.curve
            rate = (c.t_end - c.t_start) / p.span
            u = np.minimum(np.maximum((flat[sel] - p.start) / p.span, 0.0), 1.0)
            vals = c.derivatives(c.t_start + (c.t_end - c.t_start) * u, order)
            gain = p.amount / (p.s1 - p.s0)
            out[0][sel] = p.level + gain * (vals[0] - p.s0)
            for o in range(1, order + 1):
                out[o][sel] = gain * rate**o * vals[o]
        return [o.reshape(th.shape) for o in out]

    def _on_pieces(self, flat: FloatArray) -> list[tuple[int, slice | NDArray[np.intp] | NDArray[np.bool_]]]:
        """Each piece some of the angles (in [0, 2π)) lie on, and which: every one (``slice(None)``),
        a run of sorted angles (a slice), or an index or a mask, in the angles' order either way.

        Piece k holds [start_k, start_k+1) (np.searchsorted(starts, θ, "right") − 1; the first piece
        starts at 0, so every angle has one; NaN: the last). A few angles are placed by bisection and
        sorted ones by slices: the same angles as the masks', without their arrays' fixed cost.
        """
        n = flat.size
        if n <= FEW_POINTS:
            ks = [bisect_right(self._starts_list, f) - 1 for f in flat.tolist()]
            if not ks:
                return []
            if min(ks) == max(ks):
                return [(ks[0], slice(None))]
            return [(k, np.array([i for i, on in enumerate(ks) if on == k], dtype=np.intp)) for k in sorted(set(ks))]
        if bool(np.all(flat[1:] >= flat[:-1])):  # a table's angles (no NaN)
            bounds = [*np.searchsorted(flat, self._starts, side="left").tolist(), n]
            runs = [(k, bounds[k], bounds[k + 1]) for k in range(len(self._pieces)) if bounds[k + 1] > bounds[k]]
            if len(runs) == 1:
                return [(runs[0][0], slice(None))]
            return [(k, slice(lo, hi)) for k, lo, hi in runs]
        idx = np.searchsorted(self._starts, flat, side="right") - 1
        first, last = int(idx.min()), int(idx.max())
        if first == last:
            return [(first, slice(None))]
        masks = ((k, idx == k) for k in range(first, last + 1))
        return [(k, on_piece) for k, on_piece in masks if on_piece.any()]


MAX_PERIODS_PER_TURN = 1000  # lift periods on one cam turn; each one is a copy of the lift's breaks


def periods_per_turn(span_deg: float, rotation_ratio: float, what: str,
                     span_field: tuple[str, ...] | None = None) -> int:
    """How many periods of a lift over the drive angle make one cam turn.

    Parameters
    ----------
    span_deg : float
        The lift's period over the drive angle [deg].
    rotation_ratio : float
        γ, cam turns per drive turn [-]; one cam turn is 360/γ degrees of drive angle.
    what : str
        What repeats, for the error sentences ("the lift curve").
    span_field : tuple of str, optional
        The period's field, for a cam whose γ is not given (a barrel cam, a machine's camshaft: one
        cam turn a master turn): the errors name it and ask for a longer period, not another γ.

    Returns
    -------
    int
        (360/γ)/span, a whole number from 1 to :data:`MAX_PERIODS_PER_TURN` [-].

    Raises
    ------
    InvalidParameterError
        γ not positive, or one cam turn not a whole number of periods (the contour would not close).

    References
    ----------
    Bezier valve-cam notes, eq. (12): θcam = γ·θdr.
    """
    if not (math.isfinite(rotation_ratio) and rotation_ratio > 0):
        raise InvalidParameterError("rotation_ratio must be a positive number (cam turns per drive turn).")
    if not (math.isfinite(span_deg) and span_deg > 0):
        raise InvalidParameterError("The lift must span a positive drive angle.")
    drive_per_turn = 360.0 / rotation_ratio
    periods = drive_per_turn / span_deg
    turn = (f"One cam turn is {drive_per_turn!r}° of drive angle (360°/rotation_ratio)" if span_field is None
            else f"One cam turn is {drive_per_turn!r}° of master angle")
    if not periods <= MAX_PERIODS_PER_TURN:  # also inf, from a vanishing rotation_ratio
        remedy, field = ("raise rotation_ratio", ("rotation_ratio",)) if span_field is None else \
            (f"lengthen {span_field[-1]} (a cam turn holds at most {MAX_PERIODS_PER_TURN} periods)", span_field)
        raise InvalidParameterError(
            f"{turn}, more than {MAX_PERIODS_PER_TURN} periods of {what} ({span_deg!r}°): {remedy}.", field=field)
    if abs(periods - round(periods)) > 1e-9 * max(1.0, periods) or round(periods) < 1:
        raise InvalidParameterError(
            f"{turn}; {what} repeats every {span_deg!r}°, which does not fit a whole number of times, so the cam "
            "contour would not close.", field=span_field or ())
    return round(periods)


def program_periods_per_turn(period_deg: float, rotation_ratio: float | None = None) -> int:
    """How many periods of a motion program make one cam turn (:func:`periods_per_turn`).

    Parameters
    ----------
    period_deg : float
        The program's period, in master angle [deg].
    rotation_ratio : float, optional
        γ [-]; None where the cam has none (a barrel cam, a machine's camshaft: one cam turn a
        master turn), and then the errors name ``period_deg``.

    Returns
    -------
    int
        Periods a cam turn, 1 to :data:`MAX_PERIODS_PER_TURN` [-].

    References
    ----------
    Bezier valve-cam notes, eq. (12): θcam = γ·θdr (as :func:`periods_per_turn`).
    """
    if rotation_ratio is None:
        return periods_per_turn(period_deg, 1.0, "the motion program", ("period_deg",))
    return periods_per_turn(period_deg, rotation_ratio, "the motion program")


def _cam_breaks(drive_deg: ArrayLike, span_deg: float, periods: int, rotation_ratio: float) -> FloatArray:
    """Cam angles in [0, 2π) of break points given over one period of drive angle [rad]."""
    drive = np.asarray(drive_deg, dtype=np.float64)
    cam = np.concatenate([np.radians((drive + k * span_deg) * rotation_ratio) for k in range(periods)])
    return np.unique(np.mod(cam, TWO_PI))


class CurveLift:
    """One user lift curve over the drive angle (a Bezier or points curve).

    The curve carries a ``scale`` (:class:`camcore.curves.base.Scale`): drive angle
    θdr = theta_start + theta_span·τ (degrees), h = h_min + h_span·S(T) with T mapped
    linearly from τ ∈ [0, 1) to [T0, T7], periodic over theta_span. The cam angle is
    θcam = γ θdr (γ = ``rotation_ratio``, cam turns per drive turn), so
    dh/dθcam = (1/γ)·dh/dθdr (valve-cam document, eq. 12), and so on for higher orders.
    One cam turn is 360/γ degrees of drive angle; it must hold a whole number of
    periods of the curve, and the curve must close (S(T7) = S(T0)).
    """

    def __init__(self, curve: Any, rotation_ratio: float = 1.0, unit: str = "mm"):
        scale = getattr(curve, "scale", None)
        if scale is None:
            raise InvalidParameterError("A user lift curve needs a scale (drive angle and lift units).")
        span = float(scale.theta_span)
        periods = periods_per_turn(span, rotation_ratio, "the lift curve")
        tol = 1e-9 * max(1.0, abs(scale.h_span))
        if abs(scale.h_span * (curve.s_end - curve.s_start)) > tol:
            raise InvalidParameterError(
                "The lift curve does not close: its lift at the end of its span differs from the start.")
        self.curve = curve
        self.scale = scale
        self.rotation_ratio = float(rotation_ratio)
        self.unit = unit
        t_breaks = np.asarray(curve.break_points, dtype=np.float64)
        tau = (t_breaks - curve.t_start) / (curve.t_end - curve.t_start)
        self._breaks = _cam_breaks(scale.theta_start + span * tau, span, periods, rotation_ratio)

    @property
    def breaks_rad(self) -> FloatArray:
        return self._breaks

    def derivatives(self, theta: ArrayLike, order: int = 2) -> list[FloatArray]:
        th = np.asarray(theta, dtype=np.float64)
        c, sc, g = self.curve, self.scale, self.rotation_ratio
        drive_deg = np.degrees(th) / g
        tau = np.mod((drive_deg - sc.theta_start) / sc.theta_span, 1.0)
        t = c.t_start + (c.t_end - c.t_start) * tau
        vals = c.derivatives(t, order)
        # dT/dθcam = (T7 − T0)/(span_rad · γ)
        rate = (c.t_end - c.t_start) / (math.radians(sc.theta_span) * g)
        out = [sc.h_min + sc.h_span * vals[0]]
        for o in range(1, order + 1):
            out.append(sc.h_span * rate**o * vals[o])
        return out


class MotionLift:
    """A closed motion program as a cam's lift; its master angle is the drive angle.

    The cam angle is θcam = γ·x (x the master angle, γ = ``rotation_ratio``), so one cam
    turn is 360/γ degrees of master angle and must hold a whole number of the program's
    periods (one period per turn when γ = 1 and period_deg = 360). By the chain rule
    dᵏs/dθᵏ = (180/(π·γ))ᵏ·dᵏs/dxᵏ, θ in radians and x in degrees.
    """

    def __init__(self, program: MotionProgram, rotation_ratio: float | None = None):
        scale = max(abs(program.start), abs(program.start + program.advance), program.scales[0])
        if abs(program.advance) > CONTINUITY_TOLERANCE * scale:
            raise InvalidParameterError(
                f"the motion program does not close: it ends at {program.start + program.advance!r} {program.unit} "
                f"but starts at {program.start!r} {program.unit}, so it cannot be the lift of a cam.",
                field=("segments",))
        periods = program_periods_per_turn(program.period_deg, rotation_ratio)
        ratio = 1.0 if rotation_ratio is None else rotation_ratio
        self.program = program
        self.unit = program.unit
        self.rotation_ratio = float(ratio)
        self._breaks = _cam_breaks(program.breaks_deg, program.period_deg, periods, ratio)

    @property
    def breaks_rad(self) -> FloatArray:
        """Cam angles in [0, 2π) where a derivative of the lift may jump [rad]."""
        return self._breaks

    def derivatives(self, theta: ArrayLike, order: int = 2) -> list[FloatArray]:
        """[h, dh/dθ, d²h/dθ², …][: order + 1] at cam angles θ [rad] (periodic over 2π), in the
        program's unit per radian^k."""
        deg_per_rad = 180.0 / (math.pi * self.rotation_ratio)
        x = np.mod(np.asarray(theta, dtype=np.float64) * deg_per_rad, self.program.period_deg)
        vals = self.program.derivatives(x, order)
        return [v * deg_per_rad**k for k, v in enumerate(vals)]
