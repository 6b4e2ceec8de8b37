"""Indexers driven by a timing chart (camcore.indexer.timing).

A chart of one index must answer exactly what the single-curve indexer answers (INDEXMAN
technical guide, sections 2-5: the same formulas, reached through the motion program's
chain rule instead of the indexer's scales); charts the single-curve indexer cannot
describe (the oscillating unit's out and back, §4-5; unequal indexing) are checked
against dense evaluations of the chart and hand-derived peaks.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcore.errors import InvalidParameterError, NonMonotoneError, StrokeRangeError
from camcore.indexer import Indexer, Load, LoadPart, TimedIndexer, check_timing, size
from camcore.motion import Law, MotionSegment, MotionSpec, resolve_motion
from camcore.results import as_dict

MS = Law("named", {"name": "MS"})
MS_BACK = Law("named", {"name": "MS"}, "return")
#: the guide's sizing example: a 50 kg disc of Ø600 mm, μ = 0.1 at 200 mm, service factor 1.5
LOAD = Load(parts=[LoadPart(shape="disc", mass_kg=50, diameter_mm=600)], friction_coefficient=0.1,
            friction_radius_mm=200, service_factor=1.5)


def chart(*segments: MotionSegment) -> TimedIndexer:
    return TimedIndexer(program=resolve_motion(MotionSpec(list(segments), unit="deg")), speed_rpm=60)


def move(span: float, stroke: float, law: Law = MS) -> MotionSegment:
    return MotionSegment(span, stroke=stroke, law=law)


def dwell(span: float) -> MotionSegment:
    return MotionSegment(span, type="dwell")


def assert_same_fields(ours: dict[str, object], theirs: dict[str, object], skip: tuple[str, ...] = ()) -> None:
    # the two paths multiply the same closed-form values in another order: rounding only
    for name, value in theirs.items():
        if name in skip or value is None:
            continue
        assert ours[name] == pytest.approx(value, rel=1e-12, abs=1e-12), name


@pytest.mark.parametrize("dwells", [1, 2])
def test_a_chart_of_equal_indexes_is_the_single_curve_indexer(dwells: int) -> None:
    # 6 stops, θh = 270° / z, MS, 60 rpm (the guide's example), as z indexes on one chart
    theta_h = 270.0 / dwells
    segments = [move(theta_h, 60), dwell(360 / dwells - theta_h)] * dwells
    ours = chart(*segments)
    theirs = Indexer(stops=6, indexing_angle_deg=theta_h, dwells=dwells, speed_rpm=60, curve="MS")
    assert ours.dwells == dwells
    assert_same_fields(as_dict(ours.summary()), as_dict(theirs.summary()))
    # the chart's machine cycle is its whole turn (z indexes), the indexer's one index: the RMS
    # agrees (the same torque repeated), the table's length and the cycle time do not
    ours_size, theirs_size = as_dict(size(ours, LOAD)), as_dict(size(theirs, LOAD))
    assert_same_fields(ours_size, theirs_size, skip=("input_torque_table", "machine_cycle_time_s"))
    assert ours_size["machine_cycle_time_s"] == pytest.approx(dwells * theirs_size["machine_cycle_time_s"], rel=1e-15)
    x = np.linspace(0, theta_h, 101)[:-1]  # at θh the chart answers the dwell's side (right limit)
    assert_same_fields(ours.motion_at(x).columns(), theirs.motion_at(x).columns())
    assert ours.motion_at([theta_h]).jerk_rad_s3[0] == 0.0  # the dwell begins at θh
    out = [0, 11, 30, 59.5, 60]
    assert_same_fields(ours.position(out).columns(), theirs.position(out).columns())


def test_cycle_time_is_the_unit_cycle_time_of_the_chart() -> None:
    # t0 = 60/(N·z): two indexes per turn at t0 = 0.5 s run the input at 60 rpm
    program = resolve_motion(MotionSpec([move(90, 60), dwell(90), move(90, 60), dwell(90)], unit="deg"))
    unit = TimedIndexer(program=program, cycle_time_s=0.5, input_stop_time_s=0.2)
    summary = unit.summary()
    assert unit.rpm == pytest.approx(60.0, rel=1e-15)
    assert (summary.cycle_time_s, summary.machine_cycle_time_s) == (0.5, pytest.approx(0.7, rel=1e-15))
    assert summary.indexing_time_s == pytest.approx(0.25, rel=1e-15)  # 90° at 360°/s


def test_oscillating_out_and_back() -> None:
    # the guide's §4-5 oscillating unit: out 90° over 120° (MS), dwell 60°, back (MS played
    # backwards), dwell 60°; the chart closes, so h is the swing and n = 360/ψ
    unit = chart(move(120, 90), dwell(60), move(120, -90, MS_BACK), dwell(60))
    summary = unit.summary()
    assert (summary.displacement_deg, summary.stops, summary.dwells) == (90.0, 4.0, 2)
    assert (summary.indexing_angle_deg, summary.total_indexing_angle_deg) == (120.0, 240.0)
    # peaks: s′ = (90/120)·V, so ω = ω_in·0.75·Vm with Vm = 1.76 (MS) at T = 0.5, out at x = 60°
    # and back (ω < 0) at x = 240°; the largest |ω| is reported where it first occurs
    vm = Indexer(stops=4, indexing_angle_deg=120, speed_rpm=60, curve="MS").curve.characteristics.vm.value
    assert summary.omega_rad_s == pytest.approx(2 * math.pi * 0.75 * vm, rel=1e-14)
    assert summary.omega_input_angle_deg == pytest.approx(60.0, rel=1e-14)
    # position: the first time in the turn, on the way out (the way back passes 45° at 240°)
    position = unit.position([0, 45, 90])
    assert position.input_angle_deg == pytest.approx([0, 60, 120], rel=1e-14, abs=1e-12)
    with pytest.raises(StrokeRangeError, match="between 0.0° and 90.0°"):
        unit.position([90.5])


def test_sizing_of_out_and_back_against_a_dense_evaluation() -> None:
    # T_in(x) = s′·(I·α + (Tf + Tw)·sgn s′) over the whole turn: friction resists the way back
    # too. Dense check: 720 001 angles; between samples f changes by at most |f′|·Δx/2, and
    # |f′| ≤ ~1e4 N·m/deg here, so the sampled peak is within 1e4·(0.0005°)²-order of the exact
    # one (f is flat at its peak): a relative 1e-6 is far above that and far below any error
    # in the peak's formula
    unit = chart(move(120, 90), dwell(60), move(120, -90, MS_BACK), dwell(60))
    result = size(unit, LOAD)
    x = np.linspace(0, 360, 720_001)
    _s, v, a = unit.program.derivatives(x, 2)
    _, ka, _ = unit.scales
    resisting = LOAD.total_friction_torque_nm + LOAD.work_torque_nm
    f = v * (LOAD.total_inertia_kgm2 * ka * a + resisting * np.sign(v))
    fc = LOAD.service_factor
    assert result.input_torque_pos_nm == pytest.approx(fc * f.max(), rel=1e-6)
    assert result.input_torque_neg_nm == pytest.approx(fc * f.min(), rel=1e-6)
    assert result.input_torque_nm == pytest.approx(fc * np.abs(f).max(), rel=1e-6)
    # the driving peak occurs first on the way out; MS is symmetric, so the way back (played
    # backwards) drives as hard, in its own first half
    assert result.input_torque_input_angle_deg < 60
    back = (x >= 180) & (x <= 300)
    assert fc * f[back].max() == pytest.approx(result.input_torque_pos_nm, rel=1e-6)
    assert result.alpha_max_rad_s2 == pytest.approx(ka * np.abs(a).max(), rel=1e-6)


def test_unequal_indexing() -> None:
    # 4 stops, two indexes of 90° per turn: a slow one over 150° and a fast one over 90°;
    # the fast one sets the peaks: s′ = 90/90·V → ω = ω_in·Vm, at its middle (x = 150 + 45 + 45)
    unit = chart(move(150, 90), dwell(30), move(90, 90), dwell(90))
    summary = unit.summary()
    assert (summary.displacement_deg, summary.stops, summary.dwells) == (90.0, 4.0, 2)
    assert summary.indexing_angle_deg == 120.0  # the average of 150° and 90°
    vm = Indexer(stops=4, indexing_angle_deg=90, speed_rpm=60, curve="MS").curve.characteristics.vm.value
    assert summary.omega_rad_s == pytest.approx(2 * math.pi * vm, rel=1e-14)
    assert summary.omega_input_angle_deg == pytest.approx(225.0, rel=1e-14)
    assert unit.position([45, 135]).input_angle_deg == pytest.approx([75.0, 225.0], rel=1e-14)


def test_a_law_that_is_not_monotone_refuses_the_position_lookup() -> None:
    # a matched quintic between a constant-velocity stretch and a dwell at a lower level turns back
    poly = Law("polynomial", {})
    cv = Law("named", {"name": "constant-velocity"})
    unit = chart(move(90, 60, cv), move(60, -70, poly), dwell(90), move(120, 10))
    assert unit.program.characteristics.s_max > 60.5  # the quintic overshoots the 60° it starts at
    with pytest.raises(NonMonotoneError) as err:
        unit.position([60.5])
    assert err.value.field == ("segments", 1, "curve")


def test_what_is_not_a_timing_chart() -> None:
    with pytest.raises(InvalidParameterError, match="'deg'") as err:
        check_timing(resolve_motion(MotionSpec([move(270, 60), dwell(90)], unit="mm")))
    assert err.value.field == ("unit",)
    with pytest.raises(InvalidParameterError, match="period_deg must be 360"):
        check_timing(resolve_motion(MotionSpec([move(270, 60), dwell(450)], unit="deg", period_deg=720)))
    with pytest.raises(InvalidParameterError, match="never moves"):
        check_timing(resolve_motion(MotionSpec([dwell(360)], unit="deg")))
    with pytest.raises(InvalidParameterError, match="exactly one of speed_rpm"):
        TimedIndexer(program=resolve_motion(MotionSpec([move(270, 60), dwell(90)], unit="deg")))
