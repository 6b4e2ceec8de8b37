"""The turret of an indexing cam: its angle over any number of cam turns, from the indexer's law.

References
----------
.. [1] INDEXMAN technical guide, sections 2-1 to 2-4 and 5: n = 360/ψ, θh, the index law s = h·S.
"""

from __future__ import annotations

import math

import numpy as np

from ..curves.base import FloatArray
from ..curves.curve import Curve
from ..errors import InvalidParameterError
from ..indexer import Indexer


def turret_motion(indexer: Indexer, cam_angle_rad: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """φ, dφ/dθ and d²φ/dθ² of the turret at any cam angles: each turn adds one index h = 2π/stops.

    Parameters
    ----------
    indexer : Indexer
        The index law, θh and the stops.
    cam_angle_rad : ndarray
        θ, any real values; θ = 0 is the start of an index [rad].

    Returns
    -------
    tuple of ndarray
        φ [rad], dφ/dθ [-], d²φ/dθ² [1/rad], shaped as ``cam_angle_rad``.

    Raises
    ------
    InvalidParameterError
        An indexer without stops (an oscillating unit).

    References
    ----------
    INDEXMAN technical guide, section 5 (the index law over the input angle).
    """
    if indexer.stops is None:
        raise InvalidParameterError("a turret's indexer needs stops (an oscillating unit has none).")
    theta = np.asarray(cam_angle_rad, dtype=np.float64)
    turns = np.floor(theta / (2 * math.pi))
    within = np.degrees(theta - turns * 2 * math.pi)
    table = indexer.motion_at(np.clip(within, 0.0, 360.0).reshape(-1))
    shape = theta.shape
    phi = np.radians(table.output_angle_deg).reshape(shape) + turns * (2 * math.pi / indexer.stops)
    return phi, table.dout_din.reshape(shape), table.d2out_din2_per_rad.reshape(shape)


def index_law(stops: int, indexing_angle_deg: float, curve: Curve | str) -> Indexer:
    """The turret's index law: h = 360°/stops over θh of cam angle, one index per cam turn.

    Parameters
    ----------
    stops : int
        Stops per turret turn [-].
    indexing_angle_deg : float
        θh, 1 ≤ θh ≤ 359 (the cam holds the turret for the rest of the turn) [deg].
    curve : Curve or str
        The law (a curve or a catalog name) [-].

    Returns
    -------
    Indexer
        At 1 rpm (the cams' geometry needs no speed).

    Raises
    ------
    InvalidParameterError
        θh outside 1 … 359.

    References
    ----------
    INDEXMAN technical guide, sections 2-1 to 2-4 (n, θh), section 5 (the index law).
    """
    if not 1 <= indexing_angle_deg <= 359:
        raise InvalidParameterError(
            f"indexing_angle_deg must lie in 1 … 359 (the cam holds the turret in the dwell), got "
            f"{indexing_angle_deg!r}.")
    return Indexer(indexing_angle_deg=indexing_angle_deg, stops=stops, speed_rpm=1.0,
                   curve=curve)  # type: ignore[arg-type]  # a name becomes the catalog curve
