"""The rules an indexer's numbers must keep (shared by camcore's classes and the service's specs).

References
----------
.. [1] INDEXMAN technical guide, sections 2-3 (n = 360/ψ, θh, z, θt = θh·z, t0 = 60/(N·z)).
"""

from __future__ import annotations

import math
from typing import Any

from ..errors import InvalidParameterError


def check_alternatives(stops: Any, swing_angle_deg: Any, speed_rpm: Any, cycle_time_s: Any) -> None:
    """Exactly one of stops and swing angle, and exactly one of speed and cycle time.

    Parameters
    ----------
    stops : int or None
        n, stops per output turn [-].
    swing_angle_deg : float or None
        ψ, swing of an oscillating unit [deg].
    speed_rpm : float or None
        N, input speed [rpm].
    cycle_time_s : float or None
        t0, unit cycle time [s].

    References
    ----------
    INDEXMAN technical guide, sections 2 and 3 (n = 360/ψ; t0 = 60/(N·z)).
    """
    if (stops is None) == (swing_angle_deg is None):
        raise InvalidParameterError("give exactly one of stops (n) and swing_angle_deg (ψ, oscillating units).")
    check_speed_alternatives(speed_rpm, cycle_time_s)


def check_speed_alternatives(speed_rpm: Any, cycle_time_s: Any) -> None:
    """Exactly one of speed and cycle time.

    Parameters
    ----------
    speed_rpm : float or None
        N, input speed [rpm].
    cycle_time_s : float or None
        t0, unit cycle time [s].

    References
    ----------
    INDEXMAN technical guide, section 3 (t0 = 60/(N·z)).
    """
    if (speed_rpm is None) == (cycle_time_s is None):
        raise InvalidParameterError("give exactly one of speed_rpm (N) and cycle_time_s (t0 = 60/(N·z)).")


def check_total_indexing_angle(indexing_angle_deg: float, dwells: int) -> None:
    """θt = θh·z must not exceed one input turn.

    Parameters
    ----------
    indexing_angle_deg : float
        θh, input angle per index [deg].
    dwells : int
        z, indexes per input turn [-].

    References
    ----------
    INDEXMAN technical guide, section 2 (θt = θh·z).
    """
    if indexing_angle_deg * dwells > 360 * (1 + 1e-12):
        raise InvalidParameterError(
            f"the total indexing angle θt = θh·z must not exceed 360°, but indexing_angle_deg × dwells = "
            f"{indexing_angle_deg!r} × {dwells} = {indexing_angle_deg * dwells!r}."
        )


def check_curve_moves(curve: Any) -> None:
    """A curve drives an index only if it moves: S(T7) ≠ S(T0), T7 > T0.

    Parameters
    ----------
    curve : Curve
        The cam curve.

    References
    ----------
    INDEXMAN technical guide, section 5 (s = h·S: the output travels h as S goes from 0 to 1).
    """
    d_t = curve.t_end - curve.t_start
    d_s = curve.s_end - curve.s_start
    if not (math.isfinite(d_s) and d_s != 0 and d_t > 0):
        raise InvalidParameterError("the curve must move (S at T7 different from S at T0) to drive an index.")
