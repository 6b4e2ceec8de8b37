"""A parallel indexing cam's plates as solids: STEP (exact B-rep) and STL (triangles), from OpenCASCADE.

Each plate's exact contour (:mod:`camcore.cams.parallel.trace`) is fitted with lines and arcs
within the tolerance (:func:`camcore.cams.parallel.fit.fit_plate`: the plate cam's biarc fit, its
deviation measured both ways against the exact contour), closed into a planar face, extruded by
``thickness_mm`` along +z and bored (a cylinder of ``bore_diameter_mm`` about the cam axis cut
out). Plate p stands at z = p·``spacing_mm`` (its lower face; the spacing is the plates' pitch
along the cam axis, face to face: the thickness when they touch, the default), so the stack is as
its layers of rollers meet it. The plates are one compound of one solid each: one STEP file holds
them all, an STL all their facets (the kernel's mesh at a chordal deviation of half the
tolerance, the arcs fitted to the other half: every facet within the tolerance of the exact
contour's prism).

References
----------
.. [1] ISO 10303-21, ISO 10303-214 (AP214: lines, circles, planes, cylinders in B-rep solids).
.. [2] Open CASCADE Technology 7.x documentation: BRepBuilderAPI_MakeWire/MakeFace,
   BRepPrimAPI_MakePrism, BRepAlgoAPI_Cut, BRepBuilderAPI_Transform, BRep_Builder (compounds).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from ..cams.parallel.fit import fit_plate, relocated_limit
from ..cams.parallel.trace import PlateContour
from ..errors import InvalidParameterError, LimitExceededError
from ..toolpath import CutterPath
from .solid import MIN_THICKNESS_MM, _nearest_to_axis, _quiet_kernel, elements_wire, stl_triangles_estimate

#: the name of the part a STEP file holds
PRODUCT_NAME = "camcore parallel indexing cam"
#: where a fit's limit or a solid's rule is in a request
SOLID_FIELD = ("solid",)


@dataclass(frozen=True)
class ParallelPlatesSolid:
    """A parallel cam's plates to write as solids (a KernelSolid of :mod:`camcore.export.solid`).

    Attributes
    ----------
    contours : tuple of PlateContour
        Each plate's exact contour, plate 0 first.
    thickness_mm : float
        Each plate's extrusion along the cam axis [mm].
    bore_diameter_mm : float
        A bore about the cam axis through every plate; 0 for none [mm].
    spacing_mm : float or None
        The plates' pitch along the axis, lower face to lower face, at least the thickness;
        None: the thickness (the plates touch) [mm].
    tolerance_mm : float
        The largest deviation of a plate's contour from the exact one [mm].
    max_elements : int
        The most lines and arcs of each plate's contour [-].
    max_triangles : int
        The most STL facets [-].
    """

    contours: tuple[PlateContour, ...]
    thickness_mm: float
    bore_diameter_mm: float = 0.0
    spacing_mm: float | None = None
    tolerance_mm: float = 0.01
    max_elements: int = 100_000
    max_triangles: int = 1_000_000
    _fits: dict[float, tuple[CutterPath, ...]] = field(default_factory=dict, repr=False, compare=False)

    @property
    def product_name(self) -> str:
        return PRODUCT_NAME

    @property
    def pitch_mm(self) -> float:
        """The plates' pitch along the cam axis [mm]."""
        return self.thickness_mm if self.spacing_mm is None else self.spacing_mm

    def shape(self, tolerance_mm: float) -> Any:
        """:func:`build_plates` at that tolerance."""
        return build_plates(self, tolerance_mm)

    def facets_estimate(self, deflection_mm: float) -> int:
        """The facets of the plates' meshes at that chordal deviation, their contours fitted to it."""
        return sum(stl_triangles_estimate(path, self.bore_diameter_mm, deflection_mm)
                   for path in plate_paths(self, deflection_mm))


def plate_paths(solid: ParallelPlatesSolid, tolerance_mm: float) -> tuple[CutterPath, ...]:
    """Each plate's contour as lines and arcs within the tolerance, the solid's dimensions checked.

    Parameters
    ----------
    solid : ParallelPlatesSolid
        The plates and their dimensions [mm].
    tolerance_mm : float
        The fit's tolerance [mm].

    Returns
    -------
    tuple of CutterPath
        One per plate (fitted once per tolerance and kept).

    Raises
    ------
    InvalidParameterError
        A thickness under 1 µm, a spacing under the thickness, or a bore that does not fit inside
        every plate.
    LimitExceededError
        More than ``max_elements`` lines and arcs on a plate.

    References
    ----------
    Meek and Walton (1992), arc splines within a tolerance (camcore.cams.parallel.fit).
    """
    if not (math.isfinite(solid.thickness_mm) and solid.thickness_mm >= MIN_THICKNESS_MM):
        raise InvalidParameterError(f"thickness_mm must be at least {MIN_THICKNESS_MM:g} mm (1 µm).",
                                    field=(*SOLID_FIELD, "thickness_mm"))
    if not (math.isfinite(solid.pitch_mm) and solid.pitch_mm >= solid.thickness_mm):
        raise InvalidParameterError(
            f"spacing_mm ({solid.pitch_mm!r}) is the plates' pitch along the cam axis, face to face: it must be at "
            f"least the thickness, {solid.thickness_mm!r} mm, or the plates overlap.", field=(*SOLID_FIELD, "spacing_mm"))
    if tolerance_mm not in solid._fits:
        try:
            paths = tuple(fit_plate(c, 0.0, tolerance_mm, math.inf, None, solid.max_elements) for c in solid.contours)
        except LimitExceededError as error:
            raise relocated_limit(error, (*SOLID_FIELD, "tolerance_mm")) from None
        solid._fits[tolerance_mm] = paths
    paths = solid._fits[tolerance_mm]
    inner = min(_nearest_to_axis(e) for path in paths for e in path.elements)
    if not 0.0 <= solid.bore_diameter_mm < 2.0 * inner:
        raise InvalidParameterError(
            f"bore_diameter_mm must be at least 0 and smaller than the plates at their narrowest, {2.0 * inner:.6g} mm "
            "(twice the smallest distance of a contour from the axis).", field=(*SOLID_FIELD, "bore_diameter_mm"))
    return paths


def build_plates(solid: ParallelPlatesSolid, tolerance_mm: float | None = None) -> Any:
    """The plates as one OpenCASCADE compound of one solid each (module notes).

    Parameters
    ----------
    solid : ParallelPlatesSolid
        The plates, their thickness, spacing and bore [mm].
    tolerance_mm : float, optional
        The contours' fitting tolerance; default ``solid.tolerance_mm`` [mm].

    Returns
    -------
    OCP.TopoDS.TopoDS_Compound
        Plate p extruded from z = p·spacing, bored.

    Raises
    ------
    InvalidParameterError
        As :func:`plate_paths`, or a contour the kernel cannot close into a wire.

    References
    ----------
    OCCT: GC_MakeArcOfCircle, GC_MakeSegment, BRepBuilderAPI_MakeWire/MakeFace, BRepPrimAPI_MakePrism,
    BRepPrimAPI_MakeCylinder, BRepAlgoAPI_Cut, BRepBuilderAPI_Transform, BRep_Builder.
    """
    from OCP.BRep import BRep_Builder
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepBuilderAPI import (
        BRepBuilderAPI_MakeFace,
        BRepBuilderAPI_Transform,
    )
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
    from OCP.TopoDS import TopoDS_Compound

    _quiet_kernel()
    paths = plate_paths(solid, solid.tolerance_mm if tolerance_mm is None else tolerance_mm)
    z_axis = gp_Dir(0.0, 0.0, 1.0)
    compound = TopoDS_Compound()
    builder = BRep_Builder()
    builder.MakeCompound(compound)
    for p, path in enumerate(paths):
        wire = elements_wire(path.elements)
        if not wire.IsDone():
            raise InvalidParameterError(f"the kernel could not close plate {p}'s contour into a wire.",
                                        field=SOLID_FIELD)
        face = BRepBuilderAPI_MakeFace(wire.Wire(), True).Face()
        shape = BRepPrimAPI_MakePrism(face, gp_Vec(0.0, 0.0, solid.thickness_mm)).Shape()
        if solid.bore_diameter_mm > 0:
            # the cylinder reaches past both faces, so the cut leaves no skin
            bore = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.0, 0.0, -1.0), z_axis), 0.5 * solid.bore_diameter_mm,
                                            solid.thickness_mm + 2.0).Shape()
            cut = BRepAlgoAPI_Cut(shape, bore)
            cut.Build()
            shape = cut.Shape()
        lift = gp_Trsf()
        lift.SetTranslation(gp_Vec(0.0, 0.0, p * solid.pitch_mm))
        builder.Add(compound, BRepBuilderAPI_Transform(shape, lift, True).Shape())
    return compound
