"""Toolpaths (camcore.toolpath, camcore.export.TOOLPATH_FORMATS): the cutter-centre path of a
plate cam fitted with lines and arcs, checked against an exact path built independently.

The exact cutter path here comes from ``compute_profile`` only: for a roller the outward normal
is (pitch point − surface point)/Rr, so the cutter centre outside the surface is surface + Rt·N
and inside a track's outer wall pitch + (Rr − Rt)·N; for a translating flat face the normal is
the face's, turned into the cam's frame. The G-code is read back by the small reader of
tests/toolpath_reference.py, as a control reads it.
"""

from __future__ import annotations

import io
import math

import ezdxf
import numpy as np
import pytest

import camcore
from camcore._maxima import golden_max
from camcore.curves.polynomial import polynomial_from_boundary
from camcore.errors import GeometryError, InvalidParameterError, LimitExceededError
from camcore.export import TOOLPATH_FORMATS, ToolpathFile, toolpath_dxf, toolpath_gcode
from camcore.profile import Follower, Segment, compute_profile, make_cam
from camcore.toolpath import OffsetCurve, compute_toolpath
from camcore.toolpath.fit import Budget, _farthest_fit, _greedy
from camcore.toolpath.geometry import Element, biarc
from camcore.toolpath.measure import Span, measure
from tests.toolpath_reference import cutting_polylines, densify, distances_to_polyline, max_sagitta, parse_gcode

MS = camcore.named_curve("MS")
RISE_DWELL = [Segment(type="rise", angle_deg=120, lift_mm=20, curve=MS), Segment(type="dwell", angle_deg=60),
              Segment(type="return", angle_deg=120, lift_mm=20), Segment(type="dwell", angle_deg=60)]
ROLLER = make_cam(Follower(type="roller", roller_radius_mm=10), 40, segments=RISE_DWELL)
#: a small base circle: the surface is concave after the rise (smallest concave radius ~51 mm)
CONCAVE = make_cam(Follower(type="roller", roller_radius_mm=5), 20, segments=[
    Segment(type="rise", angle_deg=90, lift_mm=20), Segment(type="dwell", angle_deg=90),
    Segment(type="return", angle_deg=90, lift_mm=20), Segment(type="dwell", angle_deg=90)])
FLAT = make_cam(Follower(type="flat-faced"), 40, segments=RISE_DWELL)
#: the lift's velocity jumps where the rise leaves the base circle and the return reaches it:
#: concave corners of the pitch curve, where the roller rounds the surface with its own radius
JUMP = polynomial_from_boundary({"s": 0.0, "v": 1.0}, {"s": 1.0, "v": 0.0, "a": 0.0})
CORNERED = make_cam(Follower(type="roller", roller_radius_mm=10), 40, segments=[
    Segment(type="rise", angle_deg=120, lift_mm=15, curve=JUMP), Segment(type="dwell", angle_deg=60),
    Segment(type="return", angle_deg=120, lift_mm=15, curve=JUMP), Segment(type="dwell", angle_deg=60)])
#: 0.05°: chords of ≤ 0.05 mm, whose sagitta (≤ 2e-5 mm on radii ≥ 15 mm) is counted as slack
ANGLES = np.linspace(0.0, 360.0, 7201)
#: the G-code's arcs and lines sampled this finely for the distances [mm]
STEP_MM = 0.05


def exact_roller_path(spec: camcore.profile.CamSpec, tool_mm: float, wall: str) -> np.ndarray:
    """The exact cutter path of a roller cam from compute_profile alone (module notes), the
    roller's own arc added at each concave corner of the pitch curve."""
    p = compute_profile(spec, ANGLES)
    rr = spec.follower.roller_radius_mm
    nx, ny = (p.pitch_x_mm - p.x_mm) / rr, (p.pitch_y_mm - p.y_mm) / rr
    d = (tool_mm - rr) if wall == "surface" else (rr - tool_mm)
    pts = np.column_stack([p.pitch_x_mm + d * nx, p.pitch_y_mm + d * ny])
    turn = np.arctan2(nx[:-1] * ny[1:] - ny[:-1] * nx[1:], nx[:-1] * nx[1:] + ny[:-1] * ny[1:])
    # the corners the profile's own checks report (where the lift's velocity jumps); a corner at
    # 0° is met between the last two samples (360° is evaluated as 0°, its right limit)
    corners = sorted({int(np.argmin(np.abs(ANGLES - c))) or len(ANGLES) - 1 for c in p.checks.corners_deg})
    out, last = [], 0
    for k in corners:  # the normal turns about the pitch point
        a = math.atan2(ny[k - 1], nx[k - 1]) + turn[k - 1] * np.linspace(0.0, 1.0, 200)[1:-1]
        out += [pts[last:k], np.column_stack([p.pitch_x_mm[k] + d * np.cos(a), p.pitch_y_mm[k] + d * np.sin(a)])]
        last = k
    return np.vstack([*out, pts[last:]])


def exact_flat_path(spec: camcore.profile.CamSpec, tool_mm: float, side: float) -> np.ndarray:
    """A translating flat face's cam: the face normal (0, 1) turned by −σθ into the cam frame."""
    p = compute_profile(spec, ANGLES)
    th = np.radians(ANGLES) * spec.sigma
    nx, ny = np.sin(th), np.cos(th)
    return np.column_stack([p.x_mm + side * tool_mm * nx, p.y_mm + side * tool_mm * ny])


def gcode_paths(text: str) -> list[np.ndarray]:
    """The cut of each path, without its lead-in and lead-out; arcs sampled every STEP_MM."""
    return [poly[1:-1] for poly in cutting_polylines(parse_gcode(text), STEP_MM)]


def check_both_ways(cut: np.ndarray, exact: np.ndarray, tolerance_mm: float, min_radius_mm: float) -> float:
    """The G-code stays within the tolerance of the exact path everywhere, and the exact path
    within the tolerance of the G-code (it covers all of it). Slack: each polyline's chord
    sagitta (≤ ~2e-5 mm each), and the program's rounding to 1e-6 mm (≤ 1e-6·√2 per point)."""
    dense_cut = densify(cut, STEP_MM)
    slack = max_sagitta(exact, min_radius_mm) + max_sagitta(dense_cut, min_radius_mm) + 2e-6
    stays = distances_to_polyline(dense_cut, exact).max()
    covers = distances_to_polyline(exact, dense_cut).max()
    assert stays <= tolerance_mm + slack, (stays, tolerance_mm)
    assert covers <= tolerance_mm + slack, (covers, tolerance_mm)
    return max(stays, covers)


# ------------------------------------------------------------------ the exact offset itself
@pytest.mark.parametrize("spec", [ROLLER, FLAT, CONCAVE, make_cam(
    Follower(type="roller", roller_radius_mm=5, motion="oscillating", pivot_distance_mm=80, arm_length_mm=60), 40,
    segments=[Segment(type="rise", angle_deg=180, swing_deg=15), Segment(type="return", angle_deg=180, swing_deg=15)],
    rotation="cw")], ids=["roller", "flat", "concave", "oscillating-cw"])
def test_offset_tangent_is_the_derivative_of_the_offset(spec: camcore.profile.CamSpec) -> None:
    # dP/dθ = (a + d·b)·T analytically; central differences with h = 1e-6 rad agree to O(h²·P''')
    # ~1e-10 plus rounding ~1e-16·|P|/h ~ 1e-8 mm/rad
    curve = OffsetCurve(spec, 7.0)
    th = np.linspace(0.05, 6.2, 101)
    _, _, tx, ty, stretch = curve.sample(th)
    h = 1e-6
    xp, yp = curve.points(th + h)
    xm, ym = curve.points(th - h)
    assert np.allclose((xp - xm) / (2 * h), stretch * tx, atol=1e-6)
    assert np.allclose((yp - ym) / (2 * h), stretch * ty, atol=1e-6)


def test_offset_by_minus_the_roller_is_the_profile_surface() -> None:
    # the surface compute_profile reports: the pitch curve offset inwards by Rr (1e-12 mm: rounding)
    p = compute_profile(ROLLER, ANGLES[::100])
    x, y = OffsetCurve(ROLLER, -10.0).points(np.radians(ANGLES[::100]))
    assert np.hypot(x - p.x_mm, y - p.y_mm).max() < 1e-12


# ------------------------------------------------------------------ geometry
def test_biarc_meets_both_ends_with_their_tangents() -> None:
    rng = np.random.default_rng(7)
    for _ in range(200):
        p0, p1 = rng.normal(size=2) * 10, rng.normal(size=2) * 10
        a0, a1 = rng.uniform(-math.pi, math.pi, 2)
        t0, t1 = np.array([math.cos(a0), math.sin(a0)]), np.array([math.cos(a1), math.sin(a1)])
        pair = biarc(p0, t0, p1, t1)
        if pair is None:  # both tangents against the chord: no equal-leg biarc
            chord = p1 - p0
            assert (t0 + t1) @ chord <= 0
            continue
        first, second = pair
        assert np.allclose(first.start, p0) and np.allclose(second.end, p1, atol=1e-9)
        assert first.end == second.start
        for element, point, tangent in ((first, first.start, t0), (second, second.end, t1)):
            assert np.allclose(_tangent(element, point), tangent, atol=1e-9)
        # G1 at the joint: both arcs share its tangent
        assert np.allclose(_tangent(first, first.end), _tangent(second, second.start), atol=1e-9)


def _tangent(e: Element, point: tuple[float, float]) -> np.ndarray:
    if e.centre is None:
        d = np.subtract(e.end, e.start)
        return d / np.hypot(*d)
    r = np.subtract(point, e.centre)
    t = np.array([-r[1], r[0]]) if e.ccw else np.array([r[1], -r[0]])
    return t / np.hypot(*t)


def test_the_measurement_finds_the_largest_gap_between_its_samples() -> None:
    # a chord across 30° of the base-circle dwell of the offset (a circle of radius 46 mm about
    # the axis): the gap is the sagitta 46(1 − cos 15°) at the middle, which no sample hits (32
    # samples, an even count); golden section between them finds it to 1e-9 mm
    curve = OffsetCurve(ROLLER, -4.0)
    a, b = math.radians(315.0), math.radians(345.0)
    (x0, x1), (y0, y1) = curve.points(np.array([a, b]))
    chord = Element((float(x0), float(y0)), (float(x1), float(y1)), None, True, a, b)
    (deviation,) = measure(curve, [Span(a, b, (chord,))])
    assert deviation == pytest.approx(46.0 * (1 - math.cos(math.radians(15.0))), abs=1e-9)


def _golden_distance(curve: OffsetCurve, x: np.ndarray, y: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Distance of points from the curve within [lo, hi] by golden section on the distance itself
    (no foot equation, no slope): the reference's own way to the nearest point."""
    def closeness(t: np.ndarray) -> np.ndarray:
        px, py = curve.points(t)
        return -np.hypot(px - x, py - y)
    return -golden_max(closeness, lo, hi)[1]


def _reference_deviation(curve: OffsetCurve, span: Span) -> float:
    """The span's deviation both ways by a dense scan, then golden section between the best sample's
    neighbours (the curve → path distance by :meth:`Element.distance`, the path → curve distance by
    :func:`_golden_distance`): a second method for :func:`measure`."""
    lo, hi = span.theta0 + 1e-11, span.theta1 - 1e-11
    dense = np.linspace(lo, hi, 4001)
    step = dense[1] - dense[0]

    def from_path(t: np.ndarray) -> np.ndarray:
        px, py = curve.points(t)
        return np.min([e.distance(px, py) for e in span.elements], axis=0)

    k = int(np.argmax(from_path(dense)))
    forward = float(golden_max(from_path, max(lo, dense[k] - step), min(hi, dense[k] + step))[1][0])
    cx, cy = curve.points(dense)
    backward = 0.0
    for e in span.elements:
        u = np.linspace(0.0, 1.0, 801)

        def to_curve(uu: np.ndarray, e: Element = e) -> np.ndarray:
            if e.centre is None:
                x, y = e.start[0] + uu * (e.end[0] - e.start[0]), e.start[1] + uu * (e.end[1] - e.start[1])
            else:
                a0 = math.atan2(e.start[1] - e.centre[1], e.start[0] - e.centre[0])
                a = a0 + uu * e.sweep_rad
                x, y = e.centre[0] + e.radius_mm * np.cos(a), e.centre[1] + e.radius_mm * np.sin(a)
            near = np.argmin(np.hypot(cx[None, :] - x[:, None], cy[None, :] - y[:, None]), axis=1)
            return _golden_distance(curve, x, y, np.maximum(lo, dense[near] - step), np.minimum(hi, dense[near] + step))

        j = int(np.argmax(to_curve(u)))
        top = golden_max(to_curve, max(0.0, u[j] - u[1]), min(1.0, u[j] + u[1]), iterations=60, width=1e-12)[1]
        backward = max(backward, float(top[0]), float(to_curve(u[j:j + 1])[0]))
    return max(forward, backward)


@pytest.mark.parametrize(("spec", "tool_mm", "tolerance_mm", "stretch_deg"), [
    (ROLLER, 6.0, 0.005, (10.0, 110.0)), (CONCAVE, 2.0, 0.001, (5.0, 85.0)), (FLAT, 4.0, 0.05, (190.0, 290.0))],
    ids=["roller-rise", "concave-rise", "flat-return"])
def test_the_measurement_agrees_with_a_dense_scan_and_golden_section(
        spec: camcore.profile.CamSpec, tool_mm: float, tolerance_mm: float, stretch_deg: tuple[float, float]) -> None:
    # the spans the greedy fit makes over a stretch (no corner inside), measured by measure() (the slope
    # climbed by Illinois steps, both ways in one evaluation per round) and by the reference (a dense scan
    # and golden section on the distances themselves): both find each top within the rounding of the
    # coordinates (~1e-14 mm at 50 mm), the reference's golden sections to ~1e-13 of their brackets,
    # so they agree within 1e-12 mm; a top missed by the climb would be off by far more
    d = (-spec.model.roller_radius_mm if spec.model.roller_radius_mm else 0.0) + tool_mm
    curve = OffsetCurve(spec, d)
    a, b = map(math.radians, stretch_deg)  # within a rise or a return: spans that deviate by their fit
    x, y, tx, ty, _ = curve.travel(np.array([a, b]))
    spans = _greedy(curve, a, b, (np.array([x[0], y[0]]), np.array([tx[0], ty[0]])),
                    (np.array([x[1], y[1]]), np.array([tx[1], ty[1]])), tolerance_mm, 2 * math.pi / 2048, Budget(10**6))
    measured = measure(curve, spans)
    # the fitted spans (a last one of a grid step or so deviates by ~1e-9 mm, the one-sided limits' own
    # 1e-11 rad, where the reference's golden section, never at its bracket's end, is ~1e-12 mm off)
    wide = [k for k, span in enumerate(spans) if span.theta1 - span.theta0 > 10 * 2 * math.pi / 2048]
    chosen = [wide[k] for k in np.linspace(0, len(wide) - 1, min(len(wide), 5)).astype(int)]
    reference = [_reference_deviation(curve, spans[k]) for k in chosen]
    assert len(chosen) >= 3
    np.testing.assert_allclose(measured[chosen], reference, rtol=0, atol=1e-12)


# ------------------------------------------------------------------ the paths, read back from G-code
@pytest.mark.parametrize("tolerance_mm", [0.1, 0.01, 0.001])
def test_gcode_stays_within_the_tolerance_and_covers_the_exact_path(tolerance_mm: float) -> None:
    tp = compute_toolpath(ROLLER, 6.0, tolerance_mm)
    assert tp.max_deviation_mm <= tolerance_mm
    (cut,) = gcode_paths(toolpath_gcode(ToolpathFile(tp, 400.0)))
    # the cutter path's smallest radius of curvature: the pitch curve's (≥ 30 mm here) − 4 mm
    measured = check_both_ways(cut, exact_roller_path(ROLLER, 6.0, "surface"), tolerance_mm, 20.0)
    # the fit uses the tolerance: what the reader measures is not far below it either
    assert measured > 0.5 * tolerance_mm


def test_a_groove_is_both_walls_each_within_the_tolerance() -> None:
    tp = compute_toolpath(ROLLER, 8.0, 0.005, side="groove")
    text = toolpath_gcode(ToolpathFile(tp, 250.0, safe_z_mm=5.0, cut_z_mm=-10.0))
    inner, outer = gcode_paths(text)
    check_both_ways(inner, exact_roller_path(ROLLER, 8.0, "surface"), 0.005, 20.0)
    check_both_ways(outer, exact_roller_path(ROLLER, 8.0, "outer-wall"), 0.005, 20.0)
    # climb milling: clockwise round the island, counter-clockwise inside the outer wall
    assert [p.clockwise for p in tp.paths] == [True, False]
    assert _signed_area(inner) < 0 < _signed_area(outer)
    # the plunge is on the track's centre line (the pitch curve at 0°: radius 50 mm), inside the track
    moves = parse_gcode(text)
    plunges = [m for m in moves if m["g"] == 1.0 and m["z"] == -10.0 and m["x0"] == m["x"] and m["y0"] == m["y"]]
    assert [round(math.hypot(float(m["x"]), float(m["y"])), 9) for m in plunges] == [50.0, 50.0]


def test_a_flat_faced_cam_inside_and_outside() -> None:
    for side, sign in (("outside", 1.0), ("inside", -1.0)):
        tp = compute_toolpath(FLAT, 5.0, 0.001, side=side)
        (cut,) = gcode_paths(toolpath_gcode(ToolpathFile(tp)))
        check_both_ways(cut, exact_flat_path(FLAT, 5.0, sign), 0.001, 20.0)


def test_corners_of_the_pitch_curve_are_exact_arcs() -> None:
    # the lift's velocity jumps at 0° and 300° (concave corners): there the cutter turns about the
    # pitch point with radius Rr − Rt, an arc element of its own
    tp = compute_toolpath(CORNERED, 4.0, 0.002)
    corners = [e for e in tp.paths[0].elements if e.theta0_rad == e.theta1_rad]
    assert len(corners) == 2
    assert all(e.radius_mm == pytest.approx(6.0, abs=1e-9) for e in corners)
    (cut,) = gcode_paths(toolpath_gcode(ToolpathFile(tp)))
    check_both_ways(cut, exact_roller_path(CORNERED, 4.0, "surface"), 0.002, 6.0)


def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


# ------------------------------------------------------------------ element count against tolerance
def test_the_element_count_falls_as_the_tolerance_grows() -> None:
    counts = []
    for tolerance_mm in (0.0001, 0.001, 0.01, 0.1, 1.0):
        tp = compute_toolpath(ROLLER, 6.0, tolerance_mm)
        assert tp.max_deviation_mm <= tolerance_mm
        counts.append(tp.segments_count)
    assert counts == sorted(counts, reverse=True) and counts[0] > 5 * counts[-1], counts
    # a biarc's deviation grows as the cube of its length: ×10 in tolerance, about ÷2 in count
    assert 1.5 < counts[1] / counts[2] < 3.0, counts


# ------------------------------------------------------------------ refusals
def test_a_tool_larger_than_the_concave_radius_is_refused_with_the_angle() -> None:
    # independently: the smallest |ρ| where compute_profile's surface is concave, and its angle
    # (0.05° samples, then 1e-5° samples about the smallest: a sampled minimum is off by
    # ½|ρ''|δ², ~1e-12 mm here)
    rho = compute_profile(CONCAVE, ANGLES).radius_of_curvature_mm
    k = int(np.argmin(np.where(rho < 0, -rho, np.inf)))
    fine = np.linspace(ANGLES[k] - 0.1, ANGLES[k] + 0.1, 20001)
    rho = compute_profile(CONCAVE, fine).radius_of_curvature_mm
    assert np.all(rho < 0)
    k = int(np.argmin(-rho))
    tp = compute_toolpath(CONCAVE, 40.0, 0.01)
    assert tp.paths[0].min_concave_radius_mm == pytest.approx(-rho[k], rel=1e-9)
    assert tp.paths[0].min_concave_radius_at_deg == pytest.approx(fine[k], abs=2e-5)
    with pytest.raises(GeometryError) as info:
        compute_toolpath(CONCAVE, 60.0, 0.01)
    assert info.value.field == ("tool_radius_mm",)
    assert f"at cam angle {fine[k]:.4g}°" in str(info.value) and "allow_gouge" in str(info.value)
    # allowed: the path follows the exact offset, loops included, still within the tolerance
    tp = compute_toolpath(CONCAVE, 60.0, 0.01, allow_gouge=True)
    assert tp.paths[0].gouges and tp.max_deviation_mm <= 0.01


def test_other_refusals() -> None:
    with pytest.raises(InvalidParameterError, match="wider than the roller's track"):
        compute_toolpath(ROLLER, 12.0, 0.01, side="groove")
    with pytest.raises(InvalidParameterError, match="a groove is the track of a roller"):
        compute_toolpath(FLAT, 5.0, 0.01, side="groove")
    with pytest.raises(LimitExceededError) as info:
        compute_toolpath(ROLLER, 6.0, 0.0001, max_elements=50)
    assert info.value.field == ("tolerance_mm",)
    # a convex corner of a roller's pitch curve leaves a sharp corner on the surface: refused
    cv = camcore.named_curve("constant-velocity")
    sharp = make_cam(Follower(type="roller", roller_radius_mm=5), 30, segments=[
        Segment(type="rise", angle_deg=180, lift_mm=20, curve=cv), Segment(type="return", angle_deg=180, lift_mm=20,
                                                                           curve=cv)])
    with pytest.raises(GeometryError, match="sharp corner at cam angle 180°"):
        compute_toolpath(sharp, 3.0, 0.01)


# ------------------------------------------------------------------ large cams
@pytest.mark.parametrize("base_radius_mm", [1e5, 1e6])
@pytest.mark.parametrize("lift", ["MS", "cornered"])
def test_a_large_cam_closes_its_path(base_radius_mm: float, lift: str) -> None:
    # issue 34, point 4: at a base radius of 1e5 mm the one-sided limits at 2π (and at corners) sit
    # LEFT_LIMIT_RAD·|dP/dθ| ≈ 1e-6 mm from the next element's start, and an absolute 1e-6 mm bound
    # on that gap answered 500; the bound now grows with the path's speed there
    segments = RISE_DWELL if lift == "MS" else [
        Segment(type="rise", angle_deg=120, lift_mm=15, curve=JUMP), Segment(type="dwell", angle_deg=60),
        Segment(type="return", angle_deg=120, lift_mm=15, curve=JUMP), Segment(type="dwell", angle_deg=60)]
    spec = make_cam(Follower(type="roller", roller_radius_mm=10), base_radius_mm, segments=segments)
    tp = compute_toolpath(spec, 4.0, 0.01)
    (path,) = tp.paths
    elements = path.elements
    # closed exactly: every element starts where the one before ends, the last ends at the first's start
    assert all(a.end == b.start for a, b in zip(elements, elements[1:] + elements[:1], strict=True))
    assert path.max_deviation_mm <= 0.01
    # the tool's centre runs 4 mm off the surface, from the base circle to the 15 or 20 mm lift; the
    # elements' ends (a biarc's joint too) lie within the tolerance of that exact path
    radii = [math.hypot(*e.start) for e in elements]
    lift_mm = 20.0 if lift == "MS" else 15.0
    assert base_radius_mm + 4.0 - 0.01 <= min(radii) and max(radii) <= base_radius_mm + 4.0 + lift_mm + 0.01


# ------------------------------------------------------------------ DXF
def test_dxf_is_lines_and_arcs_in_mm_with_real_extents() -> None:
    tp = compute_toolpath(ROLLER, 8.0, 0.005, side="groove")
    doc = ezdxf.read(io.StringIO(toolpath_dxf(ToolpathFile(tp)).decode()))
    assert doc.units == ezdxf.units.MM
    msp = doc.modelspace()
    by_layer: dict[str, list[str]] = {}
    for e in msp:
        by_layer.setdefault(e.dxf.layer, []).append(e.dxftype())
    assert set(by_layer) == {"TOOLPATH_SURFACE", "TOOLPATH_OUTER_WALL", "TOOLPATH_LEAD"}
    assert len(by_layer["TOOLPATH_SURFACE"]) == len(tp.paths[0].elements)
    assert set(by_layer["TOOLPATH_SURFACE"]) <= {"LINE", "ARC"} and "ARC" in by_layer["TOOLPATH_SURFACE"]
    # every arc read back lies on the path: its ends are the elements' ends (either order: DXF
    # arcs run counter-clockwise)
    ends = {(round(x, 6), round(y, 6)) for p in tp.paths for e in p.elements for x, y in (e.start, e.end)}
    for arc in msp.query("ARC"):
        for point in (arc.start_point, arc.end_point):
            assert (round(point.x, 6), round(point.y, 6)) in ends
    # the extents are the drawing's box (the header holds real numbers, not AutoCAD's ±1e20
    # "unknown"): the exact paths' box within the tolerance (the lead-ins run to the track's
    # centre line, inside it)
    lo, hi = doc.header["$EXTMIN"], doc.header["$EXTMAX"]
    exact = np.vstack([exact_roller_path(ROLLER, 8.0, "surface"), exact_roller_path(ROLLER, 8.0, "outer-wall")])
    assert hi[1] == pytest.approx(exact[:, 1].max(), abs=0.005)
    assert lo[1] == pytest.approx(exact[:, 1].min(), abs=0.005)
    assert lo[0] == pytest.approx(exact[:, 0].min(), abs=0.005)
    assert hi[0] == pytest.approx(exact[:, 0].max(), abs=0.005)


def test_every_toolpath_format_is_in_the_registry() -> None:
    tp = compute_toolpath(ROLLER, 6.0, 0.01)
    assert set(TOOLPATH_FORMATS) == {"gcode", "dxf"}
    text = TOOLPATH_FORMATS["gcode"].write(ToolpathFile(tp)).decode()
    assert text.startswith("%\n") and "G17 G21 G90" in text and text.rstrip().endswith("M30\n%")
    assert TOOLPATH_FORMATS["gcode"].is_text and not TOOLPATH_FORMATS["dxf"].is_text


def test_the_greedy_search_finds_the_farthest_fit_of_a_brute_scan() -> None:
    # distances growing as c·(j − i)^p (p from 2 to 6, not only the cube the search predicts), a jump to
    # "no biarc" past some length, any start and first guess: the farthest j within the aim is the one a
    # scan of every j finds. Trials: 4.3 on average here, at most 9; doubling then bisection took 6.9 and 9
    # on the same 400 cases (measured once, by the search this one replaced)
    rng = np.random.default_rng(3)
    element = (Element((0.0, 0.0), (1.0, 0.0)),)
    most, total = 0, 0
    for _ in range(400):
        i, n = int(rng.integers(0, 50)), int(rng.integers(60, 400))
        c, p, aim = rng.uniform(1e-7, 1e-3), rng.uniform(2.0, 6.0), rng.uniform(1e-3, 1e-2)
        none_past = int(rng.integers(i + 1, n + 40))
        calls = [0]

        def trial(a: int, b: int, i: int = i, n: int = n, c: float = c, p: float = p, none_past: int = none_past,
                  calls: list[int] = calls) -> tuple[tuple[Element, ...] | None, float]:
            calls[0] += 1
            assert a == i and i < b <= n
            return (None, math.inf) if b > none_past else (element, c * (b - a) ** p)

        good, fit = _farthest_fit(trial, i, n, int(rng.integers(1, 200)), aim)
        fitting = [j for j in range(i + 1, n + 1) if j <= none_past and c * (j - i) ** p <= aim]
        assert good == (max(fitting) if fitting else i) and (fit is None) == (not fitting)
        most, total = max(most, calls[0]), total + calls[0]
    assert most <= 9 and total / 400 < 5


def test_a_first_guess_just_too_long_is_followed_by_one_just_short_of_it() -> None:
    # the last element's length is the next one's first guess, often a little too long: the cube law
    # below that bad point lands next to the answer (100 here, tried as 100, then 101 beyond it), where
    # the cap meant for extrapolating from a good point sent the search back to 4 steps, then 16, 64, …
    # (8 trials; the README's toolpath took 86 trials before, 58 after)
    element = (Element((0.0, 0.0), (1.0, 0.0)),)
    tried: list[int] = []

    def trial(a: int, b: int) -> tuple[tuple[Element, ...] | None, float]:
        tried.append(b)
        return element, 1e-3 * ((b - a) / 100) ** 3

    good, fit = _farthest_fit(trial, 0, 2048, 120, 1e-3)
    assert good == 100 and fit is element and tried == [120, 100, 101]
