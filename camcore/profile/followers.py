"""Followers: one class per follower type and motion, behind one interface.

Each class knows its geometry rules, the smallest base radius it can be assembled
with, and its kinematics: from the lift and its derivatives at cam angles θ to the
contact point, the pitch point, the pressure angle and the curvatures, in the fixed
frame (the cam's own frame follows by turning back by the cam angle, :mod:`.cam`).

Conventions (see :mod:`camcore.profile` for the frames): translating followers move along
+y on the line x = e; oscillating followers pivot at A = (d, 0) with an arm of length L;
a positive swing ψ moves the follower away from the cam. With J the rotation by +90° and
σ = ±1 the sense of rotation, the pitch curve's tangent and second derivative in the cam
frame are R(−σθ)u1 and R(−σθ)u2, u1 = c' − σJc, u2 = c'' − 2σJc' − c.

References
----------
.. [1] Shinzato and Kunigami (1988), eq. (6): in-line knife-edge tan φ = s'/(Rb + s).
.. [2] Bezier valve-cam notes, eq. (11): flat tappet contact offset = dh/dθ.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..curves.base import FloatArray
from ..errors import GeometryError, InvalidParameterError

FollowerType = Literal["knife-edge", "roller", "flat-faced"]
Motion = Literal["translating", "oscillating"]


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


@dataclass
class Kinematics:
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


class FollowerModel(ABC):
    """The behaviour of one follower type and motion."""

    #: whether the cam surface is the envelope of a flat face (else: offset of a pitch curve)
    flat_faced = False

    def __init__(self, follower: Follower):
        self.follower = follower

    @property
    def roller_radius_mm(self) -> float:
        """Rr of a roller; 0 for a knife-edge or a flat face [mm]."""
        return 0.0

    def check(self, base_radius_mm: float) -> None:
        """Raise :class:`GeometryError` if the follower cannot be assembled on this base circle."""

    def check_swing(self, base_radius_mm: float, lift: FloatArray) -> None:
        """Raise :class:`GeometryError` if the lift cannot be followed (oscillating arms)."""

    def min_base_radius_mm(self) -> float:
        """A lower bound of the base radius the geometry allows [mm]."""
        return 0.0

    @abstractmethod
    def kinematics(self, base_radius_mm: float, sigma: float, theta: FloatArray,
                   lift: list[FloatArray]) -> Kinematics:
        """Fixed-frame kinematics from the lift [h, h', h''] (per rad) at cam angles θ [rad]."""


# ----------------------------------------------------------------------------- point followers
class _PointFollower(FollowerModel):
    """Knife-edge and roller followers: a pitch point c(θ) and a surface offset by Rr."""

    @abstractmethod
    def pitch_point(self, base_radius_mm: float, h: FloatArray, h1: FloatArray, h2: FloatArray
                    ) -> tuple[FloatArray, ...]:
        """cx, cy, c'x, c'y, c''x, c''y and the follower point's velocity direction vx, vy."""

    def kinematics(self, base_radius_mm: float, sigma: float, theta: FloatArray,
                   lift: list[FloatArray]) -> Kinematics:
        """Pitch point from :meth:`pitch_point`, surface offset by Rr along the outward normal,
        φ = atan2(u1·v̂, −σ u1·(J v̂)), κp = −σ (u1 × u2)/|u1|³ [1/mm], ρ = 1/κp − Rr [mm]."""
        return self.kinematics_of(sigma, theta, lift, self.pitch_point(base_radius_mm, lift[0], lift[1], lift[2]))

    def kinematics_of(self, sigma: float, theta: FloatArray, lift: list[FloatArray],
                      pitch: tuple[FloatArray, ...]) -> Kinematics:
        """:meth:`kinematics` from the pitch point :meth:`pitch_point` gave (a caller that has it already)."""
        h, h1 = lift[0], lift[1]
        sg, rr = sigma, self.roller_radius_mm
        cx, cy, c1x, c1y, c2x, c2y, vx, vy = pitch
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
        return Kinematics(theta, h, h1, (sx, sy), (cx, cy), pressure, kappa, rho)


class KnifeEdgeTranslating(_PointFollower):
    """Knife-edge on the line x = e: c = (e, s0 + h), s0 = √(Rb² − e²)."""

    def check(self, base_radius_mm: float) -> None:
        """Rb + Rr must exceed the offset |e|, or the line of motion misses the base circle."""
        r = base_radius_mm + self.roller_radius_mm
        if not r > abs(self.follower.offset_mm):
            raise GeometryError(
                f"The base radius plus roller radius ({r!r} mm) must exceed the offset |e| = "
                f"{abs(self.follower.offset_mm)!r} mm, or the follower line misses the base circle.")

    def min_base_radius_mm(self) -> float:
        """|e| − Rr (at least 0): below it the line of motion misses the base circle [mm]."""
        return max(0.0, abs(self.follower.offset_mm) - self.roller_radius_mm)

    def pitch_point(self, base_radius_mm: float, h: FloatArray, h1: FloatArray, h2: FloatArray
                    ) -> tuple[FloatArray, ...]:
        """c = (e, s0 + h), c' = (0, h'), c'' = (0, h''), v̂ = (0, 1); s0 = √((Rb + Rr)² − e²) [mm]."""
        e = self.follower.offset_mm
        s0 = math.sqrt((base_radius_mm + self.roller_radius_mm) ** 2 - e * e)
        # np.zeros etc. of the shape: the *_like functions' numbers at a fraction of their call's cost
        zero, one = np.zeros(h.shape, h.dtype), np.ones(h.shape, h.dtype)
        return np.full(h.shape, e, h.dtype), s0 + h, zero, h1, zero, h2, zero, one


class RollerTranslating(KnifeEdgeTranslating):
    """Roller on the line x = e: the knife-edge's pitch curve, the surface offset by Rr."""

    @property
    def roller_radius_mm(self) -> float:
        """Rr, the roller's radius [mm]."""
        return self.follower.roller_radius_mm


class KnifeEdgeOscillating(_PointFollower):
    """Knife-edge on an arm L about the pivot (d, 0): B(α) = (d − L cos α, L sin α)."""

    def _arm(self) -> tuple[float, float]:
        d, arm = self.follower.pivot_distance_mm, self.follower.arm_length_mm
        assert d is not None and arm is not None  # checked by check()
        return float(d), float(arm)

    def alpha0(self, base_radius_mm: float) -> float:
        """Arm angle at base-circle contact, from |OB(α0)| = Rb + Rr [rad]."""
        d, arm = self._arm()
        r = base_radius_mm + self.roller_radius_mm
        return math.acos(np.clip((d * d + arm * arm - r * r) / (2 * d * arm), -1.0, 1.0))

    def check(self, base_radius_mm: float) -> None:
        """Needs d > 0, L > 0 and |d − L| < Rb + Rr < d + L, so the arm reaches the base circle."""
        d, arm = self.follower.pivot_distance_mm, self.follower.arm_length_mm
        if d is None or not (math.isfinite(d) and d > 0):
            raise GeometryError("An oscillating follower needs pivot_distance_mm > 0.")
        if arm is None or not (math.isfinite(arm) and arm > 0):
            raise GeometryError("An oscillating follower needs arm_length_mm > 0.")
        r = base_radius_mm + self.roller_radius_mm
        if not abs(d - arm) < r < d + arm:
            raise GeometryError(
                f"The arm cannot be assembled: the base-circle contact radius Rb + Rr = {r!r} mm must lie "
                f"strictly between |pivot distance − arm length| = {abs(d - arm)!r} mm and "
                f"pivot distance + arm length = {d + arm!r} mm.")

    def check_swing(self, base_radius_mm: float, lift: FloatArray) -> None:
        """The arm angle α0 + ψ (ψ = the lift [deg]) must stay inside (0, π): no swing through
        the line of centres."""
        _check_arm_angle(self.alpha0(base_radius_mm) + np.radians(lift))

    def min_base_radius_mm(self) -> float:
        """|d − L| − Rr (at least 0): the arm cannot reach a smaller base circle [mm]."""
        d, arm = self._arm()
        return max(0.0, abs(d - arm) - self.roller_radius_mm)

    def pitch_point(self, base_radius_mm: float, h: FloatArray, h1: FloatArray, h2: FloatArray
                    ) -> tuple[FloatArray, ...]:
        """B(α) = (d − L cos α, L sin α) at α = α0 + ψ, its θ-derivatives by the chain rule
        (ψ', ψ'' in deg per rad), and v̂ = (sin α, cos α) [mm]."""
        d, arm = self._arm()
        a = self.alpha0(base_radius_mm) + np.radians(h)
        a1, a2 = np.radians(h1), np.radians(h2)
        sa, ca = np.sin(a), np.cos(a)
        # B_α = L(sin α, cos α), B_αα = L(cos α, −sin α)
        c2x = arm * (ca * a1 * a1 + sa * a2)
        c2y = arm * (-sa * a1 * a1 + ca * a2)
        return d - arm * ca, arm * sa, arm * sa * a1, arm * ca * a1, c2x, c2y, sa, ca


class RollerOscillating(KnifeEdgeOscillating):
    """Roller on an arm: the knife-edge's pitch curve, the surface offset by Rr."""

    @property
    def roller_radius_mm(self) -> float:
        """Rr, the roller's radius [mm]."""
        return self.follower.roller_radius_mm


# ----------------------------------------------------------------------------- flat faces
class _FlatFollower(FollowerModel):
    """A flat face: a line with unit outward normal m at distance p from O (support
    function); the cam surface is its envelope, q = p m + (dp/dφn) J m, with radius
    ρ = p + d²p/dφn² = p + (p'' φn' − p' φn'')/φn'³ (primes: d/dθ). The face normal is
    parallel to the contact point's velocity, so the pressure angle is 0."""

    flat_faced = True

    @abstractmethod
    def support(self, base_radius_mm: float, sigma: float, h: FloatArray, h1: FloatArray, h2: FloatArray
                ) -> tuple[FloatArray, ...]:
        """p, p', p'', φn', φn'', mx, my."""

    @abstractmethod
    def face_offset(self, cx: FloatArray, cy: FloatArray) -> FloatArray:
        """Position of the contact along the face [mm]."""

    def kinematics(self, base_radius_mm: float, sigma: float, theta: FloatArray,
                   lift: list[FloatArray]) -> Kinematics:
        """Envelope of the face from its support function: contact q = p m + (dp/dφn) J m,
        ρ = p + (p'' φn' − p' φn'')/φn'³ [mm], pressure angle 0."""
        h, h1, h2 = lift[0], lift[1], lift[2]
        p, p1, p2, phi1, phi2, mx, my = self.support(base_radius_mm, sigma, h, h1, h2)
        with np.errstate(divide="ignore", invalid="ignore"):
            p_phi = p1 / phi1
            rho = p + (p2 * phi1 - p1 * phi2) / phi1**3
        cx = p * mx - p_phi * my  # p m + p_φ J m, J m = (−my, mx)
        cy = p * my + p_phi * mx
        with np.errstate(divide="ignore"):
            kappa = 1.0 / rho
        return Kinematics(theta, h, h1, (cx, cy), (cx, cy), np.zeros_like(theta), kappa, rho,
                          self.face_offset(cx, cy))


class FlatTranslating(_FlatFollower):
    """Face ⟂ the motion: p = Rb + s, φn = π/2 − σθ; contact offset = ds/dθ (valve-cam
    notes eq. 11), ρ = Rb + s + s''."""

    def support(self, base_radius_mm: float, sigma: float, h: FloatArray, h1: FloatArray, h2: FloatArray
                ) -> tuple[FloatArray, ...]:
        """Face ⟂ the motion: p = Rb + h, p' = h', p'' = h'', φn' = −σ, φn'' = 0, m = (0, 1)."""
        zero = np.zeros(h.shape, h.dtype)
        return base_radius_mm + h, h1, h2, np.full(h.shape, -sigma, h.dtype), zero, zero, np.ones(h.shape, h.dtype)

    def face_offset(self, cx: FloatArray, cy: FloatArray) -> FloatArray:
        """cx − e, the contact's distance from the stem axis along the face [mm]."""
        return cx - self.follower.offset_mm


class FlatOscillating(_FlatFollower):
    """Face through the pivot (d, 0): m = (sin α, cos α), p = d sin α, α0 = asin(Rb/d)."""

    def _pivot(self) -> float:
        d = self.follower.pivot_distance_mm
        assert d is not None  # checked by check()
        return float(d)

    def check(self, base_radius_mm: float) -> None:
        """Needs d > 0 and d > Rb: the pivot outside the base circle, so the face through it can touch."""
        d = self.follower.pivot_distance_mm
        if d is None or not (math.isfinite(d) and d > 0):
            raise GeometryError("An oscillating follower needs pivot_distance_mm > 0.")
        if not d > base_radius_mm:
            raise GeometryError(
                f"The pivot ({d!r} mm from the cam centre) must lie outside the base circle ({base_radius_mm!r} mm) "
                "for a flat face through the pivot to touch it.")

    def check_swing(self, base_radius_mm: float, lift: FloatArray) -> None:
        """The face angle asin(Rb/d) + ψ (ψ = the lift [deg]) must stay inside (0, π)."""
        _check_arm_angle(math.asin(base_radius_mm / self._pivot()) + np.radians(lift))

    def support(self, base_radius_mm: float, sigma: float, h: FloatArray, h1: FloatArray, h2: FloatArray
                ) -> tuple[FloatArray, ...]:
        """Face through the pivot: α = asin(Rb/d) + ψ, p = d sin α and its θ-derivatives,
        φn' = −α' − σ, φn'' = −α'', m = (sin α, cos α)."""
        d = self._pivot()
        a = math.asin(base_radius_mm / d) + np.radians(h)
        a1, a2 = np.radians(h1), np.radians(h2)
        p = d * np.sin(a)
        p1 = d * np.cos(a) * a1
        p2 = d * (np.cos(a) * a2 - np.sin(a) * a1 * a1)
        return p, p1, p2, -a1 - sigma, -a2, np.sin(a), np.cos(a)

    def face_offset(self, cx: FloatArray, cy: FloatArray) -> FloatArray:
        """Distance of the contact from the pivot along the face [mm]."""
        return np.hypot(cx - self._pivot(), cy)  # distance from the pivot along the face


def _check_arm_angle(alpha: FloatArray) -> None:
    if alpha.max() >= math.pi or alpha.min() <= 0:
        raise GeometryError("The swing turns the arm through the line of centres; the follower cannot run.")


#: the follower classes by (type, motion): a new follower is one class and one line here
FOLLOWERS: dict[tuple[str, str], type[FollowerModel]] = {
    ("knife-edge", "translating"): KnifeEdgeTranslating,
    ("roller", "translating"): RollerTranslating,
    ("flat-faced", "translating"): FlatTranslating,
    ("knife-edge", "oscillating"): KnifeEdgeOscillating,
    ("roller", "oscillating"): RollerOscillating,
    ("flat-faced", "oscillating"): FlatOscillating,
}
FOLLOWER_TYPES: tuple[str, ...] = tuple(dict.fromkeys(t for t, _ in FOLLOWERS))
FOLLOWER_MOTIONS: tuple[str, ...] = tuple(dict.fromkeys(m for _, m in FOLLOWERS))


def check_follower(follower: Follower) -> None:
    """The rules a follower's own fields must meet, whatever the cam (the service's spec
    calls this too, so the rule and its sentence exist once).

    Parameters
    ----------
    follower : Follower

    References
    ----------
    Shinzato and Kunigami (1988), fig. 1 (the follower geometry); docs/architecture.md,
    checks live once.
    """
    if follower.type == "roller" and not (math.isfinite(follower.roller_radius_mm) and follower.roller_radius_mm > 0):
        raise GeometryError(
            f"A roller follower needs a roller radius > 0 (roller_radius_mm > 0; it is {follower.roller_radius_mm!r} mm).")
    if follower.motion == "oscillating":
        d, arm = follower.pivot_distance_mm, follower.arm_length_mm
        if d is None or not (math.isfinite(d) and d > 0):
            raise GeometryError("An oscillating follower needs pivot_distance_mm > 0.")
        if follower.type != "flat-faced" and (arm is None or not (math.isfinite(arm) and arm > 0)):
            raise GeometryError("An oscillating follower needs arm_length_mm > 0.")


def follower_model(follower: Follower) -> FollowerModel:
    """The behaviour of this follower (its class from :data:`FOLLOWERS`).

    Parameters
    ----------
    follower : Follower
        Type (knife-edge, roller, flat-faced), motion (translating, oscillating) and dimensions.

    Returns
    -------
    FollowerModel
        An instance of the class registered for (type, motion).

    Raises
    ------
    InvalidParameterError
        An unknown type or motion.

    References
    ----------
    Shinzato and Kunigami (1988), eq. (6) (knife-edge); Bezier valve-cam notes, eq. (11)
    (flat tappet); docs/architecture.md, one class per follower type and motion.
    """
    if follower.type not in FOLLOWER_TYPES:
        raise InvalidParameterError(
            f"follower type must be {', '.join(FOLLOWER_TYPES[:-1])} or {FOLLOWER_TYPES[-1]}, not {follower.type!r}.")
    if follower.motion not in FOLLOWER_MOTIONS:
        raise InvalidParameterError(
            f"follower motion must be {' or '.join(FOLLOWER_MOTIONS)}, not {follower.motion!r}.")
    return FOLLOWERS[(follower.type, follower.motion)](follower)
