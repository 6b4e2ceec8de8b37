"""Plate-cam profiles: cam surface, pitch curve, pressure angle, radius of curvature.

Map: :mod:`.lift` (the lift over one turn: segments, a user curve, a motion program), :mod:`.followers` (one class per follower
type and motion), :mod:`.cam` (the cam: spec, geometry checks, kinematics),
:mod:`.compute` (a profile at given angles), :mod:`.checks` (exact extremes over the
turn), :mod:`.base_circle` (sizing), :mod:`.points` (profiles given only as points).
"""

from .base_circle import BaseCircleResult, size_base_circle
from .cam import CamSpec, kinematics, make_cam, validate
from .checks import ProfileChecks, profile_checks
from .compute import ProfileResult, compute_profile, contour, sample_profile
from .followers import FOLLOWERS, Follower, FollowerModel, follower_model
from .lift import CurveLift, Lift, LiftSchedule, MotionLift, Segment
from .points import chord_convexity, pressure_angle_from_lift_samples, pressure_angle_from_points

__all__ = [
    "FOLLOWERS", "BaseCircleResult", "CamSpec", "CurveLift", "Follower", "FollowerModel", "Lift", "LiftSchedule",
    "MotionLift", "ProfileChecks", "ProfileResult", "Segment", "chord_convexity", "compute_profile", "contour", "follower_model",
    "kinematics", "make_cam", "pressure_angle_from_lift_samples", "pressure_angle_from_points", "profile_checks",
    "sample_profile", "size_base_circle", "validate",
]
