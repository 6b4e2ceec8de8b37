"""A barrel cam made: its four-axis toolpath (camcore.cams.barrel.toolpath) and its solid
(camcore.export.barrel_solid). Measured on the reference machine, one computation at a time,
thread CPU time, the best of three runs."""

from __future__ import annotations

import math
from collections.abc import Sequence

from .estimate import Field, WorkEstimate, WorkTerm

#: straight moves of one pass ≈ MOVES_PER_STROKE_ROOT · Σ √(stroke/tolerance) over the moving
#: segments + MOVES_PER_SEGMENT · segments: a chord's deviation grows as the square of its
#: length (δ ≈ κL²/8), so a stretch of curvature κ needs ∫√(κ/8δ) ds chords, and for a law of
#: stroke h over any angle at any radius that is √(h/δ) times the law's ∫√|A(τ)| dτ/√8. Measured
#: 0.58-0.99 per stroke root (cycloid, MS, 3-4-5; strokes 2-100 mm, radii 20-200 mm, tolerances
#: 1e-4 to 0.1 mm, 4 and 16 segments), 2 moves a segment at its ends; set a little above
MOVES_PER_STROKE_ROOT = 1.1
MOVES_PER_SEGMENT = 2
MOVES_FIXED = 4
#: one pass: the greedy grid (4096 angles a turn) and the measurements of all its chords
#: together, each an evaluation of the lift whose cost grows with the segments: measured 17 ms
#: with 4 segments, 54 ms with 16 (about 3 ms a segment and 6 ms more); ×1.5
PASS_S = 1.5 * 6e-3
PASS_SEGMENT_S = 1.5 * 3e-3
#: one move beyond those: its share of the refits and their measurements, 0.04-0.05 ms with 4
#: segments, up to 0.11 ms with 16 (the finest tolerances refit most); ×1.5 of 0.01 ms a segment
MOVE_SEGMENT_S = 1.5 * 1e-5
#: the walls a smaller cutter leaves, measured against the exact flanks (361 angles × 5
#: positions × 2 walls, each the nearest of the cutter's path by golden section): 40 ms with 4
#: segments, 64 ms with 16, 94 ms with 32 (35 ms and 2 ms a segment); ×1.5
WALLS_S = 1.5 * 35e-3
WALLS_SEGMENT_S = 1.5 * 2e-3
#: numbers of one node in the JSON answer (cam angle, A, X)
NODE_VALUES = 3


def barrel_moves_estimate(strokes_mm: Sequence[float], segments: int, tolerance_mm: float) -> int:
    """How many straight moves one pass of a barrel cam's groove will have, before fitting.

    Parameters
    ----------
    strokes_mm : sequence of float
        The stroke of each moving segment [mm].
    segments : int
        Segments of the lift, dwells included [-].
    tolerance_mm : float
        The fitting tolerance [mm].

    Returns
    -------
    int
        Moves of one pass [-].

    References
    ----------
    A chord of a curve of curvature κ deviates by κL²/8; the measurements beside
    :data:`MOVES_PER_STROKE_ROOT`.
    """
    roots = sum(math.sqrt(abs(s) / tolerance_mm) for s in strokes_mm)
    return int(MOVES_FIXED + MOVES_PER_SEGMENT * segments + MOVES_PER_STROKE_ROOT * roots)


def barrel_toolpath_work(moves: int, passes: int, segments: int, segments_field: Field,
                         tolerance_field: Field) -> WorkEstimate:
    """Fitting the passes of a barrel cam's groove and, with two passes, measuring its walls.

    Parameters
    ----------
    moves : int
        Moves of all passes (:func:`barrel_moves_estimate` × passes) [-].
    passes : int
        1 (a cutter of the roller's size) or 2 (one pass a wall) [-].
    segments : int
        Segments of the lift [-].
    segments_field, tolerance_field : tuple
        The request fields of the segments and of the tolerance.

    Returns
    -------
    WorkEstimate
        The passes, the moves and the walls' measurement [s].

    References
    ----------
    camcore.cams.barrel.toolpath; the measurements beside the constants.
    """
    terms = [WorkTerm(segments_field, f"{passes} passes over {segments} segments",
                      passes * (PASS_S + PASS_SEGMENT_S * segments)),
             WorkTerm(tolerance_field, f"fitting about {moves} moves", moves * MOVE_SEGMENT_S * max(segments, 4))]
    if passes > 1:
        terms.append(WorkTerm(segments_field, "the walls measured against the exact flanks",
                              WALLS_S + WALLS_SEGMENT_S * segments))
    return WorkEstimate(tuple(terms))


# ---------------------------------------------------------------------------- the solid
#: the solid's work beyond its curves: the exact points and differences its surfaces are made
#: of, the fit's checks, the kernel's faces, the sewing and the STEP file. Measured (thread CPU
#: time, best of two) 0.157-0.345 s for 2 400-7 320 poles with 4 stretches and 0.529-1.065 s for
#: 7 200-17 760 poles with 16: about 30 ms, 8 ms a stretch and 50 µs a pole; ×1.5
SOLID_S = 1.5 * 0.03
SOLID_STRETCH_S = 1.5 * 8e-3
SOLID_POLE_S = 1.5 * 50e-6
#: poles per station along the groove: five surfaces, each 2 × 6 poles a station (three nodes
#: across, as 19 of the 20 measured cases kept; the 20th, 8 segments of 10 mm on a 40 mm radius at
#: 1e-4 mm, needed five across on a surface: 84 a station, still below its estimate's poles)
SOLID_POLES_PER_STATION = 60
#: the surfaces' first node spacing, and the constants of the spacing the tolerance asks: a
#: cubic Hermite misses a circle of radius r by r·h⁴/128 and a law of stroke H over β by about
#: J·(H/β⁴)·h⁴/384 (J = 3000 from MS rises at 1e-4 mm); the fit halves the spacing, so it
#: overshoots (counted ×1.5), and 4 stations more a stretch cover walls near undercut (16
#: segments of 4 mm over 22.5°: 120 stations at 0.1 mm where the spacing alone asks 56). Over
#: 20 cases (4-16 segments, radii 30-150 mm, 1e-4 to 0.1 mm) the poles estimated were 1.1-1.9
#: times those made, the seconds 1.6-4.4 times those measured
SOLID_OVERSHOOT = 1.5
SOLID_FIRST_STEP_RAD = math.radians(15.0)
SOLID_LAW_J = 3000.0
SOLID_STATIONS_PER_STRETCH = 4
#: facets of a barrel cam's STL ≈ SOLID_FACETS_FIXED + SOLID_FACETS_PER_AREA · A/(R·δ): the
#: kernel meshes the B-spline faces finer both ways as δ falls, so facets ∝ area/(ρ·δ); A the
#: walls, floor and bands, (2πR + Σ strokes) × (2·depth + 4·roller radius), R the pitch radius.
#: Measured 0.37-0.94 (δ = 0.05 and 0.005 mm; MS 4 and 16 segments, radii 50 and 150 mm, a
#: conical roller on a motion program, an oscillating arm; 5 500-86 000 facets); set at 1.0
SOLID_FACETS_PER_AREA = 1.0
SOLID_FACETS_FIXED = 2000
#: one STL facet meshed and written: 6-6.7 µs measured beyond the build (60 000-86 000 facets); ×1.5 of 7 µs
SOLID_FACET_S = 1.5 * 7e-6


def barrel_solid_stations(moves: Sequence[tuple[float, float]], outer_radius_mm: float, tolerance_mm: float) -> int:
    """How many node stations along the groove a barrel cam's solid will have, before fitting.

    Parameters
    ----------
    moves : sequence of (float, float)
        Each segment of the lift: its cam angle [rad] and stroke (0 for a dwell) [mm].
    outer_radius_mm : float
        The cam's outer radius [mm].
    tolerance_mm : float
        The solid's tolerance [mm].

    Returns
    -------
    int
        Stations [-]: per segment the most of its first spacing's, its circles' and its law's,
        × :data:`SOLID_OVERSHOOT` (the fit halves the spacing, so it overshoots), and
        :data:`SOLID_STATIONS_PER_STRETCH`.

    References
    ----------
    The cubic Hermite's error h⁴·max|f⁗|/384; camcore.export.barrel_surfaces.
    """
    aim = 0.8 * tolerance_mm
    circle = (128.0 * aim / outer_radius_mm) ** 0.25
    total = 0
    for angle, stroke in moves:
        h = min(SOLID_FIRST_STEP_RAD, circle)
        if stroke > 0:
            h = min(h, (384.0 * aim * angle**4 / (SOLID_LAW_J * stroke)) ** 0.25)
        total += math.ceil(SOLID_OVERSHOOT * max(1, math.ceil(angle / h))) + SOLID_STATIONS_PER_STRETCH
    return total


def barrel_solid_work(stretches: int, poles: int, facets: int, segments_field: Field,
                      tolerance_field: Field) -> WorkEstimate:
    """Building a barrel cam's solid and writing it (its curves apart).

    Parameters
    ----------
    stretches : int
        Segments of the lift (each a stretch of five surfaces) [-].
    poles : int
        Estimated poles (:func:`barrel_solid_stations` × :data:`SOLID_POLES_PER_STATION`) [-].
    facets : int
        Estimated STL facets (:func:`barrel_solid_facets`); 0 for a STEP file [-].
    segments_field, tolerance_field : tuple
        The request fields of the segments and of the solid's tolerance.

    Returns
    -------
    WorkEstimate
        The surfaces, the kernel's solid and file, the mesh [s].

    References
    ----------
    camcore.export.barrel_solid; the measurements beside the constants.
    """
    terms = [WorkTerm(segments_field, f"the solid's {stretches} stretches", SOLID_S + SOLID_STRETCH_S * stretches),
             WorkTerm(tolerance_field, f"about {poles} B-spline poles", SOLID_POLE_S * poles)]
    if facets:
        terms.append(WorkTerm(tolerance_field, f"about {facets} STL facets", SOLID_FACET_S * facets))
    return WorkEstimate(tuple(terms))


def barrel_solid_facets(pitch_radius_mm: float, roller_radius_mm: float, groove_depth_mm: float,
                        strokes_mm: Sequence[float], deflection_mm: float) -> int:
    """How many facets the kernel's mesh of a barrel cam will have, before meshing.

    Parameters
    ----------
    pitch_radius_mm, roller_radius_mm, groove_depth_mm : float
        R, the roller's radius and the groove's depth [mm].
    strokes_mm : sequence of float
        Each move's stroke along the groove's axis [mm].
    deflection_mm : float
        The mesh's chordal deviation [mm].

    Returns
    -------
    int
        Facets [-].

    References
    ----------
    A surface of radius of curvature ρ meshed to chordal deviation δ has edges of about
    √(8ρδ); the measurements beside :data:`SOLID_FACETS_PER_AREA`.
    """
    length = 2 * math.pi * pitch_radius_mm + sum(abs(s) for s in strokes_mm)
    area = length * (2 * groove_depth_mm + 4 * roller_radius_mm)
    return int(SOLID_FACETS_FIXED + SOLID_FACETS_PER_AREA * area / (pitch_radius_mm * deflection_mm))
