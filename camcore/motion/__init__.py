"""Motion programs: one machine cycle of one follower, matched at every join.

Map: :mod:`.spec` (the program as plain data and its rules), :mod:`.laws` (a law in real
units; what a program may leave out of a law), :mod:`.polynomials` (polynomials matched to
their neighbours, chains of them), :mod:`.resolve` (solving strokes, T4 and matched laws in
order), :mod:`.program` (evaluation, joins, characteristic values), :mod:`.results` (what a
program answers). A closed program is a cam's lift: :class:`camcore.profile.MotionLift`.

References
----------
.. [1] VDI 2143 Blatt 1 (1980), Bewegungsgesetze für Kurvengetriebe.
.. [2] Makino (1977), §5.3: the cutting-unit feed cam.
"""

from .laws import SOLVED_PARAMETERS, PlacedLaw, law_role
from .program import CONTINUITY_TOLERANCE, MotionProgram
from .resolve import resolve_motion
from .results import Join, MotionCharacteristics, MotionTable, ResolvedSegment
from .spec import (
    CYCLOID,
    SOLVE,
    SPAN_TOLERANCE,
    Law,
    MotionSegment,
    MotionSpec,
    check_program,
    check_segment,
    check_spans,
)

__all__ = [
    "CONTINUITY_TOLERANCE",
    "CYCLOID",
    "SOLVE",
    "SOLVED_PARAMETERS",
    "SPAN_TOLERANCE",
    "Join",
    "Law",
    "MotionCharacteristics",
    "MotionProgram",
    "MotionSegment",
    "MotionSpec",
    "MotionTable",
    "PlacedLaw",
    "ResolvedSegment",
    "check_program",
    "check_segment",
    "check_spans",
    "law_role",
    "resolve_motion",
]
