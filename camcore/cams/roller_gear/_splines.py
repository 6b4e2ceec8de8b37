"""The numerics of the roller-gear cam's patches (camcore.cams.roller_gear.surfaces): Lagrange and
Bernstein interpolation across a patch, the cubic Hermite interpolant along the cam angle and its
B-spline form, and the tori d = R about the cam axis.

References
----------
.. [1] L. Piegl, W. Tiller, "The NURBS Book", 2nd ed., Springer (1997), ch. 1-3, 5 (Bézier and
   B-spline curves, knot multiplicity).
.. [2] C. de Boor, "A Practical Guide to Splines", Springer (1978), ch. IV (cubic Hermite).
.. [3] J.-P. Berrut, L. N. Trefethen, "Barycentric Lagrange interpolation", SIAM Review 46 (2004).
"""

from __future__ import annotations

import math

import numpy as np

from ...curves.base import FloatArray


# ----------------------------------------------------------------------------- interpolation
def lobatto(k: int) -> FloatArray:
    """k Chebyshev–Lobatto points on [0, 1], both ends included."""
    return 0.5 * (1.0 - np.cos(np.pi * np.arange(k) / (k - 1)))


def lagrange(nodes: FloatArray, x: FloatArray) -> FloatArray:
    """The Lagrange basis at x, shape (len(x), len(nodes)), by the barycentric formula."""
    weights = 1.0 / np.prod(nodes[:, None] - nodes[None, :] + np.eye(nodes.size), axis=1)
    diff = x[:, None] - nodes[None, :]
    exact = diff == 0.0
    diff[exact] = 1.0
    terms = weights / diff
    basis = terms / terms.sum(axis=1, keepdims=True)
    hit = exact.any(axis=1)
    basis[hit] = exact[hit].astype(np.float64)
    return basis


def bernstein_poles(values: FloatArray) -> FloatArray:
    """Bézier poles through values at k Lobatto points (axis 1 of ``values``): the Bézier's ends
    are the first and last value exactly."""
    k = values.shape[1]
    x = lobatto(k)
    j = np.arange(k)
    binom = np.array([math.comb(k - 1, i) for i in range(k)], dtype=np.float64)
    basis = binom * x[:, None] ** j * (1.0 - x[:, None]) ** (k - 1 - j)
    poles = np.einsum("bj,ajx->abx", np.linalg.inv(basis), values)
    poles[:, 0], poles[:, -1] = values[:, 0], values[:, -1]
    return poles


def hermite(t: FloatArray, p: FloatArray, dp: FloatArray, x: FloatArray) -> FloatArray:
    """The cubic Hermite interpolant of values p and derivatives dp at nodes t (axis 0), at x."""
    i = np.clip(np.searchsorted(t, x, side="right") - 1, 0, t.size - 2)
    h = (t[i + 1] - t[i]).reshape(-1, *([1] * (p.ndim - 1)))
    s = ((x - t[i]) / (t[i + 1] - t[i])).reshape(h.shape)
    s2, s3 = s * s, s * s * s
    return ((2 * s3 - 3 * s2 + 1) * p[i] + (s3 - 2 * s2 + s) * h * dp[i] + (-2 * s3 + 3 * s2) * p[i + 1]
            + (s3 - s2) * h * dp[i + 1])


def hermite_poles(pieces: list[tuple[FloatArray, FloatArray, FloatArray]]) -> tuple[FloatArray, FloatArray, np.ndarray]:
    """The cubic B-spline of the Hermite interpolants of consecutive pieces: poles, knots, multiplicities.

    Parameters
    ----------
    pieces : list of (t, p, dp)
        Each piece's nodes t (n,) [rad], values p (n, ...) and derivatives dp (n, ...); a piece
        starts where the one before ends, with the same value there [mm, mm/rad].

    Returns
    -------
    tuple
        Poles (m, ...), the distinct knots (the nodes), their multiplicities: 4 at the ends, 2 at
        a piece's inner nodes (C1), 3 where two pieces join (C0: their derivatives may differ).

    References
    ----------
    Piegl and Tiller (1997), ch. 2 and 5 (a C1 Bézier spline as a B-spline with double knots).
    """
    poles: list[FloatArray] = []
    knots: list[float] = []
    mults: list[int] = []
    for n, (t, p, dp) in enumerate(pieces):
        h = np.diff(t).reshape(-1, *([1] * (p.ndim - 1)))
        if n == 0:
            poles.append(p[0])
            knots.append(float(t[0]))
            mults.append(4)
        else:
            mults[-1] = 3
        poles.append(p[0] + h[0] * dp[0] / 3)
        for i in range(1, t.size - 1):
            poles += [p[i] - h[i - 1] * dp[i] / 3, p[i] + h[i] * dp[i] / 3]
            knots.append(float(t[i]))
            mults.append(2)
        poles += [p[-1] - h[-1] * dp[-1] / 3, p[-1]]
        knots.append(float(t[-1]))
        mults.append(4)
    return np.array(poles), np.array(knots), np.array(mults)


# ----------------------------------------------------------------------------- the tori
def torus_distance(c_mm: float, points: FloatArray) -> FloatArray:
    """d(X) = √((C − ρ)² + z²): a point's distance from the circle the turret axis sweeps [mm]."""
    return np.hypot(c_mm - np.hypot(points[..., 0], points[..., 1]), points[..., 2])


def torus_coordinates(c_mm: float, theta: FloatArray, p: FloatArray, dp: FloatArray
                       ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """ψ, χ of points in the cam's frame and their θ-derivatives; ψ continuous as −θ + the azimuth in
    the fixed frame (small: the rib is near the plane of the line of centres)."""
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    rho = np.hypot(x, y)
    turn = theta.reshape(-1, *([1] * (x.ndim - 1)))
    fixed = np.arctan2(y, x) + turn
    psi = np.arctan2(np.sin(fixed), np.cos(fixed)) - turn
    dpsi = (x * dp[..., 1] - y * dp[..., 0]) / rho ** 2
    drho = (x * dp[..., 0] + y * dp[..., 1]) / rho
    depth = c_mm - rho
    chi = np.arctan2(z, depth)
    dchi = (depth * dp[..., 2] + z * drho) / (depth ** 2 + z ** 2)
    return psi, chi, dpsi, dchi


def torus_points(c_mm: float, radius_mm: float, psi: FloatArray, chi: FloatArray, dpsi: FloatArray,
                  dchi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Points of the torus d = R at (ψ, χ) and their derivatives along θ from dψ/dθ, dχ/dθ."""
    ring = c_mm - radius_mm * np.cos(chi)
    cp, sp = np.cos(psi), np.sin(psi)
    point = np.stack([ring * cp, ring * sp, radius_mm * np.sin(chi)], axis=-1)
    along_psi = np.stack([-ring * sp, ring * cp, np.zeros_like(ring)], axis=-1)
    along_chi = np.stack([radius_mm * np.sin(chi) * cp, radius_mm * np.sin(chi) * sp, radius_mm * np.cos(chi)], axis=-1)
    return point, along_psi * dpsi[..., None] + along_chi * dchi[..., None]


def distance_gradient(c_mm: float, p: FloatArray) -> FloatArray:
    rho = np.hypot(p[..., 0], p[..., 1])
    d = torus_distance(c_mm, p)
    radial = (rho - c_mm) / (d * rho)
    return np.stack([radial * p[..., 0], radial * p[..., 1], p[..., 2] / d], axis=-1)


def to_cam_frame(theta: FloatArray, v: FloatArray) -> FloatArray:
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    return np.stack([c * v[..., 0] + s * v[..., 1], -s * v[..., 0] + c * v[..., 1], v[..., 2]], axis=-1)
