"""Roller-gear (globoidal) indexing cams (camcore.cams.roller_gear), checked by independent computations.

The rollers are placed here by the index law written out — φ = h·S(θ/θh) from the catalog curve,
the roller ahead of the rib at α = φ and the one behind at α = φ − h, its axis A + t·(−cos α, 0,
sin α) with A = (C, 0, 0) — and the flank points are turned out of the cam's frame by the cam
angle; nothing here goes through the module's own contact formulas.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np
import pytest

import camcore
from camcore.cams.roller_gear import make_roller_gear_cam, rib_triangles, sample_roller_gear
from camcore.errors import GeometryError, InvalidParameterError
from camcore.export import mesh_stl
from tests.stl_mesh import directed_edges, read_stl

STOPS, C, RP, RR, LENGTH, TH = 8, 100.0, 60.0, 10.0, 20.0, 120.0
H = 2 * math.pi / STOPS


@pytest.fixture(scope="module")
def fine() -> object:
    return sample_roller_gear(make_roller_gear_cam(STOPS, C, RP, RR, LENGTH, TH, "MS"), 3601, 21)


def turret_angle(theta_rad: np.ndarray, theta_h_deg: float = TH) -> np.ndarray:
    """φ by the index law, written out: h·S(θ/θh) in the index, h after it, + h per turn [rad]."""
    turns = np.floor(theta_rad / (2 * math.pi))
    within = theta_rad - turns * 2 * math.pi
    t = np.minimum(within / math.radians(theta_h_deg), 1.0)
    return H * camcore.named_curve("MS").derivatives(t, 0)[0] + turns * H


def roller_alpha(flank: str, theta_rad: np.ndarray, theta_h_deg: float = TH) -> np.ndarray:
    return turret_angle(theta_rad, theta_h_deg) - (H if flank == "back" else 0.0)


def fixed_frame(flank: object, theta_rad: np.ndarray) -> np.ndarray:
    """The flank grid turned out of the cam's frame by θ (rows): shape (angles, positions, 3)."""
    c, s = np.cos(theta_rad)[:, None], np.sin(theta_rad)[:, None]
    x, y, z = flank.x_mm, flank.y_mm, flank.z_mm  # type: ignore[attr-defined]
    return np.stack([c * x - s * y, s * x + c * y, z], axis=-1)


def to_roller_axis(p: np.ndarray, alpha: np.ndarray, center_distance: float = C) -> tuple[np.ndarray, np.ndarray]:
    """Distance of points from the roller axis at α, and the foot's distance t from the turret axis."""
    u = np.stack(np.broadcast_arrays(-np.cos(alpha), 0.0, np.sin(alpha)), axis=-1)
    v = p - np.array([center_distance, 0.0, 0.0])
    t = np.einsum("...i,...i->...", v, u)
    return np.linalg.norm(v - t[..., None] * u, axis=-1), t


def roller_clearance(p: np.ndarray, alpha: np.ndarray, theta_h_deg: float = TH) -> np.ndarray:
    """Distance of points from the axis of the finite roller at α; inf where the foot of the
    perpendicular lies beyond the roller's ends (the point is not beside the roller)."""
    d, t = to_roller_axis(p, alpha)
    return np.where((t >= RP - LENGTH / 2) & (t <= RP + LENGTH / 2), d, np.inf)


def cam_point_at(q: np.ndarray, theta_rad: np.ndarray | float) -> np.ndarray:
    """A point fixed in the cam's frame, in the fixed frame when the cam stands at θ."""
    c, s = np.cos(theta_rad), np.sin(theta_rad)
    return np.stack([c * q[..., 0] - s * q[..., 1], s * q[..., 0] + c * q[..., 1], q[..., 2] + 0 * c], axis=-1)


@pytest.mark.parametrize("flank", ["forward", "back"])
def test_every_flank_point_is_on_its_roller(fine: object, flank: str) -> None:
    theta = np.radians(fine.cam_angle_deg)  # type: ignore[attr-defined]
    grid = getattr(fine, flank)
    d, t = to_roller_axis(fixed_frame(grid, theta), roller_alpha(flank, theta)[:, None])
    # on the roller's cylinder and at the grid's position along it; coordinates of ~100 mm
    # carry ~1e-14 mm of rounding, the index law's own ~1e-15 rad moves a point ~1e-13 mm
    assert np.abs(d - RR).max() < 1e-9
    assert np.abs(t - fine.roller_position_mm).max() < 1e-9  # type: ignore[attr-defined]


@pytest.mark.parametrize("flank", ["forward", "back"])
def test_the_flank_is_the_envelope_stationary_in_the_cam_angle(fine: object, flank: str) -> None:
    """At the cam angle that makes it, a flank point's distance from the moving roller's axis is
    stationary (it is the envelope, n·v_rel = 0), and the roller stays clear of it all turn."""
    theta = np.radians(fine.cam_angle_deg)[::20]  # type: ignore[attr-defined]
    grid = getattr(fine, flank)
    q = np.stack([grid.x_mm, grid.y_mm, grid.z_mm], axis=-1)[::20]
    delta = 1e-4

    def distance(shift: float, points: np.ndarray = q) -> np.ndarray:
        at = theta[:, None] + shift
        return to_roller_axis(cam_point_at(points, at), roller_alpha(flank, at))[0]

    def clearance(shift: float) -> np.ndarray:
        at = theta[:, None] + shift
        return roller_clearance(cam_point_at(q, at), roller_alpha(flank, at))

    slope = (distance(delta) - distance(-delta)) / (2 * delta)
    # the central difference of a function with zero slope is δ²/6 times its third derivative
    # (here ≲ 1e3 mm/rad³): ≤ 2e-6 mm/rad; a point a tenth of the radius off the contact line
    # moves at ~1 mm/rad relative to the roller
    assert np.abs(slope).max() < 2e-6
    off = q.copy()
    off[..., 2] += 0.1 * RR
    moved = (distance(delta, off) - distance(-delta, off)) / (2 * delta)
    assert np.abs(moved[np.radians(fine.cam_angle_deg)[::20] < math.radians(TH)]).max() > 0.1  # type: ignore[attr-defined]
    # clear elsewhere: the roller (its length), at every cam angle of the turn before and after
    # (0.5° apart), never holds a flank point; the contact itself is at RR to ~1e-13
    for shift in np.radians(np.arange(-360.0, 360.5, 0.5)):
        assert clearance(shift).min() > RR - 1e-9, shift


def test_pressure_angle_is_that_of_the_flank_normal_against_the_roller_velocity(fine: object) -> None:
    """The flank's normal from finite differences of the grid, against the roller's direction of motion
    w = (sin α, 0, cos α) (square to its axis in the turret's plane)."""
    theta = np.radians(fine.cam_angle_deg)  # type: ignore[attr-defined]
    for flank in ("forward", "back"):
        grid = getattr(fine, flank)
        q = np.stack([grid.x_mm, grid.y_mm, grid.z_mm], axis=-1)
        # central differences over one and two grid steps, Richardson-extrapolated (error O(step⁴))
        d_theta = (2 * (q[3:-1, 2:-2] - q[1:-3, 2:-2]) - (q[4:, 2:-2] - q[:-4, 2:-2]) / 4) / 3
        d_r = (2 * (q[2:-2, 3:-1] - q[2:-2, 1:-3]) - (q[2:-2, 4:] - q[2:-2, :-4]) / 4) / 3
        normal = cam_point_at(np.cross(d_theta, d_r), theta[2:-2, None])  # a direction turns as a point does
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
        alpha = roller_alpha(flank, theta[2:-2])[:, None]
        w = np.stack(np.broadcast_arrays(np.sin(alpha), 0.0, np.cos(alpha)), axis=-1)
        angle = np.degrees(np.arccos(np.clip(np.abs(np.einsum("...i,...i->...", normal, w)), 0.0, 1.0)))
        reported = np.abs(grid.pressure_angle_deg[2:-2, 2:-2])
        # over 0.1° and 1 mm steps the extrapolated normal is within 1.2e-6° across the flank
        # (99th percentile, measured); up to 3.1e-5° beside the index's end, where the MS law's
        # jerk jumps and the differences straddle the jump
        assert np.abs(angle - reported).max() < 5e-5, flank
    assert fine.checks.max_pressure_angle_deg > 40  # type: ignore[attr-defined]


def test_largest_pressure_angle_is_the_dense_maximum() -> None:
    cam = make_roller_gear_cam(STOPS, C, RP, RR, LENGTH, TH, "MS")
    checks = sample_roller_gear(cam, 37, 3).checks
    theta = np.linspace(0.0, math.radians(TH), 400_001)
    phi = turret_angle(theta)
    dphi = np.gradient(phi, theta)
    dense = 0.0
    for flank in ("forward", "back"):
        alpha = roller_alpha(flank, theta)
        dense = max(dense, float(np.degrees(np.arctan(np.abs(dphi) * RP / (C - RP * np.cos(alpha)))).max()))
    # the dense grid's step (3e-4°) and np.gradient's error (~1e-9) bound the gap
    assert checks.max_pressure_angle_deg == pytest.approx(dense, abs=1e-6)
    assert checks.max_pressure_angle_along_roller_deg > checks.max_pressure_angle_deg


def test_the_rib_gives_back_the_index_law_and_its_characteristic_values(fine: object) -> None:
    """The turret's angle recovered from the forward flank's points alone (each point at Rr from its
    roller's axis, at the grid's distance along it), then Vm and Am of the law from it."""
    theta = np.radians(fine.cam_angle_deg)  # type: ignore[attr-defined]
    p = fixed_frame(fine.forward, theta)  # type: ignore[attr-defined]
    r = fine.roller_position_mm  # type: ignore[attr-defined]
    v = p - np.array([C, 0.0, 0.0])
    # (P − A)·u(α) = r with u = (−cos α, 0, sin α): ρ·cos(α − α*) = r, the root nearer the line of centres
    rho, star = np.hypot(v[..., 0], v[..., 2]), np.arctan2(v[..., 2], -v[..., 0])
    roots = np.stack([star - np.arccos(r / rho), star + np.arccos(r / rho)])
    alpha = np.take_along_axis(roots, np.argmin(np.abs(roots - turret_angle(theta)[:, None]), axis=0)[None], 0)[0]
    assert np.ptp(alpha, axis=1).max() < 1e-9  # one angle per row, whatever the point used
    recovered = alpha.mean(axis=1)
    assert np.abs(recovered - turret_angle(theta)).max() < 1e-9
    # dimensionless: T = θ/θh, S = φ/h; central differences over ΔT = 1/1200
    index = theta <= math.radians(TH) + 1e-12
    t, s = theta[index] / math.radians(TH), recovered[index] / H
    v_rec = np.gradient(s, t)
    a_rec = np.diff(s, 2) / np.diff(t)[1:] ** 2
    ms = camcore.named_curve("MS").characteristics
    # a difference over ΔT carries ΔT²/6 of the third derivative (|J| ≤ 70 for MS): ≤ 1e-5 on V,
    # and the grid falls 0.04 % of ΔT from the peak of A: ≤ 1e-4 relative
    assert v_rec.max() == pytest.approx(ms.vm.value, abs=2e-5)
    assert a_rec.max() == pytest.approx(ms.am_pos.value, rel=1e-4)


def test_a_short_index_folds_the_flank_and_the_roller_cuts_it() -> None:
    """Undercut, shown by brute force: where the checks say the flank folds, some flank point lies
    inside its roller at another cam angle; the regular cam keeps every point outside (test above)."""
    cam = make_roller_gear_cam(STOPS, C, RP, RR, LENGTH, 30.0, "MS")
    result = sample_roller_gear(cam, 721, 5)
    assert result.checks.undercut and result.checks.min_regularity < 0
    assert result.checks.undercut_cam_angles_deg and max(result.checks.undercut_cam_angles_deg) <= 30.0
    theta = np.radians(result.cam_angle_deg)
    q = np.stack([result.forward.x_mm, result.forward.y_mm, result.forward.z_mm], axis=-1)
    inside = np.inf
    for shift in np.radians(np.arange(-40.0, 40.25, 0.25)):
        at = theta[:, None] + shift
        inside = min(inside, float(roller_clearance(cam_point_at(q, at), roller_alpha("forward", at, 30.0)).min()))
    assert inside < RR - 0.1, inside  # cut deeper than a tenth of a millimetre
    assert not sample_roller_gear(make_roller_gear_cam(STOPS, C, RP, RR, LENGTH, TH, "MS"), 181, 5).checks.undercut


def test_rib_stl_is_closed_with_positive_volume_and_reads_in_the_cad_kernel() -> None:
    result = sample_roller_gear(make_roller_gear_cam(STOPS, C, RP, RR, LENGTH, TH, "MS"), 181, 5)
    data = mesh_stl(rib_triangles(result), header="roller-gear rib")
    facets = read_stl(data)
    edges = directed_edges(facets)
    # closed and consistently oriented: each directed edge once and its reverse once
    assert all(n == 1 for n in edges.values()) and all(edges[(q, p)] == 1 for p, q in edges)
    volume = float(np.einsum("ij,ij->i", facets[:, 0], np.cross(facets[:, 1], facets[:, 2])).sum() / 6.0)
    assert volume > 0
    # the rib's volume by a second route, Pappus's theorem in differential form: the cross-section
    # rings' vector areas A (shoelace) along the path of their area centroids c, V = ∫ A·dc. The
    # rings are not plane sections (their points stand at different polar angles round the cam
    # axis), which this route ignores: it differs by 0.43 % here, and each route moves by < 0.05 %
    # from 181 to 2 881 samples (measured), so the two agree within 1 %
    fwd = np.stack([result.forward.x_mm, result.forward.y_mm, result.forward.z_mm], -1)
    back = np.stack([result.back.x_mm, result.back.y_mm, result.back.z_mm], -1)
    rings = np.concatenate([fwd, back[:, ::-1]], axis=1)
    following = np.roll(rings, -1, axis=1)
    edge_cross = np.cross(rings, following)
    vector_area = 0.5 * edge_cross.sum(axis=1)
    unit = vector_area / np.linalg.norm(vector_area, axis=-1, keepdims=True)
    weight = np.einsum("rki,ri->rk", edge_cross, unit)
    centroid = ((rings + following) * weight[..., None]).sum(axis=1) / (3 * weight.sum(axis=1))[:, None]
    swept = np.einsum("ij,ij->i", 0.5 * (vector_area[1:] + vector_area[:-1]), np.diff(centroid, axis=0)).sum()
    assert volume == pytest.approx(float(swept), rel=0.01)
    # an independent reader: OpenCASCADE's STL reader (RWStl) reads every facet
    from OCP.RWStl import RWStl

    with tempfile.TemporaryDirectory() as folder:
        path_stl = Path(folder) / "rib.stl"
        path_stl.write_bytes(data)
        mesh = RWStl.ReadFile_s(str(path_stl))
    assert mesh.NbTriangles() == facets.shape[0]
    nodes = np.array([[mesh.Node(i).X(), mesh.Node(i).Y(), mesh.Node(i).Z()] for i in range(1, mesh.NbNodes() + 1)])
    corners = np.array([mesh.Triangle(i).Get() for i in range(1, mesh.NbTriangles() + 1)]) - 1
    tri = nodes[corners]
    kernel_volume = float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0)
    # the kernel merges equal vertices and keeps our orientation: the same volume to float32's 1e-7
    assert kernel_volume == pytest.approx(volume, rel=1e-6)


def test_stl_limit_is_refused_with_the_field() -> None:
    result = sample_roller_gear(make_roller_gear_cam(STOPS, C, RP, RR, LENGTH, TH, "MS"), 37, 3)
    with pytest.raises(camcore.errors.LimitExceededError) as info:
        mesh_stl(rib_triangles(result), max_triangles=100, field=("samples",))
    assert info.value.field == ("samples",)


@pytest.mark.parametrize(("args", "error", "words"), [
    ((4, C, RP, RR, LENGTH, TH), InvalidParameterError, "stops must be at least 5"),
    ((STOPS, C, RP, 25.0, LENGTH, TH), GeometryError, "no room for the rib"),
    ((STOPS, C, 95.0, RR, LENGTH, TH), GeometryError, "reach the cam axis"),
    ((STOPS, C, RP, RR, 130.0, TH), GeometryError, "cross the turret's axis"),
    ((STOPS, C, RP, RR, LENGTH, 0.5), InvalidParameterError, "indexing_angle_deg must lie in 1 … 359"),
    ((STOPS, C, RP, 0.05, LENGTH, TH), GeometryError, "at least 0.1% of center_distance_mm"),
])
def test_bad_geometry_is_refused_with_the_rule(args: tuple, error: type, words: str) -> None:
    with pytest.raises(error) as info:
        make_roller_gear_cam(*args, "MS")
    assert words in str(info.value)


def test_the_rib_s_end_is_in_the_dwell_whatever_the_law_s_start() -> None:
    """At 360° the turret stands in the dwell: the last sample is that surface of revolution, as the one
    before it, not the next index's start (constant acceleration jumps to A ≠ 0 there, which folded
    the last row and reported an undercut the cam does not have)."""
    result = sample_roller_gear(make_roller_gear_cam(6, 238.3, 158.9, 20.06, 110.3, 274.0, "constant-acceleration"),
                                361, 9)
    assert not result.checks.undercut and result.checks.min_regularity > 0
    for flank in (result.forward, result.back):
        assert flank.pressure_angle_deg[-1] == pytest.approx(flank.pressure_angle_deg[-2], abs=1e-12)
        assert flank.regular[-1].all()
