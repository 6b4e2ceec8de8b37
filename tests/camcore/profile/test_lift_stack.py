"""The stacked lift (camcore.profile.lift_stack) against the schedule's own segment-by-segment
evaluation: the same numbers to the bit, every order, every section curve of the catalog, rises,
returns and dwells, at random angles, at the break points and on either side of them.

The segment-by-segment path is the reference: it is each curve's own evaluation (checked against
Makino's tables in tests/camcore/curves) put through the chain rule of the Bezier notes, eq. (12).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcore.curves.catalog import CATALOG, named_curve
from camcore.curves.sections import SectionCurve
from camcore.profile.lift import LiftSchedule, Segment
from camcore.profile.lift_stack import StackedLift

SECTION_CURVES = [name for name in CATALOG if isinstance(named_curve(name), SectionCurve)]
OTHER_CURVES = [name for name in CATALOG if not isinstance(named_curve(name), SectionCurve)]


def _one_by_one(segments: list[Segment], unit: str = "mm") -> LiftSchedule:
    schedule = LiftSchedule(segments, unit=unit)
    schedule.__dict__["_stack"] = None  # the cached stack left out: segment by segment
    return schedule


def _random_schedule(rng: np.random.Generator, curves: list[str]) -> list[Segment]:
    """Two to six segments over 360°: a rise first, then rises, dwells and returns of random curves
    (some the default cycloid), the last a return that closes."""
    count = int(rng.integers(2, 7))
    angles = rng.dirichlet(np.ones(count)) * 360.0
    angles[-1] = 360.0 - angles[:-1].sum()
    segments, up = [], 0.0
    for k, angle in enumerate(angles.tolist()):
        curve = named_curve(curves[int(rng.integers(len(curves)))]) if rng.random() < 0.85 else None
        kind = "rise" if k == 0 else "return" if k == count - 1 else str(rng.choice(["rise", "dwell", "return"]))
        if kind == "rise":
            lift = float(rng.uniform(0.5, 30.0))
            up += lift
            segments.append(Segment("rise", angle, lift, curve))
        elif kind == "dwell" or up == 0.0:
            segments.append(Segment("dwell", angle))
        else:
            drop = up if k == count - 1 else float(rng.uniform(0.0, up))
            up -= drop
            segments.append(Segment("return", angle, drop, curve))
    return segments


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.tobytes() == b.tobytes()  # −0 and +0 apart, NaN by its bits


def test_the_stack_gives_the_segments_numbers_to_the_bit():
    rng = np.random.default_rng(20261208)
    stacked = 0
    for _ in range(120):
        segments = _random_schedule(rng, SECTION_CURVES)
        schedule, reference = LiftSchedule(segments), _one_by_one(segments)
        stacked += schedule._stack is not None
        breaks = schedule.breaks_rad
        for size in (9, 40, 700, 4100):  # the few-point path ends at 8; 4100 reaches the curves' sorted path
            theta = rng.uniform(-7.0, 14.0, size)
            # break points and their float neighbours, where a section or a segment begins
            picked = breaks[rng.integers(breaks.size, size=size // 3)]
            theta[: size // 3] = picked + rng.choice([-1, 0, 1], size=picked.size) * np.spacing(picked)
            if rng.random() < 0.4:
                theta.sort()  # a table's angles
            for order in range(5):
                ours, theirs = schedule.derivatives(theta, order), reference.derivatives(theta, order)
                assert all(_same_bits(a, b) for a, b in zip(ours, theirs)), (segments, size, order)
    assert stacked == 120  # the comparison exercised the stack, not only the segment-by-segment fallback


def test_a_readme_cam_and_its_edges():
    segments = [Segment("rise", 180, 20), Segment("return", 180, 20)]  # the README's plate cam
    schedule, reference = LiftSchedule(segments), _one_by_one(segments)
    assert schedule._stack is not None
    theta = np.array([0.0, -0.0, math.pi, math.nextafter(math.pi, 0.0), 2 * math.pi, -1e-300, 1e300,
                      math.nextafter(2 * math.pi, 0.0), 4 * math.pi + 1.0, -math.pi / 2, 1.0, 2.0])
    for order in range(5):
        assert all(_same_bits(a, b) for a, b in zip(schedule.derivatives(theta, order),
                                                    reference.derivatives(theta, order)))


def test_a_nan_angle_is_left_to_the_segments():
    segments = [Segment("rise", 120, 10), Segment("dwell", 60), Segment("return", 180, 10)]
    theta = np.linspace(0.0, 7.0, 20)
    theta[5] = np.nan
    schedule = LiftSchedule(segments)
    assert schedule._stack is not None and schedule._stack.derivatives(np.mod(theta, 2 * math.pi), 2) is None
    for a, b in zip(schedule.derivatives(theta, 3), _one_by_one(segments).derivatives(theta, 3)):
        assert _same_bits(a, b)


@pytest.mark.parametrize("name", OTHER_CURVES)
def test_a_curve_without_sections_keeps_the_segments_path(name):
    segments = [Segment("rise", 90, 5, named_curve(name)), Segment("dwell", 90), Segment("return", 180, 5)]
    schedule = LiftSchedule(segments)
    assert schedule._stack is None
    theta = np.linspace(-1.0, 7.0, 50)
    assert all(_same_bits(a, b) for a, b in zip(schedule.derivatives(theta, 2),
                                                _one_by_one(segments).derivatives(theta, 2)))


def test_dwells_only_have_no_stack():
    assert StackedLift.of(LiftSchedule([Segment("dwell", 360)])._pieces, np.zeros(1)) is None


def test_each_bound_is_passed_at_exactly_one_float_angle():
    """The thresholds are the least angles whose time reaches each bound of the curve's pieces."""
    schedule = LiftSchedule([Segment("rise", 100.3, 7, named_curve("MT")), Segment("dwell", 37.1),
                             Segment("return", 222.6, 7, named_curve("asymmetric-cycloid"))])
    stack = schedule._stack
    assert stack is not None
    for piece in schedule._pieces:
        if piece.curve is None:
            continue
        c = piece.curve
        t_start, t_span, start, span = c.t_start, c.t_end - c.t_start, piece.start, piece.span

        def time(theta: float, t_start: float = t_start, t_span: float = t_span, start: float = start,
                 span: float = span) -> float:  # the segment's T(θ), as LiftSchedule.derivatives forms it
            return t_start + t_span * min(max((theta - start) / span, 0.0), 1.0)

        for bound in c.piece_starts[1:].tolist():
            at = stack._passed(start, span, t_start, t_span, bound)
            assert time(at) >= bound > time(math.nextafter(at, -math.inf))
