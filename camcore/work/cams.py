"""Barrel, parallel and roller-gear cams."""

from __future__ import annotations

import math

#: the barrel checks run 25 extreme searches (pressure angle at three radii, the pitch curve's
#: curvature both ways, and both ways at 10 radii across the roller) where a plate cam's run 3;
#: measured (with the local-grid refinement) 40-60 ms for the 4-segment request examples, up to
#: 12 times the plate checks' estimate of the same segments; ×1.5
BARREL_CHECKS_FACTOR = 18.0
#: one sampled angle of a barrel cam (lift, state, columns) measured 1.3 µs, one flank point 0.07 µs; ×1.5
BARREL_SAMPLE_S = 1.5 * 1.3e-6
BARREL_FLANK_POINT_S = 1.5 * 1e-7
#: a barrel cam's columns over the cam angle, and numbers per flank point (x, y, z of two flanks)
BARREL_COLUMNS = 10
BARREL_FLANK_VALUES = 6

#: a parallel cam's plate, its exact contour traced (camcore.cams.parallel.trace): a fixed part
#: (its crossings, the points within the chord tolerance), one plate × traced cam angle (the walk's
#: cover tests of the points it passes: about 1.3 a cam angle, each against the roller centres
#: near it) and one plate × roller × traced cam angle (both envelopes, the cells of roller centres,
#: the contacts' test). Least squares over the largest of 3 runs (thread time) of 150 cams, 4-36
#: stops, 4-72 rollers per plate, 2 or 3 plates, 16-2881 samples (traced at ≥ 720): 0.020 s,
#: 5.3 µs and 0.59 µs; kept at 0.025 s, 8 µs and 0.7 µs, ×1.5, the estimate stays above every run
#: (at most 0.81 of it, where a trace is done again finer). 8 stops × 3 plates at 1441 samples:
#: 0.09 s measured, 0.20 s estimated; at 3601: 0.19 s and 0.33 s
PARALLEL_PLATE_S = 1.5 * 0.025
PARALLEL_PLATE_SAMPLE_S = 1.5 * 8e-6
PLATE_ROLLER_SAMPLE_S = 1.5 * 0.7e-6
#: a plate's contour points per traced cam angle and contacts per answered cam angle, at most
#: seen in those runs (2.9 points where a 72-roller layer's notches need more, 1.6 contacts);
#: numbers of a contour point (x, y, roller, cam angle, pressure angle, radius) and of a contact
PARALLEL_POINTS_PER_SAMPLE = 3
PARALLEL_CONTACTS_PER_SAMPLE = 2
PARALLEL_POINT_VALUES = 6
PARALLEL_CONTACT_VALUES = 4

#: a parallel cam plate's contour fitted with lines and arcs (camcore.cams.parallel.fit, the plate
#: cam's biarc fit on each piece of the exact contour): the largest of 2 runs (thread time) of 192
#: fits, 4-36 stops, 4-72 rollers per plate, tolerances 1e-4 to 0.1 mm, the tool 0 or half the
#: smallest concave radius, measured twice on a shared 2-core machine: least squares 0-6 ms a plate
#: + 18-20 ms a piece (each piece's ~230 exact evaluations of the measurement) + 0.26-0.30 ms an
#: element; kept at 10 ms, 25 ms and 0.35 ms, ×1.5, the estimate stays above every run (at most
#: 0.80 of it)
PARALLEL_FIT_PLATE_S = 1.5 * 0.01
PARALLEL_FIT_PIECE_S = 1.5 * 0.025
PARALLEL_FIT_ELEMENT_S = 1.5 * 3.5e-4
#: the plates as solids in the CAD kernel (built, bored, written): STEP 0.06-0.26 s for 3 plates of
#: 86-342 elements, STL 0.10-1.0 s for 4 000-49 000 facets; kept at 30 ms a plate + 0.6 ms an
#: element (STEP), 40 ms a plate + 20 µs a facet (STL), ×1.5
PARALLEL_STEP_PLATE_S = 1.5 * 0.03
PARALLEL_STEP_ELEMENT_S = 1.5 * 6e-4
PARALLEL_STL_PLATE_S = 1.5 * 0.04
PARALLEL_STL_FACET_S = 1.5 * 2e-5


def parallel_pieces(rollers_per_plate: int) -> int:
    """The pieces of a parallel cam plate's contour, at most (an estimate before tracing).

    Parameters
    ----------
    rollers_per_plate : int
        m [-].

    Returns
    -------
    int
        3 + m // 16: 3 seen for 4-36 rollers, 4-6 for 72 [-].

    References
    ----------
    camcore.cams.parallel.trace (a piece per stretch of one roller's envelope).
    """
    return 3 + rollers_per_plate // 16


def parallel_elements(center_distance_mm: float, tolerance_mm: float, pieces: int) -> int:
    """Lines and arcs of one plate's fitted contour, at most (an estimate before tracing).

    Parameters
    ----------
    center_distance_mm : float
        C: the plate lies within it [mm].
    tolerance_mm : float
        The fit's tolerance [mm].
    pieces : int
        The contour's pieces (:func:`parallel_pieces`) [-].

    Returns
    -------
    int
        (2πC/tolerance)^(1/3) + 4 a piece: a biarc's error grows as the cube of its length, the
        contour is shorter than 2πC, and each piece's ends cost a few elements; the 192 fits above
        stayed within 0.89 of it [-].

    References
    ----------
    Meek and Walton (1992): a biarc's deviation grows as the cube of its length.
    """
    return math.ceil((2 * math.pi * center_distance_mm / tolerance_mm) ** (1.0 / 3.0)) + 4 * pieces


def parallel_facets(center_distance_mm: float, deflection_mm: float, pieces: int, elements: int,
                    bore_diameter_mm: float) -> int:
    """STL facets of one plate, at most (an estimate before tracing).

    Parameters
    ----------
    center_distance_mm : float
        C: no arc of the contour is larger [mm].
    deflection_mm : float
        The mesh's chordal deviation [mm].
    pieces, elements : int
        The contour's pieces and fitted elements [-].
    bore_diameter_mm : float
        The bore (0: none) [mm].

    Returns
    -------
    int
        4 × (the arcs' segments, a turn of 2π a piece at radius C, + the elements + the bore's
        segments); camcore.export.solid.stl_triangles_estimate counts the same way on the fit [-].

    References
    ----------
    A circle of radius r meshed to chordal deviation δ has about 2π·√(r/(8δ)) segments.
    """
    def segments(turn: float, r: float) -> float:
        return turn * math.sqrt(r / (8 * deflection_mm)) if r > deflection_mm else 3.0

    bore = segments(2 * math.pi, 0.5 * bore_diameter_mm) if bore_diameter_mm > 0 else 0.0
    return math.ceil(4 * (segments(2 * math.pi * pieces, center_distance_mm) + elements + bore))


#: a roller-gear cam's largest pressure angle refined (both flanks, two radii together) and the
#: rest of a 2 × 2 grid: measured 2.3 ms (3.8 ms when the radii were refined one after the
#: other); ×1.5 of 4 ms kept
RIB_PRESSURE_SEARCH_S = 1.5 * 4e-3
#: one rib flank point (both flanks: the contact, its derivatives, regularity): median 0.66 µs,
#: at most 0.86 µs over 9 runs of the largest grid (3601 × 41); ×1.5 of 0.7 µs
RIB_FLANK_POINT_S = 1.5 * 0.7e-6
#: one STL facet (the mesh indexed and written): median 0.26 µs, at most 0.54 µs over the same
#: runs (the 42 MB of vertices allocated afresh each time); ×1.5 of 0.4 µs
RIB_FACET_S = 1.5 * 0.4e-6
#: a roller-gear cam's columns over the turn, and numbers per flank point in its JSON answer (x,
#: y, z, pressure angle and regular of two flanks)
RIB_COLUMNS = 4
RIB_FLANK_VALUES = 10


def rib_facets(samples: int, length_samples: int) -> int:
    """Facets of a roller-gear rib's mesh: two per quad between consecutive cross-section
    rings, and two caps.

    Parameters
    ----------
    samples : int
        Cam angles sampled (the rings) [-].
    length_samples : int
        Points along the roller on each flank [-].

    Returns
    -------
    int
        Facets [-].

    References
    ----------
    camcore.cams.roller_gear.compute (rib_triangles: the mesh this counts).
    """
    ring = 2 * length_samples
    return 2 * (samples - 1) * ring + 4 * (length_samples - 1)
