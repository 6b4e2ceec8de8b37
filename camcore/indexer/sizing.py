"""Torque and power to index a load: the exact power balance and the catalog short form.

References
----------
.. [1] INDEXMAN technical guide, section 5 (a = (h/th²)·A, characteristic values Qm, Am),
   section 2 (n = 360/ψ), 计算分度精度 (accuracy).
.. [2] Power balance of a lossless cam drive: input torque × input speed = output torque ×
   output speed, so T_in = (dθout/dθin)·T_out = (h/θh)·V'(T)·T_out(T). The catalog short
   form replaces the peak of V'·A' by Qm·Am (Q = A·V/Am, section 5 characteristic table).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .._checks import non_negative
from ..curves.base import FloatArray
from ..curves.curve import Curve
from ..curves.extrema import power_balance_peaks
from ..errors import InvalidParameterError
from .drive import Cycle, Motor, TorqueLaw, cycle_rms, motor_scale, torque_table
from .kinematics import Indexer, index_scales, indexing_time_s
from .load import Load
from .results import Sizing
from .timing import TimedIndexer


def accuracy_mm(arc_seconds: ArrayLike, radius_mm: ArrayLike) -> Any:
    """Angular indexing accuracy converted to a length at a radius.

    Parameters
    ----------
    arc_seconds : float or array_like
        Angular error θ (may be signed, ±) [arcsec].
    radius_mm : float or array_like
        Radius r at which the error is measured (≥ 0) [mm].

    Returns
    -------
    float or ndarray
        Arc length x = 2π·r·θ/(360·60·60) [mm]; a float for scalar input.

    References
    ----------
    INDEXMAN technical guide, 计算分度精度 (last table): x = 2πr·θ/(360×60×60)
    = 0.00000485·r·θ; e.g. 90″ at 300 mm → 0.131 mm.
    """
    theta = np.asarray(arc_seconds, dtype=np.float64)
    r = np.asarray(radius_mm, dtype=np.float64)
    if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(r))):
        raise InvalidParameterError("arc_seconds and radius_mm must be finite numbers.")
    if np.any(r < 0):
        raise InvalidParameterError("radius_mm must be 0 or more.")
    x = 2.0 * math.pi * r * theta / (360.0 * 3600.0)
    return float(x) if x.ndim == 0 else x


@dataclass(frozen=True)
class _Peaks:
    """What sizing needs of the motion, one entry per sizing: peak |α| [rad/s²] and |ω|
    [rad/s], the catalog's Qm [-], and the power balance's max and min (f [N·m], input angle
    [deg], T) before the service factor."""

    alpha_max: FloatArray
    omega_max: FloatArray
    qm: FloatArray
    driving: tuple[FloatArray, FloatArray, FloatArray]
    braking: tuple[FloatArray, FloatArray, FloatArray]
    coefficients: tuple[FloatArray, FloatArray]  # c1, c2 of f = c1·V·A + c2·V (a curve's rows)


def _curve_peaks(curve: Curve, h_deg: FloatArray, theta_h_deg: FloatArray, rpm: FloatArray, inertia: float,
                 resisting: float) -> _Peaks:
    """Indexes along one curve (one per entry of the arrays):
    f(T) = (h/θh)·V'·[I·(h/th²)·A' + Tf + Tw]."""
    ch = curve.characteristics
    d_t, d_s = curve.t_end - curve.t_start, curve.s_end - curve.s_start
    kv, ka, _ = index_scales(np.radians(h_deg), indexing_time_s(theta_h_deg, rpm), d_t, d_s)
    ratio = np.radians(h_deg) / np.radians(theta_h_deg)  # h/θh, output/input angle
    # with V' = V·ΔT/ΔS, I·(h/th²)·A' = I·ka·A
    c1 = ratio * d_t / d_s * inertia * ka
    c2 = ratio * d_t / d_s * resisting
    f_max, t_max, f_min, t_min = power_balance_peaks(curve, c1, c2)

    def angle(t: FloatArray) -> FloatArray:
        return np.asarray(theta_h_deg * (t - curve.t_start) / d_t, dtype=np.float64)

    return _Peaks(alpha_max=np.abs(ka) * ch.am, omega_max=np.abs(kv) * ch.vm.value,
                  qm=np.full(f_max.shape, ch.qm_pos.value * d_t / abs(d_s)),
                  driving=(f_max, angle(t_max), t_max), braking=(f_min, angle(t_min), t_min),
                  coefficients=(np.atleast_1d(c1), np.atleast_1d(c2)))


def _chart_peaks(indexer: TimedIndexer, inertia: float, resisting: float) -> _Peaks:
    """A timing chart: f(x) = s′·[I·α(x) + (Tf + Tw)·sgn s′] (friction and work resist the motion
    both ways); Qm generalised as (θh/h)·max(s′·s″)/max|s″|, which is the curve's Qm+ for a
    chart of one index."""
    ch = indexer.program.characteristics
    kv, ka, _ = indexer.scales
    a_peak = max(abs(ch.a_max), abs(ch.a_min))
    driving, braking = indexer.power_balance_peaks(inertia * ka, resisting)
    (va_max, _, _), _ = indexer.power_balance_peaks(1.0, 0.0)

    def one(value: float) -> FloatArray:
        return np.array([value], dtype=np.float64)

    return _Peaks(alpha_max=one(ka * a_peak), omega_max=one(kv * ch.v_peak),
                  qm=one(indexer.indexing_angle_deg / indexer.displacement_deg * va_max / a_peak),
                  driving=(one(driving[0]), one(driving[1]), one(driving[2])),
                  braking=(one(braking[0]), one(braking[1]), one(braking[2])),
                  coefficients=(one(inertia * ka), one(resisting)))


#: the fields of :class:`Sizing` that depend on the design (what :func:`_figures` gives, what a
#: sweep answers per row)
FIGURE_FIELDS = ("alpha_max_rad_s2", "omega_max_rad_s", "inertia_torque_nm", "output_torque_nm",
                 "design_output_torque_nm", "input_torque_nm", "input_torque_t", "input_torque_input_angle_deg",
                 "input_torque_time_s", "input_torque_pos_nm", "input_torque_pos_t", "input_torque_neg_nm",
                 "input_torque_neg_t", "input_torque_catalog_nm", "qm", "input_power_kw", "input_power_catalog_kw",
                 "speed_rpm")


def _figures(peaks: _Peaks, load: Load, stops: FloatArray, theta_h_deg: FloatArray,
             rpm: FloatArray) -> dict[str, FloatArray]:
    """The sizing figures from the peaks, one entry per sizing (the fields of :class:`Sizing`
    that depend on the motion)."""
    inertia = load.output_inertia_kgm2
    tf = load.output_friction_torque_nm
    tw = load.output_work_torque_nm
    fc = float(load.service_factor)
    eta = float(load.efficiency)
    ti = inertia * peaks.alpha_max
    tt = ti + tf + tw
    (f_max, x_max, t_max), (f_min, x_min, t_min) = peaks.driving, peaks.braking
    # the driving peak governs unless the braking peak is larger by more than rounding
    # (for a symmetric curve without friction the two are equal up to the last bits)
    braking = np.abs(f_min) > np.abs(f_max) * (1.0 + 1e-12)
    x_peak = np.where(braking, x_min, x_max)
    t_in = fc * np.where(braking, np.abs(f_min), np.abs(f_max))
    t_cat = 360.0 / (stops * theta_h_deg) * peaks.qm * fc * tt
    w_in = 2.0 * np.pi * rpm / 60.0
    values = (peaks.alpha_max, peaks.omega_max, ti, tt, fc * tt, t_in, np.where(braking, t_min, t_max), x_peak,
              x_peak / (6.0 * rpm), fc * f_max, t_max, fc * f_min, t_min, t_cat, peaks.qm,
              w_in * t_in / eta / 1000.0, w_in * t_cat / eta / 1000.0, np.broadcast_to(rpm, t_in.shape))
    return dict(zip(FIGURE_FIELDS, values, strict=True))


def size(
    indexer: Indexer | TimedIndexer,
    load: Load,
    accuracy_arc_seconds: float | None = None,
    accuracy_radius_mm: float | None = None,
    *,
    internal_friction_torque_nm: float = 0.0,
    motor: Motor | None = None,
    table_samples: int = 181,
) -> Sizing:
    """Output and input torque and input power needed to index a load.

    Parameters
    ----------
    indexer : Indexer or TimedIndexer
        The indexer: curve, angles and speed; or a timing chart and speed (the peaks over the
        whole chart, friction and work torque resisting the motion in either direction).
    load : Load
        What the output drives: inertia, friction, work torque, service factor, efficiency.
    accuracy_arc_seconds, accuracy_radius_mm : float, optional
        If both are given, ``accuracy_mm`` = :func:`accuracy_mm` of them [arcsec, mm].
    internal_friction_torque_nm : float
        Tᵢ, the unit's own friction on the input shaft while it turns (≥ 0) [N·m]; in the
        torque table, the RMS and the motor figures, not in ``input_torque_nm``.
    motor : Motor, optional
        A motor to check (:mod:`.drive`).
    table_samples : int
        Rows of the torque table over each index [-].

    Returns
    -------
    Sizing
        - ``alpha_max_rad_s2`` = (h/th²)·Am (h in rad, Am = max|A|)
        - ``inertia_torque_nm`` Ti = I·α_max; ``output_torque_nm`` Tt = Ti + Tf + Tw;
          ``design_output_torque_nm`` = fc·Tt
        - ``input_torque_nm`` = fc·max over T of |(h/θh)·V'(T)·[I·(h/th²)·A'(T) + Tf + Tw]|,
          the exact peak of the power balance T_in·ω_in = T_out·ω_out (h/θh is the
          output/input angle ratio), with its T, input angle and time
        - ``input_torque_catalog_nm`` = 360/(n·θh)·Qm·fc·Tt (catalog short form,
          Qm = the curve's Qm+)
        - ``input_power_kw`` = 2π·N·T_in/60/η/1000; ``input_power_catalog_kw`` the same
          with the catalog torque.

    Notes
    -----
    With Tf = Tw = 0 the exact peak is fc·(h/θh)·I·(h/th²)·max(V·A) = fc·(h/θh)·Ti·Qm,
    which is the catalog form: the two agree. Friction and work torque act at the
    velocity peak (V up to Vm ≈ 1.76 for MS) while the catalog weights them with Qm
    (≈ 0.99), so with large Tf or Tw the catalog form underestimates.

    References
    ----------
    INDEXMAN technical guide, section 5 (a = (h/th²)·A, characteristic values Qm, Am);
    section 2 (n = 360/ψ); 计算分度精度 (accuracy). Power balance of a lossless drive.
    """
    if not isinstance(indexer, Indexer | TimedIndexer):
        raise InvalidParameterError("size() needs an Indexer or a TimedIndexer as its first argument.")
    if not isinstance(load, Load):
        raise InvalidParameterError("size() needs a Load as its second argument.")
    resisting = load.output_friction_torque_nm + load.output_work_torque_nm
    inertia = load.output_inertia_kgm2
    if isinstance(indexer, TimedIndexer):
        peaks = _chart_peaks(indexer, inertia, resisting)
    else:
        peaks = _curve_peaks(indexer.curve, np.array([indexer.displacement_deg]),
                             np.array([indexer.indexing_angle_deg]), np.array([indexer.rpm]), inertia, resisting)
    figures: dict[str, Any] = {name: float(value[0]) for name, value in _figures(
        peaks, load, np.array([indexer.n]), np.array([indexer.indexing_angle_deg]), np.array([indexer.rpm])).items()}
    acc = None
    if accuracy_arc_seconds is not None and accuracy_radius_mm is not None:
        acc = float(accuracy_mm(accuracy_arc_seconds, accuracy_radius_mm))
    internal = non_negative("internal_friction_torque_nm", internal_friction_torque_nm)
    cycle = _cycle(indexer, peaks)
    fc = float(load.service_factor)
    g = load.gear_ratio
    drive: dict[str, Any] = {"gear_ratio": g, "dial_inertia_kgm2": load.total_inertia_kgm2,
             "dial_displacement_deg": indexer.displacement_deg / g,
             "dial_omega_max_rad_s": figures["omega_max_rad_s"] / g,
             "dial_alpha_max_rad_s2": figures["alpha_max_rad_s2"] / g,
             "internal_friction_torque_nm": internal, "dwell_output_torque_nm": load.dwell_torque_nm / g,
             "rms_input_torque_nm": cycle_rms(cycle, fc, internal),
             "machine_cycle_time_s": cycle.cycle_s, "input_torque_table": torque_table(cycle, fc, internal, table_samples)}
    if motor is not None:
        drive |= _motor_check(motor, load, cycle, figures, internal, indexer.rpm, indexer.input_speed_rad_s)
    return Sizing(inertia_kgm2=inertia, mass_kg=load.mass_kg, friction_torque_nm=load.output_friction_torque_nm,
                  work_torque_nm=load.output_work_torque_nm, service_factor=fc, efficiency=float(load.efficiency),
                  accuracy_mm=acc, **figures, **drive)


def machine_cycle(indexer: Indexer | TimedIndexer, load: Load) -> Cycle:
    """The input torque laws of one machine cycle at the indexer's speed, as :func:`size` makes them.

    Parameters
    ----------
    indexer : Indexer or TimedIndexer
        The indexer at its speed.
    load : Load
        What the output drives.

    Returns
    -------
    Cycle
        f = c1·V·A + c2·V per moving stretch (input torque before the service factor and the
        internal friction, :mod:`.drive`).

    References
    ----------
    INDEXMAN technical guide, section 5; the power balance T_in·ω_in = T_out·ω_out.
    """
    resisting = load.output_friction_torque_nm + load.output_work_torque_nm
    inertia = load.output_inertia_kgm2
    if isinstance(indexer, TimedIndexer):
        return _cycle(indexer, _chart_peaks(indexer, inertia, resisting))
    return _cycle(indexer, _curve_peaks(indexer.curve, np.array([indexer.displacement_deg]),
                                        np.array([indexer.indexing_angle_deg]), np.array([indexer.rpm]), inertia,
                                        resisting))


def _cycle(indexer: Indexer | TimedIndexer, peaks: _Peaks) -> Cycle:
    """The machine cycle's torque laws: one index of a curve (twice for an oscillating unit's
    out and back strokes, which need the same torque), or each moving segment of a chart."""
    if isinstance(indexer, TimedIndexer):
        inertia_ka, resisting = float(peaks.coefficients[0][0]), float(peaks.coefficients[1][0])
        laws = [TorqueLaw(law.curve, inertia_ka * law.gain**2 * law.rate**3, resisting * abs(law.gain) * law.rate,
                          law.x_a, law.span, signed_friction=True)
                for law in indexer.program.placed if law.curve is not None]
        return Cycle(laws, 360.0, indexer.dwells * float(indexer.input_stop_time_s), indexer.rpm)
    law = TorqueLaw(indexer.curve, float(peaks.coefficients[0][0]), float(peaks.coefficients[1][0]), 0.0,
                    indexer.indexing_angle_deg, signed_friction=False)
    return Cycle([law], 360.0 / indexer.dwells, float(indexer.input_stop_time_s), indexer.rpm,
                 repeats=2 if indexer.swing_angle_deg is not None else 1)


def _motor_check(motor: Motor, load: Load, cycle: Cycle, figures: dict[str, float], internal: float, rpm: float,
                 input_speed_rad_s: float) -> dict[str, Any]:
    """The motor's speed, peak and RMS torque (every efficiency applied), inertia ratio, use and verdict."""
    scale = motor_scale(motor, float(load.efficiency))
    fc = float(load.service_factor)
    extremes = np.array([figures["input_torque_pos_nm"] + internal, figures["input_torque_neg_nm"] + internal,
                         internal])
    peak = float(np.abs(scale(extremes)).max())
    rms = cycle_rms(cycle, fc, internal, scale)
    speed = rpm * motor.reduction_ratio
    # the load's inertia seen at the motor: I·(dθout/dθin)²/i², largest where the output is fastest
    ratio = load.output_inertia_kgm2 * (figures["omega_max_rad_s"] / input_speed_rad_s) ** 2 \
        / motor.reduction_ratio**2 / motor.rotor_inertia_kgm2
    reasons = []
    if peak > motor.peak_torque_nm:
        reasons.append(f"the peak torque {peak:.4g} N·m exceeds the motor's peak torque {motor.peak_torque_nm:.4g} N·m")
    if rms > motor.rated_torque_nm:
        reasons.append(f"the RMS torque {rms:.4g} N·m exceeds the motor's rated torque {motor.rated_torque_nm:.4g} N·m")
    if speed > motor.max_speed_rpm:
        reasons.append(f"the motor speed {speed:.4g} rpm exceeds its maximum {motor.max_speed_rpm:.4g} rpm")
    return {"motor_speed_rpm": speed, "motor_peak_torque_nm": peak, "motor_rms_torque_nm": rms,
            "inertia_ratio": ratio, "peak_utilisation": peak / motor.peak_torque_nm,
            "rms_utilisation": rms / motor.rated_torque_nm, "motor_ok": not reasons,
            "motor_reason": "; ".join(reasons) or None}
