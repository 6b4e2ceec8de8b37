"""A profile at given cam angles: the contour in the cam's frame, pitch curve, pressure
angle and radius of curvature, with the checks over the whole turn.

References
----------
.. [1] Shinzato and Kunigami (1988): knife-edge contour x = l cos θ, y = l sin θ,
   l = y + D/2; pressure angle eq. (6) (their table 1 is reproduced by the tests).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..curves.base import FloatArray
from ..errors import InvalidParameterError
from .cam import CamSpec, kinematics, rotate_all
from .checks import ProfileChecks, profile_checks
from .followers import Kinematics


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


def _in_cam_frame(spec: CamSpec, theta: FloatArray
                  ) -> tuple[Kinematics, tuple[FloatArray, FloatArray], tuple[FloatArray, FloatArray]]:
    """The kinematics at cam angles θ [rad], and the surface and pitch points turned back by
    the cam angle into the cam's own frame (kinematic inversion)."""
    k = kinematics(spec, theta)
    back = -spec.sigma * theta
    contact, pitch = rotate_all(back, k.contact, k.pitch)
    return k, contact, pitch


def contour(spec: CamSpec, cam_angle_deg: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Cam surface (x, y) and pitch curve (x, y) in the cam frame at these cam angles.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    cam_angle_deg : array_like
        Cam angles θ [deg].

    Returns
    -------
    (ndarray, ndarray, ndarray, ndarray)
        Surface x, y and pitch-curve x, y in the cam's own frame [mm].

    References
    ----------
    Shinzato and Kunigami (1988): knife-edge contour x = l cos θ, y = l sin θ,
    l = y + D/2 (kinematic inversion into the cam's frame).
    """
    _, (sx, sy), (px, py) = _in_cam_frame(spec, np.radians(np.asarray(cam_angle_deg, dtype=np.float64)))
    return sx, sy, px, py


def compute_profile(spec: CamSpec, cam_angle_deg: ArrayLike, checks: ProfileChecks | None = None) -> ProfileResult:
    """The profile at the given cam angles (degrees) and the checks over the whole turn.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    cam_angle_deg : array_like
        Cam angles θ, finite [deg].
    checks : ProfileChecks, optional
        This cam's :func:`~camcore.profile.checks.profile_checks`, if the caller kept them
        (they depend on neither the angles nor the answer's format).

    Returns
    -------
    ProfileResult
        Lift, surface and pitch curve [mm], pressure angle [deg] and radii of curvature [mm]
        at each angle, with :func:`~camcore.profile.checks.profile_checks` of the whole turn.

    Raises
    ------
    InvalidParameterError
        A non-finite cam angle.

    References
    ----------
    Shinzato and Kunigami (1988), eq. (6) (pressure angle; their table 1 is reproduced by
    the tests); Bezier valve-cam notes, eq. (11) (flat tappet contact offset).
    """
    ang = np.asarray(cam_angle_deg, dtype=np.float64).reshape(-1)
    if not np.all(np.isfinite(ang)):
        raise InvalidParameterError("cam_angle_deg must be finite numbers.")
    k, (sx, sy), (px, py) = _in_cam_frame(spec, np.radians(ang))
    with np.errstate(divide="ignore"):
        rho_p = 1.0 / k.kappa_pitch
    checks = profile_checks(spec) if checks is None else checks
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


def sample_profile(spec: CamSpec, samples: int = 361, checks: ProfileChecks | None = None) -> ProfileResult:
    """The profile at ``samples`` cam angles evenly over 0–360°, both ends included.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    samples : int
        Number of cam angles (≥ 2) [-]; 361 gives 1° steps.
    checks : ProfileChecks, optional
        This cam's checks, if the caller kept them (as :func:`compute_profile`).

    Returns
    -------
    ProfileResult
        As :func:`compute_profile`; the last point repeats the first (360° = 0°).

    References
    ----------
    Shinzato and Kunigami (1988): the contour sampled over one turn, 0° to 360°.
    """
    if samples < 2:
        raise InvalidParameterError("samples must be at least 2.")
    return compute_profile(spec, np.linspace(0.0, 360.0, samples), checks)
