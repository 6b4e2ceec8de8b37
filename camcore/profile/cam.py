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
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from ..curves.base import FloatArray
from ..errors import CamError, GeometryError, InvalidParameterError
from ..motion.program import MotionProgram
from .followers import Follower, FollowerModel, Kinematics, check_follower, follower_model
from .lift import TWO_PI, CurveLift, LiftSchedule, MotionLift, Segment


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

    @property
    def model(self) -> FollowerModel:
        """The follower's behaviour (:mod:`.followers`)."""
        return follower_model(self.follower)


def make_cam(
    follower: Follower,
    base_radius_mm: float,
    *,
    segments: Sequence[Segment] | None = None,
    lift_curve: Any = None,
    motion: MotionProgram | None = None,
    rotation: Literal["ccw", "cw"] = "ccw",
    rotation_ratio: float = 1.0,
) -> CamSpec:
    """Build and validate a :class:`CamSpec` from segments, one user lift curve or a motion program.

    Parameters
    ----------
    follower : Follower
        Type, motion and dimensions of the follower.
    base_radius_mm : float
        Rb, the smallest radius of the cam surface (> 0) [mm].
    segments : sequence of Segment, optional
        Rise / dwell / return segments over one cam turn (their angles add to 360°).
    lift_curve : Curve, optional
        One user lift curve over the drive angle (a Bezier or points curve with a scale).
    motion : MotionProgram, optional
        A closed motion program over the drive angle (:func:`camcore.motion.resolve_motion`),
        in mm for a translating follower, in degrees of swing for an oscillating one.
        Give exactly one of ``segments``, ``lift_curve`` and ``motion``.
    rotation : {"ccw", "cw"}
        Sense of the cam's rotation.
    rotation_ratio : float
        γ, cam turns per drive turn (user lift curves and motion programs) [-].

    Returns
    -------
    CamSpec
        The cam, its lift in mm (translating followers) or degrees of swing (oscillating).

    Raises
    ------
    InvalidParameterError, GeometryError
        As :func:`validate`; not exactly one lift; a motion program in the other unit.

    References
    ----------
    Bezier valve-cam notes, eqs. (4)-(5) and (12) (rotation ratio γ = ω_cam/ω_dr,
    θcam = γ·θdr); Makino (1977), subroutine CURVE (INIT = 2: the return strokes).
    """
    unit = "deg" if follower.motion == "oscillating" else "mm"
    if sum(given is not None for given in (segments, lift_curve, motion)) != 1:
        raise InvalidParameterError("Give the lift as segments, as one lift curve or as a motion program (one of them).")
    lift: Any
    if segments is not None:
        lift = LiftSchedule(segments, unit=unit)
    elif lift_curve is not None:
        lift = CurveLift(lift_curve, rotation_ratio, unit)
    else:
        assert motion is not None
        lift = _motion_lift(motion, unit, follower.motion, rotation_ratio)
    spec = CamSpec(follower, base_radius_mm, lift, rotation)
    validate(spec)
    return spec


def _motion_lift(motion: MotionProgram, unit: str, follower_motion: str, rotation_ratio: float) -> MotionLift:
    """The program as the lift, its errors located in ``motion`` (the argument)."""
    try:
        if motion.unit != unit:
            raise InvalidParameterError(
                f"the motion program is in {motion.unit!r}, but the lift of a {follower_motion} follower is in "
                f"{unit!r} ({'degrees of swing' if unit == 'deg' else 'mm of travel'}).", field=("unit",))
        return MotionLift(motion, rotation_ratio)
    except CamError as exc:
        if exc.field != ("rotation_ratio",):  # γ is the cam's own argument, not the program's
            exc.field = ("motion", *exc.field)
        raise


def validate(spec: CamSpec) -> None:
    """Raise :class:`GeometryError` / :class:`InvalidParameterError` with the reason.

    Checks the rotation, Rb > 0, a roller radius > 0 for rollers, the follower's assembly
    (:meth:`FollowerModel.check`), a finite lift ≥ 0 on a 0.5° grid and the arm's swing.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.

    Raises
    ------
    GeometryError
        The cam cannot be assembled or run.
    InvalidParameterError
        A value out of its range.

    References
    ----------
    Shinzato and Kunigami (1988): the lift measured from the base circle, l = y + D/2
    (so the lift must be ≥ 0).
    """
    model = spec.model
    f = spec.follower
    if spec.rotation not in ("ccw", "cw"):
        raise InvalidParameterError(f"rotation must be 'ccw' or 'cw', not {spec.rotation!r}.")
    rb = spec.base_radius_mm
    if not (math.isfinite(rb) and rb > 0):
        raise GeometryError(f"The base radius must be positive (it is {rb!r} mm).")
    check_follower(f)
    if not math.isfinite(f.offset_mm):
        raise InvalidParameterError("offset_mm must be finite.")
    model.check(rb)
    h = spec.lift.derivatives(np.linspace(0.0, TWO_PI, 721), 0)[0]
    if not np.all(np.isfinite(h)):
        raise InvalidParameterError("The lift is not finite everywhere.")
    if h.min() < -1e-9 * max(1.0, float(np.abs(h).max())):
        raise GeometryError(
            f"The lift goes below zero ({float(h.min())!r}); the base circle is the smallest radius of the cam, "
            "so the lift must be ≥ 0.")
    model.check_swing(rb, h)


def kinematics(spec: CamSpec, theta: FloatArray) -> Kinematics:
    """Fixed-frame kinematics of the cam at cam angles θ [rad] (see :mod:`.followers`).

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    theta : ndarray
        Cam angles θ [rad].

    Returns
    -------
    Kinematics
        Contact and pitch points, pressure angle and curvatures in the fixed frame.

    References
    ----------
    Shinzato and Kunigami (1988), eq. (6) (pressure angle of the in-line knife-edge);
    Bezier valve-cam notes, eqs. (11)-(12) (flat tappet contact offset, rotation ratio).
    """
    return spec.model.kinematics(spec.base_radius_mm, spec.sigma, theta, spec.lift.derivatives(theta, 2))


def rotate(x: FloatArray, y: FloatArray, ang: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(x, y) turned by the angles ang [rad].

    Parameters
    ----------
    x, y : ndarray
        Points [mm].
    ang : ndarray
        Angles of rotation, counter-clockwise positive [rad].

    Returns
    -------
    (ndarray, ndarray)
        x cos a − y sin a and x sin a + y cos a [mm].

    References
    ----------
    Shinzato and Kunigami (1988): the contour x = l cos θ, y = l sin θ in the cam's frame
    (kinematic inversion: the fixed-frame point turned back by the cam angle).
    """
    (turned,) = rotate_all(ang, (x, y))
    return turned


def rotate_all(ang: FloatArray, *points: tuple[FloatArray, FloatArray]) -> list[tuple[FloatArray, FloatArray]]:
    """Several sets of points (x, y) turned by the same angles, the sines taken once.

    Parameters
    ----------
    ang : ndarray
        Angles of rotation, counter-clockwise positive [rad].
    *points : (ndarray, ndarray)
        Each an x and a y [mm].

    Returns
    -------
    list of (ndarray, ndarray)
        Each set turned, as :func:`rotate` turns it [mm].

    References
    ----------
    Shinzato and Kunigami (1988), kinematic inversion.
    """
    c, s = np.cos(ang), np.sin(ang)
    return [(c * x - s * y, s * x + c * y) for x, y in points]
