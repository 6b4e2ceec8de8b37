"""The barrel cam as a solid (camcore.export.barrel_solid), checked by routes that share nothing
with its construction:

- the STEP file is read back by the kernel's STEP reader (the writer's shape is gone): one solid,
  valid for ``BRepCheck_Analyzer``, its tight box the blank's;
- its volume (the kernel's adaptive integration over its faces) equals the blank's less the
  groove's, the groove's volume integrated here from the lift alone as the room the roller
  sweeps: on each cylinder about the axis the roller at cam angle θ holds the heights within its
  radius of its axis, the union over θ found by a search over θ at every point round the
  cylinder, and the areas integrated over the radius (Gauss-Legendre) — for a cylindrical roller,
  a conical one and an oscillating arm;
- exact flank points (the envelope formula, :func:`flank_points`) lie on the solid's faces
  within the tolerance (the kernel's point-to-face distance);
- the STL is closed, its volume (the divergence theorem) the same within its own tolerance;
- refusals name their field.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcore
from camcore._maxima import golden_max
from camcore.cams.barrel import BarrelCam, flank_points, make_barrel_cam
from camcore.curves.kinds import build_curve
from camcore.errors import CamError, LimitExceededError
from camcore.export import SOLID_FORMATS
from camcore.export.barrel_solid import BarrelSolid, build_barrel_solid
from camcore.motion import Law, MotionSegment, MotionSpec, resolve_motion
from camcore.profile import Segment
from tests.readers import count_solids, step_shape
from tests.stl_mesh import directed_edges, read_stl

MS = camcore.named_curve("MS")
RISE = [Segment("rise", 120, lift_mm=30, curve=MS), Segment("dwell", 60), Segment("return", 120, lift_mm=30),
        Segment("dwell", 60)]
SWING = [Segment("rise", 150, swing_deg=30), Segment("dwell", 30), Segment("return", 150, swing_deg=30),
         Segment("dwell", 30)]
FEED = MotionSpec([MotionSegment(30, type="dwell"), MotionSegment(60, to=10, law=Law("polynomial", {})),
                   MotionSegment(120, to=50, law=Law("named", {"name": "constant-velocity"})),
                   MotionSegment(60, to=60, law=Law("polynomial", {})), MotionSegment(30, type="dwell"),
                   MotionSegment(60, to=0)])
CAMS = {
    "cylinder": make_barrel_cam(50.0, 10.0, roller_length_mm=12.0, segments=RISE),
    "cone": make_barrel_cam(80.0, 10.0, roller_length_mm=16.0, groove_depth_mm=18.0, motion=resolve_motion(FEED),
                            roller="conical"),
    "oscillating": make_barrel_cam(60.0, 8.0, roller_length_mm=10.0, segments=SWING, follower="oscillating",
                                   arm_length_mm=80.0, initial_arm_angle_deg=-15.0),
}
#: points round each cylinder for the reference's area: the heights' span is smooth and periodic,
#: so the trapezoid rule converges fast (2 048 and 32 768 points gave the same area to 1e-12)
ROUND = 4096
#: Gauss-Legendre nodes over the depth: 4 and 12 gave the same volume to 1e-11
DEPTH_NODES = 8


def radii(cam: BarrelCam) -> tuple[float, float]:
    outer = cam.pitch_radius_mm + 0.5 * cam.roller_length_mm
    return outer, outer - cam.groove_depth_mm


def axis(cam: BarrelCam, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The roller's axis at cam angles θ, from the lift: its offset across the cam axis and its z
    (translating: (0, s); oscillating: the arm's (L(cos ψ − 1), L sin ψ))."""
    lift = cam.lift.derivatives(theta, 0)[0]
    if cam.follower == "translating":
        return np.zeros_like(lift), lift
    arm = np.radians(cam.initial_arm_angle_deg + lift)
    length = float(cam.arm_length_mm or 0.0)
    return length * (np.cos(arm) - 1.0), length * np.sin(arm)


def swept_area(cam: BarrelCam, r: float) -> float:
    """The area the roller sweeps on the cylinder of radius r: at polar angle φ the roller at θ
    (its axis the line (x, b_y, b_z) turned by θ) holds the heights b_z ± √(ρ² − (r sin(φ − θ) − b_y)²),
    ρ its radius where it crosses (a cone: x·tan α, x = r cos(φ − θ)); the groove at φ is their
    union over θ, the largest top and the smallest bottom, each by a scan and golden section."""
    tan = cam.roller_radius_mm / cam.pitch_radius_mm
    phi = np.arange(ROUND) * (2 * math.pi / ROUND)

    def reach(theta: np.ndarray, at: np.ndarray, sign: float) -> np.ndarray:
        b_y, b_z = axis(cam, theta)
        x = r * np.cos(at - theta)
        rho = x * tan if cam.roller == "conical" else np.full_like(x, cam.roller_radius_mm)
        half2 = rho**2 - (r * np.sin(at - theta) - b_y) ** 2
        inside = (half2 >= 0) & (x > 0)
        return np.where(inside, sign * b_z + np.sqrt(np.maximum(half2, 0.0)), -np.inf)

    width = math.asin(min(1.0, 2.0 * cam.roller_radius_mm / r)) + 0.1  # the roller's reach round the cylinder
    offsets = np.linspace(-width, width, 97)
    extremes = []
    for sign in (1.0, -1.0):
        grid = phi[:, None] + offsets[None, :]
        values = reach(grid.reshape(-1), np.repeat(phi, offsets.size), sign).reshape(ROUND, offsets.size)
        best = np.argmax(values, axis=1)
        lanes = np.arange(ROUND)
        lo, hi = grid[lanes, np.maximum(best - 1, 0)], grid[lanes, np.minimum(best + 1, offsets.size - 1)]
        _, refined = golden_max(lambda t, s=sign: reach(t, phi, s), lo, hi, width=1e-12)
        extremes.append(np.maximum(values[lanes, best], refined))
    top, minus_bottom = extremes
    return float((top + minus_bottom).sum() * r * (2 * math.pi / ROUND))


def groove_volume(cam: BarrelCam) -> float:
    outer, bottom = radii(cam)
    x, w = np.polynomial.legendre.leggauss(DEPTH_NODES)
    r = 0.5 * (outer - bottom) * x + 0.5 * (outer + bottom)
    return 0.5 * (outer - bottom) * sum(float(wi) * swept_area(cam, float(ri)) for ri, wi in zip(r, w, strict=True))


def extent(cam: BarrelCam) -> tuple[float, float, float]:
    """The groove's lowest and highest z and its walls' area, from exact flank points on a dense grid
    across the whole depth (the envelope formula continued below the roller's inner end)."""
    outer, bottom = radii(cam)
    flanks = flank_points(cam, np.linspace(0.0, 360.0, 3601), np.linspace(bottom, outer, 13))
    z = np.concatenate([np.asarray(f[2]).ravel() for f in flanks.values()])
    area = 0.0
    for x, y, zz in flanks.values():
        p = np.stack([x, y, zz], axis=-1)
        area += float(np.linalg.norm(np.cross(p[1:, :-1] - p[:-1, :-1], p[:-1, 1:] - p[:-1, :-1]), axis=-1).sum())
    return float(z.min()), float(z.max()), area


def kernel_volume(shape: object) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-9)  # adaptive, to 1e-9 relative a face
    return float(props.Mass())


@pytest.mark.parametrize("name", list(CAMS))
def test_the_step_solid_is_the_blank_less_the_groove_the_roller_sweeps(name: str) -> None:
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepCheck import BRepCheck_Analyzer

    cam = CAMS[name]
    tolerance, bore, margin = 0.01, 20.0, 6.0
    shape = step_shape(SOLID_FORMATS["step"].write(BarrelSolid(cam, tolerance, margin, bore)))
    assert count_solids(shape) == 1 and BRepCheck_Analyzer(shape).IsValid()
    outer, bottom = radii(cam)
    z_min, z_max, walls = extent(cam)
    box = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, box, False, False)
    lo, hi = box.CornerMin(), box.CornerMax()
    # the bands of the outer cylinder stand within the tolerance of it; the ends are exact planes (the
    # dense grid finds the groove's extremes in the dwells, where the walls are flat)
    assert (lo.Z(), hi.Z()) == pytest.approx((z_min - margin, z_max + margin), abs=1e-6)
    assert [lo.X(), lo.Y(), hi.X(), hi.Y()] == pytest.approx([-outer, -outer, outer, outer], abs=tolerance)
    expected = math.pi * (outer**2 - (bore / 2) ** 2) * (z_max - z_min + 2 * margin) - groove_volume(cam)
    # every surface lies within the tolerance of the exact one: the volumes differ by at most the
    # tolerance times the area of the surfaces fitted (the walls, the floor and the outer cylinder)
    fitted = walls + 2 * math.pi * (bottom + outer) * (z_max - z_min + 2 * margin)
    volume = kernel_volume(shape)
    assert abs(volume - expected) <= tolerance * fitted, (volume, expected)


def test_the_volume_converges_with_the_tolerance() -> None:
    """Measured: 1.47 mm³ off at 0.01 mm, 0.11 mm³ at 1e-4 mm (of 78 227 mm³ of groove): the Hermite
    bands sag inside the outer cylinder by up to r·h⁴/128, and that shrinks with the node spacing."""
    cam = CAMS["cylinder"]
    outer, bottom = radii(cam)
    z_min, z_max, walls = extent(cam)
    expected = math.pi * outer**2 * (z_max - z_min + 2 * 10.0) - groove_volume(cam)
    fitted = walls + 2 * math.pi * (bottom + outer) * (z_max - z_min + 20.0)
    errors = []
    for tolerance in (0.01, 1e-4):
        volume = kernel_volume(build_barrel_solid(BarrelSolid(cam, tolerance)))
        errors.append(abs(volume - expected))
        assert errors[-1] <= tolerance * fitted
    assert errors[1] < errors[0]


@pytest.mark.parametrize("name", list(CAMS))
def test_exact_flank_points_lie_on_the_solid_within_the_tolerance(name: str) -> None:
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS_Compound

    cam = CAMS[name]
    tolerance = 0.01
    shape = step_shape(SOLID_FORMATS["step"].write(BarrelSolid(cam, tolerance)))
    faces, builder = TopoDS_Compound(), BRep_Builder()
    builder.MakeCompound(faces)
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():  # the faces, not the solid: a point inside a solid is at distance 0 from it
        builder.Add(faces, explorer.Current())
        explorer.Next()
    outer, bottom = radii(cam)
    # angles off every node of the fit (they fall at multiples of 15° / 2^k from the breaks)
    angles = np.arange(1.3, 360.0, 7.7)
    flanks = flank_points(cam, angles, np.linspace(bottom + 0.5, outer - 0.5, 4))
    worst = 0.0
    for x, y, z in flanks.values():
        for p in zip(np.ravel(x), np.ravel(y), np.ravel(z), strict=True):
            distance = BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(gp_Pnt(*p)).Vertex(), faces)
            worst = max(worst, distance.Value())
    assert worst <= tolerance


def test_the_stl_is_closed_with_the_steps_volume() -> None:
    cam = CAMS["cylinder"]
    tolerance = 0.05
    solid = BarrelSolid(cam, tolerance, bore_diameter_mm=20.0)
    facets = read_stl(SOLID_FORMATS["stl"].write(solid))
    edges = directed_edges(facets)
    assert all(n == 1 for n in edges.values()) and all(edges[(q, p)] == 1 for p, q in edges)
    assert len(facets) <= solid.facets_estimate(tolerance / 2)
    v0, v1, v2 = facets[:, 0], facets[:, 1], facets[:, 2]
    volume = float(np.einsum("ij,ij->i", v0, np.cross(v1, v2)).sum() / 6.0)
    outer, bottom = radii(cam)
    z_min, z_max, walls = extent(cam)
    expected = math.pi * (outer**2 - 100.0) * (z_max - z_min + 20.0) - groove_volume(cam)
    fitted = walls + 2 * math.pi * (bottom + outer + 10.0) * (z_max - z_min + 20.0)
    # the surfaces within half the tolerance, the facets within the other half of them
    assert abs(volume - expected) <= tolerance * fitted


def test_refusals_name_the_field() -> None:
    cam = CAMS["cylinder"]
    with pytest.raises(CamError) as bore:
        build_barrel_solid(BarrelSolid(cam, bore_diameter_mm=88.0))
    assert bore.value.field == ("solid", "bore_diameter_mm")
    with pytest.raises(CamError) as margin:
        build_barrel_solid(BarrelSolid(cam, end_margin_mm=0.0))
    assert margin.value.field == ("solid", "end_margin_mm")
    cv = build_curve("named", {"name": "constant-velocity"})
    corner = make_barrel_cam(50.0, 10.0, segments=[Segment("rise", 180, lift_mm=20, curve=cv),
                                                   Segment("return", 180, lift_mm=20, curve=cv)])
    with pytest.raises(CamError) as kink:
        build_barrel_solid(BarrelSolid(corner))
    assert kink.value.field == ("solid",) and "velocity jumps" in str(kink.value)
    # a roller larger than the groove's tightest bend: the walls loop (the cam's checks say undercut too)
    tight = make_barrel_cam(50.0, 10.0, roller_length_mm=12.0, segments=[
        Segment("rise", 22.5, lift_mm=10, curve=MS), Segment("dwell", 22.5), Segment("return", 22.5, lift_mm=10),
        Segment("dwell", 292.5)])
    with pytest.raises(CamError) as loop:
        build_barrel_solid(BarrelSolid(tight))
    assert loop.value.field == ("roller_radius_mm",) and "undercut" in str(loop.value)
    with pytest.raises(LimitExceededError) as poles:
        build_barrel_solid(BarrelSolid(cam, 1e-4, max_poles=3000))
    assert poles.value.field == ("solid", "tolerance_mm")
    with pytest.raises(LimitExceededError) as facets:
        SOLID_FORMATS["stl"].write(BarrelSolid(cam, 0.01, max_triangles=5000))
    assert facets.value.field == ("solid", "tolerance_mm")
