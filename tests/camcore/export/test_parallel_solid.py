"""A parallel cam's plates as solids (camcore.export.parallel_solid), read back by others.

The STEP file is read through the kernel's own STEP reader (the writer's shape is gone): one solid
per plate, each one's volume (contour area − bore) × thickness and its box the contour's box ×
[p·spacing, p·spacing + thickness], the contour's area and box taken from the exact contour
(PlateContour.at at 20 000 cam angles a piece, the shoelace formula). The STL is parsed here (the
binary layout, tests/stl_mesh.py): closed, its volume by the divergence theorem, and every vertex on
the exact contour or the bore within the tolerance.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcore.cams.parallel import make_parallel_cam, sample_parallel
from camcore.cams.parallel.trace import PlateContour
from camcore.errors import InvalidParameterError, LimitExceededError
from camcore.export import SOLID_FORMATS, ParallelPlatesSolid
from camcore.export.parallel_solid import PRODUCT_NAME
from camcore.export.solid import MIN_THICKNESS_MM
from tests.polylines import distance_to_ring
from tests.readers import step_shape
from tests.stl_mesh import directed_edges, read_stl

CAM = make_parallel_cam(4, 100.0, 60.0, 12.0, 120.0, "MS", plates=3)
CONTOURS = tuple(sample_parallel(CAM, 121).contours)


def exact(contour: PlateContour) -> tuple[float, float, np.ndarray]:
    """Area [mm²], perimeter [mm] and points of the exact contour, 20 000 points a piece: the polygon's
    area misses the curve's by the perimeter × the chords' sagitta, ~1e-5 mm² here."""
    pts = np.vstack([np.column_stack([(e := contour.at(k, np.linspace(p.tau_start_rad, p.tau_end_rad, 20_000)[:-1])).x,
                                      e.y]) for k, p in enumerate(contour.pieces)])
    x, y = pts[:, 0], pts[:, 1]
    area = 0.5 * abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))
    perimeter = float(np.sum(np.hypot(np.diff(x, append=x[0]), np.diff(y, append=y[0]))))
    return area, perimeter, pts


def solids_of(data: bytes) -> list[tuple[float, tuple[float, ...]]]:
    """Volume and box of each solid in a STEP file (the kernel's reader), lowest first."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    out = []
    explorer = TopExp_Explorer(step_shape(data), TopAbs_SOLID)
    while explorer.More():
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(explorer.Current(), props)
        box = Bnd_Box()
        BRepBndLib.Add_s(explorer.Current(), box, False)
        lo, hi = box.CornerMin(), box.CornerMax()
        out.append((props.Mass(), (lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z())))
        explorer.Next()
    return sorted(out, key=lambda s: s[1][2])


@pytest.mark.parametrize(("bore", "spacing"), [(20.0, None), (0.0, 15.0)], ids=["bored-touching", "spaced"])
def test_step_holds_one_solid_per_plate_of_the_right_volume_and_place(bore: float, spacing: float | None) -> None:
    tolerance, thickness = 0.001, 12.0
    data = SOLID_FORMATS["step"].write(ParallelPlatesSolid(CONTOURS, thickness, bore, spacing, tolerance))
    assert f"PRODUCT('{PRODUCT_NAME}'".encode() in data
    solids = solids_of(data)
    assert len(solids) == 3
    pitch = thickness if spacing is None else spacing
    for p, (contour, (volume, box)) in enumerate(zip(CONTOURS, solids)):
        area, perimeter, pts = exact(contour)
        expected = (area - math.pi * bore**2 / 4) * thickness
        # the contour lies within the tolerance of the exact one: the areas differ by at most perimeter ×
        # tolerance; the kernel's volume of lines and arcs is exact to its 1e-7 mm
        assert abs(volume - expected) <= perimeter * tolerance * thickness, (p, volume, expected)
        # the box: the kernel pads it by its tolerance (1e-7 mm); the contour may stand off by the tolerance
        exact_box = (pts[:, 0].min(), pts[:, 1].min(), p * pitch, pts[:, 0].max(), pts[:, 1].max(), p * pitch + thickness)
        assert np.allclose(box, exact_box, atol=tolerance + 1e-6), (p, box, exact_box)


def test_stl_is_closed_and_on_the_exact_contour() -> None:
    tolerance, thickness, bore, pitch = 0.01, 10.0, 25.0, 12.0
    data = SOLID_FORMATS["stl"].write(ParallelPlatesSolid(CONTOURS, thickness, bore, pitch, tolerance))
    facets = read_stl(data)
    # closed and consistently oriented: each directed edge once, its reverse once (float32 vertices,
    # rounded to 1e-4 mm to name them; 2 mm apart, the plates' meshes share no vertex)
    edges = directed_edges(facets)
    assert all(n == 1 for n in edges.values()) and all(edges[(q, p)] == 1 for p, q in edges)
    z = facets[:, :, 2]
    assert z.min() == 0.0 and z.max() == pytest.approx(2 * pitch + thickness, abs=1e-5)
    total = float(np.einsum("ij,ij->i", facets[:, 0], np.cross(facets[:, 1], facets[:, 2])).sum() / 6.0)
    expected, slack = 0.0, 0.0
    for p, contour in enumerate(CONTOURS):
        area, perimeter, pts = exact(contour)
        expected += (area - math.pi * bore**2 / 4) * thickness
        slack += (perimeter + math.pi * bore) * tolerance * thickness
        # every vertex of this plate's mesh is on its contour or its bore, within the tolerance (the arcs
        # fitted to half of it, the facets' chords to the other half; float32 rounds 100 mm to ~4e-6 mm)
        mine = (z >= p * pitch - 1e-4) & (z <= p * pitch + thickness + 1e-4)
        xy = facets[:, :, :2][mine]
        to_contour = distance_to_ring(xy, pts)
        to_bore = np.abs(np.hypot(xy[:, 0], xy[:, 1]) - bore / 2)
        assert np.minimum(to_contour, to_bore).max() <= tolerance + 1e-5
    # the volume within the tolerance times the walls' area
    assert 0 < total and abs(total - expected) <= slack, (total, expected, slack)


def test_solid_refusals_name_the_field() -> None:
    with pytest.raises(InvalidParameterError) as bore:
        SOLID_FORMATS["step"].write(ParallelPlatesSolid(CONTOURS, 10.0, 90.0))
    assert bore.value.field == ("solid", "bore_diameter_mm") and "at their narrowest" in str(bore.value)
    with pytest.raises(InvalidParameterError) as spacing:
        SOLID_FORMATS["step"].write(ParallelPlatesSolid(CONTOURS, 10.0, 0.0, 9.0))
    assert spacing.value.field == ("solid", "spacing_mm")
    with pytest.raises(InvalidParameterError) as thin:
        SOLID_FORMATS["step"].write(ParallelPlatesSolid(CONTOURS, 0.999 * MIN_THICKNESS_MM))
    assert thin.value.field == ("solid", "thickness_mm")
    with pytest.raises(LimitExceededError) as facets:
        SOLID_FORMATS["stl"].write(ParallelPlatesSolid(CONTOURS, 10.0, 20.0, None, 0.001, max_triangles=1000))
    assert facets.value.field == ("solid", "tolerance_mm")
    with pytest.raises(LimitExceededError) as elements:
        SOLID_FORMATS["step"].write(ParallelPlatesSolid(CONTOURS, 10.0, 20.0, None, 1e-4, max_elements=20))
    assert elements.value.field == ("solid", "tolerance_mm")
