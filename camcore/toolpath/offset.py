"""The exact cutter-centre curve of a plate cam: its surface offset along the outward normal.

The cutter's centre runs at the tool radius Rt from the wall it cuts, on the tool's side.
Every wall here is an offset of one *base curve* B(θ) along its outward unit normal N(θ):
for a knife-edge or roller follower B is the pitch curve (the roller centre's path) and the
cam surface is B − Rr·N; a groove for a roller running in a track has the cam surface as
its inner wall and B + Rr·N as its outer wall; for a flat-faced follower B is the surface
itself. The cutter centre is then P(θ) = B(θ) + d·N(θ) with

    outside (the tool outside the wall: a plate cam, a groove's inner wall): d = w + Rt
    inside (the tool inside the wall: a groove's outer wall, a pocket):      d = w − Rt

and w the wall's offset from B (−Rr for the cam surface of a roller, +Rr for a groove's
outer wall, 0 otherwise). Everything is in the cam's own frame and comes from the lift's
analytic derivatives (kinematic inversion, :mod:`camcore.profile.cam`), never from the
sampled contour.

Derivatives. With T = −σ J N the unit tangent of B as θ grows (J the rotation by +90°, σ = ±1
the sense of rotation), dB/dθ = a·T and dN/dθ = b·T, so dP/dθ = (a + d·b)·T: the offset is
regular where its *stretch* a + d·b > 0 and turns back on itself (a cusp, a swallowtail:
the tool cuts into the wall) where it is ≤ 0. For a pitch curve a = |u1| and b = κp·|u1|
(κp its curvature, positive where convex); for a flat face a = −σ φn' ρ and b = −σ φn'
(ρ the surface's radius of curvature, φn the face normal's angle).

References
----------
.. [1] Shinzato and Kunigami (1988): the contour by kinematic inversion, x = l cos θ, y = l sin θ.
.. [2] R. T. Farouki, C. A. Neff, "Analytic properties of plane offset curves", Computer Aided
   Geometric Design 7 (1990) 83-99: the offset's speed |1 + dκ|·|B'| and its cusps where
   1 + dκ = 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..curves.base import FloatArray
from ..profile.cam import CamSpec, rotate_all

#: a left limit at a break point: the lift evaluated this far before it [rad] (the position
#: moves by ~1e-11·|dB/dθ|, about 1e-9 mm on a 100 mm cam, below any machine's resolution)
LEFT_LIMIT_RAD = 1e-11


@dataclass(frozen=True)
class BaseSample:
    """The base curve at cam angles θ in the cam's frame: point, outward normal, a and b."""

    theta: FloatArray
    x: FloatArray
    y: FloatArray
    nx: FloatArray
    ny: FloatArray
    a: FloatArray
    b: FloatArray


def base_curve(spec: CamSpec, theta: FloatArray) -> BaseSample:
    """The base curve B(θ) of a cam, its outward unit normal N(θ) and the coefficients a, b of
    dB/dθ = a·T and dN/dθ = b·T, in the cam's frame.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    theta : ndarray
        Cam angles θ [rad].

    Returns
    -------
    BaseSample
        Point [mm], normal [-], a [mm/rad] and b [1/rad] at each angle.

    References
    ----------
    Shinzato and Kunigami (1988) (kinematic inversion); Farouki and Neff (1990), offset curves.
    """
    theta = np.asarray(theta, dtype=np.float64)
    a, b, frame = _coefficients(spec, theta, True)
    assert frame is not None  # asked for
    bx, by, nx, ny = frame
    back = -spec.sigma * theta
    (bx, by), (nx, ny) = rotate_all(back, (bx, by), (nx, ny))
    return BaseSample(theta, bx, by, nx, ny, a, b)


def base_stretch(spec: CamSpec, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The coefficients a, b of :func:`base_curve` alone (what a wall's scans for its undercut, its
    curvature and its cusps read), without the point and normal or their turn into the cam's frame.

    Parameters
    ----------
    spec : CamSpec
        The cam: follower, base radius, rotation and lift.
    theta : ndarray
        Cam angles θ [rad].

    Returns
    -------
    (ndarray, ndarray)
        a [mm/rad] and b [1/rad] at each angle: :func:`base_curve`'s numbers to the bit.

    References
    ----------
    Farouki and Neff (1990), offset curves: the offset's stretch a + d·b.
    """
    a, b, _ = _coefficients(spec, np.asarray(theta, dtype=np.float64), False)
    return a, b


def _coefficients(spec: CamSpec, theta: FloatArray, frame: bool
                  ) -> tuple[FloatArray, FloatArray, tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None]:
    """a, b and, if ``frame``, the point and the outward normal before their turn by −σθ."""
    sg, rb = spec.sigma, spec.base_radius_mm
    model = spec.model
    h, h1, h2 = spec.lift.derivatives(theta, 2)
    if model.flat_faced:
        p, p1, p2, phi1, phi2, mx, my = model.support(rb, sg, h, h1, h2)  # type: ignore[attr-defined]
        rho = p + (p2 * phi1 - p1 * phi2) / phi1**3
        a, b = -sg * phi1 * rho, -sg * phi1
        if not frame:
            return a, b, None
        p_phi = p1 / phi1
        return a, b, (p * mx - p_phi * my, p * my + p_phi * mx, mx, my)
    cx, cy, c1x, c1y, c2x, c2y, _vx, _vy = model.pitch_point(rb, h, h1, h2)  # type: ignore[attr-defined]
    # u1 = c' − σ J c and u2 = c'' − 2σ J c' − c, the cam-frame derivatives turned back (camcore.profile.cam)
    u1x, u1y = c1x + sg * cy, c1y - sg * cx
    u2x, u2y = c2x + 2 * sg * c1y - cx, c2y - 2 * sg * c1x - cy
    speed = np.hypot(u1x, u1y)
    b = -sg * (u1x * u2y - u1y * u2x) / speed**2  # κp·|u1|
    if not frame:
        return speed, b, None
    return speed, b, (cx, cy, -sg * u1y / speed, sg * u1x / speed)


class OffsetCurve:
    """P(θ) = B(θ) + d·N(θ) of a cam's base curve, evaluated exactly.

    Parameters
    ----------
    spec : CamSpec
        The cam.
    offset_mm : float
        d, the signed offset from the base curve along the outward normal [mm].
    """

    def __init__(self, spec: CamSpec, offset_mm: float):
        self.spec = spec
        self.offset_mm = float(offset_mm)

    def sample(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """x, y of P, the unit tangent tx, ty of B as θ grows, and the stretch a + d·b (dP/dθ = stretch·T)."""
        return self._sampled(base_curve(self.spec, theta))

    def _sampled(self, base: BaseSample) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        d = self.offset_mm
        sg = self.spec.sigma
        tx, ty = sg * base.ny, -sg * base.nx  # T = −σ J N, J(x, y) = (−y, x)
        return base.x + d * base.nx, base.y + d * base.ny, tx, ty, base.a + d * base.b

    def points(self, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
        """x, y of P(θ) [mm]."""
        x, y, *_ = self.sample(theta)
        return x, y

    def travel(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """x, y, the unit tangent of P in the direction P moves as θ grows, and |dP/dθ| [mm/rad]."""
        return self._travelled(self.sample(theta))

    @staticmethod
    def _travelled(sampled: tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]
                   ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        x, y, tx, ty, stretch = sampled
        sign = np.where(stretch >= 0.0, 1.0, -1.0)
        return x, y, sign * tx, sign * ty, np.abs(stretch)

    def left(self, theta: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """P, the unit travel tangent and the normal N just before θ (the left limit at a break)."""
        return self._one(np.array([one_sided(theta, -1.0)]))

    def right(self, theta: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """P, the unit travel tangent and the normal N at θ (the right limit at a break)."""
        return self._one(np.array([one_sided(theta, +1.0)]))

    def _one(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        base = base_curve(self.spec, t)  # once: the point, its travel tangent and the normal all read it
        x, y, tx, ty, _ = self._travelled(self._sampled(base))
        return (np.array([x[0], y[0]]), np.array([tx[0], ty[0]]), np.array([base.nx[0], base.ny[0]]))

    def base_point(self, theta: float) -> FloatArray:
        """B(θ) [mm]."""
        base = base_curve(self.spec, np.array([theta]))
        return np.array([base.x[0], base.y[0]])


def one_sided(theta: float, side: float) -> float:
    """The cam angle a one-sided limit at a break θ is taken at.

    Parameters
    ----------
    theta : float
        The break [rad].
    side : float
        −1: the left limit, :data:`LEFT_LIMIT_RAD` before θ; +1: the right limit, θ itself [-].

    Returns
    -------
    float
        The angle [rad].

    References
    ----------
    Farouki and Neff (1990): the offset of a curve with corners, taken each side of them.
    """
    return theta - LEFT_LIMIT_RAD if side < 0 else theta


def corner_turn(spec: CamSpec, theta: float) -> float:
    """The angle the base curve's normal turns through at a corner, positive where the
    corner is convex.

    Parameters
    ----------
    spec : CamSpec
        The cam.
    theta : float
        The corner's cam angle [rad].

    Returns
    -------
    float
        The turn, in (−π, π] [rad]: > 0 for a convex corner (the normal turns the way it
        does along a convex stretch), < 0 for a concave one.

    References
    ----------
    Farouki and Neff (1990): a convex curve's normal turns with its tangent, dN/ds = κ T.
    """
    before = base_curve(spec, np.array([one_sided(theta, -1.0)]))
    after = base_curve(spec, np.array([one_sided(theta, +1.0)]))
    n0x, n0y, n1x, n1y = before.nx[0], before.ny[0], after.nx[0], after.ny[0]
    turn = math.atan2(n0x * n1y - n0y * n1x, n0x * n1x + n0y * n1y)
    # along a convex stretch N turns towards T = −σ J N, i.e. clockwise for σ = +1
    return -spec.sigma * turn
