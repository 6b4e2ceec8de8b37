"""What a machine answers: the figures at one camshaft speed, the speed limits, the rules.

References
----------
.. [1] Norton, *Design of Machinery*, chapter "Flywheels": E = ∫(T − T̄)dθ, ΔE, Cs, I = ΔE/(Cs·ω²).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..results import doc
from .rules import RuleResult


@dataclass(frozen=True)
class MotorFigures:
    """The drive's motor on the camshaft's total torque (through the gear and its efficiencies)."""

    motor_speed_rpm: float = field(metadata=doc("camshaft speed × gear ratio × the motor's reduction [rpm]"))
    peak_torque_nm: float = field(metadata=doc(
        "largest |motor torque| without a flywheel (a stiff drive carries the total torque as it comes) [N·m]"))
    rms_torque_nm: float = field(metadata=doc("RMS motor torque over the cycle without a flywheel [N·m]"))
    peak_torque_with_flywheel_nm: float | None = field(metadata=doc(
        "with the flywheel: the largest |motor torque| when the motor carries the mean torque plus the part of the "
        "fluctuation the flywheel does not absorb (motor torque falling with speed by its slip) [N·m]"))
    rms_torque_with_flywheel_nm: float | None = field(metadata=doc("the same, RMS [N·m]"))
    speed_fluctuation_with_motor: float | None = field(metadata=doc(
        "Cs of that model, (ω_max − ω_min)/ω (the motor's droop takes up part of ΔE) [-]"))
    reflected_rotor_inertia_kgm2: float = field(metadata=doc("the rotor's inertia on the camshaft, J·i² [kg·m²]"))
    motor_ok: bool = field(metadata=doc("peak, RMS (with the flywheel when there is one) and speed within the motor's"))
    motor_reason: str | None = field(metadata=doc("what is exceeded, when something is"))


@dataclass(frozen=True)
class MachineSummary:
    """The camshaft's total torque over one turn at one speed, the flywheel and the motor."""

    speed_rpm: float = field(metadata=doc("camshaft speed N [rpm]"))
    cycle_time_s: float = field(metadata=doc("one camshaft turn, 60/N [s]"))
    peak_total_nm: float = field(metadata=doc("largest |total torque| over the turn (exact, refined) [N·m]"))
    peak_total_at_deg: float = field(metadata=doc("where [deg of master angle]"))
    max_total_nm: float = field(metadata=doc("largest total torque (driving) [N·m]"))
    max_total_at_deg: float = field(metadata=doc("where [deg]"))
    min_total_nm: float = field(metadata=doc("smallest total torque (negative: the axes drive the camshaft) [N·m]"))
    min_total_at_deg: float = field(metadata=doc("where [deg]"))
    rms_total_nm: float = field(metadata=doc("root mean square over the turn (= over time at constant speed) [N·m]"))
    mean_total_nm: float = field(metadata=doc("T̄, the work per turn over 2π [N·m]"))
    work_per_cycle_j: float = field(metadata=doc("∫T dθ over one turn [J]"))
    energy_fluctuation_j: float = field(metadata=doc("ΔE = max E − min E, E(x) = ∫₀ˣ (T − T̄) dθ [J]"))
    energy_max_at_deg: float = field(metadata=doc("where E is largest (the camshaft fastest) [deg]"))
    energy_min_at_deg: float = field(metadata=doc("where E is smallest (the camshaft slowest) [deg]"))
    system_inertia_kgm2: float | None = field(metadata=doc(
        "the inertia on the camshaft (everything that turns with it, flywheel included) that keeps the requested "
        "speed fluctuation: ΔE/(Cs·ω²); or the given one [kg·m²]"))
    flywheel_inertia_kgm2: float | None = field(metadata=doc(
        "the flywheel itself: the system inertia less the motor's rotor reflected to the camshaft (0 when the rotor "
        "alone is enough) [kg·m²]"))
    speed_fluctuation: float | None = field(metadata=doc(
        "Cs = (ω_max − ω_min)/ω = ΔE/(I·ω²): requested, or left by the given inertia [-]"))
    motor: MotorFigures | None = field(metadata=doc("with a drive's motor: its check"))


@dataclass(frozen=True)
class AxisLimit:
    """One axis's first failure speed."""

    axis: str = field(metadata=doc("the axis's name, or drive for the motor"))
    speed_rpm: float | None = field(metadata=doc("camshaft speed at which it first fails; null: never [rpm]"))
    reason: str = field(metadata=doc("what fails"))
    at_deg: float | None = field(metadata=doc("where on the master angle it fails first, when it is one place [deg]"))


@dataclass(frozen=True)
class SpeedLimits:
    """How fast the machine can run: each axis's limit and the smallest."""

    axes: tuple[AxisLimit, ...] = field(metadata=doc("per axis (and the drive), its first failure speed"))
    machine_top_speed_rpm: float | None = field(metadata=doc("the smallest of them; null: no limit found [rpm]"))
    axis: str | None = field(metadata=doc("which axis sets it"))
    reason: str | None = field(metadata=doc("and why"))
    runs_within_limits: bool = field(metadata=doc("the machine's speed is at or below its top speed"))


@dataclass(frozen=True)
class AxisReport:
    """One axis: what it is, its stroke, its torque on the camshaft and its own operation's checks."""

    name: str = field(metadata=doc("the axis's name"))
    kind: str = field(metadata=doc("plate_cam, barrel_cam, indexer or motion"))
    unit: str = field(metadata=doc("its position's unit: mm or deg"))
    phase_deg: float = field(metadata=doc("φ: master angle of its own 0 [deg]"))
    peak_torque_nm: float = field(metadata=doc("largest |camshaft torque| of this axis (exact, refined) [N·m]"))
    peak_torque_at_deg: float = field(metadata=doc("where [deg of master angle]"))
    rms_torque_nm: float = field(metadata=doc("RMS of its camshaft torque over the turn [N·m]"))
    mean_torque_nm: float = field(metadata=doc("its mean camshaft torque (its work per turn over 2π) [N·m]"))
    checks: dict[str, Any] = field(metadata=doc(
        "its own operation's figures at this speed: plate_cam {dynamics, profile} as computeFollowerDynamics and "
        "computeProfile report them; barrel_cam {barrel} as computeBarrelCam; indexer {sizing} as sizeIndexer; "
        "motion {characteristics} as computeMotion"))


@dataclass(frozen=True)
class MachineResult:
    """Everything a machine answers at its speed (the timing and torque columns are separate)."""

    summary: MachineSummary
    axes: tuple[AxisReport, ...]
    speed_limits: SpeedLimits
    rules: tuple[RuleResult, ...]
    sweep: tuple[MachineSummary, ...]
