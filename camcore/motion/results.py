"""What a motion program answers: its resolved segments, its joins, its characteristic
values and its table (each a result dataclass, served as it is).

References
----------
.. [1] VDI 2143 Blatt 1 (1980): continuity of s, v, a, j at the joins of a motion program.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..curves.base import FloatArray
from ..results import doc, table_columns


@dataclass(frozen=True)
class ResolvedSegment:
    """One segment as resolved: where it lies, where it moves, its law and what was solved."""

    index: int = field(metadata=doc("the segment's place in the program, from 0"))
    type: str = field(metadata=doc("move or dwell"))
    start_deg: float = field(metadata=doc("master angle where it starts [deg]"))
    end_deg: float = field(metadata=doc("master angle where it ends [deg]"))
    from_: float = field(metadata=doc("position at its start [unit]", name="from"))
    to: float = field(metadata=doc("position at its end [unit]"))
    stroke: float = field(metadata=doc("to − from [unit]"))
    curve: str = field(metadata=doc("its law: a catalog id, 'makino 2', 'universal', 'polynomial', … or 'dwell'"))
    direction: str = field(metadata=doc("rise, or return (the law played backwards)"))
    solved: dict[str, float] = field(metadata=doc(
        "what the program solved or matched: stroke (to: null), t4 (curve 2), v0/v7 (universal, in the law's "
        "own units), degree and the end conditions v_start, a_start, j_start, v_end, … of a matched polynomial "
        "[unit/deg^k]"))


@dataclass(frozen=True)
class Join:
    """The jumps where one segment meets the next (after − before), in real units."""

    at_deg: float = field(metadata=doc("master angle of the join; period_deg for the wrap-around [deg]"))
    before: int = field(metadata=doc("the segment ending here"))
    after: int = field(metadata=doc("the segment starting here (0 at the wrap-around)"))
    ds: float = field(metadata=doc("jump in position [unit]"))
    dv: float = field(metadata=doc("jump in ds/dx [unit/deg]"))
    da: float = field(metadata=doc("jump in d²s/dx² [unit/deg²]"))
    dj: float = field(metadata=doc("jump in d³s/dx³ [unit/deg³]"))
    continuity: str = field(metadata=doc(
        "C3, C2, C1, C0 (every jump up to j, a, v, s below 1e-9 of the program's scale of that quantity: the range "
        "of s, the peak |v|, |a|, |j| over the cycle) or none"))


@dataclass(frozen=True)
class MotionCharacteristics:
    """Extremes over the whole cycle, exact (each law's own extrema), with where they occur."""

    s_max: float = field(metadata=doc("largest position [unit]"))
    s_max_at_deg: float = field(metadata=doc("where [deg]"))
    s_min: float = field(metadata=doc("smallest position [unit]"))
    s_min_at_deg: float = field(metadata=doc("where [deg]"))
    v_peak: float = field(metadata=doc("largest |v| [unit/deg]"))
    v_peak_at_deg: float = field(metadata=doc("where [deg]"))
    v_max: float = field(metadata=doc("largest v [unit/deg]"))
    v_max_at_deg: float = field(metadata=doc("where [deg]"))
    v_min: float = field(metadata=doc("smallest v (signed) [unit/deg]"))
    v_min_at_deg: float = field(metadata=doc("where [deg]"))
    a_max: float = field(metadata=doc("largest a [unit/deg²]"))
    a_max_at_deg: float = field(metadata=doc("where [deg]"))
    a_min: float = field(metadata=doc("smallest a (signed) [unit/deg²]"))
    a_min_at_deg: float = field(metadata=doc("where [deg]"))
    j_max: float = field(metadata=doc("largest j [unit/deg³]"))
    j_max_at_deg: float = field(metadata=doc("where [deg]"))
    j_min: float = field(metadata=doc("smallest j (signed) [unit/deg³]"))
    j_min_at_deg: float = field(metadata=doc("where [deg]"))


@dataclass(frozen=True)
class MotionTable:
    """The program's columns over the master angle; the time columns with a speed only."""

    x_deg: FloatArray = field(metadata=doc("master angle [deg]"))
    s: FloatArray = field(metadata=doc("position [unit]"))
    v: FloatArray = field(metadata=doc("ds/dx [unit/deg]"))
    a: FloatArray = field(metadata=doc("d²s/dx² [unit/deg²]"))
    j: FloatArray = field(metadata=doc("d³s/dx³ [unit/deg³]"))
    time_s: FloatArray | None = field(default=None, metadata=doc("x/ω from master angle 0 [s]"))
    v_per_s: FloatArray | None = field(default=None, metadata=doc("ds/dt = ω·v [unit/s]"))
    a_per_s2: FloatArray | None = field(default=None, metadata=doc("d²s/dt² = ω²·a [unit/s²]"))
    j_per_s3: FloatArray | None = field(default=None, metadata=doc("d³s/dt³ = ω³·j [unit/s³]"))

    def columns(self) -> dict[str, Any]:
        """The columns present (the time columns only with a speed)."""
        return {k: v for k, v in table_columns(self).items() if v is not None}
