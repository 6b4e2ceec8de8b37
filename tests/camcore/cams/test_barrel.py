"""Barrel cams (camcore.cams.barrel), each result against an independent construction.

- pressure angle at the pitch radius = atan(s'/R), s' from the cycloid's closed form and, for a
  motion program, from a central difference of the lift;
- flank points lie on the roller (distance to the roller's axis segment, built here from the
  arm and the cam angle in 3-D) and outside the roller at every neighbouring cam angle (so
  they are the envelope, not just points of the roller);
- the pressure angle equals the angle between the contact normal taken from those points and
  the follower point's direction of motion (a numerical derivative of its position);
- the developed centreline of an oscillating follower against the roller's axis turned about
  the pivot and cut with the pitch cylinder; radii of curvature against a numerical curvature;
- bad geometry raises with the field named.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcore.cams.barrel import BarrelCam, flank_points, make_barrel_cam, sample_barrel
from camcore.cams.barrel import barrel_profile as profile
from camcore.errors import CamError, GeometryError
from camcore.motion import Law, MotionSegment, MotionSpec, resolve_motion
from camcore.profile import Segment

R, RHO, LENGTH = 50.0, 10.0, 12.0
RISE, BETA = 30.0, 2 * math.pi / 3  # cycloid 30 mm over 120°
CYCLOID = [Segment("rise", 120, lift_mm=RISE), Segment("dwell", 60), Segment("return", 120, lift_mm=RISE),
           Segment("dwell", 60)]
SWING = [Segment("rise", 120, swing_deg=30), Segment("dwell", 60), Segment("return", 120, swing_deg=30),
         Segment("dwell", 60)]
#: rest, matched quintic, constant velocity, matched quintic, rest, cycloid back (breaks at multiples of 30°)
FEED = MotionSpec([MotionSegment(30, type="dwell"), MotionSegment(60, to=10, law=Law("polynomial", {})),
                   MotionSegment(120, to=50, law=Law("named", {"name": "constant-velocity"})),
                   MotionSegment(60, to=60, law=Law("polynomial", {})), MotionSegment(30, type="dwell"),
                   MotionSegment(60, to=0)])
#: cam angles clear of every break point (multiples of 30°) by at least 0.2° (3.5e-3 rad, far wider than
#: the steps of the numerical derivatives below)
ANGLES = np.arange(3.7, 360.0, 11.3)


def cams() -> dict[str, BarrelCam]:
    return {
        "cylinder": make_barrel_cam(R, RHO, roller_length_mm=LENGTH, segments=CYCLOID),
        "cone": make_barrel_cam(R, RHO, roller_length_mm=LENGTH, segments=CYCLOID, roller="conical"),
        "motion": make_barrel_cam(R, RHO, roller_length_mm=LENGTH, motion=resolve_motion(FEED)),
        # the same program on a larger cylinder: no undercut anywhere across the roller's length
        "motion-80": make_barrel_cam(80.0, RHO, roller_length_mm=LENGTH, motion=resolve_motion(FEED)),
        "oscillating": make_barrel_cam(R, RHO, roller_length_mm=LENGTH, segments=SWING, follower="oscillating",
                                       arm_length_mm=80.0, initial_arm_angle_deg=-15.0),
    }


def cycloid_rate(theta: np.ndarray) -> np.ndarray:
    """ds/dθ of the schedule from the cycloid's closed form, s = h(x/β − sin(2πx/β)/2π) [mm/rad]."""
    t = np.mod(theta, 2 * math.pi)
    rate = np.zeros_like(t)
    rise = t < BETA
    back = (t >= math.pi) & (t < math.pi + BETA)
    rate[rise] = RISE / BETA * (1 - np.cos(2 * math.pi * t[rise] / BETA))
    rate[back] = -RISE / BETA * (1 - np.cos(2 * math.pi * (t[back] - math.pi) / BETA))
    return rate


def numeric_rate(cam: BarrelCam, theta: np.ndarray, h: float = 1e-5) -> np.ndarray:
    """Central difference of the lift values alone: error h²/6·|s'''| ≲ 1e-8 mm/rad here."""
    s = cam.lift.derivatives
    return (s(theta + h, 0)[0] - s(theta - h, 0)[0]) / (2 * h)


# ----------------------------------------------------------------------------- 3-D construction
def axis_fixed(cam: BarrelCam, theta: float) -> tuple[np.ndarray, np.ndarray]:
    """The roller axis's point x = 0 and direction in the fixed frame at cam angle θ."""
    return axis_at_lift(cam, float(cam.lift.derivatives(np.array([theta]), 0)[0][0]))


def axis_at_lift(cam: BarrelCam, h: float) -> tuple[np.ndarray, np.ndarray]:
    """The same at lift h, built from the follower: lifted along z, or the arm vector (0, L, 0)
    turned by the arm angle about the pivot axis (∥ x)."""
    if cam.follower == "translating":
        return np.array([0.0, 0.0, h]), np.array([1.0, 0.0, 0.0])
    length = float(cam.arm_length_mm)  # type: ignore[arg-type]
    a = math.radians(cam.initial_arm_angle_deg + h)
    turn = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    pivot = np.array([0.0, -length, 0.0])
    return pivot + turn @ np.array([0.0, length, 0.0]), np.array([1.0, 0.0, 0.0])


def to_cam(theta: float) -> np.ndarray:
    """The cam turns clockwise seen from +z: cam-frame coordinates are fixed ones turned by +θ."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def axis_cam(cam: BarrelCam, theta: float) -> tuple[np.ndarray, np.ndarray]:
    point, direction = axis_fixed(cam, theta)
    return to_cam(theta) @ point, to_cam(theta) @ direction


def signed_distance(cam: BarrelCam, p: np.ndarray, theta: float) -> float:
    """Signed distance from p to the roller's surface at cam angle θ (negative inside) [mm]."""
    q, e = axis_cam(cam, theta)
    w = p - q
    along = float(w @ e)
    off = float(np.linalg.norm(w - along * e))
    if cam.roller == "conical":
        alpha = cam.cone_half_angle_rad
        return (off - along * math.tan(alpha)) * math.cos(alpha)
    return off - cam.roller_radius_mm


def distance_to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """Distance from p to the segment ab, and where along it (0..1) the nearest point is."""
    t = float(np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + t * (b - a)))), t


# ----------------------------------------------------------------------------- pressure angle
def test_pressure_angle_of_a_cycloid_is_atan_of_the_lift_rate_over_the_radius() -> None:
    cam = cams()["cylinder"]
    result = profile(cam, ANGLES)
    rate = cycloid_rate(np.radians(ANGLES))
    # closed forms against the lift code's chain rule: both ~1e-15 relative, angles to 1e-10°
    assert np.allclose(result.pressure_angle_deg, np.degrees(np.arctan(rate / R)), rtol=0, atol=1e-10)
    assert np.allclose(result.pressure_angle_inner_deg, np.degrees(np.arctan(rate / (R - LENGTH / 2))), atol=1e-10)
    assert np.allclose(result.pressure_angle_outer_deg, np.degrees(np.arctan(rate / (R + LENGTH / 2))), atol=1e-10)
    # the largest: at mid-rise, s' = 2h/β (cycloid); refined to 1e-9 rad, the angle to 1e-9°
    assert result.checks.max_pressure_angle_deg == pytest.approx(math.degrees(math.atan(2 * RISE / BETA / R)), abs=1e-9)
    assert result.checks.max_pressure_angle_at_deg == pytest.approx(60.0, abs=1e-6)
    assert result.checks.max_pressure_angle_inner_deg == pytest.approx(
        math.degrees(math.atan(2 * RISE / BETA / (R - LENGTH / 2))), abs=1e-9)


def test_pressure_angle_of_a_motion_program_against_a_numerical_derivative() -> None:
    cam = cams()["motion"]
    result = profile(cam, ANGLES)
    rate = numeric_rate(cam, np.radians(ANGLES))
    # the difference quotient errs by ≲ 1e-8 mm/rad (h²/6·s''' plus rounding 1e-15·60/1e-5):
    # below 1e-9 rad of angle at R = 50 mm; 1e-7° leaves room
    assert np.allclose(result.pressure_angle_deg, np.degrees(np.arctan(rate / R)), atol=1e-7)
    assert np.abs(result.pressure_angle_deg).max() > 10  # the program does move the follower


@pytest.mark.parametrize("name", ["cylinder", "cone", "motion", "oscillating"])
def test_pressure_angle_is_the_angle_of_the_contact_normal_to_the_follower_motion(name: str) -> None:
    """The normal from a flank point to the roller's axis (its part square to the axis), against
    the direction in which the follower point moves (central difference of its position)."""
    cam = cams()[name]
    result = profile(cam, ANGLES, length_samples=3)
    x_in, x_out = cam.roller_ends_mm
    delta = 1e-4  # of lift (mm or deg): the follower's direction of motion, also where it rests
    for i, deg in enumerate(ANGLES):
        theta = math.radians(deg)
        lift = float(cam.lift.derivatives(np.array([theta]), 0)[0][0])
        q, e = axis_at_lift(cam, lift)
        turn = to_cam(theta)
        for j, (x, column) in enumerate(((x_in, result.pressure_angle_inner_deg), (R, None),
                                         (x_out, result.pressure_angle_outer_deg))):
            p = turn.T @ np.array([result.upper.x_mm[i, j], result.upper.y_mm[i, j], result.upper.z_mm[i, j]])
            w = p - (q + x * e)
            normal = w - (w @ e) * e
            normal /= np.linalg.norm(normal)
            ahead, behind = axis_at_lift(cam, lift + delta)[0] + x * e, axis_at_lift(cam, lift - delta)[0] + x * e
            motion = (ahead - behind) / np.linalg.norm(ahead - behind)
            angle = math.degrees(math.acos(min(1.0, abs(float(normal @ motion)))))
            if column is not None:
                # the difference's direction errs by ~δ² (truncation) and 1e-14 mm/1.4e-4 mm (rounding of
                # positions ~80 mm over a step of L·δ·π/180): ≲ 1e-10 rad, so 1e-7° is far above it
                assert abs(column[i]) == pytest.approx(angle, abs=1e-7)
            elif cam.follower == "translating":
                assert abs(result.pressure_angle_deg[i]) == pytest.approx(angle, abs=1e-7)


def test_a_conical_rollers_pressure_angle_carries_cos_squared_of_its_half_angle() -> None:
    """The cone's normal square to its axis is tilted less than the cylinder's: tan φ = cos²α·s'/R."""
    result = profile(cams()["cone"], ANGLES)
    alpha = math.atan(RHO / R)
    rate = cycloid_rate(np.radians(ANGLES))
    assert np.allclose(result.pressure_angle_deg, np.degrees(np.arctan(math.cos(alpha) ** 2 * rate / R)), atol=1e-10)
    assert result.checks.cone_half_angle_deg == pytest.approx(math.degrees(alpha), rel=1e-15)


# ----------------------------------------------------------------------------- flanks in 3-D
@pytest.mark.property  # a dense scan: every flank point against the roller at every neighbouring angle
@pytest.mark.parametrize("name", ["cylinder", "cone", "motion-80", "oscillating"])
def test_flank_points_lie_on_the_roller_and_outside_it_at_every_neighbouring_angle(name: str) -> None:
    cam = cams()[name]
    x_in, x_out = cam.roller_ends_mm
    positions = np.linspace(x_in, x_out, 4)
    grids = flank_points(cam, ANGLES, positions)
    nearby = np.linspace(-0.05, 0.05, 201)  # ±2.9° around each angle, steps of 0.03°
    for i, deg in enumerate(ANGLES):
        theta = math.radians(deg)
        q, e = axis_cam(cam, theta)
        for flank in ("upper", "lower"):
            xs, ys, zs = grids[flank]
            for j, x in enumerate(positions):
                p = np.array([xs[i, j], ys[i, j], zs[i, j]])
                distance, where = distance_to_segment(p, q + x_in * e, q + x_out * e)
                # coordinates of ~60 mm carry ~1e-14 mm of rounding: 1e-9 mm is far above it
                radius = x * RHO / cam.pitch_radius_mm if cam.roller == "conical" else RHO
                assert distance == pytest.approx(radius, abs=1e-9)
                assert where * (x_out - x_in) + x_in == pytest.approx(x, abs=1e-9)
                # the envelope: no neighbouring roller position reaches inside the point; a point
                # 1° round the roller from it is 1e-3 mm inside (below), so 1e-9 mm tells them apart
                gaps = [signed_distance(cam, p, theta + d) for d in nearby]
                assert min(gaps) > -1e-9, (deg, flank, x, min(gaps))


def test_undercut_across_the_rollers_length_is_where_a_neighbouring_roller_cuts_the_flank() -> None:
    """On R = 50 the program's steep return is not undercut at the pitch radius, but it is at the
    roller's inner end (the developed curve at 44 mm bends tighter): the check says so, and there a
    neighbouring roller position reaches inside the contact point."""
    cam = cams()["motion"]
    checks = sample_barrel(cam, 5).checks
    assert checks.min_radius_of_curvature_lower_mm is not None and checks.min_radius_of_curvature_lower_mm > 0
    assert checks.undercut_lower and checks.undercut
    assert checks.min_radius_of_curvature_across_length_mm is not None
    assert checks.min_radius_of_curvature_across_length_mm <= 0
    assert checks.min_radius_of_curvature_across_length_at_radius_mm == pytest.approx(R - LENGTH / 2)
    deg = checks.min_radius_of_curvature_across_length_at_deg
    assert deg is not None
    x_in = R - LENGTH / 2
    # the program is symmetric: its two steepest bends (one on each flank, mirrored) tie to
    # rounding, and the check may name either angle; the flank undercut there is one of the two
    gaps = []
    for flank in ("lower", "upper"):
        xs, ys, zs = flank_points(cam, [deg], [x_in])[flank]
        p = np.array([xs[0, 0], ys[0, 0], zs[0, 0]])
        gaps += [signed_distance(cam, p, math.radians(deg) + d) for d in np.linspace(-0.05, 0.05, 201)]
    assert min(gaps) < -1e-6
    assert not sample_barrel(cams()["motion-80"], 5).checks.undercut


def test_a_point_of_the_roller_off_the_contact_line_is_cut_by_a_neighbouring_position() -> None:
    """The envelope test above can fail: turn a contact point 1° round the roller's axis."""
    cam = cams()["cylinder"]
    deg = 40.0
    theta = math.radians(deg)
    xs, ys, zs = flank_points(cam, [deg], [R])["lower"]
    q, e = axis_cam(cam, theta)
    p = np.array([xs[0, 0], ys[0, 0], zs[0, 0]])
    centre = q + R * e
    w = p - centre
    turned = centre + math.cos(0.0175) * w + math.sin(0.0175) * np.cross(e, w)
    gaps = [signed_distance(cam, turned, theta + d) for d in np.linspace(-0.05, 0.05, 201)]
    assert min(gaps) < -1e-4


# ----------------------------------------------------------------------------- developed curve
def test_oscillating_centreline_against_the_arm_turned_in_3d() -> None:
    """The roller's axis turned about the pivot, into the cam's frame, cut with the pitch cylinder
    (a quadratic), unrolled: u = R·(polar angle), y = z."""
    cam = cams()["oscillating"]
    result = profile(cam, ANGLES)
    for i, deg in enumerate(ANGLES):
        q, e = axis_cam(cam, math.radians(deg))
        # |q + t e|² = R² in the x-y plane (e has no z part)
        qa, ea = q[:2], e[:2]
        b, c = float(qa @ ea), float(qa @ qa) - R * R
        t = -b + math.sqrt(b * b - c)
        p = q + t * e
        polar = math.atan2(p[1], p[0])
        polar += 2 * math.pi * round((math.radians(deg) - polar) / (2 * math.pi))  # the turn it is on
        # ~1e-14 mm of rounding in the construction; 1e-9 mm is far above it
        assert result.u_mm[i] == pytest.approx(R * polar, abs=1e-9)
        assert result.y_mm[i] == pytest.approx(p[2], abs=1e-9)
    # the developed curve is not y = s: the arm moves the roller circumferentially too
    shift = result.u_mm - R * np.radians(ANGLES)
    assert np.abs(shift).max() > 1.0


@pytest.mark.parametrize("name", ["cylinder", "motion", "oscillating"])
def test_radius_of_curvature_against_a_numerical_curvature_of_the_developed_curve(name: str) -> None:
    cam = cams()[name]
    h = 1e-3  # rad: truncation ~h²·|u''''|/12 relative 1e-7, rounding 1e-16·300/h² = 3e-8
    at = profile(cam, ANGLES)
    ahead, behind = profile(cam, ANGLES + math.degrees(h)), profile(cam, ANGLES - math.degrees(h))
    u1 = (ahead.u_mm - behind.u_mm) / (2 * h)
    y1 = (ahead.y_mm - behind.y_mm) / (2 * h)
    u2 = (ahead.u_mm - 2 * at.u_mm + behind.u_mm) / h**2
    y2 = (ahead.y_mm - 2 * at.y_mm + behind.y_mm) / h**2
    kappa = (u1 * y2 - y1 * u2) / np.hypot(u1, y1) ** 3
    curved = np.abs(kappa) > 1e-4  # straight stretches (dwells, constant velocity) have no radius
    assert curved.sum() > 10 and np.isnan(at.pitch_radius_of_curvature_mm[~curved & (np.abs(kappa) < 1e-12)]).all()
    # the errors above give ≲ 1e-6 relative in κ; 1e-5 leaves room
    assert np.allclose(1 / at.pitch_radius_of_curvature_mm[curved], kappa[curved], rtol=1e-5, atol=0)
    rho_p = 1 / kappa[curved]
    assert np.allclose(at.upper.radius_of_curvature_mm[curved] + RHO, rho_p, rtol=1e-5)
    assert np.allclose(at.lower.radius_of_curvature_mm[curved] + RHO, -rho_p, rtol=1e-5)


def test_undercut_when_the_roller_is_larger_than_the_pitch_curves_smallest_radius() -> None:
    grid = np.linspace(0.0, 360.0, 72001)
    result = profile(cams()["cylinder"], grid)
    smallest = np.nanmin(np.abs(result.pitch_radius_of_curvature_mm))
    checks = result.checks
    # a 0.005° grid finds the minimum to ~(0.005°)²·ρ''/2 ≈ 1e-6 relative; the refined value is below it
    assert checks.min_pitch_radius_of_curvature_mm == pytest.approx(smallest, rel=1e-6)
    assert checks.min_pitch_radius_of_curvature_mm <= smallest
    assert checks.min_radius_of_curvature_upper_mm == pytest.approx(smallest - RHO, rel=1e-6)
    assert not checks.undercut
    big = make_barrel_cam(R, smallest + 0.5, roller_length_mm=LENGTH, segments=CYCLOID)
    under = sample_barrel(big, 37).checks
    # rise and return are mirror images: both flanks are convex somewhere with the same radius
    assert under.undercut and under.undercut_upper and under.undercut_lower
    assert under.min_radius_of_curvature_upper_mm == pytest.approx(-0.5, abs=1e-6)


def test_a_constant_velocity_groove_has_corners() -> None:
    cv = Law("named", {"name": "constant-velocity"})
    from camcore.curves.kinds import build_curve

    curve = build_curve(cv.kind, cv.parameters)
    cam = make_barrel_cam(R, RHO, segments=[Segment("rise", 180, lift_mm=20, curve=curve),
                                            Segment("return", 180, lift_mm=20, curve=curve)])
    checks = sample_barrel(cam, 5).checks
    assert checks.corners_deg == (0.0, 180.0)
    assert checks.min_radius_of_curvature_upper_mm == 0.0 and checks.min_radius_of_curvature_lower_mm == 0.0


# ----------------------------------------------------------------------------- bad geometry
@pytest.mark.parametrize(("kwargs", "field", "words"), [
    ({"roller_length_mm": 100.0}, "roller_length_mm", "twice pitch_radius_mm"),
    ({"roller_length_mm": 12.0, "groove_depth_mm": 11.0}, "groove_depth_mm", "bottom of the groove"),
    ({"roller_length_mm": 12.0, "groove_depth_mm": 56.0}, "groove_depth_mm", "through the axis"),
    ({"roller": "conical", "follower": "oscillating", "arm_length_mm": 80.0}, "roller", "apex on the cam axis"),
    ({"follower": "oscillating"}, "arm_length_mm", "arm_length_mm > 0"),
    ({"follower": "oscillating", "arm_length_mm": 80.0, "initial_arm_angle_deg": 70.0}, "initial_arm_angle_deg",
     "±89"),
    ({"follower": "oscillating", "arm_length_mm": 400.0, "initial_arm_angle_deg": -30.0}, "arm_length_mm",
     "off the cam axis"),
    ({"pitch_radius_mm": -1.0}, "pitch_radius_mm", "greater than 0"),
])
def test_bad_geometry_is_refused_naming_the_field(kwargs: dict[str, object], field: str, words: str) -> None:
    args: dict[str, object] = {"pitch_radius_mm": R, "roller_radius_mm": RHO}
    args.update(kwargs)
    lift = SWING if args.get("follower") == "oscillating" else CYCLOID
    with pytest.raises(CamError) as err:
        make_barrel_cam(segments=lift, **args)  # type: ignore[arg-type]
    assert err.value.field[0] == field and words in str(err.value)


def test_a_motion_program_in_the_wrong_unit_is_refused() -> None:
    with pytest.raises(CamError) as err:
        make_barrel_cam(R, RHO, motion=resolve_motion(FEED), follower="oscillating", arm_length_mm=80.0)
    assert err.value.field == ("motion", "unit")
    with pytest.raises(GeometryError):
        make_barrel_cam(R, RHO, roller_length_mm=2 * R, segments=CYCLOID)
