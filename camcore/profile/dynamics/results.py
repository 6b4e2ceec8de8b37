"""What the dynamics of a force-closed follower answers: a table over the cam angle and a
summary over the whole turn (each a result dataclass, served as it is).

References
----------
.. [1] Norton, *Cam Design and Manufacturing Handbook*: contact force, follower jump and
   camshaft torque of a force-closed cam-follower system.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ...curves.base import FloatArray
from ...results import doc, table_columns

#: the unit of each lift column, by the lift's unit (mm: translating, deg: oscillating)
LIFT_UNITS = {"mm": ("mm", "mm/s", "mm/s²", "N"), "deg": ("deg", "deg/s", "deg/s²", "N·m")}


@dataclass(frozen=True)
class DynamicsTable:
    """Columns over the cam angle at the given speed (the lift columns in the follower's unit:
    mm, mm/s, mm/s² for a translating follower; deg, deg/s, deg/s² of swing for an oscillating one)."""

    cam_angle_deg: FloatArray = field(metadata=doc("cam angle θ [deg]"))
    time_s: FloatArray = field(metadata=doc("t = θ/ω from cam angle 0 [s]"))
    lift: FloatArray = field(metadata=doc("lift s [mm] (translating) or swing ψ [deg] (oscillating)"))
    velocity: FloatArray = field(metadata=doc("ds/dt = ω·ds/dθ [mm/s] or dψ/dt [deg/s]"))
    acceleration: FloatArray = field(metadata=doc("d²s/dt² = ω²·d²s/dθ² [mm/s²] or d²ψ/dt² [deg/s²]"))
    spring_force: FloatArray = field(metadata=doc(
        "spring force k·s + F0 [N] (translating) or spring torque about the pivot k·ψ + T0 [N·m] (oscillating)"))
    contact_force_n: FloatArray = field(metadata=doc(
        "the cam's force on the follower along the follower's motion, m·a + c·v + k·s + F0 + F_ext (rigid "
        "follower); oscillating: the torque about the pivot over the lever arm of the follower point (the arm "
        "length, or the contact's distance from the pivot along a flat face); negative = the follower has left "
        "the cam [N]"))
    normal_force_n: FloatArray = field(metadata=doc("contact_force_n / cos φ, along the common normal [N]"))
    camshaft_torque_nm: FloatArray = field(metadata=doc(
        "the torque the camshaft must supply, by virtual work: contact force × ds/dθ (translating, ds/dθ in "
        "m/rad) or the pivot torque × dψ/dθ (oscillating); negative where the follower drives the cam [N·m]"))
    contact_stress_mpa: FloatArray | None = field(default=None, metadata=doc(
        "with roller: the Hertz line-contact pressure p0 of the roller on the cam surface, 0 where the contact "
        "force is ≤ 0 [MPa]"))
    contact_torque_nm: FloatArray | None = field(default=None, metadata=doc(
        "oscillating follower: the cam's torque on the arm about its pivot, I·ψ̈ + c·ψ̇ + k·ψ + T0 + T_ext [N·m]"))

    def columns(self) -> dict[str, FloatArray]:
        """The columns, by name, leaving out those that do not apply (None)."""
        return {name: value for name, value in table_columns(self).items() if value is not None}


@dataclass(frozen=True)
class DynamicsSummary:
    """Figures over the whole cam turn, exact: extremes refined between the lift's break points,
    not read off the sampled table."""

    speed_rpm: float = field(metadata=doc("camshaft speed N [rpm]"))
    safety_margin_n: float = field(metadata=doc("the contact force the follower must keep [N]"))
    min_contact_force_n: float = field(metadata=doc("smallest contact force over the turn [N]"))
    min_contact_force_at_deg: float = field(metadata=doc("where [deg]"))
    separates: bool = field(metadata=doc(
        "the contact force falls below the safety margin somewhere at this speed (the follower jumps); a minimum "
        "within 1e-12 of the largest force of the margin counts as meeting it (rounding)"))
    jump_speed_rpm: float | None = field(metadata=doc(
        "the lowest camshaft speed at which the contact force first falls to the safety margin, damping "
        "included (relative accuracy 1e-9); 0 when the spring cannot hold the follower even at rest; null when no "
        "speed does: only a lift that never decelerates, i.e. a cam without motion (a closed lift decelerates "
        "somewhere, and there the inertia force grows with ω² past any spring)"))
    jump_at_deg: float | None = field(metadata=doc("where the contact force first falls to the margin, at the jump "
                                                   "speed [deg]"))
    min_preload_n: float | None = field(metadata=doc(
        "translating follower: the smallest spring preload F0 that keeps the contact force at or above the margin "
        "at this speed (may be negative) [N]"))
    min_preload_nm: float | None = field(metadata=doc(
        "oscillating follower: the smallest spring preload torque T0 that keeps the margin at this speed [N·m]"))
    max_normal_force_n: float = field(metadata=doc("largest normal force over the turn [N]"))
    max_normal_force_at_deg: float = field(metadata=doc("where [deg]"))
    peak_camshaft_torque_nm: float = field(metadata=doc("largest |camshaft torque| over the turn [N·m]"))
    peak_camshaft_torque_at_deg: float = field(metadata=doc("where [deg]"))
    max_camshaft_torque_nm: float = field(metadata=doc("largest camshaft torque (driving) [N·m]"))
    max_camshaft_torque_at_deg: float = field(metadata=doc("where [deg]"))
    min_camshaft_torque_nm: float = field(metadata=doc(
        "smallest camshaft torque (signed; negative: the follower drives the cam back) [N·m]"))
    min_camshaft_torque_at_deg: float = field(metadata=doc("where [deg]"))
    rms_camshaft_torque_nm: float = field(metadata=doc(
        "root mean square of the camshaft torque over one turn (= over time at constant speed) [N·m]"))
    max_contact_stress_mpa: float | None = field(metadata=doc("with roller: largest Hertz pressure [MPa]"))
    max_contact_stress_at_deg: float | None = field(metadata=doc("with roller: where [deg]"))
    effective_modulus_mpa: float | None = field(metadata=doc(
        "with roller: E*, 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2 [MPa]"))


@dataclass(frozen=True)
class FollowerDynamics:
    """The table and the summary of one follower at one speed."""

    unit: str
    table: DynamicsTable
    summary: DynamicsSummary
