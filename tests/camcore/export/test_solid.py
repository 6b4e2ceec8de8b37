"""Solids (camcore.export.SOLID_FORMATS): the plate cam extruded with its bore, by OpenCASCADE.

The STEP file is read back through the kernel's own STEP reader (a second path through the
file: the writer's shape is gone) as one solid; its volume must be (contour area − bore
area) × thickness and its box the contour's box × [0, thickness], with the contour area and
box taken independently from ``compute_profile``'s surface at 0.001°. The STL is parsed here
(binary layout, 50 bytes a facet): closed (every edge shared by exactly two facets, in
opposite directions), its volume by the divergence theorem.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcore
from camcore.errors import InvalidParameterError, LimitExceededError
from camcore.export import SOLID_FORMATS, SolidCam, solid_step, solid_stl
from camcore.export.solid import MIN_THICKNESS_MM
from camcore.profile import Follower, Segment, compute_profile, make_cam
from tests.readers import count_solids, step_shape
from tests.stl_mesh import directed_edges, read_stl

MS = camcore.named_curve("MS")
ROLLER = make_cam(Follower(type="roller", roller_radius_mm=10), 40, segments=[
    Segment(type="rise", angle_deg=120, lift_mm=20, curve=MS), Segment(type="dwell", angle_deg=60),
    Segment(type="return", angle_deg=120, lift_mm=20), Segment(type="dwell", angle_deg=60)])
FLAT = make_cam(Follower(type="flat-faced", motion="oscillating", pivot_distance_mm=90), 35, segments=[
    Segment(type="rise", angle_deg=150, swing_deg=12), Segment(type="dwell", angle_deg=30),
    Segment(type="return", angle_deg=150, swing_deg=12), Segment(type="dwell", angle_deg=30)], rotation="cw")


def exact_contour(spec: camcore.profile.CamSpec) -> tuple[float, float, np.ndarray]:
    """Area [mm²], perimeter [mm] and points of the exact surface, 360 001 points: the polygon's
    area misses the curve's by at most perimeter × sagitta ≈ 400 × 1e-9 mm²."""
    p = compute_profile(spec, np.linspace(0.0, 360.0, 360001))
    x, y = p.x_mm[:-1], p.y_mm[:-1]
    area = 0.5 * abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))
    perimeter = float(np.sum(np.hypot(np.diff(p.x_mm), np.diff(p.y_mm))))
    return area, perimeter, np.column_stack([x, y])


def read_step(data: bytes) -> tuple[int, float, tuple[float, ...]]:
    """Solids, volume and box of a STEP file, through the kernel's STEP reader."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    shape = step_shape(data)
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box, False)
    lo, hi = box.CornerMin(), box.CornerMax()
    return count_solids(shape), props.Mass(), (lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z())


@pytest.mark.parametrize(("spec", "bore"), [(ROLLER, 20.0), (FLAT, 0.0)], ids=["roller-bored", "flat-oscillating"])
def test_step_reads_back_as_one_solid_of_the_right_volume_and_box(spec: camcore.profile.CamSpec, bore: float) -> None:
    tolerance, thickness = 0.001, 12.0
    solids, volume, box = read_step(solid_step(SolidCam(spec, thickness, bore, tolerance)))
    area, perimeter, pts = exact_contour(spec)
    assert solids == 1
    # the contour lies within the tolerance of the exact surface, so the areas differ by at most
    # perimeter × tolerance (here ~0.4 mm² of ~7 000 mm²); the kernel's volume is exact for lines
    # and arcs (to its 1e-7 mm precision)
    expected = (area - math.pi * bore**2 / 4) * thickness
    assert abs(volume - expected) <= perimeter * tolerance * thickness
    # and far closer in fact: arcs fitted either side of the curve leave ~1e-6 of the area
    assert volume == pytest.approx(expected, rel=2e-5)
    # the box: the kernel pads its box by the shapes' tolerance (1e-7 mm) and the contour may
    # stand off the exact surface by the fitting tolerance
    exact_box = (pts[:, 0].min(), pts[:, 1].min(), 0.0, pts[:, 0].max(), pts[:, 1].max(), thickness)
    assert np.allclose(box, exact_box, atol=tolerance + 1e-6), (box, exact_box)


def test_stl_is_closed_with_the_right_volume() -> None:
    tolerance, thickness, bore = 0.01, 10.0, 25.0
    data = solid_stl(SolidCam(ROLLER, thickness, bore, tolerance))
    facets = read_stl(data)
    # closed and consistently oriented: each directed edge once, and its reverse once
    # (float32 vertices, rounded to 1e-4 mm to name them)
    edges = directed_edges(facets)
    assert all(n == 1 for n in edges.values())
    assert all(edges[(q, p)] == 1 for p, q in edges)
    # volume by the divergence theorem, Σ v0 · (v1 × v2) / 6: positive for outward normals. The
    # facets lie within the tolerance of the exact surface (half for the arcs, half for the
    # chords), so the volume within perimeter × tolerance × thickness; float32 vertices add ~1e-6
    v0, v1, v2 = facets[:, 0], facets[:, 1], facets[:, 2]
    volume = float(np.einsum("ij,ij->i", v0, np.cross(v1, v2)).sum() / 6.0)
    area, perimeter, _ = exact_contour(ROLLER)
    expected = (area - math.pi * bore**2 / 4) * thickness
    assert 0 < volume and abs(volume - expected) <= perimeter * tolerance * thickness
    assert facets[:, :, 2].min() == 0.0 and facets[:, :, 2].max() == pytest.approx(thickness, abs=1e-5)


def test_solid_refusals_name_the_field() -> None:
    with pytest.raises(InvalidParameterError) as info:
        solid_step(SolidCam(ROLLER, 10.0, 80.5))
    assert info.value.field == ("solid", "bore_diameter_mm") and "smaller than the cam at its narrowest" in str(info.value)
    with pytest.raises(LimitExceededError) as limit:
        solid_stl(SolidCam(ROLLER, 10.0, 20.0, 0.001, max_triangles=1000))
    assert limit.value.field == ("solid", "tolerance_mm")
    assert set(SOLID_FORMATS) == {"step", "stl"}
    # thinner than 1 µm: the kernel refuses 1e-7 mm (its confusion tolerance), so camcore does first
    with pytest.raises(InvalidParameterError) as thin:
        solid_step(SolidCam(ROLLER, 0.999 * MIN_THICKNESS_MM))
    assert thin.value.field == ("solid", "thickness_mm") and "at least 0.001 mm" in str(thin.value)
    assert read_step(solid_step(SolidCam(ROLLER, MIN_THICKNESS_MM)))[0] == 1


def test_the_same_cam_is_the_same_step_file_however_many_came_before() -> None:
    # OpenCASCADE names a file's product after a count of the files the process has written
    # ("Open CASCADE STEP translator 8.0 17"): the part is named for what it is instead
    import re

    stamp = re.compile(rb"FILE_NAME\('[^']*','[^']*'")  # the moment of writing, in the header
    first, second = (stamp.sub(b"", solid_step(SolidCam(ROLLER, 12.0, 20.0, 0.01))) for _ in range(2))
    assert first == second
    assert b"PRODUCT('camcore plate cam','camcore plate cam'" in first
