"""Results of the indexer computations, each defined once (the service serves them).

References
----------
.. [1] INDEXMAN technical guide, sections 2, 3 and 5 (times, peaks, torques).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..results import doc, table_columns
from .drive import TorqueTable

FloatArray = NDArray[np.float64]


# --------------------------------------------------------------------------- results
@dataclass(frozen=True)
class MotionSummary:
    """Times and exact peaks of one index (field names as in docs/api.md, /v1/indexers/motion).

    Peaks come from the curve's closed-form characteristic values, not from a sampled
    table; ``*_input_angle_deg`` [deg] and ``*_time_s`` [s] say where (from the start of
    the index) each first occurs.
    """

    indexing_time_s: float = field(metadata=doc("th = (θh/360)·(60/N) [s]"))
    cycle_time_s: float = field(metadata=doc("unit cycle time t0 = 60/(N·z) [s]"))
    dwell_time_s: float = field(metadata=doc("t2 = t0 − th [s]"))
    machine_cycle_time_s: float = field(metadata=doc("tm = t0 + ts [s]"))
    displacement_deg: float = field(metadata=doc("h = 360/n or ψ [deg]"))
    stops: float = field(metadata=doc("n (360/ψ for oscillating units, may be fractional)"))
    indexing_angle_deg: float = field(metadata=doc("θh [deg]"))
    total_indexing_angle_deg: float = field(metadata=doc("θt = θh·z [deg]"))
    dwell_angle_deg: float = field(metadata=doc("input angle of one dwell, 360/z − θh [deg]"))
    dwells: int = field(metadata=doc("z"))
    speed_rpm: float = field(metadata=doc("N [rpm]"))
    omega_rad_s: float = field(metadata=doc("largest |ω| [rad/s]"))
    omega_input_angle_deg: float
    omega_time_s: float
    alpha_rad_s2: float = field(metadata=doc("largest |α| [rad/s²]"))
    alpha_pos_rad_s2: float = field(metadata=doc("largest α [rad/s²]"))
    alpha_pos_input_angle_deg: float
    alpha_pos_time_s: float
    alpha_neg_rad_s2: float = field(metadata=doc("most negative α (signed) [rad/s²]"))
    alpha_neg_input_angle_deg: float
    alpha_neg_time_s: float
    jerk_rad_s3: float = field(metadata=doc("largest |jerk| [rad/s³]"))
    jerk_pos_rad_s3: float
    jerk_pos_input_angle_deg: float
    jerk_pos_time_s: float
    jerk_neg_rad_s3: float
    jerk_neg_input_angle_deg: float
    jerk_neg_time_s: float

@dataclass(frozen=True)
class MotionTable:
    """Output motion over the input angle (columns of equal length).

    ``dout_din`` = dθout/dθin [-] and ``d2out_din2_per_rad`` = d²θout/dθin² [1/rad] are
    the motion over input angle (independent of speed); the rest is over time.
    """

    input_angle_deg: FloatArray = field(metadata=doc("from the start of the index [deg]"))
    time_s: FloatArray = field(metadata=doc("from the start of the index [s]"))
    output_angle_deg: FloatArray = field(metadata=doc("from the start position [deg]"))
    omega_rad_s: FloatArray
    alpha_rad_s2: FloatArray
    jerk_rad_s3: FloatArray
    dout_din: FloatArray
    d2out_din2_per_rad: FloatArray

    def columns(self) -> dict[str, FloatArray]:
        return table_columns(self)


@dataclass(frozen=True)
class IndexerMotion:
    """Result of :meth:`Indexer.motion`: the ``summary`` and the ``table``."""

    summary: MotionSummary
    table: MotionTable


@dataclass(frozen=True)
class IndexerPosition:
    """Result of :meth:`Indexer.position` (field names as in docs/api.md, /v1/indexers/position).

    ``t``, ``v``, ``a`` are the curve's dimensionless T, V, A at each output angle (as
    found by the chosen method; for the table method they are interpolated).
    """

    output_angle_deg: FloatArray
    input_angle_deg: FloatArray = field(metadata=doc("θh·u [deg]"))
    time_s: FloatArray = field(metadata=doc("th·u [s]"))
    omega_rad_s: FloatArray = field(metadata=doc("(h/th)·V' [rad/s]"))
    alpha_rad_s2: FloatArray = field(metadata=doc("(h/th²)·A' [rad/s²]"))
    t: FloatArray
    v: FloatArray
    a: FloatArray
    method: str = field(metadata={"internal": True})

    def columns(self) -> dict[str, FloatArray]:
        return table_columns(self)




@dataclass(frozen=True)
class Sizing:
    """Result of :func:`size` (field names as in docs/api.md, /v1/indexers/sizing).

    Torques [N·m], power [kW], inertia [kg·m²], α [rad/s²]. ``input_torque_nm`` is the
    service-factored peak of |T_in| over the index (the larger of the driving peak
    ``input_torque_pos_nm`` and the braking peak ``input_torque_neg_nm``, signed; a tie
    within 1e-12 relative goes to the driving peak); ``input_torque_t`` is the curve's T
    where it occurs (for the catalog curves, T = the fraction of the index).
    """

    inertia_kgm2: float
    mass_kg: float
    alpha_max_rad_s2: float
    omega_max_rad_s: float
    inertia_torque_nm: float
    friction_torque_nm: float
    work_torque_nm: float
    output_torque_nm: float
    design_output_torque_nm: float
    service_factor: float
    efficiency: float
    input_torque_nm: float
    input_torque_t: float
    input_torque_input_angle_deg: float
    input_torque_time_s: float
    input_torque_pos_nm: float
    input_torque_pos_t: float
    input_torque_neg_nm: float
    input_torque_neg_t: float
    input_torque_catalog_nm: float
    qm: float
    input_power_kw: float
    input_power_catalog_kw: float
    speed_rpm: float
    accuracy_mm: float | None = None
    # drives: the dial behind a gear, the whole machine cycle, the motor
    gear_ratio: float = field(default=1.0, metadata=doc("g, output-shaft turns per dial turn"))
    dial_inertia_kgm2: float = field(default=0.0, metadata=doc(
        "the dial's own inertia (inertia_kgm2 is it at the output shaft, /g²) [kg·m²]"))
    dial_displacement_deg: float = field(default=0.0, metadata=doc("the dial's travel per index, h/g [deg]"))
    dial_omega_max_rad_s: float = field(default=0.0, metadata=doc("the dial's peak |ω| [rad/s]"))
    dial_alpha_max_rad_s2: float = field(default=0.0, metadata=doc("the dial's peak |α| [rad/s²]"))
    internal_friction_torque_nm: float = field(default=0.0, metadata=doc(
        "the unit's own friction on the input shaft while it turns, as given [N·m]"))
    dwell_output_torque_nm: float = field(default=0.0, metadata=doc(
        "the torque the output holds during the dwell (dwell_torque_nm/g) [N·m]"))
    rms_input_torque_nm: float = field(default=0.0, metadata=doc(
        "RMS of the input torque over the machine cycle (index, dwell, input stop; fc applied to the load, "
        "internal friction added; lossless as input_torque_nm) [N·m]"))
    machine_cycle_time_s: float = field(default=0.0, metadata=doc(
        "the cycle of the torque table and the RMS: index, dwell and input stop (both strokes of an "
        "oscillating unit; one input turn of a timing chart) [s]"))
    input_torque_table: TorqueTable | None = field(default=None, metadata=doc("the input torque over the machine cycle"))
    motor_speed_rpm: float | None = field(default=None, metadata=doc("with motor: N·i [rpm]"))
    motor_peak_torque_nm: float | None = field(default=None, metadata=doc(
        "with motor: peak |torque| at the motor, every efficiency applied [N·m]"))
    motor_rms_torque_nm: float | None = field(default=None, metadata=doc(
        "with motor: RMS torque at the motor over the machine cycle, every efficiency applied [N·m]"))
    inertia_ratio: float | None = field(default=None, metadata=doc(
        "with motor: the load's largest inertia seen at the motor, I·(dθout/dθin)²max/i², over the rotor's [-]"))
    peak_utilisation: float | None = field(default=None, metadata=doc("with motor: motor peak torque / its peak rating"))
    rms_utilisation: float | None = field(default=None, metadata=doc("with motor: motor RMS torque / its rated torque"))
    motor_ok: bool | None = field(default=None, metadata=doc("with motor: peak, RMS and speed within its ratings"))
    motor_reason: str | None = field(default=None, metadata=doc("with motor: why not, when not ok"))

