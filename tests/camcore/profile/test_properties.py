"""Property tests for plate-cam profiles over random segment schedules (Hypothesis).

For random rise/dwell/return/dwell schedules, laws, lifts, base radii and follower types:
- the cam contour closes (the surface point at 360° is the one at 0°);
- the reported radius of curvature agrees with the circle through three neighbouring
  contour points (finite differences of the computed contour).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import camcore
from camcore import profile as P

pytestmark = pytest.mark.property

#: laws with continuous acceleration, so the surface curvature is continuous everywhere
LAWS = ["MS", "cycloid", "MT", "3-4-5", "4-5-6-7", "MCV50"]


@st.composite
def cams(draw: st.DrawFn) -> P.CamSpec:
    # four segments of at least 30° adding to 360°
    cuts = sorted(draw(st.lists(st.integers(30, 300), min_size=3, max_size=3, unique=True)))
    angles = [cuts[0], cuts[1] - cuts[0], cuts[2] - cuts[1], 360 - cuts[2]]
    if min(angles) < 30:
        angles = [90, 90, 90, 90]
    lift = draw(st.floats(1.0, 20.0))
    law = camcore.named_curve(draw(st.sampled_from(LAWS)))
    segments = [P.Segment("rise", angles[0], lift, law), P.Segment("dwell", angles[1]),
                P.Segment("return", angles[2], lift, law), P.Segment("dwell", angles[3])]
    kind = draw(st.sampled_from(["knife-edge", "roller", "flat-faced"]))
    rr = draw(st.floats(2.0, 8.0)) if kind == "roller" else 0.0
    # a base radius large against lift and roller keeps the cam convex and free of undercut
    rb = draw(st.floats(4 * lift + 20, 200.0))
    follower = P.Follower(type=kind, roller_radius_mm=rr)
    return P.make_cam(follower, rb, segments=segments, rotation=draw(st.sampled_from(["ccw", "cw"])))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cams())
def test_contour_closes(cam: P.CamSpec) -> None:
    x, y, px, py = P.contour(cam, np.array([0.0, 360.0]))
    size = cam.base_radius_mm + 40
    # a full turn of rotation matrices rounds to ~1e-15 of the radius
    assert math.hypot(x[1] - x[0], y[1] - y[0]) <= 1e-12 * size
    assert math.hypot(px[1] - px[0], py[1] - py[0]) <= 1e-12 * size


def three_point_radius(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Radius of the circle through (x0, y0), (x1, y1), (x2, y2) along the first axis."""
    a = np.hypot(x[1] - x[0], y[1] - y[0])
    b = np.hypot(x[2] - x[1], y[2] - y[1])
    c = np.hypot(x[2] - x[0], y[2] - y[0])
    area2 = np.abs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]))
    return a * b * c / (2 * area2)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cams(), st.lists(st.floats(0.0, 360.0), min_size=5, max_size=5))
def test_radius_of_curvature_agrees_with_finite_differences(cam: P.CamSpec, angles: list[float]) -> None:
    breaks = np.degrees(np.asarray(cam.lift.breaks_rad, dtype=np.float64))
    theta = np.array([a for a in angles if np.min(np.abs(((a - breaks) + 180) % 360 - 180)) > 0.5])
    if theta.size == 0:
        theta = np.array([0.5 * (breaks[0] + breaks[1])])
    # the three-point circle at spacing h has an O(h²) error (the curvature changes along the
    # chord); two spacings and Richardson's step, (4·R(h) − R(2h))/3, cancel it, leaving
    # O(h⁴) ≈ 1e-11 and the chords' rounding (~1e-16·R/(h in rad)² ≈ 1e-7 relative at 0.01°).
    # One spacing alone missed by 1.1e-5 on a steep MS rise (R ≈ 239 mm at 1.875°).
    h = 0.01  # degrees
    result = P.compute_profile(cam, theta)
    n = theta.size

    def three_point(step: float) -> np.ndarray:
        x, y, _, _ = P.contour(cam, np.concatenate([theta - step, theta, theta + step]))
        return three_point_radius(x.reshape(3, n), y.reshape(3, n))

    fd = (4 * three_point(h) - three_point(2 * h)) / 3
    reported = np.asarray(result.radius_of_curvature_mm)
    # what is left is O(h⁴) and the chords' rounding. A coordinate is known to ~eps·|P|, and the
    # radius is read from the sagitta s²/(8R) of a chord s: relative error ~eps·|P|·8R/s², below
    # 1e-7 for the usual radii but 7e-6 on a nearly flat stretch (R ≈ 5939 mm was drawn once and
    # the difference was 1.5e-6: the finite difference, not the formula, is the rougher there).
    # Allowed: 1e-6, plus 4× that bound (three points, two coordinates, Richardson's 4/3 weight).
    x, y, _, _ = P.contour(cam, np.concatenate([theta, theta + h]))
    chord = np.hypot(x[n:] - x[:n], y[n:] - y[:n])
    rounding = 8 * np.finfo(np.float64).eps * np.hypot(x[:n], y[:n]) * np.abs(reported) / chord**2
    assert np.all(np.abs(np.abs(reported) - fd) <= (1e-6 + 4 * rounding) * np.abs(fd)), (theta, reported, fd, rounding)
