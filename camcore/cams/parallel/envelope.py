"""The exact envelope of a turret roller in the cam's frame: the two offsets of its pitch curve.

A roller of arm angle α₀ at θ = 0 is the oscillating roller follower of
:mod:`camcore.profile.followers` whose arm angle is α₀ + φ(τ) (φ the turret's angle,
:meth:`ParallelCam.turret`): its pitch point c(τ), c′, c″ and the follower's kinematics
(contact point, pressure angle, pitch-curve curvature κp) are that model's, in closed form from
φ, φ′, φ″ (written out in its operations: the same numbers). τ is the roller's own cam angle, any real number: a turn later the same
roller stands where the next m/stops rollers of its layer stood (:mod:`.geometry`), so one
roller followed over ``stops`` turns is its layer's whole closed path (a *chain*).

In the cam's frame the pitch curve is P(τ) = R(−τ)·c(τ) with P′ = R(−τ)·u1, u1 = c′ − J·c
(J the turn by +90°). With T the unit tangent of P and N = J·T its left normal, the roller's
circle touches its envelope at the two points

    E_s(τ) = P(τ) + s·Rr·N(τ),   s = −1 (the follower model's contact point) or +1,

and E_s′ = |u1|·(1 + s·Rr·κp)·T (the offset's speed; Farouki and Neff 1990), so the branch
runs along T where 1 + s·Rr·κp > 0 and turns back (a cusp: the roller undercuts itself)
where it is not. On side s the roller lies on the −s·N side of E_s: going along T with s = +1
(against T with s = −1) the roller is on the right and the cam's side on the left.

References
----------
.. [1] Shinzato and Kunigami (1988): the pitch curve and pressure angle of an oscillating
   roller follower by kinematic inversion (:mod:`camcore.profile.followers`).
.. [2] R. T. Farouki, C. A. Neff, "Analytic properties of plane offset curves", Computer Aided
   Geometric Design 7 (1990) 83-99.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...curves.base import FloatArray
from .geometry import ParallelCam


@dataclass(frozen=True)
class EnvelopePoints:
    """Both-side quantities of roller envelope points (arrays of one shape), in the cam's frame.

    ``x, y`` the point [mm]; ``tx, ty`` the unit tangent T of the pitch curve as τ grows;
    ``speed`` = |u1| = |dP/dτ| [mm/rad]; ``stretch`` = |u1|·(1 + s·Rr·κp), dE/dτ = stretch·T
    [mm/rad]; ``px, py`` the roller's
    centre [mm]; ``pressure_deg`` within ±90° and ``drives`` (the plate pushes the turret on)
    of a contact there; ``kappa`` the pitch curve's curvature on the side of the point
    (positive where it bends towards it: convex seen from the plate) [1/mm]; ``rho`` the
    envelope's radius of curvature, positive convex [mm].
    """

    x: FloatArray
    y: FloatArray
    tx: FloatArray
    ty: FloatArray
    speed: FloatArray
    stretch: FloatArray
    px: FloatArray
    py: FloatArray
    pressure_deg: FloatArray
    drives: NDArray[np.bool_]
    kappa: FloatArray
    rho: FloatArray


def envelope(cam: ParallelCam, alpha0: FloatArray | float, side: FloatArray | float,
             tau: FloatArray) -> EnvelopePoints:
    """Envelope points of rollers (α₀, side s) at their cam angles τ, all broadcast together.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha0 : ndarray or float
        Each roller's arm angle at τ = 0 [rad].
    side : ndarray or float
        −1 (the follower model's contact point, P − Rr·N) or +1 (P + Rr·N) [-].
    tau : ndarray
        The roller's cam angle, any real value [rad].

    Returns
    -------
    EnvelopePoints
        Points, tangents, stretch, centres, pressure angles, curvatures (module notes).

    References
    ----------
    Shinzato and Kunigami (1988), the oscillating roller follower; Farouki and Neff (1990),
    the offset's speed and curvature.
    """
    alpha0, side, tau = _together(alpha0, side, tau)
    return _on_side(cam, _roller(cam, alpha0, tau), side)


def _together(*values: FloatArray | float) -> tuple[FloatArray, ...]:
    """Arm angles, sides and cam angles as float arrays of one shape (broadcast)."""
    return tuple(np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in values)))


def both_sides(cam: ParallelCam, alpha0: FloatArray | float, tau: FloatArray) -> EnvelopePoints:
    """Envelope points of rollers on both sides: arrays of shape (2, *shape), side −1 first.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha0 : ndarray or float
        Each roller's arm angle at τ = 0 [rad].
    tau : ndarray
        The roller's cam angle, broadcast against ``alpha0`` [rad].

    Returns
    -------
    EnvelopePoints
        As :func:`envelope`, the roller's quantities computed once for both sides.

    References
    ----------
    Farouki and Neff (1990): the two offsets of one curve.
    """
    alpha0, tau = _together(alpha0, tau)
    state = _roller(cam, alpha0, tau)
    stacked = tuple(np.stack([v, v]) for v in state)
    side = np.broadcast_to(np.array([-1.0, 1.0]).reshape((2,) + (1,) * alpha0.ndim), (2, *alpha0.shape))
    return _on_side(cam, stacked, side)


def _roller(cam: ParallelCam, alpha0: FloatArray, tau: FloatArray, pressure: bool = True) -> tuple[Any, ...]:
    """The side-free part: centre, unit tangent, |u1|, pressure angle (None unless asked) and κp of the
    pitch curve.

    The turret roller is the oscillating roller follower of :mod:`camcore.profile.followers` (pivot at
    C, arm Rp, σ = +1) whose arm angle is α₀ + φ: its pitch point (``KnifeEdgeOscillating.pitch_point``,
    the lift α₀ + φ in degrees) and kinematics (``_PointFollower.kinematics_of``) are written out here
    in the model's operations and order, so the same numbers to the bit, without the quantities the
    envelope does not use (the solvers ask for a few points at a time, a hundred times a plate;
    tests/camcore/cams/test_parallel_envelope.py compares them with the model).
    """
    phi, d1, d2 = cam.turret(tau)
    arm, pivot = float(cam.roller_pitch_radius_mm), float(cam.center_distance_mm)
    # the model's arm angle: its α₀ (0) plus the lift, which is α₀ + φ in degrees
    a = 0.0 + np.radians(np.degrees(alpha0 + phi))
    a1, a2 = np.radians(np.degrees(d1)), np.radians(np.degrees(d2))
    sa, ca = np.sin(a), np.cos(a)
    c2x = arm * (ca * a1 * a1 + sa * a2)
    c2y = arm * (-sa * a1 * a1 + ca * a2)
    cx, cy, c1x, c1y = pivot - arm * ca, arm * sa, arm * sa * a1, arm * ca * a1
    # u1 = c′ − J·c, u2 = c″ − 2J·c′ − c (σ = +1): the pitch curve's derivatives, in the fixed frame
    u1x, u1y = c1x + cy, c1y - cx
    u2x = c2x + 2.0 * c1y - cx
    u2y = c2y - 2.0 * c1x - cy
    speed = np.hypot(u1x, u1y)
    kappa_pitch = -1.0 * (u1x * u2y - u1y * u2x) / speed**3
    # the follower's pressure angle, φ = atan2(u1·v̂, −u1·(J v̂)), v̂ = (sin α, cos α)
    p = np.arctan2(u1x * sa + u1y * ca, -1.0 * (-u1x * ca + u1y * sa)) if pressure else None
    cos_t, sin_t = np.cos(tau), np.sin(tau)
    # into the cam's frame, R(−τ)
    tx = (cos_t * u1x + sin_t * u1y) / speed
    ty = (-sin_t * u1x + cos_t * u1y) / speed
    px, py = cos_t * cx + sin_t * cy, -sin_t * cx + cos_t * cy
    return px, py, tx, ty, speed, p, kappa_pitch


@dataclass(frozen=True)
class EnvelopeTrack:
    """What the solvers follow an envelope by: its points [mm], the pitch curve's unit tangent T [-]
    and the stretch, dE/dτ = stretch·T [mm/rad] (:class:`EnvelopePoints`' numbers, to the bit)."""

    x: FloatArray
    y: FloatArray
    tx: FloatArray
    ty: FloatArray
    stretch: FloatArray


def track(cam: ParallelCam, alpha0: FloatArray | float, side: FloatArray | float, tau: FloatArray) -> EnvelopeTrack:
    """Envelope points with their tangents and stretch only: :func:`envelope` without the pressure
    angles and radii of curvature, for the solvers' steps.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha0 : ndarray or float
        Each roller's arm angle at τ = 0 [rad].
    side : ndarray or float
        −1 or +1 [-].
    tau : ndarray
        The roller's cam angle [rad].

    Returns
    -------
    EnvelopeTrack
        Points [mm], unit tangents [-], stretch [mm/rad].

    References
    ----------
    Farouki and Neff (1990), the offset's speed.
    """
    alpha0, side, tau = _together(alpha0, side, tau)
    px, py, tx, ty, speed, _, kappa_pitch = _roller(cam, alpha0, tau, pressure=False)
    rr = cam.roller_radius_mm
    kappa = -side * kappa_pitch
    return EnvelopeTrack(px - side * rr * ty, py + side * rr * tx, tx, ty, speed * (1.0 - rr * kappa))


def _on_side(cam: ParallelCam, state: tuple[FloatArray, ...], side: FloatArray) -> EnvelopePoints:
    px, py, tx, ty, speed, p, kappa_pitch = state
    rr = cam.roller_radius_mm
    x, y = px - side * rr * ty, py + side * rr * tx  # P + s·Rr·J·T
    # the follower's pressure angle is that of its contact point (s = −1); on the other side the
    # normal is reversed, so the same angle with the sense turned over
    drives0 = np.abs(p) < math.pi / 2
    folded = np.degrees(np.where(drives0, p, p - np.sign(p) * math.pi))
    drives = np.where(side < 0, drives0, ~drives0)
    kappa = -side * kappa_pitch
    with np.errstate(divide="ignore"):
        rho = 1.0 / kappa - rr
    return EnvelopePoints(x, y, tx, ty, speed, speed * (1.0 - rr * kappa), px, py, folded, drives, kappa, rho)


def centres(cam: ParallelCam, alpha0: FloatArray | float, tau: FloatArray
            ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Roller centres P(τ) in the cam's frame and their first two derivatives.

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    alpha0 : ndarray or float
        Each roller's arm angle at τ = 0 [rad].
    tau : ndarray
        The roller's cam angle [rad].

    Returns
    -------
    tuple of ndarray
        x, y [mm], x′, y′ [mm/rad], x″, y″ [mm/rad²].

    References
    ----------
    camcore.profile.cam (kinematic inversion): P′ = R(−τ)·u1, P″ = R(−τ)·u2 with
    u1 = c′ − J·c, u2 = c″ − 2J·c′ − c; camcore.profile.followers (the oscillating follower's
    pitch point).
    """
    tau = np.asarray(tau, dtype=np.float64)
    phi, d1, d2 = cam.turret(tau)
    # the oscillating roller follower's pitch point B(α) = (C − Rp·cos α, Rp·sin α) and its
    # derivatives (camcore.profile.followers, KnifeEdgeOscillating.pitch_point), written out here:
    # the tracing and fitting ask for a few points at a time, thousands of times
    # (tests/camcore/cams/test_parallel_contour.py checks they agree with the model)
    rp = cam.roller_pitch_radius_mm
    alpha = alpha0 + phi
    sa, ca = np.sin(alpha), np.cos(alpha)
    d1sq = d1 * d1
    cx, cy = cam.center_distance_mm - rp * ca, rp * sa
    c1x, c1y = rp * sa * d1, rp * ca * d1
    c2x, c2y = rp * (ca * d1sq + sa * d2), rp * (ca * d2 - sa * d1sq)
    # u1 = c′ − J·c, u2 = c″ − 2J·c′ − c, turned into the cam's frame by R(−τ)
    u1x, u1y = c1x + cy, c1y - cx
    u2x, u2y = c2x + 2 * c1y - cx, c2y - 2 * c1x - cy
    cos_t, sin_t = np.cos(tau), np.sin(tau)
    return (cos_t * cx + sin_t * cy, cos_t * cy - sin_t * cx, cos_t * u1x + sin_t * u1y,
            cos_t * u1y - sin_t * u1x, cos_t * u2x + sin_t * u2y, cos_t * u2y - sin_t * u2x)
