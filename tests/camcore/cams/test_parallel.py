"""Parallel indexing cams (camcore.cams.parallel), checked by independent computations.

The rollers here are placed by the index law directly — φ = h·S(θ/θh) from the catalog curve,
B = A + Rp·(−cos(α₀ + φ), sin(α₀ + φ)), turned into the cam's frame — not through the follower
model or ParallelCam.centres; distances are taken to the contour as the polyline it is.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcore
from camcore.cams.parallel import make_parallel_cam, sample_parallel
from camcore.errors import GeometryError, InvalidParameterError

C, RP, RR, TH = 100.0, 60.0, 12.0, 120.0


@pytest.fixture(scope="module")
def three_plates() -> tuple:
    cam = make_parallel_cam(4, C, RP, RR, TH, "MS", plates=3)
    return cam, sample_parallel(cam, 181)


def turret_angle(theta_rad: np.ndarray, stops: int = 4, theta_h_deg: float = TH) -> np.ndarray:
    """φ by the index law, written out: h·S(θ/θh) in the index, h after it, + h per turn [rad]."""
    h = 2 * math.pi / stops
    turns = np.floor(theta_rad / (2 * math.pi))
    within = theta_rad - turns * 2 * math.pi
    t = np.minimum(within / math.radians(theta_h_deg), 1.0)
    s = camcore.named_curve("MS").derivatives(t, 0)[0]
    return h * s + turns * h


def centres(alpha0: np.ndarray, theta: np.ndarray, phi: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Roller centres in the cam's frame (the cam turned by θ counter-clockwise)."""
    alpha = alpha0 + (turret_angle(theta) if phi is None else phi)
    bx, by = C - RP * np.cos(alpha), RP * np.sin(alpha)
    return np.cos(theta) * bx + np.sin(theta) * by, -np.sin(theta) * bx + np.cos(theta) * by


def distance_to_polyline(px: np.ndarray, py: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Distance from each point to the closed polyline (x, y), segment by segment."""
    ax, ay = x, y
    bx, by = np.roll(x, -1), np.roll(y, -1)
    dx, dy = bx - ax, by - ay
    out = np.full(px.shape, np.inf)
    for lo in range(0, px.size, 256):
        qx, qy = px.reshape(-1)[lo:lo + 256, None], py.reshape(-1)[lo:lo + 256, None]
        u = np.clip(((qx - ax) * dx + (qy - ay) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
        d = np.hypot(ax + u * dx - qx, ay + u * dy - qy).min(axis=1)
        out.reshape(-1)[lo:lo + 256] = d
    return out


def test_every_vertex_is_at_the_roller_radius_from_its_roller(three_plates: tuple) -> None:
    _cam, result = three_plates
    for plate in result.plates:
        alpha0 = np.radians(plate.roller_start_angle_deg)[plate.roller]
        bx, by = centres(alpha0, np.radians(plate.contact_cam_angle_deg))
        # the vertices are put on their rollers' circles: rounding of 100 mm coordinates, a few 1e-14
        assert np.abs(np.hypot(plate.x_mm - bx, plate.y_mm - by) - RR).max() < 1e-9


def test_no_roller_enters_its_plate_and_the_contacts_touch(three_plates: tuple) -> None:
    """At 3 600 cam angles over the turn (ten times the answer's sampling, off its grid), every roller of a
    plate keeps at least its radius from the contour; the listed contacts are at the radius."""
    _cam, result = three_plates
    theta = (np.arange(3600) + 0.37) * (2 * math.pi / 3600)
    for plate in result.plates:
        alpha0 = np.radians(plate.roller_start_angle_deg)
        bx, by = centres(alpha0[:, None], theta[None, :])
        d = distance_to_polyline(bx, by, plate.x_mm, plate.y_mm)
        # the contour is a polyline through exact points: a chord between two points of a roller's circle
        # cuts into it by the sagitta, (spacing)²/(8·Rr) at most, ≤ 5e-3 mm here
        spacing = np.hypot(np.diff(plate.x_mm, append=plate.x_mm[0]), np.diff(plate.y_mm, append=plate.y_mm[0]))
        sagitta = spacing.max() ** 2 / (8 * RR)
        assert sagitta < 5e-3
        assert d.min() >= RR - sagitta - 1e-9
        c = plate.contacts
        bx, by = centres(alpha0[c.roller], np.radians(c.cam_angle_deg))
        touching = distance_to_polyline(bx, by, plate.x_mm, plate.y_mm)
        # a contact is an envelope point within 0.1 % of Rr (12e-3 mm) of the contour: its roller is
        # as near as that, and no nearer than the sagitta
        assert np.all(touching - RR <= 1.2e-2) and np.all(touching - RR >= -sagitta - 1e-9)
        assert c.roller.size > 0


def test_pressure_angle_is_the_angle_between_the_normal_and_the_velocity(three_plates: tuple) -> None:
    """At every contact: the normal is the line from the nearest contour point to the roller's centre, the
    velocity is the centre's (fixed frame) by a central difference of the index law."""
    _cam, result = three_plates
    eps = 1e-6
    for plate in result.plates:
        c = plate.contacts
        index = c.cam_angle_deg < TH - 1  # in the index, where the turret moves (clear of its end)
        alpha0 = np.radians(plate.roller_start_angle_deg)[c.roller[index]]
        theta = np.radians(c.cam_angle_deg[index])
        phi = turret_angle(theta)
        # fixed-frame centre velocity per radian of cam angle
        dphi = (turret_angle(theta + eps) - turret_angle(theta - eps)) / (2 * eps)
        vx, vy = RP * np.sin(alpha0 + phi) * dphi, RP * np.cos(alpha0 + phi) * dphi
        # the nearest contour point to the centre, in the cam frame, turned back to the fixed frame
        bx, by = centres(alpha0, theta, phi)
        x, y = plate.x_mm, plate.y_mm
        k = np.argmin((x[None, :] - bx[:, None]) ** 2 + (y[None, :] - by[:, None]) ** 2, axis=1)
        nx, ny = bx - x[k], by - y[k]
        cs, sn = np.cos(theta), np.sin(theta)
        fx, fy = cs * nx - sn * ny, sn * nx + cs * ny
        cos_p = (fx * vx + fy * vy) / (np.hypot(fx, fy) * np.hypot(vx, vy))
        moving = np.hypot(vx, vy) > 1e-3
        expected = np.degrees(np.arccos(np.clip(np.abs(cos_p), 0, 1)))[moving]
        # the nearest vertex stands for the touching point: the vertex spacing (≤ 0.5 mm) over Rr turns
        # the normal by up to ~2°
        assert np.abs(np.abs(c.pressure_angle_deg[index][moving]) - expected).max() < 2.5
        assert np.array_equal(c.drives[index][moving], (cos_p > 0)[moving])


def test_the_plates_produce_the_index_law(three_plates: tuple) -> None:
    """The turret angle the contours allow — the one where every plate's rollers touch it and none enters
    (found by a golden-section search on the polyline distances) — is the index law's, so the motion they
    produce has its characteristic values: Vm = 1.76 for MS (INDEXMAN guide, section 5)."""
    _cam, result = three_plates
    theta = np.radians(np.linspace(2.0, TH - 2.0, 59))
    recovered = []
    for th in theta:
        law = float(turret_angle(np.array([th]))[0])

        def margin(phi: float, th: float = float(th)) -> float:
            worst = np.inf
            for plate in result.plates:
                alpha0 = np.radians(plate.roller_start_angle_deg)
                bx, by = centres(alpha0, np.full(alpha0.shape, th), np.full(alpha0.shape, phi))
                worst = min(worst, float(distance_to_polyline(bx, by, plate.x_mm, plate.y_mm).min() - RR))
            return worst

        a, b = law - 0.01, law + 0.01
        r = (math.sqrt(5) - 1) / 2
        for _ in range(45):
            x1, x2 = b - r * (b - a), a + r * (b - a)
            if margin(x1) >= margin(x2):
                b = x2
            else:
                a = x1
        recovered.append(0.5 * (a + b))
    recovered_arr = np.array(recovered)
    # the plates hold the turret within the polyline's straying (2e-3 mm) over the arm (60 mm) and the
    # contacts' leverage: 1e-4 rad
    assert np.abs(recovered_arr - turret_angle(theta)).max() < 1e-4
    h, th_rad = 2 * math.pi / 4, math.radians(TH)
    velocity = np.gradient(recovered_arr, theta) * th_rad / h
    # the largest dimensionless velocity of the recovered motion against MS's Vm: the angle's 1e-4 rad
    # over a 2° step is 3e-3 of the slope, and the 2° grid misses the peak by ≤ 1e-3
    assert velocity.max() == pytest.approx(camcore.named_curve("MS").characteristics.vm.value, abs=0.02)


def test_checks_of_the_three_plate_example(three_plates: tuple) -> None:
    _cam, result = three_plates
    checks = result.checks
    assert checks.conjugate and checks.unheld_cam_angles_deg == []
    assert np.all(result.held_forward) and np.all(result.held_back)
    assert 0 < checks.max_pressure_angle_deg < 60
    assert checks.turret_axis_clearance_mm > 0
    assert not checks.undercut
    # in the dwell the turret stands at a whole index; over the index it follows the law
    assert result.turret_angle_deg[result.cam_angle_deg > TH] == pytest.approx(90.0, abs=1e-12)


def test_two_plates_report_where_the_turret_is_not_held() -> None:
    """The same turret with two plates: at the start of the index plate 1's roller stands on the line of
    centres (pressure angle 90°) and for a stretch no contact holds it one of the two ways."""
    result = sample_parallel(make_parallel_cam(4, C, RP, RR, TH, "MS", plates=2), 181)
    assert not result.checks.conjugate
    stretch = (result.cam_angle_deg > 5) & (result.cam_angle_deg < 20)
    assert not (result.held_forward & result.held_back)[stretch].any()
    unheld = ~(result.held_forward & result.held_back)
    assert result.checks.unheld_cam_angles_deg == pytest.approx(list(result.cam_angle_deg[unheld][:10]))


@pytest.mark.parametrize("kwargs, error, match", [
    ({"rollers_per_plate": 8, "roller_radius_mm": 24}, GeometryError, "rollers of a plate collide"),
    ({"center_distance_mm": 70}, GeometryError, "reach the cam axis"),
    ({"rollers_per_plate": 6}, InvalidParameterError, "multiple of stops"),
    ({"plates": 4}, InvalidParameterError, "plates must be 2 or 3"),
    ({"indexing_angle_deg": 360}, InvalidParameterError, "1 … 359"),
    ({"roller_radius_mm": 0.05}, GeometryError, "at least 0.1% of center_distance_mm"),
])
def test_bad_geometry_is_refused(kwargs: dict, error: type, match: str) -> None:
    args = {"stops": 4, "center_distance_mm": C, "roller_pitch_radius_mm": RP, "roller_radius_mm": RR,
            "indexing_angle_deg": TH, "plates": 3, **kwargs}
    with pytest.raises(error, match=match):
        make_parallel_cam(**args)


def test_a_plate_past_the_turret_axis_is_refused() -> None:
    # two stops: the dwell rollers stand at ±90°, farther from the cam axis than the turret's axis
    with pytest.raises(GeometryError, match="reaches the turret's axis"):
        sample_parallel(make_parallel_cam(2, 80, 60, 10, 180, plates=3), 61)
