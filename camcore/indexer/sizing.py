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

from ..curves.curve import Curve
from ..curves.extrema import peaks_of
from ..errors import InvalidParameterError
from .kinematics import Indexer
from .load import Load
from .results import Sizing
from .timing import TimedIndexer


def _power_balance_peaks(curve: Curve, c1: float, c2: float) -> tuple[float, float, float, float]:
    """Exact max and min over [T0, T7] of f(T) = c1·V·A + c2·V, with the T of each.

    Candidates are each piece's ends (one-sided) and the roots of
    f' = c1·(J·V + A²) + c2·A, from :meth:`Curve.critical_points`. Ties: earliest T.
    """
    # f' = c1·(J·V + A²) + c2·A: its roots and the piece ends are where f can peak
    t_all, k_all = curve.critical_points(lambda d: c1 * (d[3] * d[1] + d[2] * d[2]) + c2 * d[2])
    _, v, a = curve.eval_pieces(t_all, k_all, 2)
    top, bottom = peaks_of(t_all, np.asarray(c1 * v * a + c2 * v, dtype=np.float64))
    return top.value, top.t, bottom.value, bottom.t


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
    """What sizing needs of the motion: peak |α| [rad/s²] and |ω| [rad/s], the catalog's Qm [-],
    and the power balance's max and min (f [N·m], input angle [deg], T) before the service factor."""

    alpha_max: float
    omega_max: float
    qm: float
    driving: tuple[float, float, float]
    braking: tuple[float, float, float]


def _curve_peaks(indexer: Indexer, inertia: float, resisting: float) -> _Peaks:
    """One index along one curve: f(T) = (h/θh)·V'·[I·(h/th²)·A' + Tf + Tw]."""
    c = indexer.curve
    ch = c.characteristics
    d_t, d_s = indexer.spans
    kv, ka, _ = indexer.scales
    ratio = indexer.displacement_rad / math.radians(indexer.indexing_angle_deg)  # h/θh, output/input angle
    # with V' = V·ΔT/ΔS, I·(h/th²)·A' = I·ka·A
    c1 = ratio * d_t / d_s * inertia * ka
    c2 = ratio * d_t / d_s * resisting
    f_max, t_max, f_min, t_min = _power_balance_peaks(c, c1, c2)
    return _Peaks(alpha_max=abs(ka) * ch.am, omega_max=abs(kv) * ch.vm.value, qm=ch.qm_pos.value * d_t / abs(d_s),
                  driving=(f_max, float(indexer.angle_of_t(t_max)), t_max),
                  braking=(f_min, float(indexer.angle_of_t(t_min)), t_min))


def _chart_peaks(indexer: TimedIndexer, inertia: float, resisting: float) -> _Peaks:
    """A timing chart: f(x) = s′·[I·α(x) + (Tf + Tw)·sgn s′] (friction and work resist the motion
    both ways); Qm generalised as (θh/h)·max(s′·s″)/max|s″|, which is the curve's Qm+ for a
    chart of one index."""
    ch = indexer.program.characteristics
    kv, ka, _ = indexer.scales
    a_peak = max(abs(ch.a_max), abs(ch.a_min))
    driving, braking = indexer.power_balance_peaks(inertia * ka, resisting)
    (va_max, _, _), _ = indexer.power_balance_peaks(1.0, 0.0)
    return _Peaks(alpha_max=ka * a_peak, omega_max=kv * ch.v_peak,
                  qm=indexer.indexing_angle_deg / indexer.displacement_deg * va_max / a_peak, driving=driving, braking=braking)


def size(
    indexer: Indexer | TimedIndexer,
    load: Load,
    accuracy_arc_seconds: float | None = None,
    accuracy_radius_mm: float | None = None,
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
    inertia = load.total_inertia_kgm2
    tf = load.total_friction_torque_nm
    tw = float(load.work_torque_nm)
    peaks = _chart_peaks(indexer, inertia, tf + tw) if isinstance(indexer, TimedIndexer) else \
        _curve_peaks(indexer, inertia, tf + tw)
    ti = inertia * peaks.alpha_max
    tt = ti + tf + tw
    fc = float(load.service_factor)
    eta = float(load.efficiency)
    (f_max, x_max, t_max), (f_min, x_min, t_min) = peaks.driving, peaks.braking
    # the driving peak governs unless the braking peak is larger by more than rounding
    # (for a symmetric curve without friction the two are equal up to the last bits)
    braking = abs(f_min) > abs(f_max) * (1.0 + 1e-12)
    x_peak, t_peak = (x_min, t_min) if braking else (x_max, t_max)
    t_in = fc * (abs(f_min) if braking else abs(f_max))
    t_cat = 360.0 / (indexer.n * indexer.indexing_angle_deg) * peaks.qm * fc * tt
    w_in = indexer.input_speed_rad_s
    acc = None
    if accuracy_arc_seconds is not None and accuracy_radius_mm is not None:
        acc = float(accuracy_mm(accuracy_arc_seconds, accuracy_radius_mm))
    return Sizing(
        inertia_kgm2=inertia,
        mass_kg=load.mass_kg,
        alpha_max_rad_s2=peaks.alpha_max,
        omega_max_rad_s=peaks.omega_max,
        inertia_torque_nm=ti,
        friction_torque_nm=tf,
        work_torque_nm=tw,
        output_torque_nm=tt,
        design_output_torque_nm=fc * tt,
        service_factor=fc,
        efficiency=eta,
        input_torque_nm=t_in,
        input_torque_t=t_peak,
        input_torque_input_angle_deg=x_peak,
        input_torque_time_s=x_peak / (6.0 * indexer.rpm),
        input_torque_pos_nm=fc * f_max,
        input_torque_pos_t=t_max,
        input_torque_neg_nm=fc * f_min,
        input_torque_neg_t=t_min,
        input_torque_catalog_nm=t_cat,
        qm=peaks.qm,
        input_power_kw=w_in * t_in / eta / 1000.0,
        input_power_catalog_kw=w_in * t_cat / eta / 1000.0,
        speed_rpm=indexer.rpm,
        accuracy_mm=acc,
    )
