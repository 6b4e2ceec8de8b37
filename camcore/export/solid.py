"""The plate cam as a solid: STEP (exact B-rep) and STL (triangles), from OpenCASCADE.

The cam surface is fitted with lines and arcs within ``tolerance_mm`` (the biarcs of
:mod:`camcore.toolpath`, deviation measured against the exact surface both ways), closed
into a planar face, extruded by ``thickness_mm`` along +z from z = 0, and the bore (a
cylinder of ``bore_diameter_mm`` about the cam axis) cut out. Arcs stay exact circles in the
STEP file (AP214 B-rep), so a CAD or CAM program reads circles, not a spline or a polyline.
The STL's facets are the kernel's mesh of that solid, at a chordal deviation of half the
tolerance, the arcs fitted to the other half, so every facet lies within ``tolerance_mm`` of
the exact surface.

The kernel is OpenCASCADE Technology through its CadQuery Python bindings (the
``cadquery-ocp-novtk`` wheel: README, "The CAD kernel", says why this one).

References
----------
.. [1] ISO 10303-21 (STEP physical file) and ISO 10303-214 (AP214, automotive design: the
   B-rep solid, circles, lines, planes, cylinders).
.. [2] 3D Systems, "StereoLithography Interface Specification" (1988/1989): the binary STL
   layout (80-byte header, triangle count, 50 bytes per facet).
.. [3] Open CASCADE Technology 7.x documentation: BRepBuilderAPI_MakeFace, BRepPrimAPI_MakePrism,
   BRepAlgoAPI_Cut, STEPControl_Writer, BRepMesh_IncrementalMesh, StlAPI_Writer.
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from ..errors import InvalidParameterError, LimitExceededError
from ..profile.cam import CamSpec
from ..toolpath import CutterPath, Element
from ..toolpath.compute import fit_surface
from .registry import FileFormat

#: the name of the part a STEP file holds (its PRODUCT), as a CAD tool lists it
PRODUCT_NAME = "camcore plate cam"
_PRODUCT = re.compile(rb"PRODUCT\('[^']*',\s*'[^']*'")
#: the thinnest plate [mm]: 1 µm, 10 000 times the kernel's confusion tolerance
#: (Precision::Confusion, 1e-7 mm: a shorter extrusion is no solid, BRepSweep_Prism refuses it,
#: and at 2e-7 mm the kernel still made one, with a different STEP file), far below any plate
#: anyone cuts (shim stock starts at 0.01 mm)
MIN_THICKNESS_MM = 1e-3


class KernelSolid(Protocol):
    """What the kernel's writers take: a solid that builds its own shape (the plate cam's
    :class:`SolidCam`; other cams add theirs, each in its own module).

    ``tolerance_mm``: the largest deviation of the solid from the exact surfaces [mm];
    ``max_triangles``: the most STL facets [-]; ``product_name``: the part's name in a STEP file.
    ``shape(tolerance_mm)`` builds the OpenCASCADE ``TopoDS_Shape`` with its surfaces fitted within
    that tolerance; ``facets_estimate(deflection_mm)`` tells, before any meshing, how many facets a
    mesh at that chordal deviation will have.
    """

    tolerance_mm: float
    max_triangles: int

    @property
    def product_name(self) -> str: ...

    def shape(self, tolerance_mm: float) -> Any: ...

    def facets_estimate(self, deflection_mm: float) -> int: ...


@dataclass(frozen=True)
class SolidCam:
    """A plate cam to write as a solid.

    Attributes
    ----------
    cam : CamSpec
        The cam.
    thickness_mm : float
        Extrusion along the cam axis [mm].
    bore_diameter_mm : float
        Diameter of the bore about the axis; 0 for none [mm].
    tolerance_mm : float
        Largest deviation of the solid's contour from the exact surface [mm].
    max_elements : int
        Largest number of lines and arcs of the contour [-].
    max_triangles : int
        Largest number of STL facets [-].
    """

    cam: CamSpec
    thickness_mm: float
    bore_diameter_mm: float = 0.0
    tolerance_mm: float = 0.01
    max_elements: int = 100_000
    max_triangles: int = 1_000_000

    @property
    def product_name(self) -> str:
        return PRODUCT_NAME

    def shape(self, tolerance_mm: float) -> Any:
        """:func:`build_solid` at that tolerance."""
        return build_solid(self, tolerance_mm)

    def facets_estimate(self, deflection_mm: float) -> int:
        """:func:`stl_triangles_estimate` of the contour fitted to that deviation."""
        return stl_triangles_estimate(_contour(self, deflection_mm), self.bore_diameter_mm, deflection_mm)


def _contour(solid: SolidCam, tolerance_mm: float) -> CutterPath:
    if not (math.isfinite(solid.thickness_mm) and solid.thickness_mm >= MIN_THICKNESS_MM):
        raise InvalidParameterError(f"thickness_mm must be at least {MIN_THICKNESS_MM:g} mm (1 µm).",
                                    field=("solid", "thickness_mm"))
    path = fit_surface(solid.cam, tolerance_mm, solid.max_elements)
    inner = min(_nearest_to_axis(e) for e in path.elements)
    if not 0.0 <= solid.bore_diameter_mm < 2.0 * inner:
        raise InvalidParameterError(
            f"bore_diameter_mm must be at least 0 and smaller than the cam at its narrowest, {2.0 * inner:.6g} mm "
            "(twice the smallest distance of the surface from the axis).", field=("solid", "bore_diameter_mm"))
    return path


def _nearest_to_axis(e: Element) -> float:
    """The smallest distance of an element's points from the axis (0, 0) [mm]."""
    ends = min(math.hypot(*e.start), math.hypot(*e.end))
    if e.centre is None:
        dx, dy = e.end[0] - e.start[0], e.end[1] - e.start[1]
        length2 = dx * dx + dy * dy
        u = 0.0 if length2 == 0 else min(1.0, max(0.0, -(e.start[0] * dx + e.start[1] * dy) / length2))
        return min(ends, math.hypot(e.start[0] + u * dx, e.start[1] + u * dy))
    # on the arc, the nearest point to the axis lies on the line from the centre through the axis
    cx, cy = e.centre
    dist = math.hypot(cx, cy)
    if dist == 0.0:
        return ends
    r = e.radius_mm
    towards = (cx - r * cx / dist, cy - r * cy / dist)
    if e.distance(np.array([towards[0]]), np.array([towards[1]]))[0] < 1e-9 * max(1.0, r):
        return min(ends, abs(dist - r))
    return ends


def load_kernel() -> None:
    """Load the OpenCASCADE bindings now (one extension module, ~1.5 s), and keep the
    kernel's reports of each transfer off stdout but for failures.

    A service calls this before a request's timed work, so the load does not fall inside
    its deadline; the writers call it too (it costs nothing once loaded).

    Returns
    -------
    None

    References
    ----------
    OCP (CadQuery's OpenCASCADE bindings): ``OCP.Message.Message.DefaultMessenger_s``,
    ``Message_Printer.SetTraceLevel``.
    """
    _quiet_kernel()


def _quiet_kernel() -> None:
    """OCCT reports each transfer on stdout; keep only its failures (a service's stdout is its log)."""
    from OCP.Message import Message, Message_Gravity

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)


def build_solid(solid: SolidCam, tolerance_mm: float | None = None) -> Any:
    """The cam as an OpenCASCADE solid (a ``TopoDS_Shape``).

    Parameters
    ----------
    solid : SolidCam
        The cam, its thickness and bore [mm].
    tolerance_mm : float, optional
        The contour's fitting tolerance; default ``solid.tolerance_mm`` [mm].

    Returns
    -------
    OCP.TopoDS.TopoDS_Shape
        The extruded face with the bore cut out.

    Raises
    ------
    InvalidParameterError
        A thickness under MIN_THICKNESS_MM (1 µm), or a bore that does not fit inside the cam.
    GeometryError
        A surface that cannot be fitted (undercut, a sharp corner): as camcore.toolpath.

    References
    ----------
    OCCT: GC_MakeArcOfCircle, GC_MakeSegment, BRepBuilderAPI_MakeWire/MakeFace,
    BRepPrimAPI_MakePrism, BRepPrimAPI_MakeCylinder, BRepAlgoAPI_Cut.
    """
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Vec

    _quiet_kernel()
    path = _contour(solid, solid.tolerance_mm if tolerance_mm is None else tolerance_mm)
    z_axis = gp_Dir(0.0, 0.0, 1.0)
    wire = elements_wire(path.elements)
    if not wire.IsDone():
        raise InvalidParameterError("the kernel could not close the contour into a wire.", field=("solid",))
    face = BRepBuilderAPI_MakeFace(wire.Wire(), True).Face()
    shape = BRepPrimAPI_MakePrism(face, gp_Vec(0.0, 0.0, solid.thickness_mm)).Shape()
    if solid.bore_diameter_mm > 0:
        # the cylinder reaches past both faces, so the cut leaves no skin
        axis = gp_Ax2(gp_Pnt(0.0, 0.0, -1.0), z_axis)
        bore = BRepPrimAPI_MakeCylinder(axis, 0.5 * solid.bore_diameter_mm, solid.thickness_mm + 2.0).Shape()
        cut = BRepAlgoAPI_Cut(shape, bore)
        cut.Build()
        shape = cut.Shape()
    return shape


def elements_wire(elements: Sequence[Element]) -> Any:
    """A contour's lines and arcs in the plane z = 0 as the kernel's wire (its builder: ``IsDone()``,
    ``Wire()``).

    Parameters
    ----------
    elements : sequence of Element
        Lines and arcs end to end, in mm [mm].

    Returns
    -------
    OCP.BRepBuilderAPI.BRepBuilderAPI_MakeWire
        The wire's builder, every element added (an arc as an exact circle).

    References
    ----------
    OCCT: GC_MakeSegment, GC_MakeArcOfCircle, BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire.
    """
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
    from OCP.GC import GC_MakeArcOfCircle, GC_MakeSegment
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pnt

    z_axis = gp_Dir(0.0, 0.0, 1.0)
    wire = BRepBuilderAPI_MakeWire()
    for e in elements:
        p0, p1 = gp_Pnt(e.start[0], e.start[1], 0.0), gp_Pnt(e.end[0], e.end[1], 0.0)
        if e.centre is None:
            curve = GC_MakeSegment(p0, p1).Value()
        else:
            circle = gp_Circ(gp_Ax2(gp_Pnt(e.centre[0], e.centre[1], 0.0), z_axis), e.radius_mm)
            # an arc of a circle about +z runs counter-clockwise: a clockwise element from its end
            curve = GC_MakeArcOfCircle(circle, p0, p1, True).Value() if e.ccw else \
                GC_MakeArcOfCircle(circle, p1, p0, True).Value()
        wire.Add(BRepBuilderAPI_MakeEdge(curve).Edge())
    return wire


def _through_file(suffix: str, write: Callable[[str], None]) -> bytes:
    """What a kernel writer puts in a file (OCCT writes to paths), read back and removed."""
    fd, name = tempfile.mkstemp(suffix=suffix)
    os.close(fd)
    try:
        write(name)
        with open(name, "rb") as f:
            return f.read()
    finally:
        os.unlink(name)


def solid_step(solid: KernelSolid) -> bytes:
    """A solid as a STEP AP214 file (module notes).

    Parameters
    ----------
    solid : KernelSolid
        The solid (a plate cam: its thickness and bore [mm], the contour's tolerance [mm]).

    Returns
    -------
    bytes
        The STEP file (ISO 10303-21 text), lengths in mm.

    References
    ----------
    ISO 10303-21, ISO 10303-214; OCCT STEPControl_Writer (schema AP214IS, unit MM).
    """
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    shape = solid.shape(solid.tolerance_mm)

    def write(name: str) -> None:
        Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
        Interface_Static.SetCVal_s("write.step.unit", "MM")
        writer = STEPControl_Writer()
        writer.Transfer(shape, STEPControl_AsIs)
        if writer.Write(name) != IFSelect_RetDone:
            raise InvalidParameterError("the kernel could not write the STEP file.", field=("solid",))

    # the part's name in a CAD tree: the kernel names it after a count of the files this process
    # has written ("Open CASCADE STEP translator 8.0 17"), so the same cam gave other bytes
    name = solid.product_name.encode()
    return _PRODUCT.sub(b"PRODUCT('" + name + b"','" + name + b"'", _through_file(".step", write), count=1)


def stl_triangles_estimate(path: CutterPath, bore_diameter_mm: float, deflection_mm: float) -> int:
    """The number of facets a mesh at this chordal deviation will have, before meshing.

    Parameters
    ----------
    path : CutterPath
        The contour's lines and arcs.
    bore_diameter_mm : float
        The bore (0: none) [mm].
    deflection_mm : float
        Chordal deviation of the mesh [mm].

    Returns
    -------
    int
        Edge segments of both outlines × 4 (two facets per side-wall quad, about one per
        segment on each flat face) [-].

    References
    ----------
    A circle of radius r meshed to chordal deviation δ has ⌈2π / (2 acos(1 − δ/r))⌉ segments.
    """
    def segments(sweep: float, r: float) -> int:
        if deflection_mm >= r:
            return 3
        return max(1, math.ceil(abs(sweep) / (2.0 * math.acos(1.0 - deflection_mm / r))))

    count = sum(1 if e.centre is None else segments(e.sweep_rad, e.radius_mm) for e in path.elements)
    if bore_diameter_mm > 0:
        count += segments(2 * math.pi, 0.5 * bore_diameter_mm)
    return 4 * count


def solid_stl(solid: KernelSolid) -> bytes:
    """A solid as a binary STL of the kernel's mesh (module notes).

    Parameters
    ----------
    solid : KernelSolid
        The solid (a plate cam: its thickness and bore [mm]), the tolerance [mm] and the facet limit [-].

    Returns
    -------
    bytes
        The binary STL (facets in mm).

    Raises
    ------
    LimitExceededError
        More facets than ``solid.max_triangles`` (estimated before meshing, counted after).

    References
    ----------
    3D Systems (1989), binary STL; OCCT BRepMesh_IncrementalMesh (linear deflection),
    StlAPI_Writer.
    """
    from OCP.BRep import BRep_Tool
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.IMeshTools import IMeshTools_MeshAlgoType, IMeshTools_Parameters
    from OCP.StlAPI import StlAPI_Writer
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    half = 0.5 * solid.tolerance_mm
    estimate = solid.facets_estimate(half)
    if estimate > solid.max_triangles:
        raise LimitExceededError("STL facets", estimate, solid.max_triangles, field=("solid", "tolerance_mm"))
    shape = solid.shape(half)
    params = IMeshTools_Parameters()
    params.Deflection, params.Angle, params.Relative, params.InParallel = half, 0.5, False, False
    # Delabella's Delaunay triangulation: the default (Watson) takes seconds on a flat face
    # bounded by thousands of points (5 s a face at 18 000 facets here), Delabella ~0.1 s
    params.MeshAlgo = IMeshTools_MeshAlgoType.IMeshTools_MeshAlgoType_Delabella
    BRepMesh_IncrementalMesh(shape, params)
    count = 0
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        tri = BRep_Tool.Triangulation_s(TopoDS.Face(explorer.Current()), TopLoc_Location())
        count += 0 if tri is None else tri.NbTriangles()
        explorer.Next()
    if count > solid.max_triangles:
        raise LimitExceededError("STL facets", count, solid.max_triangles, field=("solid", "tolerance_mm"))

    def write(name: str) -> None:
        writer = StlAPI_Writer()
        writer.ASCIIMode = False
        if not writer.Write(shape, name):
            raise InvalidParameterError("the kernel could not write the STL file.", field=("solid",))

    return _through_file(".stl", write)


#: solid downloads, by name; ``cost(elements)`` of the contour, measured on camcore.work's
#: reference machine (kernel build and write ~30-60 ms, meshing ~0.1 ms a contour element), ×2
SOLID_FORMATS: dict[str, FileFormat[KernelSolid]] = {f.name: f for f in (
    FileFormat("step", "model/step", "cam.step",
               "STEP AP214 solid in mm (OpenCASCADE): the plate cam extruded with its bore, lines and arcs within "
               "the tolerance", solid_step, lambda elements: 2 * (0.06 + 2e-4 * elements)),
    FileFormat("stl", "model/stl", "cam.stl",
               "binary STL in mm (OpenCASCADE mesh): facets within the tolerance of the exact surface",
               solid_stl, lambda elements: 2 * (0.08 + 1e-3 * elements)),
)}
