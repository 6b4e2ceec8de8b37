"""The barrel cam as a solid: a cylinder with its groove cut, built in OpenCASCADE (a
:class:`~camcore.export.solid.KernelSolid` for the writers of :data:`SOLID_FORMATS`).

The groove
----------
The groove is the room the roller sweeps: every point at radius r from the groove's bottom
radius r_b up to the cam's outer radius r_o that some position of the roller (its axis, the
line of :mod:`camcore.cams.barrel`, continued down to r_b) holds within the roller's radius.
Its walls are the two envelopes of the roller (:func:`flank_on_cylinder`, the exact contact of
the module notes there, continued over r_b … r_o), and its floor is the cylinder r_b between
them: where no roller position reaches, the bottom clearance. (An end mill's flat end leaves
the floor a little above r_b beside the walls where the groove climbs steeply; the roller
never touches it.)

The solid
---------
The solid is sewn from its faces, with no Boolean operation (a cut of the blank by a groove
body took 0.4-0.6 s in the kernel; the faces are sewn in tens of milliseconds). Between
consecutive break points of the lift: each wall, the floor and the two bands of the outer
cylinder that meet the walls' outer edges, bicubic B-spline surfaces within ``tolerance_mm`` of
the exact ones (:mod:`camcore.export.barrel_surfaces`), sharing their edges pole for pole; the
blank's ends are planes at the groove's lowest point less ``end_margin_mm`` and its highest plus
it, bounded by the bands' edges and the bore's circle; the bore a cylinder about the axis.

Refused: a lift whose velocity jumps (a corner: the groove's walls have a corner there), a
groove whose walls turn back somewhere between r_b and r_o (undercut: the envelope loops, no
roller could cut it), and a bore that reaches the groove's floor.

References
----------
.. [1] L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed. (1997), 2.2-2.5 (B-spline basis, knot
   multiplicity and continuity) and 9.2 (interpolation); the bicubic Hermite patch in Bezier form.
.. [2] Open CASCADE Technology 7.x documentation: Geom_BSplineSurface, Geom_BSplineCurve,
   BRepBuilderAPI_MakeFace, BRepBuilderAPI_Sewing, BRepBuilderAPI_MakeSolid,
   BRepLib::OrientClosedSolid, BRepPrimAPI_MakeCylinder, ShapeFix_Face.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..cams.barrel.geometry import BarrelCam
from ..curves.base import FloatArray
from ..deadline import checkpoint
from ..errors import GeometryError, InvalidParameterError
from .barrel_surfaces import BarrelSurfaces, barrel_surfaces

#: the name of the part in a STEP file
PRODUCT_NAME = "camcore barrel cam"
#: the sewing's tolerance: the faces share their edges pole for pole, so it only meets rounding [mm]
SEWING_MM = 1e-6


@dataclass(frozen=True)
class BarrelSolid:
    """A barrel cam to write as a solid (module notes).

    Attributes
    ----------
    cam : BarrelCam
        The cam.
    tolerance_mm : float
        The largest deviation of the solid's surfaces from the exact ones [mm].
    end_margin_mm : float or None
        The blank's length beyond the groove at each end; None: the roller's radius [mm].
    bore_diameter_mm : float
        The bore about the cam axis; 0: none [mm].
    max_poles : int
        The most B-spline poles of all the surfaces [-].
    max_triangles : int
        The most STL facets [-].
    """

    cam: BarrelCam
    tolerance_mm: float = 0.01
    end_margin_mm: float | None = None
    bore_diameter_mm: float = 0.0
    max_poles: int = 400_000
    max_triangles: int = 1_000_000

    @property
    def product_name(self) -> str:
        return PRODUCT_NAME

    @property
    def margin_mm(self) -> float:
        """The blank's length beyond the groove at each end [mm]."""
        return self.cam.roller_radius_mm if self.end_margin_mm is None else self.end_margin_mm

    def surfaces(self, tolerance_mm: float) -> BarrelSurfaces:
        """:func:`barrel_surfaces` of the cam at that tolerance."""
        return barrel_surfaces(self.cam, tolerance_mm, self.margin_mm, self.max_poles)

    def shape(self, tolerance_mm: float) -> Any:
        """:func:`build_barrel_solid` at that tolerance."""
        return build_barrel_solid(self, tolerance_mm)

    def facets_estimate(self, deflection_mm: float) -> int:
        """:func:`barrel_facets_estimate` of this cam at that deviation."""
        return barrel_facets_estimate(self.cam, deflection_mm)


def barrel_facets_estimate(cam: BarrelCam, deflection_mm: float) -> int:
    """The number of facets a mesh of the barrel cam at this chordal deviation will have.

    Parameters
    ----------
    cam : BarrelCam
        The cam.
    deflection_mm : float
        Chordal deviation of the mesh [mm].

    Returns
    -------
    int
        :func:`camcore.work.barrel.barrel_solid_facets` of the cam, its strokes the total
        rise and fall along the axis, ∫|dy/dθ| dθ (an oscillating arm's y = L·sin ψ moves at
        most L·|dψ|) [-].

    References
    ----------
    camcore.work.barrel (the measurements of the kernel's meshes).
    """
    from ..work.barrel import barrel_solid_facets

    theta = np.linspace(0.0, 2 * math.pi, 7201)
    rate = np.abs(cam.lift.derivatives(theta, 1)[1])
    if cam.follower == "oscillating":
        rate = float(cam.arm_length_mm or 0.0) * np.radians(rate)
    travel = float(np.trapezoid(rate, theta))
    return barrel_solid_facets(cam.pitch_radius_mm, cam.roller_radius_mm, cam.groove_depth_mm, [travel],
                               deflection_mm)


def build_barrel_solid(solid: BarrelSolid, tolerance_mm: float | None = None) -> Any:
    """The barrel cam as an OpenCASCADE solid (a ``TopoDS_Shape``).

    Parameters
    ----------
    solid : BarrelSolid
        The cam, its end margins and bore [mm].
    tolerance_mm : float, optional
        The surfaces' fitting tolerance; default ``solid.tolerance_mm`` [mm].

    Returns
    -------
    OCP.TopoDS.TopoDS_Shape
        The solid, its faces sewn.

    Raises
    ------
    InvalidParameterError, GeometryError
        A bore that reaches the groove's floor; as :func:`barrel_surfaces`; the kernel failing to
        close the faces into a solid.

    References
    ----------
    OCCT: Geom_BSplineSurface, Geom_BSplineCurve, BRepBuilderAPI_MakeFace, BRepBuilderAPI_Sewing,
    BRepBuilderAPI_MakeSolid, BRepLib::OrientClosedSolid, BRepPrimAPI_MakeCylinder, ShapeFix_Face.
    """
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeSolid, BRepBuilderAPI_Sewing
    from OCP.BRepLib import BRepLib
    from OCP.TopAbs import TopAbs_SHELL
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    from .solid import load_kernel

    load_kernel()
    surfaces = solid.surfaces(solid.tolerance_mm if tolerance_mm is None else tolerance_mm)
    bore = 0.5 * solid.bore_diameter_mm
    if not (math.isfinite(bore) and 0.0 <= bore < surfaces.bottom_radius_mm):
        raise InvalidParameterError(
            f"bore_diameter_mm must be at least 0 and smaller than the groove's bottom diameter, "
            f"{2 * surfaces.bottom_radius_mm:.6g} mm.", field=("solid", "bore_diameter_mm"))
    sewing = BRepBuilderAPI_Sewing(SEWING_MM)
    for stretch in surfaces.stretches:
        for poles, ku, kv in stretch.values():
            checkpoint()
            sewing.Add(BRepBuilderAPI_MakeFace(_surface(poles, ku, kv), SEWING_MM).Face())
    for face in _ends_and_bore(surfaces, bore):
        sewing.Add(face)
    sewing.Perform()
    explorer = TopExp_Explorer(sewing.SewedShape(), TopAbs_SHELL)
    if not explorer.More():
        raise GeometryError("the kernel could not close the cam's faces into a shell.", field=("solid",))
    body = BRepBuilderAPI_MakeSolid(TopoDS.Shell(explorer.Current())).Solid()
    BRepLib.OrientClosedSolid_s(body)
    return body


def _knots(values: FloatArray) -> tuple[Any, Any]:
    """A knot vector as the kernel takes it: the distinct knots and their multiplicities."""
    from OCP.collections import Array1_double, Array1_int

    distinct, counts = np.unique(values, return_counts=True)
    knots, mults = Array1_double(1, len(distinct)), Array1_int(1, len(distinct))
    for i, (value, count) in enumerate(zip(distinct.tolist(), counts.tolist(), strict=True), start=1):
        knots.SetValue(i, value)
        mults.SetValue(i, count)
    return knots, mults


def _surface(poles: FloatArray, ku: FloatArray, kv: FloatArray) -> Any:
    """A bicubic Geom_BSplineSurface from its poles and knots."""
    from OCP.collections import Array2_gp_Pnt
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt

    grid = Array2_gp_Pnt(1, poles.shape[0], 1, poles.shape[1])
    for (i, j), _ in np.ndenumerate(poles[..., 0]):
        grid.SetValue(i + 1, j + 1, gp_Pnt(*poles[i, j].tolist()))
    (uk, um), (vk, vm) = _knots(ku), _knots(kv)
    return Geom_BSplineSurface(grid, uk, vk, um, vm, 3, 3, False, False)


def _edge(poles: FloatArray, knots: FloatArray) -> Any:
    """An edge on the cubic Geom_BSplineCurve of these poles and knots."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.collections import Array1_gp_Pnt
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt

    points = Array1_gp_Pnt(1, poles.shape[0])
    for i, p in enumerate(poles.tolist(), start=1):
        points.SetValue(i, gp_Pnt(*p))
    k, m = _knots(knots)
    return BRepBuilderAPI_MakeEdge(Geom_BSplineCurve(points, k, m, 3, False)).Edge()


def _ends_and_bore(surfaces: BarrelSurfaces, bore: float) -> list[Any]:
    """The blank's two end faces, each bounded by its bands' far edges (and the bore's circle),
    and the bore's cylindrical face."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pln, gp_Pnt
    from OCP.ShapeFix import ShapeFix_Face
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    faces = []
    up = gp_Dir(0.0, 0.0, 1.0)
    for band, z in (("lower_band", surfaces.z0_mm), ("upper_band", surfaces.z1_mm)):
        wire = BRepBuilderAPI_MakeWire()
        for stretch in surfaces.stretches:
            poles, ku, _ = stretch[band]
            wire.Add(_edge(poles[:, -1], ku))
        if not wire.IsDone():
            raise GeometryError("the kernel could not close the cam's end into a wire.", field=("solid",))
        make = BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0.0, 0.0, z), up), wire.Wire(), True)
        if bore > 0:
            circle = BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(0.0, 0.0, z), up), bore)).Edge()
            make.Add(BRepBuilderAPI_MakeWire(circle).Wire())
        fix = ShapeFix_Face(make.Face())
        fix.FixOrientation()
        faces.append(fix.Face())
    if bore > 0:
        cylinder = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.0, 0.0, surfaces.z0_mm), up), bore,
                                            surfaces.z1_mm - surfaces.z0_mm).Shape()
        explorer = TopExp_Explorer(cylinder, TopAbs_FACE)
        while explorer.More():  # its side: the one face that is not a plane
            face = TopoDS.Face(explorer.Current())
            if not _is_plane(face):
                faces.append(face)
            explorer.Next()
    return faces


def _is_plane(face: Any) -> bool:
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Plane

    return bool(BRepAdaptor_Surface(face).GetType() == GeomAbs_Plane)
