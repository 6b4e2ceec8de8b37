"""Barrel, parallel and roller-gear cams."""

from __future__ import annotations

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
