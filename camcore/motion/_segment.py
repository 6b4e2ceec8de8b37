"""A segment while its program is resolved (mutable; camcore.motion.resolve only)."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..curves.curve import Curve
from .laws import PlacedLaw
from .spec import SOLVE, Law, MotionSegment

#: what each kind of adaptive end does, for messages
_ADAPTIVE = {
    "polynomial": "a polynomial with omitted start/end meets its neighbour",
    "universal": "a universal curve with omitted v0/v7 takes its neighbour's velocity",
    "stroke": "to: null solves the stroke to meet the previous segment's velocity",
    "t4": "curve 2 without t4 solves T4 to meet the next segment's acceleration",
}


def describe_adaptive(kind: str) -> str:
    """What an adaptive end of the given kind does (for messages)."""
    return _ADAPTIVE[kind]


@dataclass
class Segment:
    """What is known of one segment so far; ``placed`` once its law is in real units."""

    index: int
    segment: MotionSegment
    law: Law | None
    x_a: float
    span: float
    role: str = "dwell"
    matched: tuple[bool, bool] = (False, False)
    s_a: float | None = None
    stroke: float | None = None
    curve: Curve | None = None
    normal: tuple[list[float], list[float]] = ([], [])
    placed: PlacedLaw | None = None
    solved: dict[str, float] = field(default_factory=dict)
    waiting: str = ""

    def adaptive_start(self) -> str:
        """How the start takes its conditions from the previous segment ('' if it does not)."""
        if self.matched[0]:
            return self.role
        return "stroke" if self.segment.to == SOLVE else ""

    def adaptive_end(self) -> str:
        """How the end takes its conditions from the next segment ('' if it does not)."""
        if self.matched[1]:
            return self.role
        return "t4" if self.role == "solved" else ""
