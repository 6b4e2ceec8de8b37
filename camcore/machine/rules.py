"""Timing rules between axes: where they are broken, and how far an axis may move in phase.

A rule reads "while axis B satisfies its condition, axis A must satisfy its own". A condition is
one of: the axis is moving (or standing still), its position is at most a value, at least a
value. Each condition holds on a set of master angles, a union of closed stretches of the circle
[0°, 360°): exact for moving (the axes' dwells are stretches between break points), and for a
position from every crossing of the level, bracketed on a 0.05° grid of the master angle and
refined to machine precision (a crossing and its return within one grid cell are not seen).

The rule is broken where B's set meets the complement of A's. For a rule that holds, every
stretch of B's set lies inside a stretch [a1, a2] of A's set; moving axis A later by δ moves that
stretch to [a1 + δ, a2 + δ], which still holds B's stretch [b1, b2] while δ ≤ b1 − a1: the
*phase slack* later is the smallest b1 − a1 over B's stretches, and earlier the smallest a2 − b2.
A condition that holds everywhere leaves unlimited slack (None).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._solvers import scan_roots
from ..curves.base import FloatArray
from ..errors import InvalidParameterError
from ..results import doc
from .axes import MachineAxis, merge_spans

#: the grid that brackets a position's crossings of a level [deg]
CROSSING_GRID_DEG = 0.05
FULL = 360.0


@dataclass(frozen=True)
class Condition:
    """What an axis must satisfy: ``moving`` (True: not in a dwell; False: in a dwell), or its
    position ``at_most`` / ``at_least`` a value in the axis's unit (mm or deg). Exactly one."""

    axis: str
    moving: bool | None = None
    at_most: float | None = None
    at_least: float | None = None

    def __post_init__(self) -> None:
        given = [name for name in ("moving", "at_most", "at_least") if getattr(self, name) is not None]
        if len(given) != 1:
            raise InvalidParameterError("a condition gives exactly one of moving, at_most and at_least.")


@dataclass(frozen=True)
class Rule:
    """While ``when`` holds, ``require`` must hold."""

    when: Condition
    require: Condition


@dataclass(frozen=True)
class Violation:
    """One stretch of master angle where a rule is broken."""

    from_deg: float = field(metadata=doc("where it starts [deg of master angle]"))
    to_deg: float = field(metadata=doc("where it ends; below from_deg when it runs through 360° [deg]"))
    depth: float = field(metadata=doc(
        "how far the required axis is beyond its limit at worst in the stretch (its unit), or, for a moving "
        "condition, the stretch's length [deg]"))
    depth_unit: str = field(metadata=doc("mm, deg (of the axis's position) or deg of master angle"))


@dataclass(frozen=True)
class RuleResult:
    """A rule checked over one master turn."""

    rule: str = field(metadata=doc("the rule in words"))
    holds: bool = field(metadata=doc("the required condition holds wherever the other one does"))
    violations: tuple[Violation, ...] = field(metadata=doc("where it is broken"))
    slack_earlier_deg: float | None = field(metadata=doc(
        "holding rules: how far the required axis's phase may move earlier before the rule breaks; null: any amount"))
    slack_later_deg: float | None = field(metadata=doc("the same, later [deg]"))


def _words(c: Condition, unit: str) -> str:
    if c.moving is not None:
        return f"{c.axis} is {'moving' if c.moving else 'standing still'}"
    if c.at_most is not None:
        return f"{c.axis} is at most {c.at_most:g} {unit}"
    return f"{c.axis} is at least {c.at_least:g} {unit}"


def master_spans(spans: list[tuple[float, float]], phase: float) -> list[tuple[float, float]]:
    """Own-angle stretches moved to master angles, split where they pass 360°, merged.

    Parameters
    ----------
    spans : list of (float, float)
        Stretches [a, b] of the axis's own angle [deg].
    phase : float
        φ, the axis's phase [deg].

    Returns
    -------
    list of (float, float)
        The same stretches over the master angle, within [0, 360] [deg].

    References
    ----------
    The phase of an axis: x = θ + φ (module notes).
    """
    out: list[tuple[float, float]] = []
    for a, b in spans:
        a2, b2 = a + phase, b + phase
        shift = FULL * math.floor(a2 / FULL)
        a2, b2 = a2 - shift, b2 - shift
        if b2 <= FULL:
            out.append((a2, b2))
        else:
            out += [(a2, FULL), (0.0, b2 - FULL)]
    return merge_spans(out)


def _complement(spans: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The rest of [0, 360] (closed stretches: the shared edges are kept on both sides)."""
    out, edge = [], 0.0
    for a, b in spans:
        if a > edge:
            out.append((edge, a))
        edge = max(edge, b)
    if edge < FULL:
        out.append((edge, FULL))
    return out


def _intersect(first: list[tuple[float, float]], second: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Stretches in both (a common edge alone is not an overlap)."""
    out = []
    for a, b in first:
        for c, d in second:
            lo, hi = max(a, c), min(b, d)
            if hi > lo:
                out.append((lo, hi))
    return merge_spans(out)


def condition_set(c: Condition, axis: MachineAxis) -> list[tuple[float, float]]:
    """Master angles where a condition holds.

    Parameters
    ----------
    c : Condition
        Moving, standing still, or the position at most / at least a level.
    axis : MachineAxis
        The axis it is about.

    Returns
    -------
    list of (float, float)
        Closed stretches of [0, 360], in order [deg].

    References
    ----------
    Dowell and Jarratt (1971), the Illinois method (the crossings of a level, refined).
    """
    if c.moving is not None:
        still = master_spans([(math.degrees(a), math.degrees(b)) for a, b in axis.dwells()], axis.phase_deg)
        return _complement(still) if c.moving else still
    level = float(c.at_most if c.at_most is not None else c.at_least)  # type: ignore[arg-type]
    sign = 1.0 if c.at_most is not None else -1.0

    def margin(x_deg: FloatArray) -> FloatArray:  # ≥ 0 where the condition holds
        return sign * (level - axis.position(axis.own(np.radians(x_deg))))

    grid = np.unique(np.concatenate([np.linspace(0.0, FULL, round(FULL / CROSSING_GRID_DEG) + 1),
                                     np.mod(np.degrees(axis.breaks()) + axis.phase_deg, FULL)]))
    roots, _ = scan_roots(margin, grid)
    edges = np.unique(np.concatenate([[0.0, FULL], roots]))
    mids = 0.5 * (edges[:-1] + edges[1:])
    inside = margin(mids) >= 0
    spans = [(float(a), float(b)) for a, b, ok in zip(edges[:-1], edges[1:], inside, strict=True) if ok]
    return merge_spans(spans)


def _depth(c: Condition, axis: MachineAxis, a: float, b: float) -> tuple[float, str]:
    if c.moving is not None:
        return b - a, "deg of master angle"
    x = np.linspace(a, b, 257)
    p = axis.position(axis.own(np.radians(x)))
    beyond = p - float(c.at_most) if c.at_most is not None else float(c.at_least) - p  # type: ignore[arg-type]
    return float(max(beyond.max(), 0.0)), axis.unit


def _joined(spans: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Stretches of the circle: one that ends at 360° and one that starts at 0° are one (its end < start)."""
    if len(spans) > 1 and spans[0][0] == 0.0 and spans[-1][1] == FULL:
        return [(spans[-1][0], spans[0][1] + FULL), *spans[1:-1]]
    return spans


def check_rule(rule: Rule, axes: dict[str, MachineAxis]) -> RuleResult:
    """Where a timing rule is broken over one master turn, and its phase slack.

    Parameters
    ----------
    rule : Rule
        While ``when`` holds, ``require`` must hold.
    axes : dict of str to MachineAxis
        The machine's axes by name.

    Returns
    -------
    RuleResult
        Whether it holds, the stretches where it does not (with their depth), and for a rule that
        holds the phase slack earlier and later of the required axis [deg].

    References
    ----------
    The module notes: the containment of the stretches, and the slack as their distances.
    """
    a_axis, b_axis = axes[rule.require.axis], axes[rule.when.axis]
    words = f"while {_words(rule.when, b_axis.unit)}, {_words(rule.require, a_axis.unit)}"
    b_set = condition_set(rule.when, b_axis)
    a_set = condition_set(rule.require, a_axis)
    broken = _joined(_intersect(b_set, _complement(a_set)))
    violations = []
    for lo, hi in broken:
        depth, unit = _depth(rule.require, a_axis, lo, hi)
        violations.append(Violation(lo, hi - FULL if hi > FULL else hi, depth, unit))
    if violations:
        return RuleResult(words, False, tuple(violations), None, None)
    a_round, b_round = _joined(a_set), _joined(b_set)
    if not b_round or (len(a_round) == 1 and a_round[0] == (0.0, FULL)):
        return RuleResult(words, True, (), None, None)
    later, earlier = math.inf, math.inf
    for b1, b2 in b_round:
        for a1, a2 in a_round:
            for turn in (0.0, FULL, -FULL):
                if a1 + turn <= b1 + 1e-9 and b2 <= a2 + turn + 1e-9:
                    later = min(later, b1 - (a1 + turn))
                    earlier = min(earlier, a2 + turn - b2)
    return RuleResult(words, True, (), max(earlier, 0.0), max(later, 0.0))
