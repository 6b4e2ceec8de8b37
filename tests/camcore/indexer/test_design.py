"""Designing an indexer (camcore.indexer.design): every candidate sized as size() sizes it, the best the
brute-force optimum of the candidate set under the same requirements, written out here independently.

The requirements (INDEXMAN technical guide, sections 2, 3 and 5): one index and one dwell per input
turn, t0 = 60/N, the indexing time th = θh/360·t0, so the dwell t0 − th must leave the dwell the
process needs; the design output torque within the rated; a motor's peak, RMS and speed within its
ratings.
"""

from __future__ import annotations

import itertools

import pytest

from camcore import named_curve
from camcore.errors import InvalidParameterError
from camcore.indexer import Indexer, Load, LoadPart, Motor, size
from camcore.indexer.design import NamedMotor, design_indexer

LOAD = Load(parts=[LoadPart(shape="disc", mass_kg=50, diameter_mm=600)], friction_coefficient=0.1,
            friction_radius_mm=200, service_factor=1.5)
CURVES = [(name, named_curve(name)) for name in ("MS", "MCV50", "TR", "cycloid")]
ANGLES = [90.0, 120.0, 150.0, 180.0, 210.0, 240.0, 270.0, 300.0]
MOTORS = [NamedMotor(f"{rated} N·m", Motor(rated_torque_nm=rated, peak_torque_nm=3 * rated, rotor_inertia_kgm2=3e-4,
                                            max_speed_rpm=3000, reduction_ratio=10))
          for rated in (0.64, 1.27, 2.39)]
RPM = 60.0  # t0 = 1 s
MIN_DWELL_S = 0.4  # so θh ≤ 216°


def brute_force(motors: list[NamedMotor | None], rated_output: float | None = None) -> list[tuple]:
    """(angle, curve, motor name, sizing) of every feasible combination, by the requirements written out."""
    out = []
    for angle, (name, curve), motor in itertools.product(ANGLES, CURVES, motors):
        s = size(Indexer(stops=6, indexing_angle_deg=angle, speed_rpm=RPM, curve=curve), LOAD,
                 motor=None if motor is None else motor.motor, table_samples=2)
        dwell_ok = 1.0 - angle / 360.0 >= MIN_DWELL_S
        torque_ok = rated_output is None or s.design_output_torque_nm <= rated_output
        if dwell_ok and torque_ok and (motor is None or s.motor_ok):
            out.append((angle, name, None if motor is None else motor.name, s))
    return out


def test_without_motors_the_best_is_the_smallest_feasible_peak_input_torque() -> None:
    design = design_indexer(6, LOAD, RPM, ANGLES, CURVES, min_dwell_s=MIN_DWELL_S)
    feasible = brute_force([None])
    best = min(feasible, key=lambda row: row[3].input_torque_nm)
    assert design.best is not None and design.criterion == "input_torque"
    assert (design.best.indexing_angle_deg, design.best.curve) == best[:2]
    assert design.best.input_torque_nm == best[3].input_torque_nm  # the same sizing, the same number
    assert design.max_indexing_angle_deg == pytest.approx(216.0, rel=1e-15)
    ranked = [c for c in design.candidates if c.feasible]
    assert len(ranked) == len(feasible) == 5 * 4  # 90°…210° by 4 curves
    assert [c.input_torque_nm for c in ranked] == sorted(c.input_torque_nm for c in ranked)
    assert all("dwell" in (c.reason or "") for c in design.candidates if not c.feasible)


def test_with_motors_the_best_is_the_smallest_motor_that_carries_a_design() -> None:
    design = design_indexer(6, LOAD, RPM, ANGLES, CURVES, min_dwell_s=MIN_DWELL_S, motors=MOTORS)
    feasible = brute_force(list(MOTORS))
    smallest = min(m.motor.rated_torque_nm for m in MOTORS if any(row[2] == m.name for row in feasible))
    assert design.best is not None and design.criterion == "motor"
    chosen = next(m for m in MOTORS if m.name == design.best.motor)
    assert chosen.motor.rated_torque_nm == smallest
    # among that motor's designs, the smallest RMS use
    own = [row[3].rms_utilisation for row in feasible if row[2] == design.best.motor]
    assert design.best.rms_utilisation == min(own)
    assert sum(c.feasible for c in design.candidates) == len(feasible)
    # the smallest motor is too small for every design: each of its rows says why
    weakest = MOTORS[0].name
    assert all(not c.feasible and f"motor {weakest}" in (c.reason or "") for c in design.candidates
               if c.motor == weakest and c.indexing_angle_deg <= 216)


def test_the_rated_output_torque_and_the_rms_criterion() -> None:
    rated = 90.0
    design = design_indexer(6, LOAD, RPM, ANGLES, CURVES, min_dwell_s=MIN_DWELL_S, rated_output_torque_nm=rated,
                            criterion="rms_input_torque")
    feasible = brute_force([None], rated_output=rated)
    assert design.best is not None
    assert design.best.rms_input_torque_nm == min(row[3].rms_input_torque_nm for row in feasible)
    assert all(c.design_output_torque_nm <= rated for c in design.candidates if c.feasible)


def test_no_feasible_candidate_and_bad_requests() -> None:
    design = design_indexer(6, LOAD, RPM, ANGLES, CURVES, min_dwell_s=MIN_DWELL_S, rated_output_torque_nm=1.0)
    assert design.best is None and all(not c.feasible for c in design.candidates)
    assert {"rated_output_torque_nm"} <= {m for c in design.candidates for m in c.missed}
    with pytest.raises(InvalidParameterError, match="whole cycle") as e:
        design_indexer(6, LOAD, RPM, ANGLES, CURVES, min_dwell_s=1.0)
    assert e.value.field == ("min_dwell_s",)
    with pytest.raises(InvalidParameterError, match="needs motors") as e:
        design_indexer(6, LOAD, RPM, ANGLES, CURVES, criterion="motor")
    assert e.value.field == ("criterion",)
