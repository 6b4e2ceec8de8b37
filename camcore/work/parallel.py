"""A parallel indexing cam's plates: traced, fitted with lines and arcs, made solids in the CAD
kernel, and the answer's numbers, known before any of it runs (the constants and their
measurements are in camcore.work.cams)."""

from __future__ import annotations

from . import cams
from .estimate import Field, WorkEstimate, WorkTerm, per_item_work


def trace_work(plates: int, rollers_per_plate: int, traced: int, at: Field = ()) -> WorkEstimate:
    """Tracing plates' exact contours (camcore.cams.parallel.trace).

    Parameters
    ----------
    plates : int
        Plates traced [-].
    rollers_per_plate : int
        Rollers on each plate's layer [-].
    traced : int
        Cam angles traced over the turn [-].
    at : tuple
        Where the cam is in the request (its ``plates`` and ``samples`` are named under it).

    Returns
    -------
    WorkEstimate
        A fixed part per plate, one per plate × traced cam angle and one per plate × roller × cam angle.

    References
    ----------
    camcore.cams.parallel.trace; the measurements beside :data:`camcore.work.cams.PARALLEL_PLATE_S`.
    """
    return WorkEstimate((
        WorkTerm((*at, "plates"), f"tracing {plates} plates", plates * cams.PARALLEL_PLATE_S),
        WorkTerm((*at, "samples"), f"walking {plates} plates × {traced} traced cam angles",
                 plates * traced * cams.PARALLEL_PLATE_SAMPLE_S))) + per_item_work(
        plates * rollers_per_plate * traced, cams.PLATE_ROLLER_SAMPLE_S, (*at, "samples"),
        f"{plates} plates × {rollers_per_plate} rollers × {traced} traced cam angles")


def fit_work(center_distance_mm: float, rollers_per_plate: int, tolerance_mm: float, plates: int,
             field: Field) -> tuple[WorkEstimate, int, int]:
    """Fitting plates' contours with lines and arcs within a tolerance (camcore.cams.parallel.fit).

    Parameters
    ----------
    center_distance_mm : float
        Distance from the camshaft to the turret's axis [mm].
    rollers_per_plate : int
        Rollers on each plate's layer [-].
    tolerance_mm : float
        Largest deviation of the fit [mm].
    plates : int
        Plates fitted [-].
    field : tuple
        The request field that sets the tolerance.

    Returns
    -------
    tuple
        The work, and each plate's pieces and elements at most [-] (cams.parallel_pieces, cams.parallel_elements).

    References
    ----------
    camcore.cams.parallel.fit; the measurements beside :data:`camcore.work.cams.PARALLEL_FIT_PLATE_S`.
    """
    pieces = cams.parallel_pieces(rollers_per_plate)
    elements = cams.parallel_elements(center_distance_mm, tolerance_mm, pieces)
    seconds = plates * (cams.PARALLEL_FIT_PLATE_S + pieces * cams.PARALLEL_FIT_PIECE_S + elements * cams.PARALLEL_FIT_ELEMENT_S)
    return WorkEstimate((WorkTerm(field, f"fitting {plates} plates' contours, about {elements} lines and arcs each",
                                  seconds),)), pieces, elements


def solid_work(center_distance_mm: float, rollers_per_plate: int, plates: int, tolerance_mm: float,
               bore_diameter_mm: float, stl: bool, field: Field) -> WorkEstimate:
    """The plates as solids (camcore.export.parallel_solid): their contours fitted (at half the
    tolerance for a mesh, which keeps the other half for its facets) and the CAD kernel's work.

    Parameters
    ----------
    center_distance_mm : float
        Distance from the camshaft to the turret's axis [mm].
    rollers_per_plate : int
        Rollers on each plate's layer [-].
    plates : int
        Plates made [-].
    tolerance_mm : float
        The solid's tolerance [mm].
    bore_diameter_mm : float
        The camshaft's bore [mm].
    stl : bool
        A mesh (else STEP).
    field : tuple
        The request field of the tolerance.

    Returns
    -------
    WorkEstimate
        The fit and the kernel's work.

    References
    ----------
    camcore.export.parallel_solid; the measurements beside :data:`camcore.work.cams.PARALLEL_STEP_PLATE_S`.
    """
    tolerance = tolerance_mm / (2 if stl else 1)
    fit, pieces, elements = fit_work(center_distance_mm, rollers_per_plate, tolerance, plates, field)
    if stl:
        facets = cams.parallel_facets(center_distance_mm, tolerance, pieces, elements, bore_diameter_mm)
        kernel = plates * (cams.PARALLEL_STL_PLATE_S + facets * cams.PARALLEL_STL_FACET_S)
        what = f"meshing {plates} plates of about {facets} facets each"
    else:
        kernel = plates * (cams.PARALLEL_STEP_PLATE_S + elements * cams.PARALLEL_STEP_ELEMENT_S)
        what = f"the STEP solids of {plates} plates, about {elements} edges each"
    return fit + WorkEstimate((WorkTerm(field, what, kernel),))


def contour_points(plates: int, traced: int) -> int:
    """The plates' contour points, at most.

    Parameters
    ----------
    plates : int
        Plates traced [-].
    traced : int
        Cam angles traced over the turn [-].

    Returns
    -------
    int
        Points of all plates [-]: :data:`camcore.work.cams.PARALLEL_POINTS_PER_SAMPLE` a traced cam angle.

    References
    ----------
    The traces measured beside :data:`camcore.work.cams.PARALLEL_POINTS_PER_SAMPLE`.
    """
    return plates * cams.PARALLEL_POINTS_PER_SAMPLE * traced


def answer_values(plates: int, samples: int, traced: int) -> int:
    """The numbers of the plates in a JSON answer: their contours' points and their contacts.

    Parameters
    ----------
    plates : int
        Plates answered [-].
    samples : int
        Cam angles answered [-].
    traced : int
        Cam angles traced over the turn [-].

    Returns
    -------
    int
        Numbers written [-].

    References
    ----------
    The traces measured beside :data:`camcore.work.cams.PARALLEL_POINTS_PER_SAMPLE`.
    """
    return (cams.PARALLEL_POINT_VALUES * contour_points(plates, traced)
            + plates * cams.PARALLEL_CONTACT_VALUES * cams.PARALLEL_CONTACTS_PER_SAMPLE * samples)
