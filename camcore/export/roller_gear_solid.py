"""The roller-gear (globoidal) cam as a solid: its rib on its globoidal body, from OpenCASCADE.

The faces are the B-spline patches of :mod:`camcore.cams.roller_gear.surfaces` (the body's and the
rib's dimensions are chosen there): both flanks through the exact flank points, within the
tolerance, the rib's top on the turned outer globoid, the body's root below and above the rib on the
inner one. The kernel adds the rib's two ends (planar, in the plane of the line of centres, between
the flanks' end curves, the top's and the root's), the body's end faces (planes z = ±H) and the
bore (a cylinder, if any), sews the faces into one closed shell along the edges they share, makes the
solid and checks it (``BRepCheck_Analyzer``). No boolean operation is used: the faces meet where the
patches were fitted to meet, so the solid is built in tens of milliseconds where a fuse of the rib
with a toroidal body took seconds (each B-spline face cut by a torus ~0.1-0.3 s here).

A STEP file holds the patches as B-spline surfaces (AP214); the STL's facets are the kernel's mesh at
a chordal deviation of half the tolerance, the patches fitted to the other half.

References
----------
.. [1] ISO 10303-21, ISO 10303-214 (AP214: B-spline surfaces, planes, cylinders in a B-rep solid).
.. [2] Open CASCADE Technology 7.x documentation: Geom_BSplineSurface, BRepBuilderAPI_MakeFace,
   BRepBuilderAPI_Sewing, BRepBuilderAPI_MakeSolid, BRepLib::OrientClosedSolid, BRepCheck_Analyzer.
.. [3] L. Piegl, W. Tiller, "The NURBS Book", 2nd ed., Springer (1997), ch. 3 (tensor-product
   B-spline surfaces).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..cams.roller_gear.body import check_solid_body
from ..cams.roller_gear.geometry import RollerGearCam
from ..cams.roller_gear.surfaces import MAX_THETA_NODES, Patch, RibSurfaces, fit_rib_surfaces
from ..errors import GeometryError
from ..work.roller_gear import rib_solid_facets
from .solid import load_kernel

#: the part's name in a STEP file
PRODUCT_NAME = "camcore roller-gear cam"
#: the sewing's tolerance [mm]: the faces' shared edges are the same poles (to rounding, ~1e-13 mm)
#: or an edge cut from a torus patch whose across polynomial keeps within 1e-10·C of its path
#: (surfaces.TORUS_FIT), both far inside it; ten times OpenCASCADE's confusion (1e-7 mm)
SEWING_MM = 1e-6


@dataclass(frozen=True)
class RollerGearSolid:
    """A roller-gear cam to write as a solid (the KernelSolid of :mod:`camcore.export.solid`).

    Attributes
    ----------
    cam : RollerGearCam
        The cam.
    tolerance_mm : float
        The flanks' largest deviation from the exact flank [mm].
    bore_diameter_mm : float
        A bore about the cam axis; 0 for none [mm].
    root_clearance_mm : float
        The body's torus beyond the circle of the rollers' outer rims [mm].
    body_length_mm : float or None
        The body's length along the cam axis; None: the rib's extent and half a roller radius at each end [mm].
    max_theta_nodes : int
        The most cam angles the patches take over the turn [-].
    max_triangles : int
        The most STL facets [-].
    """

    cam: RollerGearCam
    tolerance_mm: float = 0.01
    bore_diameter_mm: float = 0.0
    root_clearance_mm: float = 0.0
    body_length_mm: float | None = None
    max_theta_nodes: int = MAX_THETA_NODES
    max_triangles: int = 1_000_000

    @property
    def product_name(self) -> str:
        return PRODUCT_NAME

    def surfaces(self, tolerance_mm: float | None = None) -> RibSurfaces:
        """The fitted patches (:func:`camcore.cams.roller_gear.surfaces.fit_rib_surfaces`), the bore checked."""
        c, r_out, rr = self.cam.center_distance_mm, self.cam.roller_ends_mm[1], self.cam.roller_radius_mm
        check_solid_body(c, r_out, rr, self.root_clearance_mm, self.bore_diameter_mm)
        return fit_rib_surfaces(self.cam, self.tolerance_mm if tolerance_mm is None else tolerance_mm,
                                self.root_clearance_mm, self.body_length_mm, self.max_theta_nodes)

    def shape(self, tolerance_mm: float) -> Any:
        """:func:`build_roller_gear_solid` with the flanks fitted to that tolerance."""
        return build_roller_gear_solid(self, tolerance_mm)

    def facets_estimate(self, deflection_mm: float) -> int:
        """:func:`roller_gear_facets_estimate` at that chordal deviation."""
        return roller_gear_facets_estimate(self.cam, deflection_mm)


def roller_gear_facets_estimate(cam: RollerGearCam, deflection_mm: float) -> int:
    """The facets of the kernel's mesh of a roller-gear cam at a chordal deviation, before meshing.

    Parameters
    ----------
    cam : RollerGearCam
        The cam.
    deflection_mm : float
        The mesh's chordal deviation [mm].

    Returns
    -------
    int
        :func:`camcore.work.roller_gear.rib_solid_facets` of its dimensions [-].

    References
    ----------
    camcore.work.roller_gear (the formula and its measurements).
    """
    return rib_solid_facets(cam.stops, cam.center_distance_mm, cam.roller_pitch_radius_mm, cam.roller_radius_mm,
                            cam.roller_length_mm, deflection_mm)


# ----------------------------------------------------------------------------- the kernel's shapes
def _array1(values: Any, kind: str) -> Any:
    from OCP.collections import Array1_double, Array1_int

    array = (Array1_double if kind == "real" else Array1_int)(1, len(values))
    for i, v in enumerate(values):
        array.SetValue(i + 1, float(v) if kind == "real" else int(v))
    return array


def _surface(poles: np.ndarray, u: tuple[np.ndarray, np.ndarray, int], v: tuple[np.ndarray, np.ndarray, int]) -> Any:
    from OCP.collections import Array2_gp_Pnt
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt

    grid = Array2_gp_Pnt(1, poles.shape[0], 1, poles.shape[1])
    for i in range(poles.shape[0]):
        for j in range(poles.shape[1]):
            x, y, z = poles[i, j]
            grid.SetValue(i + 1, j + 1, gp_Pnt(float(x), float(y), float(z)))
    return Geom_BSplineSurface(grid, _array1(u[0], "real"), _array1(v[0], "real"), _array1(u[1], "int"),
                               _array1(v[1], "int"), u[2], v[2])


def _patch_surface(patch: Patch) -> Any:
    k = patch.v_degree + 1
    return _surface(patch.poles, (patch.u_knots, patch.u_mults, patch.u_degree),
                    (np.array([0.0, 1.0]), np.array([k, k]), patch.v_degree))


def _chi(c_mm: float, point: np.ndarray) -> float:
    return math.atan2(float(point[2]), c_mm - math.hypot(float(point[0]), float(point[1])))


def build_roller_gear_solid(solid: RollerGearSolid, tolerance_mm: float | None = None) -> Any:
    """The roller-gear cam as an OpenCASCADE solid (module notes).

    Parameters
    ----------
    solid : RollerGearSolid
        The cam, the body's bore, clearance and length [mm].
    tolerance_mm : float, optional
        The flanks' fitting tolerance; default ``solid.tolerance_mm`` [mm].

    Returns
    -------
    OCP.TopoDS.TopoDS_Solid
        One closed solid, checked valid.

    Raises
    ------
    InvalidParameterError, GeometryError, LimitExceededError
        As :func:`camcore.cams.roller_gear.surfaces.fit_rib_surfaces`, a bore too large, or a shell
        the kernel could not close into a valid solid.

    References
    ----------
    OCCT: Geom_BSplineSurface, GeomAdaptor iso-curves, BRepBuilderAPI_MakeEdge/MakeWire/MakeFace,
    BRepBuilderAPI_Sewing, BRepBuilderAPI_MakeSolid, BRepLib::OrientClosedSolid, BRepCheck_Analyzer.
    """
    from OCP.BRepBuilderAPI import (
        BRepBuilderAPI_MakeEdge,
        BRepBuilderAPI_MakeFace,
        BRepBuilderAPI_MakeSolid,
        BRepBuilderAPI_MakeWire,
        BRepBuilderAPI_Sewing,
    )
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepLib import BRepLib
    from OCP.Geom import Geom_CylindricalSurface, Geom_TrimmedCurve
    from OCP.gp import gp_Ax2, gp_Ax3, gp_Circ, gp_Dir, gp_Pnt
    from OCP.ShapeFix import ShapeFix_Face
    from OCP.TopAbs import TopAbs_SHELL
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    load_kernel()
    fit = solid.surfaces(tolerance_mm)
    c, half = fit.center_distance_mm, fit.half_length_mm
    surfaces = {(p.band, p.part): _patch_surface(p) for p in fit.patches}
    patches = {(p.band, p.part): p for p in fit.patches}
    faces = [BRepBuilderAPI_MakeFace(s, 1e-7).Face() for s in surfaces.values()]

    def iso(band: str, part: str, at_end: bool, across: tuple[float, float] | None = None) -> Any:
        """The patch's curve at the start or end of its cam angles (trimmed across), as an edge."""
        patch = patches[(band, part)]
        curve = surfaces[(band, part)].UIso(float(patch.u_knots[-1] if at_end else patch.u_knots[0]))
        if across is not None:
            curve = Geom_TrimmedCurve(curve, *across)
        return BRepBuilderAPI_MakeEdge(curve).Edge()

    def across_of(band: str, part: str, at_end: bool, point: np.ndarray) -> float:
        """Where a point of the torus's meridian lies across a torus patch's end (χ linear across)."""
        poles = patches[(band, part)].poles[-1 if at_end else 0]
        lo, hi = _chi(c, poles[0]), _chi(c, poles[-1])
        return (_chi(c, point) - lo) / (hi - lo)

    def corner(band: str, part: str, at_end: bool, across_end: int) -> np.ndarray:
        return patches[(band, part)].poles[-1 if at_end else 0, across_end]

    # the rib's ends: at θ = 0 its root stands on the body's root below the rib's other end (the
    # below patch's end at 2π), at θ = 2π on the root above the rib's start (the above patch's start)
    for at_end, part, root_band, root_part in ((False, "index", "below", "dwell"), (True, "dwell", "above", "index")):
        lo, hi = corner("back", part, at_end, -1), corner("forward", part, at_end, -1)
        root_at_end = not at_end
        span = (across_of(root_band, root_part, root_at_end, lo), across_of(root_band, root_part, root_at_end, hi))
        wire = BRepBuilderAPI_MakeWire()
        for edge in (iso("forward", part, at_end), iso("top", part, at_end), iso("back", part, at_end),
                     iso(root_band, root_part, root_at_end, span)):
            wire.Add(edge)
        if not wire.IsDone():
            raise GeometryError("the kernel could not close the rib's end.", field=("solid",))
        faces.append(BRepBuilderAPI_MakeFace(wire.Wire(), True).Face())
    # the body's ends, each bounded by its patches' end circles and the bore
    radius = 0.5 * solid.bore_diameter_mm
    z_axis = gp_Dir(0.0, 0.0, 1.0)
    for band, side in (("below", 0.0), ("above", 1.0)):
        wire = BRepBuilderAPI_MakeWire()
        for part in ("index", "dwell"):
            wire.Add(BRepBuilderAPI_MakeEdge(surfaces[(band, part)].VIso(side)).Edge())
        maker = BRepBuilderAPI_MakeFace(wire.Wire(), True)
        if radius > 0:
            z = half if side else -half
            circle = BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(0.0, 0.0, z), z_axis), radius)).Edge()
            maker.Add(TopoDS.Wire(BRepBuilderAPI_MakeWire(circle).Wire().Reversed()))
        face = maker.Face()
        if radius > 0:  # the bore's wire turned against the outer one, whichever way the plane faces
            fix = ShapeFix_Face(face)
            fix.FixOrientation()
            face = fix.Face()
        faces.append(face)
    if radius > 0:
        bore = Geom_CylindricalSurface(gp_Ax3(gp_Pnt(0.0, 0.0, 0.0), z_axis), radius)
        faces.append(BRepBuilderAPI_MakeFace(bore, 0.0, 2 * math.pi, -half, half, 1e-7).Face())
    sewing = BRepBuilderAPI_Sewing(SEWING_MM)
    for face in faces:
        sewing.Add(face)
    sewing.Perform()
    explorer = TopExp_Explorer(sewing.SewedShape(), TopAbs_SHELL)
    if sewing.NbFreeEdges() or not explorer.More():
        raise GeometryError(f"the kernel could not sew the cam's faces into a closed shell ({sewing.NbFreeEdges()} free "
                            "edges).", field=("solid",))
    shape = BRepBuilderAPI_MakeSolid(TopoDS.Shell(explorer.Current())).Solid()
    BRepLib.OrientClosedSolid_s(shape)
    if not BRepCheck_Analyzer(shape).IsValid():
        raise GeometryError("the kernel found the cam's solid invalid.", field=("solid",))
    return shape
