"""Where the input angle starts: at the start of the index (camcore's own convention), or at
the centre of the dwell, where the catalog's timing charts put the input shaft's keyway (its
"reference position").

References
----------
.. [1] INDEXMAN technical guide, section 4-2: with the input keyway at its reference position a
   standard indexer is at the centre of the cam's dwell; 4-3: a standard oscillating unit at the
   centre of one of its two dwells.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Literal

import numpy as np

from ..errors import InvalidParameterError
from .drive import TorqueTable
from .kinematics import Indexer

InputAngleOrigin = Literal["index-start", "dwell-centre"]
INPUT_ANGLE_ORIGINS: tuple[str, ...] = ("index-start", "dwell-centre")


def origin_shift_deg(indexer: Any, origin: str) -> float:
    """How far the origin lies before the start of the index [deg of input].

    Parameters
    ----------
    indexer : Indexer or TimedIndexer
        The unit.
    origin : str
        ``index-start`` (0) or ``dwell-centre`` (half the dwell that precedes the index).

    Returns
    -------
    float
        An input angle from the index start plus this is the angle from the origin [deg].

    Raises
    ------
    InvalidParameterError
        An unknown origin, or ``dwell-centre`` for a timing chart (its origin is its own 0°).

    References
    ----------
    INDEXMAN technical guide, sections 4-2 and 4-3 (the keyway at the centre of the dwell).
    """
    if origin not in INPUT_ANGLE_ORIGINS:
        raise InvalidParameterError(f"input_angle_origin must be one of {', '.join(INPUT_ANGLE_ORIGINS)}, "
                                    f"not {origin!r}.", field=("input_angle_origin",))
    if origin == "index-start":
        return 0.0
    if not isinstance(indexer, Indexer):
        raise InvalidParameterError("input_angle_origin 'dwell-centre' is for a single-curve indexer; a timing "
                                    "chart's input angles start at its own 0°.", field=("input_angle_origin",))
    return 0.5 * (360.0 / indexer.dwells - indexer.indexing_angle_deg)


def to_origin(result: Any, shift_deg: float, cycle_deg: float) -> Any:
    """A result (summary, motion table, positions, sizing) with every ``*input_angle_deg`` field
    measured from the origin: shifted by ``shift_deg`` and wrapped into one cycle [0, cycle).
    A torque table's rows are rotated to start at the origin (its times from there too).

    Parameters
    ----------
    result : dataclass instance
        A result of :mod:`camcore.indexer`.
    shift_deg : float
        :func:`origin_shift_deg` [deg].
    cycle_deg : float
        The input angle of one cycle (360/z) [deg].

    Returns
    -------
    dataclass instance
        The same result, its input angles from the origin.

    References
    ----------
    INDEXMAN technical guide, section 4-2.
    """
    if shift_deg == 0.0:
        return result
    changes: dict[str, Any] = {}
    for f in dataclasses.fields(result):
        value = getattr(result, f.name)
        if f.name.endswith("input_angle_deg") and value is not None:
            moved = np.asarray(value, dtype=np.float64) + shift_deg
            # an index (0 … θh) moves inside the cycle; a value past its end wraps
            moved = np.where(moved >= cycle_deg, moved - cycle_deg, moved)
            changes[f.name] = float(moved) if np.ndim(moved) == 0 else moved
        elif isinstance(value, TorqueTable):
            changes[f.name] = _rotated(value, shift_deg)
    return dataclasses.replace(result, **changes)


def _rotated(table: TorqueTable, shift_deg: float) -> TorqueTable:
    """The machine cycle's torque table from the origin: the rows from the origin (inside the
    dwell, where the torque is constant) to the cycle's end first, then the rest; a row at the
    origin opens and closes the cycle."""
    x, time, torque = table.input_angle_deg, table.time_s, table.input_torque_nm
    span_deg, span_s = float(x[-1]), float(time[-1])
    x0 = span_deg - shift_deg
    k = int(np.searchsorted(x, x0, side="right"))  # rows 0 … k−1 lie before the origin
    f = (x0 - x[k - 1]) / (x[k] - x[k - 1])
    t0 = float(time[k - 1] + f * (time[k] - time[k - 1]))
    q0 = float(torque[k - 1] + f * (torque[k] - torque[k - 1]))
    return TorqueTable(
        input_angle_deg=np.concatenate([[0.0], x[k:] - x0, x[:k] + shift_deg, [span_deg]]),
        time_s=np.concatenate([[0.0], time[k:] - t0, time[:k] + (span_s - t0), [span_s]]),
        input_torque_nm=np.concatenate([[q0], torque[k:], torque[:k], [q0]]))
