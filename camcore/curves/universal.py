"""Makino's universal cam curve and the curves of his subroutine CURVE.

Eight break points T0 ≤ T1 ≤ … ≤ T7 cut the stroke into sections of quarter-sine,
constant and zero acceleration (Makino 1977, fig. 1, eqs. (1)-(9)):

    I    [T0, T1)  A = Amp·sin(π(T−T0) / 2(T1−T0))
    II   [T1, T2)  A = Amp
    III  [T2, T3)  A = Amp·cos(π(T−T2) / 2(T3−T2))
    IV   [T3, T4)  A = 0
    V    [T4, T5)  A = −Amm·sin(π(T−T4) / 2(T5−T4))
    VI   [T5, T6)  A = −Amm
    VII  [T6, T7)  A = −Amm·cos(π(T−T6) / 2(T7−T6))

with m = Amm/Amp (eq. 10) and Amp from eq. (11). When m is not given the curve is
closed in both displacement (S7) and velocity (V7); for V7 = V0 this is Makino's
equal-area rule RATIO = (C1+C2+C3)/(C5+C6+C7) (Fortran line 86).

References
----------
H. Makino, "Universal Cam Curve and Its Application" (1977), eqs. (1)-(16),
appendix 1 (subroutine CURVE), table 2.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .._checks import finite
from ..errors import InvalidBreakPointsError, InvalidParameterError, StrokeClosureError
from .sections import Section, SectionCurve

PI = math.pi

#: shortest non-empty section, as a fraction of T7 − T0 (shorter ones are merged away):
#: the jerk ~ A/length of a section stays finite
MIN_SECTION = 1e-9


def check_break_points(t: Sequence[float]) -> tuple[float, ...]:
    """Validate eight break points T0..T7 and return them as floats.

    A section shorter than 1e-9 of T7 − T0 (rounding noise, e.g. T1 = T3 − 1 ulp) is merged
    into its start point, so that its jerk ~ A/length cannot overflow; T7 itself is kept.

    Parameters
    ----------
    t : sequence of float
        Break points T0 ≤ T1 ≤ … ≤ T7, finite, T7 > T0 [-].

    Returns
    -------
    tuple of float
        The eight break points [-], with vanishing sections merged.

    Raises
    ------
    InvalidBreakPointsError
        Not eight points, not finite, out of order, or T7 = T0.

    References
    ----------
    Makino (1977), fig. 1 and eqs. (1)-(9): the eight break points of the universal curve.
    """
    if len(t) != 8:
        raise InvalidBreakPointsError(f"the universal curve needs 8 break points T0..T7, got {len(t)}.")
    pts = tuple(float(x) for x in t)
    for i, x in enumerate(pts):
        if not math.isfinite(x):
            raise InvalidBreakPointsError(f"break point T{i} must be a finite number, not {x!r}.")
    for i in range(7):
        if pts[i + 1] < pts[i]:
            raise InvalidBreakPointsError(
                f"break points must satisfy T0 ≤ T1 ≤ … ≤ T7, but T{i + 1} = {pts[i + 1]!r} "
                f"is less than T{i} = {pts[i]!r}."
            )
    if not pts[7] > pts[0]:
        raise InvalidBreakPointsError("the curve needs T7 > T0 (a stroke of positive duration).")
    # a section shorter than MIN_SECTION of the stroke is rounding noise (e.g. T1 = T3 − 1 ulp in
    # curve 4) whose jerk ~ A/length would overflow: it is merged into its start point
    shortest = MIN_SECTION * (pts[7] - pts[0])
    snapped = list(pts)
    for i in range(7):
        if 0 < snapped[i + 1] - snapped[i] < shortest:
            snapped[i + 1] = snapped[i]
    if snapped[7] != pts[7]:  # keep T7 itself: move the last break points back instead
        for i in range(7, 0, -1):
            if snapped[i] == snapped[i - 1] and pts[i] != pts[i - 1]:
                snapped[i - 1] = pts[7] if i == 7 else snapped[i]
        snapped[7] = pts[7]
    pts = tuple(snapped)
    return pts


def _section_constants(t: tuple[float, ...]) -> tuple[float, ...]:
    """Makino's C1..C7 (lines 76-82 of CURVE)."""
    t0, t1, t2, t3, t4, t5, t6, t7 = t
    return (
        2 * (t1 - t0) / PI,
        t2 - t1,
        2 * (t3 - t2) / PI,
        t4 - t3,
        2 * (t5 - t4) / PI,
        t6 - t5,
        2 * (t7 - t6) / PI,
    )


def _stroke_per_amplitude(t: tuple[float, ...]) -> tuple[float, float, float, float]:
    """Displacement and velocity gained per unit Amp and lost per unit Amm.

    Returns (P, N, Cp, Cn): S7 − S0 − V0(T7−T0) = Amp·P − Amm·N   (eq. 11)
                            V7 − V0             = Amp·Cp − Amm·Cn (eqs. 2-8)
    """
    t0, _t1, t2, t3, t4, _t5, t6, t7 = t
    c1, c2, c3, _c4, c5, c6, c7 = _section_constants(t)
    p = c3 * c3 + 0.5 * c2 * c2 - c1 * c1 + c3 * (t7 - t3) + c2 * (t7 - t2) + c1 * (t7 - t0)
    n = c7 * c7 + 0.5 * c6 * c6 - c5 * c5 + c6 * (t7 - t6) + c5 * (t7 - t4)
    return p, n, c1 + c2 + c3, c5 + c6 + c7


class UniversalCurve(SectionCurve):
    """Makino's universal cam curve with known amplitudes.

    Build it with :func:`universal_curve` (which solves eq. (11)) or directly from
    amplitudes, as Makino's special curve 2 does.

    Parameters
    ----------
    t : sequence of 8 floats
        Break points T0..T7 [dimensionless time].
    amp, amm : float
        Positive peak acceleration Amp and negative peak magnitude Amm.
    v0, s0 : float
        Velocity and displacement at T0.
    s7, v7 : float, optional
        The law's displacement and velocity at T7 (the targets the amplitudes were
        solved for); omitted, they follow from eq. (11) and eqs. (2)-(8) in closed form.
        The last section is evaluated about T7 from these, so the curve ends exactly
        at them (and at A = 0 where section VII is a quarter wave down to rest).
    """

    def __init__(self, t: Sequence[float], amp: float, amm: float, v0: float = 0.0, s0: float = 0.0,
                 s7: float | None = None, v7: float | None = None):
        pts = check_break_points(t)
        self.t = pts
        self.amp = float(amp)
        self.amm = float(amm)
        self.v0 = float(v0)
        self.s0 = float(s0)
        t0, t1, t2, t3, t4, t5, t6, t7 = pts
        if s7 is None or v7 is None:
            p, n, cp, cn = _stroke_per_amplitude(pts)
            s7 = self.s0 + self.v0 * (t7 - t0) + self.amp * p - self.amm * n if s7 is None else s7
            v7 = self.v0 + self.amp * cp - self.amm * cn if v7 is None else v7
        # (start, end, kind, amplitude) of sections I..VII: A = amplitude·sin or ·cos of
        # a quarter wave over the section, or constant
        shapes = [(t0, t1, "sin", self.amp), (t1, t2, "const", self.amp), (t2, t3, "cos", self.amp),
                  (t3, t4, "const", 0.0), (t4, t5, "sin", -self.amm), (t5, t6, "const", -self.amm),
                  (t6, t7, "cos", -self.amm)]
        present = [i for i, (start, end, _, _) in enumerate(shapes) if end > start]
        # a lone section keeps its start values (T0 exact); otherwise the last one is taken about T7
        last = present[-1] if len(present) > 1 else -1

        def section(i: int) -> Section:
            start, end, kind, amplitude = shapes[i]
            length = end - start
            if kind == "const":
                return Section(start, length, alpha=amplitude, from_end=i == last)
            omega = PI / (2 * length) if length > 0 else 0.0
            if i != last:
                if kind == "sin":
                    return Section(start, length, beta=amplitude, omega=omega)
                return Section(start, length, gamma=amplitude, omega=omega)
            # about the end, τ = T − end: sin(ω(T − start)) = cos ωτ, cos(ω(T − start)) = −sin ωτ
            if kind == "sin":
                return Section(start, length, gamma=amplitude, omega=omega, from_end=True)
            return Section(start, length, beta=-amplitude, omega=omega, from_end=True)

        sections = [section(i) for i in range(7)]
        super().__init__(sections, s0=self.s0, v0=self.v0, s_end=float(s7), v_end=float(v7))

    @property
    def m(self) -> float:
        """Ratio Amm/Amp (infinite when Amp = 0)."""
        return self.amm / self.amp if self.amp != 0 else math.inf

    @property
    def s7(self) -> float:
        return self.s_end

    @property
    def v7(self) -> float:
        return self.v_end


def universal_curve(
    t: Sequence[float],
    *,
    m: float | None = None,
    v0: float = 0.0,
    v7: float | None = None,
    s0: float = 0.0,
    s7: float = 1.0,
) -> UniversalCurve:
    """Makino's universal cam curve from break points and end conditions.

    Parameters
    ----------
    t : sequence of 8 floats
        Break points T0 ≤ … ≤ T7 [-] (dimensionless time).
    m : float, optional
        Ratio Amm/Amp [-]. Given, Amp follows from eq. (11) and V7 is whatever results.
        Omitted, Amp and Amm are solved so that the curve ends at both S7 and V7.
    v0, v7 : float
        Velocity at T0 and (when m is omitted) at T7 [-]; v7 defaults to v0, which is
        Makino's equal-area rule (Fortran line 86).
    s0, s7 : float
        Displacement at T0 and at T7 [-].

    Returns
    -------
    UniversalCurve

    Raises
    ------
    InvalidBreakPointsError
        Break points out of order or not finite.
    StrokeClosureError
        No amplitude reaches S7 (and V7) with these break points.

    References
    ----------
    Makino (1977), eqs. (1)-(11) (sections, m = Amm/Amp, Amp from eq. 11) and subroutine
    CURVE, line 86 (the equal-area ratio for V7 = V0).
    """
    pts = check_break_points(t)
    v0 = finite("V0", v0)
    s0 = finite("S0", s0)
    s7 = finite("S7", s7)
    p, n, cp, cn = _stroke_per_amplitude(pts)
    rise = s7 - s0 - v0 * (pts[7] - pts[0])
    scale = max(abs(p), abs(n), abs(cp), abs(cn), 1e-300)
    if m is not None:
        if v7 is not None:
            raise InvalidParameterError("give either m or V7, not both: with m fixed, V7 is a result.")
        m = finite("m", m)
        denominator = p - m * n
        if abs(denominator) <= 1e-12 * scale:
            raise StrokeClosureError(
                f"with these break points and m = {m!r} the acceleration sections move the "
                "follower no net distance, so no Amp reaches S7 (eq. 11 divides by zero)."
            )
        amp = rise / denominator
        return UniversalCurve(pts, amp, m * amp, v0=v0, s0=s0, s7=s7)
    v7 = v0 if v7 is None else finite("V7", v7)
    dv = v7 - v0
    det = -p * cn + n * cp
    if abs(det) <= 1e-12 * scale * scale:
        if cn == 0 and cp > 0 and dv == 0:
            raise StrokeClosureError(
                "the break points leave no deceleration section (T4 = T7), so no ratio m "
                "can bring the velocity back to V7 = V0; give m, or widen T4..T7."
            )
        raise StrokeClosureError(
            "these break points cannot reach both S7 and V7: the acceleration and "
            "deceleration sections are not independent (give m instead of V7)."
        )
    amp = (-rise * cn + n * dv) / det
    amm = (p * dv - cp * rise) / det
    return UniversalCurve(pts, amp, amm, v0=v0, s0=s0, s7=s7, v7=v7)
