"""What a motion program is made of: segments over the master angle, and their rules.

A program is one machine cycle of ``period_deg`` degrees of master angle (a cam or
input-shaft angle), made of segments that follow each other from master angle 0. A moving
segment goes from its start position s_a (the previous segment's end, ``start`` for the
first) to ``to`` (absolute), or by ``stroke`` (signed, relative), or — with ``to`` =
:data:`SOLVE` (the API's ``"to": null``) — by the stroke that makes the velocity continuous
at its start. Its law is any curve spec (:class:`Law`, as
:func:`camcore.curves.kinds.build_curve` takes it; the cycloid by default). A dwell holds
its position. These are plain data; :func:`camcore.motion.resolve.resolve_motion` turns them
into a :class:`~camcore.motion.program.MotionProgram`.

The checks here are the program's own rules, shared by the core and the service's specs
(one rule, one sentence): each raises :class:`InvalidParameterError` naming the segment.

References
----------
.. [1] VDI 2143 Blatt 1 (1980), Bewegungsgesetze für Kurvengetriebe: motion tasks and
   transitions between them.
.. [2] Makino (1977), §5.3: one stroke split into two universal curves (curves 1 and 2).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from .._checks import finite
from ..curves.kinds import Law
from ..errors import InvalidParameterError

#: ``to`` of a segment whose stroke is solved (the API's ``"to": null``)
SOLVE: Literal["solve"] = "solve"
#: the spans of a program must add to its period within this fraction of the period: the
#: rounding of a sum of spans is ~1e-16 per span, a real mistake is ≥ 1e-6 of a turn
SPAN_TOLERANCE = 1e-9
#: what a matched polynomial meets at its ends: derivatives up to this order (quintic: s, v,
#: a; septic: s, v, a, j)
MATCH_ORDERS = {"acceleration": 2, "jerk": 3}
#: the units of slave positions: mm (translating follower), deg (swing, indexer output)
UNITS = ("mm", "deg")
SEGMENT_TYPES = ("move", "dwell")


#: the law of a segment that gives none
CYCLOID = Law("named", {"name": "cycloid"})


@dataclass(frozen=True)
class MotionSegment:
    """One segment: its span of master angle [deg], where it ends, and its law.

    ``to``: absolute end position [mm or deg], or :data:`SOLVE`; ``stroke``: signed
    relative travel [mm or deg] (give one of them for a move, neither for a dwell);
    ``law``: None = cycloid; ``match``: what a polynomial with omitted ends meets at them
    (``acceleration``: quintic, ``jerk``: septic).
    """

    span_deg: float
    to: float | Literal["solve"] | None = None
    stroke: float | None = None
    law: Law | None = None
    type: Literal["move", "dwell"] = "move"
    match: Literal["acceleration", "jerk"] = "acceleration"


@dataclass(frozen=True)
class MotionSpec:
    """A machine cycle: segments from master angle 0 over ``period_deg`` [deg], starting
    at position ``start`` [mm or deg], slave positions in ``unit``."""

    segments: Sequence[MotionSegment]
    start: float = 0.0
    period_deg: float = 360.0
    unit: str = "mm"


def check_segment(index: int | None, segment: MotionSegment) -> None:
    """A segment's own rules: its span, and how it ends.

    Parameters
    ----------
    index : int or None
        The segment's place in the program, named in messages and fields [-]; None where the
        caller knows where the segment is (a spec validator: the field's location has it).
    segment : MotionSegment
        The segment.

    Raises
    ------
    InvalidParameterError
        A span that is not a positive number; a dwell with an end position or a law; a move
        with both ``to`` and ``stroke``, or neither; ``match`` not acceleration or jerk.

    References
    ----------
    VDI 2143 Blatt 1 (1980): segments of a motion program, rest (dwell) and transition.
    """
    name = "" if index is None else f"segments[{index}]: "
    where: tuple[str | int, ...] = () if index is None else ("segments", index)
    if segment.type not in SEGMENT_TYPES:
        raise InvalidParameterError(f"{name}type must be 'move' or 'dwell', not {segment.type!r}.",
                                    field=(*where, "type"))
    span = finite(f"{name}span_deg", segment.span_deg)
    if not span > 0:
        raise InvalidParameterError(f"{name}span_deg must be greater than 0, got {span!r}.", field=(*where, "span_deg"))
    if segment.match not in MATCH_ORDERS:
        raise InvalidParameterError(f"{name}match must be 'acceleration' or 'jerk', not {segment.match!r}.",
                                    field=(*where, "match"))
    if segment.type == "dwell":
        if segment.to is not None or segment.stroke is not None or segment.law is not None:
            raise InvalidParameterError(f"{name}a dwell holds its position; give it no to, stroke or curve.",
                                        field=where)
        return
    if segment.to is not None and segment.stroke is not None:
        raise InvalidParameterError(f"{name}give to (absolute; null = solved) or stroke (relative), not both.",
                                    field=where)
    if segment.to is None and segment.stroke is None:
        raise InvalidParameterError(
            f"{name}a move needs to (an absolute end position, or null to solve it) or a stroke.", field=where)
    if segment.to is not None and segment.to != SOLVE:
        finite(f"{name}to", segment.to)
    if segment.stroke is not None:
        finite(f"{name}stroke", segment.stroke)


def check_spans(spans_deg: Sequence[float], period_deg: float) -> None:
    """The spans of a program's segments add up to its period.

    Parameters
    ----------
    spans_deg : sequence of float
        Each segment's span [deg].
    period_deg : float
        The program's period [deg].

    Raises
    ------
    InvalidParameterError
        The sum differs from the period by more than :data:`SPAN_TOLERANCE` of the period.

    References
    ----------
    VDI 2143 Blatt 1 (1980): a motion program covers one machine cycle.
    """
    total = math.fsum(spans_deg)
    if abs(total - period_deg) > SPAN_TOLERANCE * period_deg:
        raise InvalidParameterError(
            f"the segments' spans add up to {total!r}°, but they must add up to period_deg = {period_deg!r}° "
            "(one machine cycle).", field=("segments",))


def check_program(spec: MotionSpec, segments: bool = True) -> None:
    """Every rule of a program that needs no law built: segments, spans, start, unit.

    Parameters
    ----------
    spec : MotionSpec
        The program.
    segments : bool
        Also each segment's own rules (:func:`check_segment`); a caller that has checked
        them one by one, where each is, leaves them out [-].

    Raises
    ------
    InvalidParameterError
        The first rule broken, naming its segment.

    References
    ----------
    VDI 2143 Blatt 1 (1980): a motion program covers one machine cycle.
    """
    if not spec.segments:
        raise InvalidParameterError("a motion program needs at least one segment.", field=("segments",))
    period = finite("period_deg", spec.period_deg)
    if not period > 0:
        raise InvalidParameterError(f"period_deg must be greater than 0, got {period!r}.", field=("period_deg",))
    finite("start", spec.start)
    if spec.unit not in UNITS:
        raise InvalidParameterError(f"unit must be 'mm' or 'deg', not {spec.unit!r}.", field=("unit",))
    if segments:
        for i, segment in enumerate(spec.segments):
            check_segment(i, segment)
    check_spans([s.span_deg for s in spec.segments], period)
