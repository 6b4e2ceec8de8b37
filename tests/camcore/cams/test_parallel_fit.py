"""A plate's contour, and a cutter's path round it, as lines and arcs (camcore.cams.parallel.fit),
measured against the exact contour by a route of its own.

The exact contour here is each piece evaluated at 20 000 cam angles (the tests' own dense sampling
of PlateContour.at) and the elements at 200 points each; a point's distance from a dense polyline
is taken to the segments beside its nearest vertices (tests/polylines.py). The fit's own
measurement (camcore.toolpath.fit) is not used.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcore.cams.parallel import make_parallel_cam, sample_parallel
from camcore.cams.parallel.envelope import centres
from camcore.cams.parallel.fit import PieceCurve, concave_radius, fit_plate
from camcore.cams.parallel.trace import PlateContour
from camcore.errors import GeometryError, LimitExceededError
from camcore.toolpath import Element, path_area
from tests.polylines import distance_to_ring

#: points of the exact contour per piece: a piece of ≤ 500 mm at 20 000 points has chords ≤ 0.025 mm
#: long, which stand off it by (0.025)²/(8·Rr) ≤ 1e-5 mm at Rr = 8 mm, the smallest here
DENSE = 20_000
#: points along each element (elements of a few mm: points 0.03 mm apart)
ALONG = 200


@pytest.fixture(scope="module", params=[(4, 12.0), (8, 10.0)], ids=["4stops", "8stops"])
def plates(request: pytest.FixtureRequest) -> tuple[float, list]:
    stops, rr = request.param
    cam = make_parallel_cam(stops, 100.0, 60.0, rr, 120.0, "MS", plates=3)
    result = sample_parallel(cam, 181)
    return rr, list(zip(result.plates, result.contours))


def exact_ring(contour: PlateContour) -> np.ndarray:
    """The exact contour, densely: every piece at DENSE cam angles, shape (n, 2), closed implicitly."""
    # each piece without its end: that is the next piece's start
    pts = [np.column_stack([(e := contour.at(k, np.linspace(p.tau_start_rad, p.tau_end_rad, DENSE)[:-1])).x, e.y])
           for k, p in enumerate(contour.pieces)]
    return np.vstack(pts)


def path_points(elements: tuple[Element, ...]) -> np.ndarray:
    """The elements' points, each element without its end (the next one's start)."""
    return np.vstack([e.points(ALONG)[:-1] for e in elements])


@pytest.mark.parametrize("tolerance", [0.01, 0.001])
def test_the_contour_fitted_within_the_tolerance(plates: tuple[float, list], tolerance: float) -> None:
    _rr, items = plates
    for plate, contour in items:
        path = fit_plate(contour, 0.0, tolerance, math.inf, None)
        ring = exact_ring(contour)
        pts = path_points(path.elements)
        # the path → the contour (its points' distance), and the contour → the path (the dense contour's
        # points' distance from the elements); each within the tolerance and the dense chords' 1e-5 mm
        forward = distance_to_ring(pts, ring)
        backward = distance_to_ring(ring, pts)
        assert max(forward.max(), backward.max()) <= tolerance + 1e-5, (forward.max(), backward.max())
        # and the fit measured it too, to the same figure (its golden-section refinement finds the maxima the
        # dense sampling may miss by a little)
        assert path.max_deviation_mm <= tolerance
        assert path.max_deviation_mm >= 0.5 * max(forward.max(), backward.max())
        # closed, each element starting where the one before ends, clockwise round the plate
        ends = [(e.start, e.end) for e in path.elements]
        assert all(math.dist(ends[k - 1][1], ends[k][0]) == 0.0 for k in range(len(ends)))
        assert path.clockwise and path_area(list(path.elements)) < 0
        x, y = ring[:, 0], ring[:, 1]
        area = 0.5 * abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))
        length = float(np.sum(np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)))
        assert abs(abs(path_area(list(path.elements))) - area) <= length * tolerance


def test_the_cutter_path_keeps_the_tool_radius_from_the_plate(plates: tuple[float, list]) -> None:
    """Every point of the path lies at the tool radius from the exact contour (within the tolerance) and
    no nearer: the tool touches the plate and does not cut into it. Round a corner the path is an arc
    about the corner."""
    rr, items = plates
    tolerance = 0.005
    for plate, contour in items:
        radius, at = concave_radius(contour, plate.radius_of_curvature_mm, plate.contact_cam_angle_deg)
        assert radius >= rr * (1 - 1e-9)  # a concave stretch is a roller's own circle or rounder
        rt = 0.5 * rr
        path = fit_plate(contour, rt, tolerance, radius, at)
        ring = exact_ring(contour)
        d = distance_to_ring(path_points(path.elements), ring)
        assert np.abs(d - rt).max() <= tolerance + 1e-5, np.abs(d - rt).max()
        corners = sum(p.corner for p in contour.pieces)
        arcs = [e for e in path.elements if e.centre is not None and e.radius_mm == pytest.approx(rt, abs=1e-9)]
        assert len(arcs) >= corners


def test_the_offset_is_the_envelope_of_smaller_circles() -> None:
    """PieceCurve's point, tangent and stretch (dP/dθ) against the rollers' centres: at Rr − Rt from
    the centre, and a central difference of the points (h = 1e-6 rad, error ~h²·|P‴| ≈ 1e-9 mm/rad)."""
    cam = make_parallel_cam(4, 100.0, 60.0, 12.0, 120.0, "MS", plates=3)
    contour = sample_parallel(cam, 121).contours[1]
    for k, p in enumerate(contour.pieces):
        curve = PieceCurve(contour, k, 12.0 - 4.0)
        theta = np.linspace(p.side * p.tau_start_rad, p.side * p.tau_end_rad, 41)[1:-1]
        x, y, tx, ty, stretch = curve.sample(theta)
        px, py, *_ = centres(cam, p.alpha0_rad, p.side * theta)
        assert np.hypot(x - px, y - py) == pytest.approx(8.0, abs=1e-12)
        h = 1e-6
        xa, ya = curve.points(theta + h)
        xb, yb = curve.points(theta - h)
        vx, vy = (xa - xb) / (2 * h), (ya - yb) / (2 * h)
        assert np.abs(vx - stretch * tx).max() < 1e-5 * max(1.0, float(np.abs(stretch).max()))
        assert np.abs(vy - stretch * ty).max() < 1e-5 * max(1.0, float(np.abs(stretch).max()))


def test_refusals_name_the_field(plates: tuple[float, list]) -> None:
    _rr, items = plates
    plate, contour = items[1]
    radius, at = concave_radius(contour, plate.radius_of_curvature_mm, plate.contact_cam_angle_deg)
    with pytest.raises(GeometryError) as gouge:
        fit_plate(contour, radius * 1.01, 0.01, radius, at)
    assert gouge.value.field == ("tool_radius_mm",) and "is larger than the concave radius of curvature" in str(
        gouge.value)
    with pytest.raises(LimitExceededError) as limit:
        fit_plate(contour, 0.0, 1e-4, radius, at, max_elements=20)
    assert limit.value.field == ("tolerance_mm",)
