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
