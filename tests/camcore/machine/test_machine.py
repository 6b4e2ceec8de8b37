"""Machines (camcore.machine): several axes on one camshaft.

Every figure is checked against a closed form derived here or against an independent route:

* two identical cycloid cams (rise 180°, return 180°) have the inertia torque
  T = m·ω²·s'·s'' = m·ω²·(2h²/π²)·(sin 2θ − ½ sin 4θ) over the whole turn (the return's s' and s''
  both change sign), so phased 180° apart the torques add, and phased 90° apart the sin 2θ halves
  cancel and the total is −(2m·ω²·h²/π²)·sin 4θ, ΔE = m·ω²·h²/π²;
* a torque T0·sin θ (a constant force on a harmonic lift over the turn) has E = T0·(1 − cos θ),
  ΔE = 2·T0, and the flywheel I = ΔE/(Cs·ω²) (Norton, *Design of Machinery*, "Flywheels");
* one axis answers what its own computation does (follower dynamics, the indexer's sizing);
* speed limits: at the limit speed the axis's own computation meets its limit;
* the motor with a flywheel carries 1/(1 + iλ) of each harmonic (the periodic solution of a first-order
  drive), so a pure sine is carried with amplitude T0/√(1 + λ²) and phase −atan λ;
* a rule's violations and phase slack against a dense scan of the same rule.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from camcore import named_curve
from camcore.errors import InvalidParameterError
from camcore.indexer import Indexer, Load, LoadPart, Motor, size
from camcore.machine import (
    Condition,
    Drive,
    DrivenLoad,
    Flywheel,
    IndexerAxis,
    LiftLoadAxis,
    Machine,
    PlateCamAxis,
    Rule,
)
from camcore.machine.rules import check_rule
from camcore.motion import Law, MotionSegment, MotionSpec, resolve_motion
from camcore.profile import Follower, Segment, make_cam
from camcore.profile.dynamics import RollerMaterials, TranslatingLoad, follower_dynamics
from camcore.profile.lift import MotionLift

CYCLOID = named_curve("cycloid")
H_MM = 20.0
MASS_KG = 2.0
N_RPM = 300.0
OMEGA = 2 * math.pi * N_RPM / 60
LOAD = Load(parts=[LoadPart(shape="disc", mass_kg=50, diameter_mm=600)], friction_coefficient=0.1,
            friction_radius_mm=200, service_factor=1.5)


def cycloid_motion(name: str, phase: float, *, mass: float = MASS_KG, force: float = 0.0, law: str = "cycloid",
                   efficiency: float = 1.0) -> LiftLoadAxis:
    """A slave rising h over 180° and returning over 180° by ``law``, driving a mass and a force."""
    rise, back = Law("named", {"name": law}), Law("named", {"name": law}, "return")
    program = resolve_motion(MotionSpec([MotionSegment(180, H_MM, law=rise), MotionSegment(180, 0.0, law=back)]))
    return LiftLoadAxis(name, phase, MotionLift(program), "mm", DrivenLoad(mass, 0.0, force, efficiency), "motion", {})


def plate(name: str = "cam", phase: float = 0.0, **kw: object) -> PlateCamAxis:
    cam = make_cam(Follower("roller", roller_radius_mm=10.0), 40.0, segments=[
        Segment("rise", 120, H_MM, curve=named_curve("MS")), Segment("dwell", 60),
        Segment("return", 120, H_MM, curve=CYCLOID), Segment("dwell", 60)])
    return PlateCamAxis(name, phase, cam, TranslatingLoad(0.5, 2.0, 30.0), **kw)  # type: ignore[arg-type]


def inertia_torque(theta: np.ndarray) -> np.ndarray:
    """m·ω²·s'·s'' of the cycloid rise/return of h over 180° each, in SI (closed form, module notes)."""
    h = H_MM * 1e-3
    return MASS_KG * OMEGA**2 * (2 * h * h / math.pi**2) * (np.sin(2 * theta) - 0.5 * np.sin(4 * theta))


X_DEG = np.linspace(0.0, 360.0, 1441)


def test_two_cycloid_cams_180_apart_add_and_90_apart_cancel_their_sin_2theta_halves() -> None:
    theta = np.radians(X_DEG)
    amplitude = MASS_KG * OMEGA**2 * (H_MM * 1e-3) ** 2 / math.pi**2  # m·ω²·h²/π² [N·m]
    apart_180 = Machine([cycloid_motion("a", 0), cycloid_motion("b", 180)])
    total = apart_180.torque_columns(X_DEG, N_RPM)["total_nm"]
    # the closed form's own rounding: a few ulp of the amplitude (2.2e-16 × ~10 terms)
    np.testing.assert_allclose(total, 2 * inertia_torque(theta), rtol=0, atol=1e-13 * amplitude)
    apart_90 = Machine([cycloid_motion("a", 0), cycloid_motion("b", 90)])
    columns = apart_90.torque_columns(X_DEG, N_RPM)
    np.testing.assert_allclose(columns["total_nm"], -2 * amplitude * np.sin(4 * theta), rtol=0, atol=1e-13 * amplitude)
    summary = apart_90.summary(N_RPM)
    # exact figures of −2A·sin 4θ: peak 2A (at 22.5°, 112.5°, ...), mean 0, RMS 2A/√2, ΔE = A/2·2 = A
    assert summary.peak_total_nm == pytest.approx(2 * amplitude, rel=1e-12)
    assert summary.mean_total_nm == pytest.approx(0.0, abs=1e-13 * amplitude)
    assert summary.rms_total_nm == pytest.approx(2 * amplitude / math.sqrt(2), rel=1e-12)
    assert summary.energy_fluctuation_j == pytest.approx(amplitude, rel=1e-12)
    assert math.isclose(summary.peak_total_at_deg % 90.0, 67.5, abs_tol=1e-6) or math.isclose(
        summary.peak_total_at_deg % 90.0, 22.5, abs_tol=1e-6)


def test_a_pure_sine_torque_has_delta_e_two_t0_and_its_flywheel() -> None:
    # a harmonic lift h·(1 − cos θ)/2 against a constant force F: T = F·s' = F·(h/2)·sin θ (η = 1, no mass)
    force_n = 500.0
    t0 = force_n * H_MM * 1e-3 / 2
    axis = cycloid_motion("sine", 0, mass=0.0, force=force_n, law="simple-harmonic")
    np.testing.assert_allclose(Machine([axis]).torque_columns(X_DEG, N_RPM)["total_nm"],
                               t0 * np.sin(np.radians(X_DEG)), rtol=0, atol=1e-13 * t0)
    cs = 0.02
    summary = Machine([axis], flywheel=Flywheel(speed_fluctuation=cs)).summary(N_RPM)
    assert summary.energy_fluctuation_j == pytest.approx(2 * t0, rel=1e-12)
    assert summary.system_inertia_kgm2 == pytest.approx(2 * t0 / (cs * OMEGA**2), rel=1e-12)
    assert summary.energy_min_at_deg == pytest.approx(0.0, abs=1e-6) or summary.energy_min_at_deg == pytest.approx(
        360.0, abs=1e-6)
    assert summary.energy_max_at_deg == pytest.approx(180.0, abs=1e-6)
    given = Machine([axis], flywheel=Flywheel(inertia_kgm2=3.0)).summary(N_RPM)
    assert given.speed_fluctuation == pytest.approx(2 * t0 / (3.0 * OMEGA**2), rel=1e-12)


def test_the_motor_with_a_flywheel_carries_each_harmonic_as_a_first_order_drive() -> None:
    force_n = 500.0
    t0 = force_n * H_MM * 1e-3 / 2
    axis = cycloid_motion("sine", 0, mass=0.0, force=force_n, law="simple-harmonic")
    motor = Motor(rated_torque_nm=2.0, peak_torque_nm=6.0, rotor_inertia_kgm2=1e-4, max_speed_rpm=6000)
    drive = Drive(motor, gear_ratio=10.0, efficiency=1.0, slip=0.05)
    inertia = 0.2
    m = Machine([axis], flywheel=Flywheel(inertia_kgm2=inertia), drive=drive)
    summary = m.summary(N_RPM)
    system = inertia + 1e-4 * 100
    c = 10.0 * 2.0 / (0.05 * OMEGA)  # the motor's slope on the camshaft [N·m·s/rad]
    lam = system * OMEGA / c
    carried = t0 / math.sqrt(1 + lam * lam)  # the first harmonic's amplitude on the camshaft
    assert summary.motor is not None
    # at the motor: /10 (gear), η = 1; the FFT of a pure harmonic is exact to rounding
    # the peak read on 32768 angles of the trigonometric interpolant: within (π/32768)²/2 = 4.6e-9 of it
    assert summary.motor.peak_torque_with_flywheel_nm == pytest.approx(carried / 10, rel=5e-9)
    assert summary.motor.rms_torque_with_flywheel_nm == pytest.approx(carried / 10 / math.sqrt(2), rel=1e-9)
    assert summary.motor.peak_torque_nm == pytest.approx(t0 / 10, rel=1e-12)  # stiff: the total as it comes
    # the speed fluctuation the droop leaves: Δω = −(T_m − T̄)/c, so Cs = (2·carried/c)/ω, below ΔE/(I·ω²)
    assert summary.motor.speed_fluctuation_with_motor == pytest.approx(2 * carried / (c * OMEGA), rel=1e-9)
    assert summary.motor.speed_fluctuation_with_motor < summary.speed_fluctuation  # type: ignore[operator]


def test_one_plate_cam_axis_is_its_own_follower_dynamics() -> None:
    axis = plate(safety_margin_n=5.0)
    m = Machine([axis])
    own = follower_dynamics(axis.cam, axis.load, N_RPM, 361, safety_margin_n=5.0)
    x = np.linspace(0.0, 360.0, 361)
    assert np.array_equal(m.torque_columns(x, N_RPM)["cam_nm"], own.table.camshaft_torque_nm)
    report = m.axis_reports(N_RPM)[0]
    assert report.checks["dynamics"] == dataclasses.asdict(follower_dynamics(
        axis.cam, axis.load, N_RPM, 2, safety_margin_n=5.0).summary)
    # both refine the same function's extreme between grid points to 1e-9 rad: the same value to rounding
    assert report.peak_torque_nm == pytest.approx(own.summary.peak_camshaft_torque_nm, rel=1e-13)
    # Gauss-Legendre on 0.5° cells here, 1° there: both exact far below 1e-12 for these smooth pieces
    assert report.rms_torque_nm == pytest.approx(own.summary.rms_camshaft_torque_nm, rel=1e-12)
    limits = m.speed_limits(N_RPM)
    assert limits.machine_top_speed_rpm == own.summary.jump_speed_rpm
    assert limits.axis == "cam" and "jump" in (limits.reason or "")


def test_one_indexer_axis_is_its_own_sizing() -> None:
    unit = Indexer(stops=6, indexing_angle_deg=120, speed_rpm=N_RPM)
    axis = IndexerAxis("table", 0.0, unit, LOAD, internal_friction_torque_nm=1.5)
    sized = size(unit, LOAD, internal_friction_torque_nm=1.5, table_samples=181)
    table = sized.input_torque_table
    assert table is not None
    inside = table.input_angle_deg < 120.0  # the index's rows (the dwell's rows are the internal friction)
    own = np.radians(table.input_angle_deg[inside])
    # the same expression at the same input angle, reached through radians and back: an ulp of the angle apart
    np.testing.assert_allclose(axis.torque(own, OMEGA), table.input_torque_nm[inside], rtol=0,
                               atol=1e-13 * np.abs(table.input_torque_nm).max())
    assert np.all(axis.torque(np.radians(np.array([130.0, 200.0, 359.0])), OMEGA) == 1.5)
    report = Machine([axis]).axis_reports(N_RPM)[0]
    # the sizing's exact peak is fc·max|f|; the machine's adds the internal friction on the same stretch
    assert report.peak_torque_nm == pytest.approx(sized.input_torque_nm + 1.5, rel=1e-12)
    # RMS over the whole turn: the sizing's own (no input stop time), to quadrature rounding
    assert report.rms_torque_nm == pytest.approx(sized.rms_input_torque_nm, rel=1e-10)


def test_an_indexer_geared_twice_per_turn_torques_twice_as_often_and_twice_as_much() -> None:
    slow = Indexer(stops=6, indexing_angle_deg=120, speed_rpm=2 * N_RPM)
    axis = IndexerAxis("table", 30.0, slow, LOAD, ratio=2)
    x = np.linspace(0.0, 360.0, 721)
    own = np.radians(np.mod(2 * (x - 30.0), 360.0))
    expected = 2 * IndexerAxis("t", 0.0, slow, LOAD).torque(own, 2 * OMEGA)
    np.testing.assert_allclose(Machine([axis]).torque_columns(x, N_RPM)["table_nm"], expected, rtol=1e-12,
                               atol=1e-12 * np.abs(expected).max())


def test_top_speed_limits_meet_their_limits() -> None:
    roller = RollerMaterials(width_mm=8.0)
    # 197 MPa at rest, 192 at 300 rpm, 215 at 600 (the inertia first relieves the contact, then loads it)
    axis = plate(roller=roller, allowed_stress_mpa=205.0)
    limit = axis.speed_limit()
    assert limit.speed_rpm is not None and "Hertz" in limit.reason
    at = follower_dynamics(axis.cam, axis.load, limit.speed_rpm, 2, roller=roller).summary
    assert at.max_contact_stress_mpa == pytest.approx(205.0, rel=1e-9)  # the quadratic's root, refined to 1e-9 rad
    below = follower_dynamics(axis.cam, axis.load, 0.999 * limit.speed_rpm, 2, roller=roller).summary
    assert below.max_contact_stress_mpa < 205.0  # type: ignore[operator]
    assert limit.speed_rpm < follower_dynamics(axis.cam, axis.load, 100.0, 2).summary.jump_speed_rpm  # type: ignore[operator]

    unit = Indexer(stops=6, indexing_angle_deg=120, speed_rpm=60)
    table = IndexerAxis("table", 0.0, unit, LOAD, rated_output_torque_nm=300.0)
    rpm = table.speed_limit().speed_rpm
    assert rpm is not None
    at_limit = size(Indexer(stops=6, indexing_angle_deg=120, speed_rpm=rpm), LOAD)
    assert at_limit.design_output_torque_nm == pytest.approx(300.0, rel=1e-12)


def test_the_motor_limit_is_where_its_peak_torque_is_reached() -> None:
    motor = Motor(rated_torque_nm=50.0, peak_torque_nm=2.0, rotor_inertia_kgm2=1e-4, max_speed_rpm=1e5)
    m = Machine([cycloid_motion("a", 0), cycloid_motion("b", 45)], drive=Drive(motor, gear_ratio=5.0, efficiency=0.9))
    limits = m.speed_limits(N_RPM)
    peak = [lim for lim in limits.axes if "peak torque" in lim.reason]
    assert len(peak) == 1 and peak[0].speed_rpm is not None
    figures = m.summary(peak[0].speed_rpm).motor
    assert figures is not None
    # the search takes the peak on a grid of every quadrature node (0.06°): its own 1e-6 of the refined peak
    assert figures.peak_torque_nm == pytest.approx(2.0, rel=2e-6)
    assert limits.machine_top_speed_rpm == peak[0].speed_rpm and limits.axis == "drive"
    assert limits.runs_within_limits is (peak[0].speed_rpm >= N_RPM)


def dense_holds(machine: Machine, rule: Rule, step_deg: float = 0.01) -> tuple[bool, np.ndarray]:
    """The rule on a dense grid of the master angle, condition by condition (independent of rules.py)."""
    x = np.arange(0.0, 360.0, step_deg)

    def holds(c: Condition) -> np.ndarray:
        axis = machine.by_name[c.axis]
        own = axis.own(np.radians(x))
        if c.moving is not None:
            _, v, _ = axis.derivatives_per_deg(own)
            return (np.abs(v) > 1e-12) == c.moving
        p = axis.position(own)
        return p <= c.at_most if c.at_most is not None else p >= c.at_least  # type: ignore[operator]

    broken = holds(rule.when) & ~holds(rule.require)
    return not broken.any(), x[broken]


def test_rule_violations_match_a_dense_scan() -> None:
    table = IndexerAxis("table", 200.0, Indexer(stops=6, indexing_angle_deg=120, speed_rpm=60), LOAD)
    m = Machine([plate("feed"), table])
    rule = Rule(Condition("table", moving=True), Condition("feed", at_most=2.0))
    result = check_rule(rule, m.by_name)
    ok, where = dense_holds(m, rule)
    assert result.holds is ok is False
    assert len(result.violations) == 1
    v = result.violations[0]
    # every broken grid point lies in the reported stretch, and the stretch's ends are within a grid step of them
    assert where.min() >= v.from_deg - 1e-9 and where.max() <= v.to_deg + 1e-9
    assert where.min() - v.from_deg < 0.01 and v.to_deg - where.max() < 0.01
    feed = m.by_name["feed"]
    worst = feed.position(feed.own(np.radians(where))).max() - 2.0
    assert v.depth == pytest.approx(worst, abs=1e-3)  # the reported depth is sampled at 257 points in the stretch


@pytest.mark.parametrize("side", ["later", "earlier"])
def test_phase_slack_is_the_distance_to_the_first_violation_of_a_dense_scan(side: str) -> None:
    table = IndexerAxis("table", 305.0, Indexer(stops=6, indexing_angle_deg=45, speed_rpm=60), LOAD)
    rule = Rule(Condition("table", moving=True), Condition("feed", at_most=2.0))
    result = check_rule(rule, Machine([plate("feed"), table]).by_name)
    assert result.holds
    slack = result.slack_later_deg if side == "later" else result.slack_earlier_deg
    assert slack is not None and slack > 1.0
    sign = 1.0 if side == "later" else -1.0
    feed = plate("feed")

    def holds(delta: float) -> bool:
        feed.phase_deg = (sign * delta) % 360.0
        return dense_holds(Machine([feed, table]), rule)[0]

    # a coarse scan for the first broken shift, then a fine one over the coarse step before it
    coarse = next(d for d in np.arange(0.0, slack + 2.0, 0.25) if not holds(d))
    first_broken = next(d for d in np.arange(max(coarse - 0.25, 0.0), coarse + 0.01, 0.01) if not holds(d))
    # the scan's own resolution: its step in phase and the grid's step in master angle (0.01° each)
    assert abs(first_broken - slack) <= 0.02


def test_a_rule_on_standing_still_has_exact_edges() -> None:
    pusher = cycloid_motion("pusher", 0.0)
    table = IndexerAxis("table", 0.0, Indexer(stops=8, indexing_angle_deg=90, speed_rpm=60), LOAD)
    result = check_rule(Rule(Condition("table", moving=True), Condition("pusher", moving=False)),
                        Machine([pusher, table]).by_name)
    # the pusher never stands still: the whole index (0°-90° of the master) breaks the rule, exactly
    assert not result.holds and [(v.from_deg, v.to_deg, v.depth) for v in result.violations] == [(0.0, 90.0, 90.0)]


def test_bad_machines_are_refused_naming_the_field() -> None:
    unit = Indexer(stops=6, indexing_angle_deg=120, speed_rpm=60)
    with pytest.raises(InvalidParameterError, match="whole number") as e:
        IndexerAxis("t", 0.0, unit, LOAD, ratio=1.5)  # type: ignore[arg-type]
    assert e.value.field == ("ratio",)
    with pytest.raises(InvalidParameterError, match="input cannot stand still"):
        IndexerAxis("t", 0.0, Indexer(stops=6, indexing_angle_deg=120, speed_rpm=60, input_stop_time_s=0.2), LOAD)
    with pytest.raises(InvalidParameterError, match="must be even"):
        IndexerAxis("t", 0.0, Indexer(swing_angle_deg=90, indexing_angle_deg=120, speed_rpm=60), LOAD)
    with pytest.raises(InvalidParameterError, match="not an axis") as e:
        Machine([plate("feed")], [Rule(Condition("table", moving=True), Condition("feed", at_most=1.0))])
    assert e.value.field == ("rules", 0, "while", "axis")
    with pytest.raises(InvalidParameterError, match="unique"):
        Machine([plate("feed"), plate("feed")])
    with pytest.raises(InvalidParameterError, match="needs the roller"):
        plate(allowed_stress_mpa=500.0)
    with pytest.raises(InvalidParameterError, match="exactly one"):
        Flywheel(speed_fluctuation=0.1, inertia_kgm2=1.0)
    with pytest.raises(InvalidParameterError, match="efficiency"):
        DrivenLoad(1.0, efficiency=1.5)
