"""Residual vibration of an indexer's load on a torsionally elastic drive train.

The output shaft follows the cam exactly; between it and the load inertia I sits the drive
train's torsional stiffness k (shaft, coupling, the table's own compliance), with damping
ratio ζ. The load's error x = y − s (its angle minus the cam's output angle) obeys the
follower equation of :mod:`camcore.dynamics.vibration`, I·(ẍ + s̈) = −k·x − c·ẋ, so

    ωn = √(k/I),  fn = ωn/2π,  τ = th·fn,  s = h·S(t/th)   (h the index, th the indexing time)

and x = h·X(t/th). During the index the error is the response to the cam's acceleration;
after it, a free vibration whose envelope A·e^{−ζωn·t} (A the residual amplitude, the
contract's √(x² + ((ẋ + ζωn·x)/ωd)²)) decays to the tolerance ε after
t_s = ln(A/ε)/(ζωn): the settling time. Undamped (ζ = 0) with A > ε it never settles.
Each index is taken to start from rest (the previous one settled).

Angles here are in arc-seconds [arcsec]: h = 3600·(360/n) for n stops.

References
----------
.. [1] M. P. Koster, *Vibrations of Cam Mechanisms* (1974): the single-degree-of-freedom
   model and its residual vibration (docs/sources.md).
.. [2] INDEXMAN technical guide, sections 2, 3 and 5 (h = 360/n, th = (θh/360)·(60/N), the
   dwell t0 − th, the input stop ts); camcore.indexer.kinematics.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from .._checks import count, positive
from ..errors import InvalidParameterError
from ..indexer.kinematics import Indexer
from ..results import doc, table_columns
from .vibration import TAU_MAX, TAU_MIN, FollowerResponse, check_damping

FloatArray = NDArray[np.float64]
T = TypeVar("T")


@dataclass(frozen=True)
class VibrationTable:
    """The load's angular error over one index and the dwell that follows it."""

    time_s: FloatArray = field(metadata=doc("time from the start of the index [s]"))
    output_error_arcsec: FloatArray = field(metadata=doc(
        "the load's angle minus the cam's output angle, x = y − s [arcsec]"))

    def columns(self) -> dict[str, FloatArray]:
        """The table's columns by name."""
        return table_columns(self)


@dataclass(frozen=True)
class IndexerVibration:
    """Residual vibration of an indexer's load (docs/api.md, computeIndexerVibration)."""

    inertia_kgm2: float = field(metadata=doc("load inertia I [kg·m²]"))
    stiffness_nm_rad: float = field(metadata=doc("torsional stiffness k from the output shaft to the load [N·m/rad]"))
    damping_ratio: float = field(metadata=doc("ζ [-]"))
    natural_frequency_hz: float = field(metadata=doc("fn = √(k/I)/2π [1/s]"))
    tau: float = field(metadata=doc("τ = th·fn, the indexing time over the natural period [-]"))
    indexing_time_s: float = field(metadata=doc("th [s]"))
    dwell_time_s: float = field(metadata=doc(
        "time the output stands still before the next index, t0 − th + ts (the input's stop included) [s]"))
    displacement_arcsec: float = field(metadata=doc("h, the index [arcsec]"))
    residual_amplitude_arcsec: float = field(metadata=doc(
        "amplitude of the vibration left when the index ends, √(x² + ((ẋ + ζωn·x)/ωd)²) at th [arcsec]"))
    peak_error_arcsec: float = field(metadata=doc("largest |x| during the index [arcsec]"))
    tolerance_arcsec: float = field(metadata=doc("ε, the error allowed at the dwell [arcsec]"))
    settling_time_s: float | None = field(metadata=doc(
        "after the index ends, until the envelope A·e^{−ζωn·t} stays within ε: ln(A/ε)/(ζωn), 0 when "
        "A ≤ ε; null when it never does (ζ = 0 and A > ε) [s]"))
    settles_within_dwell: bool = field(metadata=doc("settling_time_s ≤ dwell_time_s"))
    table: VibrationTable = field(metadata={"internal": True, **doc("the error over the index and the dwell")})


def _located(check: Callable[[str, Any], T], name: str, value: Any) -> T:
    """``check(name, value)`` with its error located at the argument ``name``."""
    try:
        return check(name, value)
    except InvalidParameterError as exc:
        raise InvalidParameterError(str(exc), field=(name,)) from None


def indexer_vibration(indexer: Indexer, inertia_kgm2: float, stiffness_nm_rad: float, damping_ratio: float = 0.0,
                      tolerance_arcsec: float = 10.0, samples: int = 501) -> IndexerVibration:
    """Natural frequency, τ, residual amplitude and settling time of an indexer's load.

    Parameters
    ----------
    indexer : Indexer
        The unit (its curve, normalised, drives the load over th).
    inertia_kgm2 : float
        I, the load inertia on the output (> 0) [kg·m²].
    stiffness_nm_rad : float
        k, torsional stiffness from the output shaft to the load (> 0) [N·m/rad].
    damping_ratio : float
        ζ, 0 ≤ ζ < 1 [-].
    tolerance_arcsec : float
        ε, the angular error allowed at the dwell (> 0) [arcsec].
    samples : int
        Rows of the table, evenly over [0, th + dwell], both ends included (≥ 2) [-].

    Returns
    -------
    IndexerVibration
        fn [1/s], τ [-], the residual amplitude, peak error and tolerance [arcsec], the
        settling time [s] (None: never) and whether it fits in the dwell, and the table.

    Raises
    ------
    InvalidParameterError
        A value out of range, or τ = th·fn outside [10⁻³, 10³].

    References
    ----------
    Koster (1974); INDEXMAN technical guide, sections 2, 3 and 5.
    """
    inertia = _located(positive, "inertia_kgm2", inertia_kgm2)
    stiffness = _located(positive, "stiffness_nm_rad", stiffness_nm_rad)
    zeta = check_damping(damping_ratio)
    tolerance = _located(positive, "tolerance_arcsec", tolerance_arcsec)
    rows = _located(count, "samples", samples)
    if rows < 2:
        raise InvalidParameterError(f"samples must be at least 2, got {rows}.", field=("samples",))
    omega_n = math.sqrt(stiffness / inertia)
    frequency = omega_n / (2.0 * math.pi)
    th = indexer.indexing_time_s
    tau = th * frequency
    if not TAU_MIN <= tau <= TAU_MAX:
        raise InvalidParameterError(
            f"τ = th·fn = {th:.6g} s × {frequency:.6g} Hz = {tau:.6g} must lie within {TAU_MIN:g} ≤ τ ≤ {TAU_MAX:g}: "
            "change stiffness_nm_rad or the load's inertia (τ < 0.001: the load does not follow the cam at all; "
            "τ > 1000: the drive is rigid, nothing vibrates).", field=("stiffness_nm_rad",))
    try:
        response = FollowerResponse(indexer.curve, tau, zeta)
    except InvalidParameterError as exc:  # about the indexer's curve
        exc.field = ("indexer", *exc.field)
        raise
    h = indexer.displacement_deg * 3600.0
    dwell = max(0.0, indexer.machine_cycle_time_s - th)
    residual = h * response.residual_amplitude
    settling_u = response.settling(tolerance, h)
    settling = None if settling_u is None else settling_u * th
    times = np.linspace(0.0, th + dwell, rows)
    error = h * response.deviation(times / th)
    return IndexerVibration(
        inertia_kgm2=inertia, stiffness_nm_rad=stiffness, damping_ratio=zeta, natural_frequency_hz=frequency,
        tau=tau, indexing_time_s=th, dwell_time_s=dwell, displacement_arcsec=h, residual_amplitude_arcsec=residual,
        peak_error_arcsec=h * response.peak_deviation, tolerance_arcsec=tolerance, settling_time_s=settling,
        settles_within_dwell=settling is not None and settling <= dwell,
        table=VibrationTable(time_s=times, output_error_arcsec=error))
