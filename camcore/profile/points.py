"""Profiles given only as points: the numerical pressure angle from neighbouring points
and the chord convexity test.

References
----------
.. [1] Shinzato and Kunigami (1988), program list 1, lines 420-1240 (pressure angle from
   contour points), eqs. (1), (4)-(6).
.. [2] Bezier valve-cam notes: the convexity test on consecutive chords.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..curves.base import FloatArray
from ..errors import InvalidParameterError


# ============================================================================ point data
def _same_point(px: FloatArray, py: FloatArray) -> bool:
    """Last point = first point, within 1e-9 of the contour's size (rounding of a full turn)."""
    size = max(float(np.abs(px).max()), float(np.abs(py).max()), 1.0)
    return bool(np.hypot(px[0] - px[-1], py[0] - py[-1]) <= 1e-9 * size)


def chord_convexity(x: ArrayLike, y: ArrayLike) -> bool:
    """The valve-cam document's convexity test on a closed sampled contour.

    For consecutive chord vectors a = P_i − P_{i−1}, b = P_{i+1} − P_i the contour is
    convex when cos φi = a·b/(|a||b|) > 0 and sin φi = (a × b)/(|a||b|) > 0 at every i
    (the document's contour runs counter-clockwise; a clockwise contour is reversed
    first). A repeated closing point (last = first) is dropped; zero-length chords are
    skipped.

    Parameters
    ----------
    x, y : array_like
        Points of a closed contour in order [mm].

    Returns
    -------
    bool
        True when cos φi > 0 and sin φi > 0 at every point: each corner turns left by less
        than 90° going counter-clockwise.

    References
    ----------
    Bezier valve-cam notes, convexity test: cos φi > 0 and sin φi > 0 for consecutive chord
    vectors a, b.
    """
    px, py = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    if px.size > 1 and _same_point(px, py):
        px, py = px[:-1], py[:-1]
    area2 = float(np.sum(px * np.roll(py, -1) - np.roll(px, -1) * py))
    if area2 < 0:
        px, py = px[::-1], py[::-1]
    ax, ay = px - np.roll(px, 1), py - np.roll(py, 1)
    keep = np.hypot(ax, ay) > 0
    ax, ay = ax[keep], ay[keep]
    bx, by = np.roll(ax, -1), np.roll(ay, -1)
    dot = ax * bx + ay * by
    cross = ax * by - ay * bx
    return bool(np.all(dot > 0) and np.all(cross > 0))


def pressure_angle_from_points(
    x: ArrayLike, y: ArrayLike, cam_angle_deg: ArrayLike | None = None, closed: bool = True
) -> FloatArray:
    """Pressure angle of a knife-edge in-line follower from contour points only.

    Shinzato (1988), program list 1, lines 420–1240, reimplemented with atan2: the
    tangent at P_i is the chord P_{i+1} − P_{i−1} (eq. 1); the follower moves along the
    radius through P_i at the cam angle θ_i (the paper's stroke line, eqs. 4–5). The
    pressure angle is the angle between the contour normal and that radius,

        β = atan2(t·r̂, t·ê),  r̂ = (cos θ, sin θ), ê = (−sin θ, cos θ),

    positive where the radius grows with θ (the follower is pushed out) and negative
    where it shrinks, the paper's sign. The points are in the paper's convention
    x = l cos θ, y = l sin θ (θ increasing along the list). ``cam_angle_deg`` defaults to
    the polar angle of each point. With ``closed`` the list is one full turn (a repeated
    closing point, last = first, is allowed and handled like the paper's 0/360 case);
    otherwise the end points get NaN.

    Parameters
    ----------
    x, y : array_like
        Contour points, same length, at least 3 [mm].
    cam_angle_deg : array_like, optional
        Cam angle θ of each point [deg]; default the polar angle of the point.
    closed : bool
        The points are one full turn (the neighbours of the ends wrap around).

    Returns
    -------
    ndarray
        Pressure angle β at each point [deg]; NaN at the ends of an open list.

    Raises
    ------
    InvalidParameterError
        Mismatched lengths or fewer than 3 points.

    References
    ----------
    Shinzato and Kunigami (1988), program list 1, lines 420-1240, eqs. (1), (4)-(5); eq. (6),
    the analytic value the tests compare it with.
    """
    px = np.asarray(x, dtype=np.float64).reshape(-1)
    py = np.asarray(y, dtype=np.float64).reshape(-1)
    if px.shape != py.shape or px.size < 3:
        raise InvalidParameterError("x and y need the same length, at least 3 points.")
    th = np.arctan2(py, px) if cam_angle_deg is None else np.radians(np.asarray(cam_angle_deg, dtype=np.float64))
    dup = closed and _same_point(px, py)
    n = px.size - 1 if dup else px.size
    i = np.arange(px.size)
    if closed:
        nxt = np.mod(i + 1, n)
        prv = np.mod(i - 1, n)
    else:
        nxt, prv = np.minimum(i + 1, n - 1), np.maximum(i - 1, 0)
    tx, ty = px[nxt] - px[prv], py[nxt] - py[prv]
    c, s = np.cos(th), np.sin(th)
    beta = np.degrees(np.arctan2(tx * c + ty * s, -tx * s + ty * c))
    if not closed:
        beta[0] = beta[-1] = np.nan
    return beta


def pressure_angle_from_lift_samples(
    lift_mm: ArrayLike, base_radius_mm: float, cam_angle_deg: ArrayLike
) -> FloatArray:
    """The paper's whole numerical method from lift samples over one closed turn:
    contour x = l cos θ, y = l sin θ with l = h + Rb (Shinzato eq. above fig. 2), then
    :func:`pressure_angle_from_points`.

    Parameters
    ----------
    lift_mm : array_like
        Lift h of an in-line knife-edge follower at each angle [mm].
    base_radius_mm : float
        Rb, the base-circle radius (the paper's D/2) [mm].
    cam_angle_deg : array_like
        Cam angle θ of each sample, one full turn [deg].

    Returns
    -------
    ndarray
        Pressure angle at each sample [deg].

    References
    ----------
    Shinzato and Kunigami (1988), program list 1 (contour from the lift, then the pressure
    angle from neighbouring points); eq. (6), β = atan((l − D/2)/(θ·l)) for the check.
    """
    h = np.asarray(lift_mm, dtype=np.float64)
    th = np.radians(np.asarray(cam_angle_deg, dtype=np.float64))
    r = h + base_radius_mm
    return pressure_angle_from_points(r * np.cos(th), r * np.sin(th), cam_angle_deg)
