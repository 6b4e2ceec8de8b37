"""The barrel cam and its geometry: dimensions, the follower's state over the cam angle, the
contact along the roller (the frames and formulas: :mod:`camcore.cams.barrel`).

References
----------
.. [1] Shinzato and Kunigami (1988), eq. (6): the pressure angle, atan(s'/radius of the contact).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ..._maxima import periodic_grid_max
from ...curves.base import FloatArray
from ...errors import CamError, GeometryError, InvalidParameterError
from ...motion.program import MotionProgram
from ...profile.checks import lift_check_grid as check_grid
from ...profile.lift import Lift, LiftSchedule, MotionLift, Segment

Roller = Literal["cylindrical", "conical"]
FollowerMotion = Literal["translating", "oscillating"]

#: largest arm angle [deg]: at 90° the roller would move along the cam axis no more
MAX_ARM_ANGLE_DEG = 89.0


@dataclass(frozen=True)
class BarrelCam:
    """A barrel cam: pitch radius, roller, follower and lift (see the module notes).

    ``lift`` is in mm for a translating follower and in degrees of swing for an oscillating one;
    ``initial_arm_angle_deg`` is ψ0, the arm angle at zero swing.
    """

    pitch_radius_mm: float
    roller_radius_mm: float
    roller_length_mm: float
    groove_depth_mm: float
    lift: Lift
    roller: Roller = "cylindrical"
    follower: FollowerMotion = "translating"
    arm_length_mm: float | None = None
    initial_arm_angle_deg: float = 0.0

    @property
    def cone_half_angle_rad(self) -> float:
        """α of a conical roller (apex on the cam axis): tan α = ρ/R; 0 for a cylinder [rad]."""
        return math.atan2(self.roller_radius_mm, self.pitch_radius_mm) if self.roller == "conical" else 0.0

    @property
    def roller_ends_mm(self) -> tuple[float, float]:
        """x_in, x_out: the roller's ends along its axis [mm]."""
        half = 0.5 * self.roller_length_mm
        return self.pitch_radius_mm - half, self.pitch_radius_mm + half


def check_barrel_geometry(pitch_radius_mm: float, roller_radius_mm: float, roller_length_mm: float,
                          groove_depth_mm: float, roller: str, follower: str, arm_length_mm: float | None) -> None:
    """Raise with the rule when the dimensions cannot make a barrel cam (the lift apart).

    Parameters
    ----------
    pitch_radius_mm, roller_radius_mm, roller_length_mm, groove_depth_mm : float
        R, ρ (at the pitch radius), ℓ, and the groove's depth from the cylinder's outer radius
        R + ℓ/2 [mm].
    roller : {"cylindrical", "conical"}
        The roller's shape.
    follower : {"translating", "oscillating"}
        The follower's motion.
    arm_length_mm : float or None
        L of an oscillating follower [mm].

    Raises
    ------
    GeometryError, InvalidParameterError
        With a sentence naming the field and the rule.

    References
    ----------
    The module notes (frames, roller ends, the conical roller's apex).
    """
    for name, value in (("pitch_radius_mm", pitch_radius_mm), ("roller_radius_mm", roller_radius_mm),
                        ("roller_length_mm", roller_length_mm), ("groove_depth_mm", groove_depth_mm)):
        if not (math.isfinite(value) and value > 0):
            raise InvalidParameterError(f"{name} must be a finite number greater than 0, got {value!r}.",
                                        field=(name,))
    if roller not in ("cylindrical", "conical"):
        raise InvalidParameterError(f"roller must be 'cylindrical' or 'conical', not {roller!r}.", field=("roller",))
    if follower not in ("translating", "oscillating"):
        raise InvalidParameterError(f"follower must be 'translating' or 'oscillating', not {follower!r}.",
                                    field=("follower",))
    if not roller_length_mm < 2 * pitch_radius_mm:
        raise GeometryError(
            f"roller_length_mm ({roller_length_mm!r}) must be less than twice pitch_radius_mm ({pitch_radius_mm!r}): "
            "the roller is centred on the pitch radius, and its inner end would reach the cam axis.",
            field=("roller_length_mm",))
    if groove_depth_mm < roller_length_mm:
        raise GeometryError(
            f"groove_depth_mm ({groove_depth_mm!r}) must be at least roller_length_mm ({roller_length_mm!r}): the "
            "roller's inner end would run on the bottom of the groove.", field=("groove_depth_mm",))
    if not groove_depth_mm < pitch_radius_mm + 0.5 * roller_length_mm:
        raise GeometryError(
            f"groove_depth_mm ({groove_depth_mm!r}) must be less than the cam's outer radius, pitch_radius_mm + "
            f"roller_length_mm/2 = {pitch_radius_mm + 0.5 * roller_length_mm!r}: the groove would cut through the axis.",
            field=("groove_depth_mm",))
    if follower == "oscillating":
        if arm_length_mm is None or not (math.isfinite(arm_length_mm) and arm_length_mm > 0):
            raise InvalidParameterError("an oscillating follower needs arm_length_mm > 0.", field=("arm_length_mm",))
        if roller == "conical":
            raise GeometryError(
                "a conical roller needs its apex on the cam axis to roll, and an oscillating arm moves the roller's "
                "axis off the cam axis: use a cylindrical roller on an oscillating follower.", field=("roller",))


def make_barrel_cam(pitch_radius_mm: float, roller_radius_mm: float, *, roller_length_mm: float | None = None,
                    groove_depth_mm: float | None = None, segments: Sequence[Segment] | None = None,
                    motion: MotionProgram | None = None, roller: Roller = "cylindrical",
                    follower: FollowerMotion = "translating", arm_length_mm: float | None = None,
                    initial_arm_angle_deg: float = 0.0) -> BarrelCam:
    """Build and check a :class:`BarrelCam` from segments or a motion program.

    Parameters
    ----------
    pitch_radius_mm : float
        R, the radius at which the developed groove is drawn [mm].
    roller_radius_mm : float
        ρ, the roller's radius (a cone's at the pitch radius) [mm].
    roller_length_mm : float, optional
        ℓ, the roller's working length, centred on the pitch radius; default ρ [mm].
    groove_depth_mm : float, optional
        The groove's depth below the cam's outer radius R + ℓ/2; default ℓ [mm].
    segments : sequence of Segment, optional
        Rise / dwell / return over one cam turn (lift_mm, or swing_deg for an oscillating follower).
    motion : MotionProgram, optional
        A closed motion program over one cam turn (mm, or deg of swing). Exactly one of the two.
    roller : {"cylindrical", "conical"}
        The roller's shape (a cone has its apex on the cam axis: tan α = ρ/R).
    follower : {"translating", "oscillating"}
        The follower's motion.
    arm_length_mm : float, optional
        L, oscillating follower only [mm].
    initial_arm_angle_deg : float
        ψ0, the arm angle at zero swing (oscillating) [deg].

    Returns
    -------
    BarrelCam
        The checked cam.

    Raises
    ------
    InvalidParameterError, GeometryError
        A value out of range; dimensions that cannot be built (:func:`check_barrel_geometry`);
        an arm that turns to ±89° or moves the roller's axis off the pitch cylinder.

    References
    ----------
    The module notes; Makino (1977), subroutine CURVE (returns play the rise backwards).
    """
    length = roller_radius_mm if roller_length_mm is None else roller_length_mm
    depth = length if groove_depth_mm is None else groove_depth_mm
    check_barrel_geometry(pitch_radius_mm, roller_radius_mm, length, depth, roller, follower, arm_length_mm)
    if not (math.isfinite(initial_arm_angle_deg) and abs(initial_arm_angle_deg) < MAX_ARM_ANGLE_DEG):
        raise InvalidParameterError(f"initial_arm_angle_deg must lie within ±{MAX_ARM_ANGLE_DEG}°.",
                                    field=("initial_arm_angle_deg",))
    unit = "deg" if follower == "oscillating" else "mm"
    if (segments is None) == (motion is None):
        raise InvalidParameterError("give the lift as segments or as a motion program (one of them).")
    lift: Lift
    if segments is not None:
        lift = LiftSchedule(segments, unit=unit)
    else:
        assert motion is not None
        try:
            if motion.unit != unit:
                raise InvalidParameterError(
                    f"the motion program is in {motion.unit!r}, but the lift of a {follower} follower is in {unit!r}.",
                    field=("unit",))
            lift = MotionLift(motion)
        except CamError as exc:
            exc.field = ("motion", *exc.field)
            raise
    cam = BarrelCam(pitch_radius_mm, roller_radius_mm, length, depth, lift, roller, follower, arm_length_mm,
                    initial_arm_angle_deg)
    if follower == "oscillating":
        _check_arm(cam)
    return cam


def _check_arm(cam: BarrelCam) -> None:
    """The arm stays within ±89° and the roller's axis keeps crossing the pitch cylinder."""
    grid = check_grid(cam.lift)
    breaks = np.asarray(cam.lift.breaks_rad, dtype=np.float64)
    _, top = periodic_grid_max(lambda t: cam.lift.derivatives(t, 0)[0], grid, breaks)
    _, neg = periodic_grid_max(lambda t: -cam.lift.derivatives(t, 0)[0], grid, breaks)
    extremes = [cam.initial_arm_angle_deg + top, cam.initial_arm_angle_deg - neg]
    worst = max(extremes, key=abs)
    if not abs(worst) < MAX_ARM_ANGLE_DEG:
        raise GeometryError(
            f"the arm turns to {worst!r}° (initial_arm_angle_deg plus the swing); it must stay within "
            f"±{MAX_ARM_ANGLE_DEG}° of square to the cam axis.", field=("initial_arm_angle_deg",))
    assert cam.arm_length_mm is not None
    offset = cam.arm_length_mm * (1.0 - math.cos(math.radians(worst)))
    if not offset < cam.roller_ends_mm[0]:
        raise GeometryError(
            f"at an arm angle of {worst!r}° the roller's axis lies {offset!r} mm off the cam axis, beyond the radius of "
            f"the roller's inner end ({cam.roller_ends_mm[0]!r} mm): shorten arm_length_mm or reduce the swing.",
            field=("arm_length_mm",))


# ---------------------------------------------------------------------------- kinematics
@dataclass(frozen=True)
class _State:
    """The follower's state at cam angles θ (arrays, fixed frame unless said)."""

    theta: FloatArray
    lift: FloatArray  # mm or deg
    b_y: FloatArray  # the roller axis's offset from the cam axis [mm]
    b_z: FloatArray  # its axial position [mm]
    arm: FloatArray  # ψa [rad] (0 for translating)
    rate: FloatArray  # s' [mm/rad] (translating) or ψ'L [mm/rad] (oscillating)
    u: FloatArray  # developed pitch curve and its first two derivatives [mm, mm/rad, mm/rad²]
    y: FloatArray
    u1: FloatArray
    y1: FloatArray
    u2: FloatArray
    y2: FloatArray


def _state(cam: BarrelCam, theta: FloatArray, radius_mm: float | None = None,
           lift: tuple[FloatArray, FloatArray, FloatArray] | None = None) -> _State:
    """The follower's state, its developed curve drawn on the cylinder of ``radius_mm`` (default R);
    ``lift``: the lift and its two derivatives at θ when the caller has them (several radii at once)."""
    h, h1, h2 = cam.lift.derivatives(theta, 2) if lift is None else lift
    r = cam.pitch_radius_mm if radius_mm is None else radius_mm
    if cam.follower == "translating":
        zero = np.zeros_like(h)
        return _State(theta, h, zero, h, zero, h1, r * theta, h, np.full_like(h, r), h1, zero, h2)
    length = float(cam.arm_length_mm)  # type: ignore[arg-type]  # checked: oscillating has an arm
    arm = math.radians(cam.initial_arm_angle_deg) + np.radians(h)
    p1, p2 = np.radians(h1), np.radians(h2)
    c, s = np.cos(arm), np.sin(arm)
    b_y, b_z = length * (c - 1.0), length * s
    by1 = -length * s * p1
    by2 = -length * (c * p1 * p1 + s * p2)
    # u = R(θ + asin(b_y/R)): derivatives of g = asin(b_y/R)
    root = np.sqrt(r * r - b_y * b_y)
    g1 = by1 / root
    g2 = by2 / root + b_y * by1 * by1 / root**3
    u = r * (theta + np.arcsin(b_y / r))
    return _State(theta, h, b_y, b_z, arm, length * p1, u, b_z, r * (1.0 + g1), length * c * p1,
                  r * g2, length * (c * p2 - s * p1 * p1))


def _pressure(cam: BarrelCam, st: _State, x: FloatArray | float) -> FloatArray:
    """Signed pressure angle at axis position x [rad] (positive while the follower is driven to +z)."""
    if cam.follower == "translating":
        return np.arctan2(math.cos(cam.cone_half_angle_rad) ** 2 * st.rate, x)
    return np.arctan2(st.rate - x * np.sin(st.arm), x * np.cos(st.arm))


def _pitch_x(cam: BarrelCam, st: _State) -> FloatArray:
    """The position along the roller's axis where it crosses the pitch cylinder [mm]."""
    return np.sqrt(cam.pitch_radius_mm**2 - st.b_y**2)


def _curvature(st: _State) -> FloatArray:
    """Signed curvature of the developed pitch curve, positive bending towards +y [1/mm]."""
    return (st.u1 * st.y2 - st.y1 * st.u2) / np.hypot(st.u1, st.y1) ** 3


def flank_points(cam: BarrelCam, cam_angle_deg: ArrayLike, positions_mm: ArrayLike
                 ) -> dict[str, tuple[FloatArray, FloatArray, FloatArray]]:
    """Both flanks in 3-D in the cam's frame: the contact points along the roller's length.

    Parameters
    ----------
    cam : BarrelCam
        The cam.
    cam_angle_deg : array_like
        Cam angles θ, shape (n,) [deg].
    positions_mm : array_like
        Positions x along the roller's axis, shape (m,), from x_in to x_out [mm].

    Returns
    -------
    dict
        ``"upper"`` and ``"lower"`` (the +z and −z walls of the groove): (x, y, z), each of
        shape (n, m), in the cam's frame (z the cam axis) [mm].

    References
    ----------
    The module notes (the envelope condition).
    """
    theta = np.radians(np.asarray(cam_angle_deg, dtype=np.float64)).reshape(-1)
    x = np.asarray(positions_mm, dtype=np.float64).reshape(1, -1)
    st = _state(cam, theta)
    fixed = _fixed_flanks(cam, st.b_y[:, None], st.b_z[:, None], st.rate[:, None], st.arm[:, None], x)
    cos_t, sin_t = np.cos(theta)[:, None], np.sin(theta)[:, None]
    out = {}
    for name, (py, pz) in fixed.items():
        xx = np.broadcast_to(x, py.shape)
        out[name] = (cos_t * xx - sin_t * py, sin_t * xx + cos_t * py, np.array(pz))
    return out


def _fixed_flanks(cam: BarrelCam, b_y: FloatArray, b_z: FloatArray, rate: FloatArray, arm: FloatArray,
                  x: FloatArray, sides: tuple[str, ...] = ("upper", "lower")) -> dict[str, tuple[FloatArray, FloatArray]]:
    """Both flanks' contact points in the fixed frame at positions x along the roller's axis:
    (y, z) of each side asked for, the follower's state broadcast against x (the module notes'
    envelope)."""
    shape = np.broadcast_shapes(np.shape(b_y), np.shape(x))
    if cam.follower == "translating":
        a = np.broadcast_to(math.cos(cam.cone_half_angle_rad) ** 2 * rate, shape)
        c = np.broadcast_to(x, shape)
    else:
        a = np.broadcast_to(rate * np.cos(arm), shape)
        c = np.broadcast_to(x - rate * np.sin(arm), shape)
    norm = np.hypot(a, c)
    ny, nz = -a / norm, c / norm
    radius = np.tan(cam.cone_half_angle_rad) * x if cam.roller == "conical" else np.full_like(x, cam.roller_radius_mm)
    signs = {"upper": 1.0, "lower": -1.0}
    return {name: (b_y + signs[name] * radius * ny, b_z + signs[name] * radius * nz) for name in sides}


def flank_on_cylinder(cam: BarrelCam, cam_angle_rad: ArrayLike, radius_mm: ArrayLike,
                      iterations: int = 60) -> dict[str, tuple[FloatArray, FloatArray, FloatArray]]:
    """Both flanks where they cross the cylinder of a radius about the cam axis, pointwise.

    The contact at position x along the roller's axis lies at (x, y(x)) across the cam axis in
    the fixed frame, so at radius r = √(x² + y(x)²): x is found by the fixed point
    x ← √(r² − y(x)²), which contracts by |y·dy/dx|/x (y moves by the roller's radius as the
    contact normal turns, slowly along the roller): 6 steps to rounding for the request examples,
    13 for a 12 mm roller on a 30 mm pitch radius climbing 30 mm in 120°; it stops when a step
    moves x by less than 1e-13 of the radius.

    Parameters
    ----------
    cam : BarrelCam
        The cam.
    cam_angle_rad : array_like
        Cam angles θ [rad].
    radius_mm : array_like
        Radii r about the cam axis, the same shape, each larger than the roller's reach across
        the axis there [mm].
    iterations : int
        The most fixed-point steps [-].

    Returns
    -------
    dict
        ``"upper"`` and ``"lower"``: (x, y, z) in the cam's frame, the shape of the inputs [mm].

    References
    ----------
    The module notes (the envelope condition); the contraction mapping theorem.
    """
    theta = np.asarray(cam_angle_rad, dtype=np.float64)
    r = np.broadcast_to(np.asarray(radius_mm, dtype=np.float64), theta.shape).reshape(-1)
    st = _state(cam, theta.reshape(-1))
    out = {}
    cos_t, sin_t = np.cos(theta.reshape(-1)), np.sin(theta.reshape(-1))
    for name in ("upper", "lower"):
        x = np.sqrt(np.maximum(r * r - st.b_y**2, 0.0))
        for _ in range(iterations):
            py, pz = _fixed_flanks(cam, st.b_y, st.b_z, st.rate, st.arm, x, (name,))[name]
            step = np.sqrt(np.maximum(r * r - py * py, 0.0)) - x
            x = x + step
            if not np.abs(step).max(initial=0.0) > 1e-13 * float(r.max(initial=1.0)):
                break
        py, pz = _fixed_flanks(cam, st.b_y, st.b_z, st.rate, st.arm, x, (name,))[name]
        out[name] = tuple(np.reshape(v, theta.shape) for v in (cos_t * x - sin_t * py, sin_t * x + cos_t * py, pz))
    return out  # type: ignore[return-value]
