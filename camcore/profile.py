"""Plate-cam profiles: cam surface, pitch curve, pressure angle, radius of curvature.

A plate cam turns about the origin O. Everything is computed by *kinematic
inversion*: the follower's contact (or roller-centre) point ``c(θ)`` is found in the
fixed frame and then turned back by the cam angle into the cam's own frame,

    p(θ) = R(−σθ) c(θ),    σ = +1 for a counter-clockwise cam, −1 for clockwise,

with R(a) the rotation by a. Derivatives with respect to the cam angle θ (radians)
come from the analytic derivatives of the lift (chain rule through the motion curve),
never from differences of the sampled contour. With J the rotation by +90°,
d/dθ R(−σθ) = −σ R(−σθ) J, so the tangent and second derivative of p are

    p'  = R(−σθ) u1,  u1 = c' − σ J c
    p'' = R(−σθ) u2,  u2 = c'' − 2σ J c' − c.

Frames and conventions
----------------------
* Translating followers move along +y in the fixed frame, on the line x = e
  (``offset_mm``). At cam angle 0 the follower sits above the cam centre.
* Oscillating followers: pivot A = (d, 0) (``pivot_distance_mm``), arm of length L
  (``arm_length_mm``), follower point B(α) = (d − L cos α, L sin α) where α is the
  arm angle measured from the line A→O. |OB|² = d² + L² − 2dL cos α grows with α,
  so a positive swing ψ moves the follower away from the cam: α = α0 + ψ, with α0
  from |OB(α0)| = Rb + Rr (base circle contact; needs |d − L| < Rb + Rr < d + L).
* A ccw cam traverses its contour clockwise in its own frame as θ grows.

Quantities
----------
* Knife-edge and roller (Rr = 0 for knife-edge): pitch point c(θ). The pitch-curve
  curvature is κp = −σ (u1 × u2)/|u1|³ (positive where convex: for a ccw cam the
  contour runs clockwise); ρp = 1/κp. The cam surface is c − Rr n̂, n̂ = σ J û1 the
  outward normal of the pitch curve, and ρ = ρp − Rr (negative where concave).
  Pressure angle φ between the common normal and the follower point's velocity
  direction v̂ (v̂ = +y for translating; v̂ = dB/dα/|dB/dα| for oscillating):
  φ = atan2(u1·v̂, −σ u1·(J v̂)). For a translating follower u1 = (σ(s0+s), s' − σe),
  so φ = atan2(s' − σe, s0 + s), s0 = √((Rb+Rr)² − e²) — the textbook formula; for
  the in-line knife-edge tan φ = s'/(Rb + s), Shinzato (1988) eq. (6).
  Positive while the cam pushes the follower out.
* Flat-faced: the face is a line with unit outward normal m at distance p from O
  (support function). In the cam frame its normal angle is φn(θ); the envelope
  (cam surface) touches at q = p m + (dp/dφn) J m and has ρ = p + d²p/dφn²
  = p + (p'' φn' − p' φn'')/φn'³ (primes: d/dθ).
  Translating (face ⟂ motion): p = Rb + s, φn = π/2 − σθ, so the contact point in the
  fixed frame is (σ s', Rb + s) — contact offset = ds/dθ as in the valve-cam
  document eq. (11) — and ρ = Rb + s + s''. Oscillating: the face is a line through
  the pivot, m = (sin α, cos α), p = d sin α, α0 = asin(Rb/d). In both cases the face
  normal is parallel to the velocity of the contact point, so φ = 0.

References
----------
- S. Shinzato, M. Kunigami (1988): knife-edge contour x = l cos θ, y = l sin θ,
  l = y + D/2, numerical pressure angle from the neighbouring points, eq. (6).
- "Bezier valve cam" document: rotation ratio γ = ω_cam/ω_dr, θcam = γ θdr,
  dh/dθcam = (1/γ) dh/dθdr (eq. 12), flat tappet contact offset = dh/dθ (eq. 11),
  convexity test cos φi > 0 and sin φi > 0 for consecutive chord vectors.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike

from .curve import Curve, FloatArray
from .errors import GeometryError, InvalidParameterError
from .transform import ReturnCurve

TWO_PI = 2.0 * math.pi
#: angles (degrees) of a lift schedule must add to 360 within this tolerance
ANGLE_TOLERANCE_DEG = 1e-9
#: grid over one cam turn used to bracket the extremes of the checks
CHECK_GRID = 7200
#: a schedule "closes" when its final level equals its initial level within this (mm or deg)
CLOSURE_TOLERANCE = 1e-9

FollowerType = Literal["knife-edge", "roller", "flat-faced"]
Motion = Literal["translating", "oscillating"]


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

    kind: ``"rise"``, ``"dwell"`` or ``"return"``; ``angle_deg``: its cam angle;
    ``lift_mm`` (translating followers) or ``swing_deg`` (oscillating): the rise or the
    drop; ``curve``: the motion law of a rise (a return plays it backwards with
    :class:`ReturnCurve`; pass a curve that rises, S: S0 → S7). ``None`` = cycloid.
    """

    kind: Literal["rise", "dwell", "return"]
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
            raise InvalidParameterError("A lift schedule needs at least one segment.")
        total = 0.0
        for i, seg in enumerate(segments):
            if seg.kind not in ("rise", "dwell", "return"):
                raise InvalidParameterError(
                    f"segments[{i}]: type must be 'rise', 'dwell' or 'return', not {seg.kind!r}.")
            if not (math.isfinite(seg.angle_deg) and seg.angle_deg > 0):
                raise InvalidParameterError(f"segments[{i}]: angle_deg must be a positive number of degrees.")
            if seg.kind != "dwell" and not (math.isfinite(seg.amount) and seg.amount >= 0):
                raise InvalidParameterError(
                    f"segments[{i}]: the {seg.kind} must be a finite, non-negative lift (it is {seg.amount!r}).")
            total += seg.angle_deg
        if abs(total - 360.0) > ANGLE_TOLERANCE_DEG:
            raise InvalidParameterError(
                f"The segment angles add to {total!r}°; they must add to 360° (one cam turn).")
        pieces: list[_Piece] = []
        level = float(initial)
        start = 0.0
        for i, seg in enumerate(segments):
            span = math.radians(seg.angle_deg)
            if seg.kind == "dwell":
                pieces.append(_Piece(start, span, level, 0.0, None, 0.0, 1.0))
            else:
                from .catalog import named_curve

                rise = seg.curve if seg.curve is not None else named_curve("cycloid")
                curve = rise if seg.kind == "rise" else ReturnCurve(rise)
                s0, s1 = curve.s_start, curve.s_end
                if s1 == s0 or (seg.kind == "rise") != (s1 > s0):
                    raise InvalidParameterError(
                        f"segments[{i}]: the curve of a {seg.kind} must run from S0 to a different S7 "
                        "(give the rising curve; a return plays it backwards).")
                amount = seg.amount if seg.kind == "rise" else -seg.amount
                pieces.append(_Piece(start, span, level, amount, curve, s0, s1))
                level += amount
                if level < -CLOSURE_TOLERANCE:
                    raise GeometryError(
                        f"segments[{i}]: the return drops the follower {-level!r} below the base circle.")
            start += span
        if abs(level - initial) > CLOSURE_TOLERANCE * max(1.0, abs(initial)):
            raise InvalidParameterError(
                f"The schedule does not close: it ends at {level!r} {unit} but starts at {initial!r} {unit}; "
                "the rises must equal the returns over one turn.")
        self.segments = tuple(segments)
        self.unit = unit
        self.initial = float(initial)
        self._pieces = pieces
        self._starts = np.array([p.start for p in pieces])
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

    def derivatives(self, theta: ArrayLike, order: int = 2) -> list[FloatArray]:
        th = np.asarray(theta, dtype=np.float64)
        flat = np.mod(th.reshape(-1), TWO_PI)
        idx = np.clip(np.searchsorted(self._starts, flat, side="right") - 1, 0, len(self._pieces) - 1)
        out = [np.zeros_like(flat) for _ in range(order + 1)]
        for k, p in enumerate(self._pieces):
            sel = idx == k
            if not sel.any():
                continue
            if p.curve is None:
                out[0][sel] = p.level
                continue
            c = p.curve
            rate = (c.t_end - c.t_start) / p.span
            u = np.clip((flat[sel] - p.start) / p.span, 0.0, 1.0)
            vals = c.derivatives(c.t_start + (c.t_end - c.t_start) * u, order)
            gain = p.amount / (p.s1 - p.s0)
            out[0][sel] = p.level + gain * (vals[0] - p.s0)
            for o in range(1, order + 1):
                out[o][sel] = gain * rate**o * vals[o]
        return [o.reshape(th.shape) for o in out]


class CurveLift:
    """One user lift curve over the drive angle (a Bezier or points curve).

    The curve carries a ``scale`` (:class:`camcore.curve.Scale`): drive angle
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
        if not (math.isfinite(rotation_ratio) and rotation_ratio > 0):
            raise InvalidParameterError("rotation_ratio must be a positive number (cam turns per drive turn).")
        span = float(scale.theta_span)
        if not (math.isfinite(span) and span > 0):
            raise InvalidParameterError("The lift curve must span a positive drive angle.")
        drive_per_turn = 360.0 / rotation_ratio
        periods = drive_per_turn / span
        if abs(periods - round(periods)) > 1e-9 * max(1.0, periods) or round(periods) < 1:
            raise InvalidParameterError(
                f"One cam turn is {drive_per_turn!r}° of drive angle (360°/rotation_ratio); the lift curve spans "
                f"{span!r}°, which does not fit a whole number of times, so the cam contour would not close.")
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
        drive = scale.theta_start + span * tau
        reps = int(round(periods))
        cam = np.concatenate([np.radians((drive + k * span) * rotation_ratio) for k in range(reps)])
        self._breaks = np.unique(np.mod(cam, TWO_PI))

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


# ============================================================================ follower
@dataclass(frozen=True)
class Follower:
    """Follower geometry.

    type: ``knife-edge`` | ``roller`` | ``flat-faced``; motion: ``translating`` |
    ``oscillating``. ``offset_mm`` (e): translating follower's line of motion is x = e.
    ``roller_radius_mm`` (Rr): roller followers only. ``arm_length_mm`` (L) and
    ``pivot_distance_mm`` (d): oscillating followers (a flat face passes through the pivot,
    so L is not used for it).
    """

    type: FollowerType = "knife-edge"
    motion: Motion = "translating"
    offset_mm: float = 0.0
    roller_radius_mm: float = 0.0
    arm_length_mm: float | None = None
    pivot_distance_mm: float | None = None


@dataclass(frozen=True)
class CamSpec:
    """A plate cam: follower, base-circle radius, rotation and lift over one cam turn.

    ``base_radius_mm`` is the radius of the base circle = the smallest radius of the cam
    surface (the roller's pitch circle is Rb + Rr). ``lift`` is a :class:`LiftSchedule`,
    a :class:`CurveLift` or any object with the :class:`Lift` protocol, in mm for
    translating followers and in degrees of swing for oscillating followers.
    """

    follower: Follower
    base_radius_mm: float
    lift: Any
    rotation: Literal["ccw", "cw"] = "ccw"

    @property
    def sigma(self) -> float:
        return 1.0 if self.rotation == "ccw" else -1.0


def make_cam(
    follower: Follower,
    base_radius_mm: float,
    *,
    segments: Sequence[Segment] | None = None,
    lift_curve: Any = None,
    rotation: Literal["ccw", "cw"] = "ccw",
    rotation_ratio: float = 1.0,
) -> CamSpec:
    """Build and validate a :class:`CamSpec` from segments or one user lift curve."""
    unit = "deg" if follower.motion == "oscillating" else "mm"
    if (segments is None) == (lift_curve is None):
        raise InvalidParameterError("Give the lift either as segments or as one lift curve, not both.")
    lift = LiftSchedule(segments, unit=unit) if segments is not None else CurveLift(lift_curve, rotation_ratio, unit)
    spec = CamSpec(follower, base_radius_mm, lift, rotation)
    validate(spec)
    return spec


def validate(spec: CamSpec) -> None:
    """Raise :class:`GeometryError` / :class:`InvalidParameterError` with the reason."""
    f = spec.follower
    if f.type not in ("knife-edge", "roller", "flat-faced"):
        raise InvalidParameterError(f"follower type must be knife-edge, roller or flat-faced, not {f.type!r}.")
    if f.motion not in ("translating", "oscillating"):
        raise InvalidParameterError(f"follower motion must be translating or oscillating, not {f.motion!r}.")
    if spec.rotation not in ("ccw", "cw"):
        raise InvalidParameterError(f"rotation must be 'ccw' or 'cw', not {spec.rotation!r}.")
    rb = spec.base_radius_mm
    if not (math.isfinite(rb) and rb > 0):
        raise GeometryError(f"The base radius must be positive (it is {rb!r} mm).")
    rr = f.roller_radius_mm if f.type == "roller" else 0.0
    if f.type == "roller" and not (math.isfinite(rr) and rr > 0):
        raise GeometryError(f"A roller follower needs a roller radius > 0 (it is {rr!r} mm).")
    if not math.isfinite(f.offset_mm):
        raise InvalidParameterError("offset_mm must be finite.")
    if f.motion == "translating":
        if f.type != "flat-faced" and not rb + rr > abs(f.offset_mm):
            raise GeometryError(
                f"The base radius plus roller radius ({rb + rr!r} mm) must exceed the offset |e| = "
                f"{abs(f.offset_mm)!r} mm, or the follower line misses the base circle.")
    else:
        d = f.pivot_distance_mm
        if d is None or not (math.isfinite(d) and d > 0):
            raise GeometryError("An oscillating follower needs pivot_distance_mm > 0.")
        if f.type == "flat-faced":
            if not d > rb:
                raise GeometryError(
                    f"The pivot ({d!r} mm from the cam centre) must lie outside the base circle ({rb!r} mm) "
                    "for a flat face through the pivot to touch it.")
        else:
            arm = f.arm_length_mm
            if arm is None or not (math.isfinite(arm) and arm > 0):
                raise GeometryError("An oscillating follower needs arm_length_mm > 0.")
            r = rb + rr
            if not abs(d - arm) < r < d + arm:
                raise GeometryError(
                    f"The arm cannot be assembled: the base-circle contact radius Rb + Rr = {r!r} mm must lie "
                    f"strictly between |pivot distance − arm length| = {abs(d - arm)!r} mm and "
                    f"pivot distance + arm length = {d + arm!r} mm.")
    h = spec.lift.derivatives(np.linspace(0.0, TWO_PI, 721), 0)[0]
    if not np.all(np.isfinite(h)):
        raise InvalidParameterError("The lift is not finite everywhere.")
    if h.min() < -1e-9 * max(1.0, float(np.abs(h).max())):
        raise GeometryError(
            f"The lift goes below zero ({float(h.min())!r}); the base circle is the smallest radius of the cam, "
            "so the lift must be ≥ 0.")
    if f.motion == "oscillating":
        psi = np.radians(h)
        if f.type == "flat-faced":
            a0 = math.asin(rb / f.pivot_distance_mm)
        else:
            a0 = _alpha0(spec)
        a = a0 + psi
        if a.max() >= math.pi or a.min() <= 0:
            raise GeometryError("The swing turns the arm through the line of centres; the follower cannot run.")


def _alpha0(spec: CamSpec) -> float:
    f = spec.follower
    rr = f.roller_radius_mm if f.type == "roller" else 0.0
    d, arm, r = f.pivot_distance_mm, f.arm_length_mm, spec.base_radius_mm + rr
    assert d is not None and arm is not None
    return math.acos(np.clip((d * d + arm * arm - r * r) / (2 * d * arm), -1.0, 1.0))


# ============================================================================ kinematics
def _rot(x: FloatArray, y: FloatArray, ang: FloatArray) -> tuple[FloatArray, FloatArray]:
    c, s = np.cos(ang), np.sin(ang)
    return c * x - s * y, s * x + c * y


@dataclass
class _Kin:
    """Fixed-frame quantities at cam angles θ (all arrays)."""

    theta: FloatArray
    lift: FloatArray  # in the lift unit (mm or deg)
    lift_d1: FloatArray  # per rad
    contact: tuple[FloatArray, FloatArray]  # cam-surface contact, fixed frame
    pitch: tuple[FloatArray, FloatArray]  # roller centre / knife point / flat contact
    pressure: FloatArray  # rad
    kappa_pitch: FloatArray  # 1/mm, positive convex (knife/roller); for flat: 1/rho
    rho_cam: FloatArray  # mm, of the cam surface
    offset: FloatArray | None = None  # flat: contact position along the face


def _kinematics(spec: CamSpec, theta: FloatArray) -> _Kin:
    f = spec.follower
    sg = spec.sigma
    rb = spec.base_radius_mm
    vals = spec.lift.derivatives(theta, 2)
    h, h1, h2 = vals[0], vals[1], vals[2]
    if f.type == "flat-faced":
        if f.motion == "translating":
            p, p1, p2 = rb + h, h1, h2
            phi1 = np.full_like(theta, -sg)
            phi2 = np.zeros_like(theta)
            mx, my = np.zeros_like(theta), np.ones_like(theta)
        else:
            d = float(f.pivot_distance_mm)  # type: ignore[arg-type]
            a = math.asin(rb / d) + np.radians(h)
            a1, a2 = np.radians(h1), np.radians(h2)
            p = d * np.sin(a)
            p1 = d * np.cos(a) * a1
            p2 = d * (np.cos(a) * a2 - np.sin(a) * a1 * a1)
            phi1 = -a1 - sg
            phi2 = -a2
            mx, my = np.sin(a), np.cos(a)
        with np.errstate(divide="ignore", invalid="ignore"):
            p_phi = p1 / phi1
            rho = p + (p2 * phi1 - p1 * phi2) / phi1**3
        cx = p * mx - p_phi * my  # p m + p_φ J m, J m = (−my, mx)
        cy = p * my + p_phi * mx
        if f.motion == "translating":
            offset = cx - f.offset_mm
        else:
            d = float(f.pivot_distance_mm)  # type: ignore[arg-type]
            offset = np.hypot(cx - d, cy)  # distance from the pivot along the face
        with np.errstate(divide="ignore"):
            kappa = 1.0 / rho
        return _Kin(theta, h, h1, (cx, cy), (cx, cy), np.zeros_like(theta), kappa, rho, offset)

    rr = f.roller_radius_mm if f.type == "roller" else 0.0
    if f.motion == "translating":
        e = f.offset_mm
        s0 = math.sqrt((rb + rr) ** 2 - e * e)
        cx, cy = np.full_like(theta, e), s0 + h
        c1x, c1y = np.zeros_like(theta), h1
        c2x, c2y = np.zeros_like(theta), h2
        vx, vy = np.zeros_like(theta), np.ones_like(theta)
    else:
        d = float(f.pivot_distance_mm)  # type: ignore[arg-type]
        arm = float(f.arm_length_mm)  # type: ignore[arg-type]
        a = _alpha0(spec) + np.radians(h)
        a1, a2 = np.radians(h1), np.radians(h2)
        sa, ca = np.sin(a), np.cos(a)
        cx, cy = d - arm * ca, arm * sa
        # B_α = L(sin α, cos α), B_αα = L(cos α, −sin α)
        c1x, c1y = arm * sa * a1, arm * ca * a1
        c2x = arm * (ca * a1 * a1 + sa * a2)
        c2y = arm * (-sa * a1 * a1 + ca * a2)
        vx, vy = sa, ca
    # u1 = c' − σ J c, u2 = c'' − 2σ J c' − c, with J(x, y) = (−y, x)
    u1x, u1y = c1x + sg * cy, c1y - sg * cx
    u2x = c2x + 2 * sg * c1y - cx
    u2y = c2y - 2 * sg * c1x - cy
    speed = np.hypot(u1x, u1y)
    cross = u1x * u2y - u1y * u2x
    kappa = -sg * cross / speed**3
    # φ = atan2(u1·v̂, −σ u1·(J v̂)), J v̂ = (−vy, vx)
    pressure = np.arctan2(u1x * vx + u1y * vy, -sg * (-u1x * vy + u1y * vx))
    # outward normal n = σ J û1
    nx, ny = -sg * u1y / speed, sg * u1x / speed
    sx, sy = cx - rr * nx, cy - rr * ny
    with np.errstate(divide="ignore"):
        rho = 1.0 / kappa - rr
    return _Kin(theta, h, h1, (sx, sy), (cx, cy), pressure, kappa, rho)


# ============================================================================ results
@dataclass(frozen=True)
class ProfileChecks:
    """Exact extremes over the whole cam turn (not just the sampled angles).

    ``max_pressure_angle_deg`` is the largest |φ| (the signed value at that angle is
    ``max_pressure_angle_signed_deg``); ``min_radius_of_curvature_mm`` the smallest
    radius of curvature of the convex parts of the cam surface (knife-edge, roller:
    from the largest pitch-curve curvature; flat-faced: min of Rb + s + s'' or the
    oscillating equivalent, which may be negative = the cam cannot be made).
    ``convex``: the cam surface has no concave part (flat-faced: ρ > 0 everywhere AND the
    valve-cam document's neighbouring-chord test on the sampled contour).
    ``undercut``: roller radius ≥ the pitch curve's radius of curvature somewhere on a
    convex part (the roller cannot generate the surface). ``corners_deg``: cam angles where
    the lift's velocity jumps (the surface has a corner there, radius 0).
    """

    max_pressure_angle_deg: float
    max_pressure_angle_at_deg: float
    max_pressure_angle_signed_deg: float
    min_radius_of_curvature_mm: float
    min_radius_of_curvature_at_deg: float
    min_pitch_radius_of_curvature_mm: float | None
    convex: bool
    undercut: bool
    corners_deg: tuple[float, ...] = ()
    face_min_mm: float | None = None
    face_max_mm: float | None = None
    face_width_mm: float | None = None

    def as_dict(self) -> dict[str, Any]:
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out["corners_deg"] = list(self.corners_deg)
        return out


@dataclass(frozen=True)
class ProfileResult:
    """Columns over ``cam_angle_deg`` plus the checks.

    ``lift`` is in mm (translating) or degrees of swing (oscillating): see
    :meth:`columns` for the API names ``lift_mm`` / ``swing_deg``. ``pitch_x_mm``,
    ``pitch_y_mm``: roller centre path (= the surface for a knife-edge; the face contact
    point for a flat-faced follower). ``contact_offset_mm``: flat-faced only, position of
    the contact along the face (from the stem axis, or from the pivot when oscillating).
    """

    cam_angle_deg: FloatArray
    lift: FloatArray
    lift_unit: str
    x_mm: FloatArray
    y_mm: FloatArray
    pitch_x_mm: FloatArray
    pitch_y_mm: FloatArray
    pressure_angle_deg: FloatArray
    radius_of_curvature_mm: FloatArray
    pitch_radius_of_curvature_mm: FloatArray
    contact_offset_mm: FloatArray | None
    checks: ProfileChecks

    @property
    def lift_name(self) -> str:
        return "swing_deg" if self.lift_unit == "deg" else "lift_mm"

    def columns(self) -> dict[str, FloatArray]:
        out = {
            "cam_angle_deg": self.cam_angle_deg,
            self.lift_name: self.lift,
            "x_mm": self.x_mm,
            "y_mm": self.y_mm,
            "pitch_x_mm": self.pitch_x_mm,
            "pitch_y_mm": self.pitch_y_mm,
            "pressure_angle_deg": self.pressure_angle_deg,
            "radius_of_curvature_mm": self.radius_of_curvature_mm,
        }
        if self.contact_offset_mm is not None:
            out["contact_offset_mm"] = self.contact_offset_mm
        return out


def contour(spec: CamSpec, cam_angle_deg: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Cam surface (x, y) and pitch curve (x, y) in the cam frame at these cam angles."""
    th = np.radians(np.asarray(cam_angle_deg, dtype=np.float64))
    k = _kinematics(spec, th)
    back = -spec.sigma * th
    sx, sy = _rot(k.contact[0], k.contact[1], back)
    px, py = _rot(k.pitch[0], k.pitch[1], back)
    return sx, sy, px, py


def compute_profile(spec: CamSpec, cam_angle_deg: ArrayLike) -> ProfileResult:
    """The profile at the given cam angles (degrees) and the checks over the whole turn."""
    ang = np.asarray(cam_angle_deg, dtype=np.float64).reshape(-1)
    if not np.all(np.isfinite(ang)):
        raise InvalidParameterError("cam_angle_deg must be finite numbers.")
    th = np.radians(ang)
    k = _kinematics(spec, th)
    back = -spec.sigma * th
    sx, sy = _rot(k.contact[0], k.contact[1], back)
    px, py = _rot(k.pitch[0], k.pitch[1], back)
    with np.errstate(divide="ignore"):
        rho_p = 1.0 / k.kappa_pitch
    checks = profile_checks(spec)
    return ProfileResult(
        cam_angle_deg=ang,
        lift=k.lift,
        lift_unit=spec.lift.unit,
        x_mm=sx,
        y_mm=sy,
        pitch_x_mm=px,
        pitch_y_mm=py,
        pressure_angle_deg=np.degrees(k.pressure),
        radius_of_curvature_mm=k.rho_cam,
        pitch_radius_of_curvature_mm=rho_p,
        contact_offset_mm=k.offset,
        checks=checks,
    )


def sample_profile(spec: CamSpec, samples: int = 361) -> ProfileResult:
    """The profile at ``samples`` cam angles evenly over 0–360°, both ends included."""
    if samples < 2:
        raise InvalidParameterError("samples must be at least 2.")
    return compute_profile(spec, np.linspace(0.0, 360.0, samples))


# ---------------------------------------------------------------- exact extremes
def _check_grid(spec: CamSpec, n: int = CHECK_GRID) -> FloatArray:
    """A fine grid over [0, 2π) with every break point and its left neighbour."""
    base = np.linspace(0.0, TWO_PI, n, endpoint=False)
    br = np.asarray(spec.lift.breaks_rad, dtype=np.float64)
    left = np.mod(br - 1e-10, TWO_PI)
    return np.unique(np.concatenate([base, br, left]))


def _golden_max(fun: Callable[[FloatArray], FloatArray], a: float, b: float, iters: int = 80) -> tuple[float, float]:
    """Maximum of a unimodal scalar function on [a, b] by golden-section search."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    x1, x2 = b - g * (b - a), a + g * (b - a)
    f1, f2 = float(fun(np.array([x1]))[0]), float(fun(np.array([x2]))[0])
    for _ in range(iters):
        if b - a < 1e-13:
            break
        if f1 < f2:
            a, x1, f1 = x1, x2, f2
            x2 = a + g * (b - a)
            f2 = float(fun(np.array([x2]))[0])
        else:
            b, x2, f2 = x2, x1, f1
            x1 = b - g * (b - a)
            f1 = float(fun(np.array([x1]))[0])
    return (x1, f1) if f1 >= f2 else (x2, f2)


def _exact_max(fun: Callable[[FloatArray], FloatArray], grid: FloatArray,
               breaks: FloatArray) -> tuple[float, float]:
    """Max of fun over the turn: the best grid point, refined by golden section between its
    neighbours (not across a break, where the function may jump)."""
    vals = fun(grid)
    vals = np.where(np.isfinite(vals), vals, -np.inf)
    i = int(np.argmax(vals))
    best_t, best_v = float(grid[i]), float(vals[i])
    lo = float(grid[i - 1]) if i > 0 else float(grid[-1]) - TWO_PI
    hi = float(grid[i + 1]) if i + 1 < len(grid) else float(grid[0]) + TWO_PI
    # the grid holds every break and its left neighbour: no break lies strictly inside (lo, hi)
    for a, b in ((lo, best_t), (best_t, hi)):
        t, v = _golden_max(fun, a, b)
        if v > best_v:
            best_t, best_v = t, v
    return float(np.mod(best_t, TWO_PI)), best_v


def _corners(spec: CamSpec) -> list[float]:
    br = np.asarray(spec.lift.breaks_rad, dtype=np.float64)
    if br.size == 0:
        return []
    right = spec.lift.derivatives(br, 1)
    left = spec.lift.derivatives(br - 1e-9, 1)
    scale = max(1.0, float(np.abs(spec.lift.derivatives(_check_grid(spec, 720), 1)[1]).max()))
    jump = np.abs(right[1] - left[1]) > 1e-6 * scale
    return [float(np.degrees(b)) for b in br[jump]]


def profile_checks(spec: CamSpec) -> ProfileChecks:
    """Largest |pressure angle|, smallest radius of curvature, convexity, undercut."""
    grid = _check_grid(spec)
    br = np.asarray(spec.lift.breaks_rad, dtype=np.float64)
    f = spec.follower

    def abs_pressure(t: FloatArray) -> FloatArray:
        return np.abs(_kinematics(spec, t).pressure)

    t_p, v_p = _exact_max(abs_pressure, grid, br)
    signed = float(_kinematics(spec, np.array([t_p])).pressure[0])
    corners = _corners(spec)
    face: dict[str, float | None] = {"face_min_mm": None, "face_max_mm": None, "face_width_mm": None}
    if f.type == "flat-faced":
        t_r, neg = _exact_max(lambda t: -_kinematics(spec, t).rho_cam, grid, br)
        rho_min = -neg
        rho_p_min: float | None = None
        kin = _kinematics(spec, grid)
        off = kin.offset
        assert off is not None
        t_hi, off_max = _exact_max(lambda t: _kinematics(spec, t).offset, grid, br)  # type: ignore[arg-type,return-value]
        t_lo, off_min_neg = _exact_max(lambda t: -_kinematics(spec, t).offset, grid, br)  # type: ignore[operator]
        face = {"face_min_mm": -off_min_neg, "face_max_mm": off_max, "face_width_mm": off_max + off_min_neg}
        # the chord test on an even 0.1° grid: the check grid's break-point neighbours sit an
        # ulp apart, and chords that short turn the cross product into rounding noise
        even = np.linspace(0.0, 2 * math.pi, 3601)[:-1]
        kin_even = _kinematics(spec, even)
        sx, sy = _rot(kin_even.contact[0], kin_even.contact[1], -spec.sigma * even)
        convex = bool(rho_min > 0 and chord_convexity(sx, sy))
        undercut = False
    else:
        rr = f.roller_radius_mm if f.type == "roller" else 0.0
        t_r, kmax = _exact_max(lambda t: _kinematics(spec, t).kappa_pitch, grid, br)
        _, kmin_neg = _exact_max(lambda t: -_kinematics(spec, t).kappa_pitch, grid, br)
        rho_p_min = 1.0 / kmax if kmax > 0 else math.inf
        rho_min = rho_p_min - rr
        undercut = bool(f.type == "roller" and kmax > 0 and rr >= rho_p_min)
        convex = bool(-kmin_neg > 0 and not undercut)
    if corners:
        rho_min, t_r = 0.0, math.radians(corners[0])
        if f.type == "flat-faced":
            convex = False
    return ProfileChecks(
        max_pressure_angle_deg=math.degrees(v_p),
        max_pressure_angle_at_deg=math.degrees(t_p),
        max_pressure_angle_signed_deg=math.degrees(signed),
        min_radius_of_curvature_mm=float(rho_min),
        min_radius_of_curvature_at_deg=math.degrees(t_r),
        min_pitch_radius_of_curvature_mm=rho_p_min,
        convex=convex,
        undercut=undercut,
        corners_deg=tuple(corners),
        **face,
    )


# ============================================================================ point data
def _same_point(px: FloatArray, py: FloatArray) -> bool:
    """Last point = first point, within 1e-9 of the contour's size (rounding of a full turn)."""
    size = max(float(np.abs(px).max()), float(np.abs(py).max()), 1.0)
    return bool(np.hypot(px[0] - px[-1], py[0] - py[-1]) <= 1e-9 * size)


def chord_convexity(x: ArrayLike, y: ArrayLike) -> bool:
    """The valve-cam document's convexity test on a closed sampled contour.

    For consecutive chord vectors a = P_i − P_{i−1}, b = P_{i+1} − P_i the contour is
    convex when cos φi = a·b/(|a||b|) > 0 and sin φi = (a × b)/(|a||b|) > 0 at every i
    (the document's contour runs counter-clockwise; a clockwise contour is reversed
    first). A repeated closing point (last = first) is dropped; zero-length chords are
    skipped.
    """
    px, py = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    if px.size > 1 and _same_point(px, py):
        px, py = px[:-1], py[:-1]
    area2 = float(np.sum(px * np.roll(py, -1) - np.roll(px, -1) * py))
    if area2 < 0:
        px, py = px[::-1], py[::-1]
    ax, ay = px - np.roll(px, 1), py - np.roll(py, 1)
    keep = np.hypot(ax, ay) > 0
    ax, ay = ax[keep], ay[keep]
    bx, by = np.roll(ax, -1), np.roll(ay, -1)
    dot = ax * bx + ay * by
    cross = ax * by - ay * bx
    return bool(np.all(dot > 0) and np.all(cross > 0))


def pressure_angle_from_points(
    x: ArrayLike, y: ArrayLike, cam_angle_deg: ArrayLike | None = None, closed: bool = True
) -> FloatArray:
    """Pressure angle of a knife-edge in-line follower from contour points only.

    Shinzato (1988), program list 1, lines 420–1240, reimplemented with atan2: the
    tangent at P_i is the chord P_{i+1} − P_{i−1} (eq. 1); the follower moves along the
    radius through P_i at the cam angle θ_i (the paper's stroke line, eqs. 4–5). The
    pressure angle is the angle between the contour normal and that radius,

        β = atan2(t·r̂, t·ê),  r̂ = (cos θ, sin θ), ê = (−sin θ, cos θ),

    positive where the radius grows with θ (the follower is pushed out) and negative
    where it shrinks, the paper's sign. The points are in the paper's convention
    x = l cos θ, y = l sin θ (θ increasing along the list). ``cam_angle_deg`` defaults to
    the polar angle of each point. With ``closed`` the list is one full turn (a repeated
    closing point, last = first, is allowed and handled like the paper's 0/360 case);
    otherwise the end points get NaN.
    """
    px = np.asarray(x, dtype=np.float64).reshape(-1)
    py = np.asarray(y, dtype=np.float64).reshape(-1)
    if px.shape != py.shape or px.size < 3:
        raise InvalidParameterError("x and y need the same length, at least 3 points.")
    th = np.arctan2(py, px) if cam_angle_deg is None else np.radians(np.asarray(cam_angle_deg, dtype=np.float64))
    dup = closed and _same_point(px, py)
    n = px.size - 1 if dup else px.size
    i = np.arange(px.size)
    if closed:
        nxt = np.mod(i + 1, n)
        prv = np.mod(i - 1, n)
    else:
        nxt, prv = np.minimum(i + 1, n - 1), np.maximum(i - 1, 0)
    tx, ty = px[nxt] - px[prv], py[nxt] - py[prv]
    c, s = np.cos(th), np.sin(th)
    beta = np.degrees(np.arctan2(tx * c + ty * s, -tx * s + ty * c))
    if not closed:
        beta[0] = beta[-1] = np.nan
    return beta


def pressure_angle_from_lift_samples(
    lift_mm: ArrayLike, base_radius_mm: float, cam_angle_deg: ArrayLike
) -> FloatArray:
    """The paper's whole numerical method from lift samples over one closed turn:
    contour x = l cos θ, y = l sin θ with l = h + Rb (Shinzato eq. above fig. 2), then
    :func:`pressure_angle_from_points`."""
    h = np.asarray(lift_mm, dtype=np.float64)
    th = np.radians(np.asarray(cam_angle_deg, dtype=np.float64))
    r = h + base_radius_mm
    return pressure_angle_from_points(r * np.cos(th), r * np.sin(th), cam_angle_deg)


# ============================================================================ base circle
@dataclass(frozen=True)
class BaseCircleResult:
    """The smallest base radius meeting the limits and which one decided it.

    ``active_constraint``: ``"pressure_angle"``, ``"radius_of_curvature"`` or
    ``"geometry"`` (no limit binds; the smallest radius the follower geometry allows).
    """

    base_radius_mm: float
    active_constraint: str
    max_pressure_angle_deg: float
    min_radius_of_curvature_mm: float
    radius_for_pressure_angle_mm: float | None
    radius_for_curvature_mm: float | None


def _lower_bound(spec: CamSpec) -> float:
    f = spec.follower
    rr = f.roller_radius_mm if f.type == "roller" else 0.0
    lo = 0.0
    if f.motion == "translating" and f.type != "flat-faced":
        lo = max(lo, abs(f.offset_mm) - rr)
    if f.motion == "oscillating" and f.type != "flat-faced":
        lo = max(lo, abs(float(f.pivot_distance_mm) - float(f.arm_length_mm)) - rr)  # type: ignore[arg-type]
    return lo


def _solve_radius(spec: CamSpec, margin: Callable[[CamSpec], float], what: str) -> float:
    """Smallest Rb with margin(spec(Rb)) ≥ 0 (margin assumed to grow with Rb).

    Brackets the root by doubling, then the Illinois variant of regula falsi (superlinear on
    the smooth margins of the pressure angle and curvature, and never leaving the bracket);
    where the geometry cannot be assembled the margin is unknown and the step bisects.
    Stops at 1e-10 relative.
    """
    lo = _lower_bound(spec)
    span = max(1.0, spec.base_radius_mm)

    def at(rb: float) -> float:
        s = replace(spec, base_radius_mm=rb)
        try:
            validate(s)
        except GeometryError:
            return -math.inf
        return float(margin(s))

    hi = max(lo * 1.5, span)
    for _ in range(60):
        f_hi = at(hi)
        if f_hi >= 0:
            break
        hi = 2 * hi + 1.0
    else:
        raise GeometryError(f"No base radius up to {hi!r} mm meets the {what} limit.")
    a, b = lo, hi
    f_a, f_b = at(a) if a > 0 else -math.inf, f_hi
    side = 0
    for _ in range(200):
        if b - a <= 1e-10 * max(1.0, b) or f_b == 0:  # f_b = 0: the limit is met exactly at b
            break
        if math.isfinite(f_a) and f_b > f_a:
            m = b - f_b * (b - a) / (f_b - f_a)
            if not a < m < b:
                m = 0.5 * (a + b)
        else:
            m = 0.5 * (a + b)
        f_m = at(m)
        if f_m >= 0:
            b, f_b = m, f_m
            if side == 1 and math.isfinite(f_a):
                f_a *= 0.5  # Illinois: halve the stale end so the bracket shrinks from both sides
            side = 1
        else:
            a, f_a = m, f_m
            if side == -1:
                f_b *= 0.5
            side = -1
    return b


def size_base_circle(
    spec: CamSpec,
    max_pressure_angle_deg: float | None = None,
    min_radius_of_curvature_mm: float | None = None,
) -> BaseCircleResult:
    """Smallest base radius with max |pressure angle| ≤ the limit and min radius of curvature
    ≥ the limit (either may be None). Flat-faced followers always need a convex cam
    (ρ > 0): a missing curvature limit means 0.

    Each limit is solved on its own by bisection to 1e-10 relative on the exact extremes
    over the cam angle (grid + golden section, :func:`profile_checks`); the answer is the
    larger radius. For translating followers the pressure angle tan φ = (s' − σe)/(s0 + s)
    falls monotonically as Rb grows; the flat-faced translating case is closed form,
    Rb = ρreq − min(s + s'').
    """
    f = spec.follower
    if max_pressure_angle_deg is not None and not (0 < max_pressure_angle_deg < 90):
        raise InvalidParameterError("max_pressure_angle_deg must lie between 0 and 90 degrees.")
    if min_radius_of_curvature_mm is not None and not (math.isfinite(min_radius_of_curvature_mm)
                                                       and min_radius_of_curvature_mm >= 0):
        raise InvalidParameterError("min_radius_of_curvature_mm must be a finite number ≥ 0.")
    if f.type == "flat-faced" and min_radius_of_curvature_mm is None:
        min_radius_of_curvature_mm = 0.0
    if max_pressure_angle_deg is None and min_radius_of_curvature_mm is None:
        raise InvalidParameterError("Give a pressure-angle limit, a curvature limit, or both.")
    r_p: float | None = None
    r_c: float | None = None
    if max_pressure_angle_deg is not None and f.type != "flat-faced":
        lim = max_pressure_angle_deg
        r_p = _solve_radius(spec, lambda s: lim - profile_checks(s).max_pressure_angle_deg, "pressure-angle")
    if min_radius_of_curvature_mm is not None:
        req = min_radius_of_curvature_mm
        if _corners(spec):
            raise GeometryError("The lift's velocity jumps, so the cam has a corner (radius 0) at any base radius.")
        if f.type == "flat-faced" and f.motion == "translating":
            grid = _check_grid(spec)
            br = np.asarray(spec.lift.breaks_rad, dtype=np.float64)

            def neg_ss(t: FloatArray) -> FloatArray:
                v = spec.lift.derivatives(t, 2)
                return -(v[0] + v[2])

            _, m = _exact_max(neg_ss, grid, br)
            # ρ = Rb + s + s'' > req strictly at the minimum would need Rb > req − min; take equality
            r_c = req + m
            if r_c <= 0:
                r_c = None
        else:
            def curvature_margin(s: CamSpec) -> float:
                c = profile_checks(s)
                # an undercut cam fails however large its nominal radius: a negative margin
                return c.min_radius_of_curvature_mm - req if not c.undercut else -1.0 - abs(c.min_radius_of_curvature_mm)

            r_c = _solve_radius(spec, curvature_margin, "radius-of-curvature")
    candidates = [(r, n) for r, n in ((r_p, "pressure_angle"), (r_c, "radius_of_curvature")) if r is not None]
    if candidates:
        rb, active = max(candidates)
    else:
        rb, active = max(_lower_bound(spec), 1e-9), "geometry"
    final = replace(spec, base_radius_mm=rb)
    validate(final)
    ch = profile_checks(final)
    return BaseCircleResult(rb, active, ch.max_pressure_angle_deg, ch.min_radius_of_curvature_mm, r_p, r_c)


__all__ = [
    "BaseCircleResult", "CamSpec", "CurveLift", "Follower", "Lift", "LiftSchedule", "ProfileChecks",
    "ProfileResult", "Segment", "chord_convexity", "compute_profile", "contour", "make_cam",
    "pressure_angle_from_lift_samples", "pressure_angle_from_points", "profile_checks", "sample_profile",
    "size_base_circle", "validate",
]

