"""Drives (camcore.indexer.drive through size()): the torque over the machine cycle, its RMS,
the dial behind a gear, the motor check.

The RMS is checked against an independent integration: the input torque rebuilt from the
indexer's own motion table (Indexer.motion_at: dθout/dθin and α, not the drive's torque
laws), T_in = fc·(dθout/dθin)·(I·α + Tf + Tw) + Tᵢ, integrated by composite Simpson over
400 001 input angles of the index, plus Tᵢ² over the dwell and 0 over the input stop.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from camcore.indexer import Indexer, Load, LoadPart, Motor, size
from camcore.results import as_dict

#: the guide's sizing example: a 50 kg disc of Ø600 mm, μ = 0.1 at 200 mm, service factor 1.5
LOAD = Load(parts=[LoadPart(shape="disc", mass_kg=50, diameter_mm=600)], friction_coefficient=0.1,
            friction_radius_mm=200, work_torque_nm=5, service_factor=1.5)
GUIDE = Indexer(stops=6, indexing_angle_deg=270, speed_rpm=60, curve="MS", input_stop_time_s=0.25)


def simpson(y: np.ndarray, dx: float) -> float:
    return float(dx / 3 * (y[0] + y[-1] + 4 * y[1:-1:2].sum() + 2 * y[2:-1:2].sum()))


@pytest.mark.parametrize("curve", ["MS", "MCV50", "cycloid", "TR"])
def test_rms_against_an_independent_integration(curve: str) -> None:
    unit = Indexer(stops=6, indexing_angle_deg=270, speed_rpm=60, curve=curve, input_stop_time_s=0.25)
    internal = 2.0
    result = size(unit, LOAD, internal_friction_torque_nm=internal)
    x = np.linspace(0, 270, 400_001)
    table = unit.motion_at(x)
    torque = LOAD.service_factor * table.dout_din * (
        LOAD.total_inertia_kgm2 * table.alpha_rad_s2 + LOAD.total_friction_torque_nm + LOAD.work_torque_nm) + internal
    seconds_per_deg = 1 / (6 * 60)
    square = simpson(torque**2, x[1] - x[0]) * seconds_per_deg + internal**2 * 90 * seconds_per_deg
    cycle = 1.0 + 0.25  # t0 = 60/N = 1 s, plus the input stop
    # Simpson's error: h⁴·max|f⁗|/180 per unit length on each smooth piece, O(h²) where the
    # jerk of the curve jumps (T² has a kink in its second derivative there): with h =
    # 6.75e-4° that is below 1e-9 relative; 1e-8 leaves room for it and for nothing else
    assert result.rms_input_torque_nm == pytest.approx(math.sqrt(square / cycle), rel=1e-8)
    assert result.machine_cycle_time_s == cycle
    # the table samples the index every 1.5°: its largest row is at most the exact peak plus the
    # internal friction, and near it (the torque is flat at its peak: a relative 1e-3 is
    # ~f″·(0.75°)²/2 with room)
    assert result.input_torque_table is not None
    peak = result.input_torque_nm + internal
    assert peak * (1 - 1e-3) < result.input_torque_table.input_torque_nm.max() <= peak * (1 + 1e-15)


def test_internal_friction_alone_gives_its_share_of_the_cycle() -> None:
    # no load: the input carries Tᵢ while it turns (1 s) and nothing while it stands (0.25 s)
    result = size(GUIDE, Load(service_factor=1), internal_friction_torque_nm=3.0)
    assert result.rms_input_torque_nm == pytest.approx(3.0 * math.sqrt(1.0 / 1.25), rel=1e-14)
    assert result.input_torque_nm == 0.0  # the catalog's lossless input torque leaves it out


def test_a_dial_behind_a_2_to_1_belt_is_the_reflected_load_at_the_output() -> None:
    # g = 2 output turns per dial turn: I/g² and T/g at the output shaft
    geared = Load(parts=LOAD.parts, friction_coefficient=0.1, friction_radius_mm=200, work_torque_nm=5,
                  gear_ratio=2, dwell_torque_nm=40)
    direct = Load(inertia_kgm2=LOAD.total_inertia_kgm2 / 4, friction_torque_nm=LOAD.total_friction_torque_nm / 2,
                  work_torque_nm=2.5)
    ours, theirs = as_dict(size(GUIDE, geared)), as_dict(size(GUIDE, direct))
    for name, value in theirs.items():
        if name in ("mass_kg", "gear_ratio", "dial_inertia_kgm2", "dial_displacement_deg", "dial_omega_max_rad_s",
                    "dial_alpha_max_rad_s2", "dwell_output_torque_nm", "input_torque_table") or value is None:
            continue
        assert ours[name] == pytest.approx(value, rel=1e-14), name
    assert ours["dial_inertia_kgm2"] == LOAD.total_inertia_kgm2 and ours["dwell_output_torque_nm"] == 20
    assert ours["dial_displacement_deg"] == 30 and ours["dial_omega_max_rad_s"] == ours["omega_max_rad_s"] / 2


def test_a_motor_that_passes_and_one_that_fails_on_rms_only() -> None:
    # 10:1 reduction at 95 %, unit efficiency 0.9: driving torque at the motor T/(10·0.9·0.95)
    load = Load(parts=LOAD.parts, friction_coefficient=0.1, friction_radius_mm=200, efficiency=0.9)
    base = size(GUIDE, load, internal_friction_torque_nm=1.0,
                motor=Motor(rated_torque_nm=100, peak_torque_nm=100, rotor_inertia_kgm2=1e-3, max_speed_rpm=3000,
                            reduction_ratio=10, reduction_efficiency=0.95))
    assert base.motor_ok is True and base.motor_reason is None
    assert base.motor_speed_rpm == 600
    assert base.motor_peak_torque_nm == pytest.approx((base.input_torque_nm + 1.0) / (10 * 0.9 * 0.95), rel=1e-12)
    # the inertia ratio: I·(ω_max/ω_in)²/i² over the rotor
    w_in = 2 * math.pi
    assert base.inertia_ratio == pytest.approx(
        LOAD.total_inertia_kgm2 * (base.omega_max_rad_s / w_in) ** 2 / 100 / 1e-3, rel=1e-12)
    assert base.motor_rms_torque_nm is not None and base.motor_peak_torque_nm is not None
    rated = 0.9 * base.motor_rms_torque_nm
    failing = size(GUIDE, load, internal_friction_torque_nm=1.0,
                   motor=Motor(rated_torque_nm=rated, peak_torque_nm=2 * base.motor_peak_torque_nm,
                               rotor_inertia_kgm2=1e-3, max_speed_rpm=3000, reduction_ratio=10,
                               reduction_efficiency=0.95))
    assert failing.motor_ok is False and failing.motor_reason is not None
    assert "RMS" in failing.motor_reason and "peak" not in failing.motor_reason
    assert failing.rms_utilisation == pytest.approx(1 / 0.9, rel=1e-12)
    assert failing.peak_utilisation == pytest.approx(0.5, rel=1e-12)


def test_an_oscillating_unit_runs_out_and_back_in_its_cycle() -> None:
    # ψ = 60°: the back stroke needs the same torque as the out stroke (module notes), so the
    # RMS equals the rotary unit's with h = 60° and the table holds both strokes
    swing = Indexer(swing_angle_deg=60, indexing_angle_deg=270, speed_rpm=60, curve="MS", input_stop_time_s=0.25)
    ours, theirs = size(swing, LOAD), size(GUIDE, LOAD)
    assert ours.rms_input_torque_nm == pytest.approx(theirs.rms_input_torque_nm, rel=1e-14)
    assert ours.machine_cycle_time_s == 2 * theirs.machine_cycle_time_s
    assert ours.input_torque_table is not None and theirs.input_torque_table is not None
    assert ours.input_torque_table.time_s[-1] == pytest.approx(2.5, rel=1e-15)
    assert len(ours.input_torque_table.time_s) == 2 * len(theirs.input_torque_table.time_s)


def bisect_zero(fn, lo: float, hi: float) -> float:
    """A sign change of fn in [lo, hi], by plain bisection to the float resolution."""
    f_lo = fn(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if (fn(mid) > 0) == (f_lo > 0):
            lo, f_lo = mid, fn(mid)
        else:
            hi = mid
    return 0.5 * (lo + hi)


def test_motor_rms_is_split_where_the_input_torque_changes_sign() -> None:
    """The motor's torque kinks where the input torque (with internal friction) is zero:
    T/(i·η·η_r) driving, T·η·η_r/i braking. The RMS must split there, not where the load's
    torque alone is zero. Independent: the motion table (Indexer.motion_at), the zero found by
    bisection on it, and composite Simpson on each side (200 001 points each)."""
    load = Load(parts=LOAD.parts, friction_coefficient=0.02, friction_radius_mm=200, efficiency=0.8)
    internal, i, eta_r = 4.0, 10.0, 0.9
    motor = Motor(rated_torque_nm=100, peak_torque_nm=100, rotor_inertia_kgm2=1e-3, max_speed_rpm=3000,
                  reduction_ratio=i, reduction_efficiency=eta_r)
    result = size(GUIDE, load, internal_friction_torque_nm=internal, motor=motor)

    def torque(x: np.ndarray) -> np.ndarray:
        table = GUIDE.motion_at(np.atleast_1d(x))
        return load.service_factor * table.dout_din * (
            load.total_inertia_kgm2 * table.alpha_rad_s2 + load.total_friction_torque_nm) + internal

    def at_motor(t: np.ndarray) -> np.ndarray:
        losses = 0.8 * eta_r
        return np.where(t >= 0, t / (i * losses), t * losses / i)

    x = np.linspace(0, 270, 20_001)
    sign = np.sign(torque(x))
    cells = np.nonzero(sign[:-1] * sign[1:] < 0)[0]
    # braking in the second half of the index: the input torque crosses zero twice there
    assert cells.size == 2
    zeros = [bisect_zero(lambda u: float(torque(np.array([u]))[0]), x[c], x[c + 1]) for c in cells]
    edges = [0.0, *zeros, 270.0]
    square = 0.0
    for a, b in itertools.pairwise(edges):
        xs = np.linspace(a, b, 200_001)
        square += simpson(at_motor(torque(xs)) ** 2, xs[1] - xs[0])
    seconds_per_deg = 1 / (6 * 60)
    square = (square + at_motor(np.array([internal]))[0] ** 2 * 90) * seconds_per_deg
    # smooth on each side of the splits: Simpson's h⁴ error is far below 1e-10 with h ≤ 1e-3°;
    # splitting where the load's torque alone is zero (as before issue 21) was off by 4.2e-7 here
    assert result.motor_rms_torque_nm == pytest.approx(math.sqrt(square / 1.25), rel=1e-10)
