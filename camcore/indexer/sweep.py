"""Sizing over a grid of designs at once: stops × indexing angles × curves × speeds.

Every combination is sized by the same arithmetic as :func:`camcore.indexer.size` (its
peaks and figures over arrays), one curve at a time: the power-balance peaks of all the
combinations of a curve are refined together (:func:`camcore.curves.extrema.power_balance_peaks`).

References
----------
.. [1] INDEXMAN technical guide, sections 2, 3 and 5 (n, θh, N or t0, the curve's
   characteristic values; the sizing example).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..curves.base import FloatArray
from ..curves.curve import Curve
from ..errors import InvalidParameterError
from .checks import check_curve_moves, check_speed_alternatives
from .load import Load
from .sizing import _curve_peaks, _figures

#: the columns of a sweep: the design, then the sizing figures (as in :class:`Sizing`)
DESIGN_COLUMNS = ("stops", "indexing_angle_deg", "curve", "speed_rpm")


def size_sweep(load: Load, stops: Sequence[int], indexing_angle_deg: Sequence[float], curves: Sequence[Curve],
               curve_names: Sequence[str], speed_rpm: Sequence[float] | None = None,
               cycle_time_s: Sequence[float] | None = None) -> dict[str, list[object] | FloatArray]:
    """Size every combination of stops, indexing angles, curves and speeds (or cycle times).

    Parameters
    ----------
    load : Load
        The load, the same for every design.
    stops : sequence of int
        n values (≥ 1) [-].
    indexing_angle_deg : sequence of float
        θh values, 0 < θh ≤ 360 [deg].
    curves : sequence of Curve
        The curves; ``curve_names`` names each in the answer.
    curve_names : sequence of str
        One name per curve (the ``curve`` column).
    speed_rpm : sequence of float, optional
        N values [rpm].
    cycle_time_s : sequence of float, optional
        t0 values instead (N = 60/t0, one index per input turn) [s].

    Returns
    -------
    dict
        Columns: ``stops``, ``indexing_angle_deg``, ``curve``, ``speed_rpm`` (with
        ``cycle_time_s`` when given), then the sizing figures, one row per combination in
        the order stops, angle, curve, speed (the last varies fastest).

    References
    ----------
    INDEXMAN technical guide, section 5 (sizing example); :func:`camcore.indexer.size`.
    """
    check_speed_alternatives(speed_rpm, cycle_time_s)
    if len(curves) != len(curve_names):
        raise InvalidParameterError("give one name per curve.")
    for i, curve in enumerate(curves):
        try:
            check_curve_moves(curve)
        except InvalidParameterError as exc:
            exc.field = ("curves", i)
            raise
    speeds = np.asarray(speed_rpm if speed_rpm is not None else [60.0 / t for t in cycle_time_s or ()], dtype=np.float64)
    n_arr = np.asarray(stops, dtype=np.float64)
    theta = np.asarray(indexing_angle_deg, dtype=np.float64)
    if not (n_arr.size and theta.size and speeds.size and curves):
        raise InvalidParameterError("give at least one value of each: stops, indexing angles, curves, speeds.")
    grid_n, grid_theta, grid_speed = (g.reshape(-1) for g in np.meshgrid(n_arr, theta, speeds, indexing="ij"))
    resisting = load.output_friction_torque_nm + load.output_work_torque_nm
    parts: list[dict[str, FloatArray]] = []
    for curve in curves:
        peaks = _curve_peaks(curve, 360.0 / grid_n, grid_theta, grid_speed, load.output_inertia_kgm2, resisting)
        parts.append(_figures(peaks, load, grid_n, grid_theta, grid_speed))
    # rows in the order stops, angle, curve, speed: (n, θ, speed) blocks interleaved by curve
    per = n_arr.size * theta.size
    order = np.arange(len(curves) * grid_n.size).reshape(len(curves), per, speeds.size).transpose(1, 0, 2).reshape(-1)
    names = [name for name in curve_names for _ in range(grid_n.size)]
    columns: dict[str, list[object] | FloatArray] = {
        "stops": np.tile(grid_n, len(curves))[order], "indexing_angle_deg": np.tile(grid_theta, len(curves))[order],
        "curve": [names[i] for i in order],
    }
    for name in parts[0]:
        columns[name] = np.concatenate([p[name] for p in parts])[order]
    if cycle_time_s is not None:
        columns["cycle_time_s"] = np.asarray(60.0 / np.asarray(columns["speed_rpm"]), dtype=np.float64)
    return columns
