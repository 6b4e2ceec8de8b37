"""An independent reference for the follower response: the equation stepped in time by RK4.

camcore.dynamics evaluates the Duhamel integral in closed form on Chebyshev subcells, with a
complex first-order state. This steps the real second-order equation instead,

    X'' + 2ζΩ·X' + Ω²·X = −A'(u),   X(0) = X'(0) = 0,   u ∈ [0, 1],

by the classical fourth-order Runge–Kutta method with a fixed step, the steps aligned with
the curve's pieces (so the acceleration is smooth within each step: a step that ends at a
piece's end takes that piece's formula, its left limit). Two runs, with n and 2n steps per
unit of u, give Richardson's extrapolation X* = X_2n + (X_2n − X_n)/15 and an estimate of
its error, |X_2n − X_n|/15 ≥ the error of X_2n (RK4's error falls 16-fold per halving).

The peak max |X| is taken over the steps and refined on each step where X' changes sign by
the quintic Hermite interpolant of X, X', X'' (from the equation) at the step's two ends,
whose error is h⁶·|X⁽⁶⁾|/720·… ≈ (Ωh)⁶·|X| (< 1e-13 here).

Everything runs vectorised over many curves, τ and ζ at once (one Python loop over steps).

References
----------
.. [1] E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*,
   2nd ed. (Springer, 1993), §II.1 (the classical Runge–Kutta method), §II.4 (Richardson
   extrapolation of the global error).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camcore.curves import Curve


@dataclass(frozen=True)
class Reference:
    residual: np.ndarray  # (curves, cases), extrapolated
    residual_error: np.ndarray  # estimate of the extrapolated value's error (bounds it, see module)
    peak: np.ndarray
    peak_error: np.ndarray
    final: np.ndarray  # X at u = 1


def _grid(curve: Curve, steps_per_unit: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Steps u_k → u_k + h_k aligned with the pieces (normalised to u ∈ [0, 1]), the piece of
    each step, and the factor from A to A' (ΔT²/ΔS)."""
    d_t, d_s = curve.t_end - curve.t_start, curve.s_end - curve.s_start
    bounds = (curve.break_points - curve.t_start) / d_t
    starts, widths, pieces = [], [], []
    for k in range(len(bounds) - 1):
        length = bounds[k + 1] - bounds[k]
        if length <= 0:
            continue
        n = max(2, int(np.ceil(length * steps_per_unit)))
        starts.append(bounds[k] + length * np.arange(n) / n)
        widths.append(np.full(n, length / n))
        pieces.append(np.full(n, k))
    return np.concatenate(starts), np.concatenate(widths), np.concatenate(pieces), d_t**2 / d_s


def _accel(curve: Curve, u: np.ndarray, piece: np.ndarray, factor: float) -> np.ndarray:
    return curve.eval_pieces(curve.t_start + (curve.t_end - curve.t_start) * u, piece, 2)[2] * factor


def _run(curves: list[Curve], omega: np.ndarray, zeta: np.ndarray, steps_per_unit: int
         ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """RK4 over all curves at once: (X(1), X'(1), peak) shaped (curves, cases)."""
    grids = [_grid(c, steps_per_unit) for c in curves]
    n = max(g[0].size for g in grids)
    # curves with fewer steps pad with empty steps (h = 0) at u = 1
    h = np.zeros((len(curves), n))
    a0, am, a1 = (np.zeros((len(curves), n)) for _ in range(3))
    for i, (curve, (u, w, piece, factor)) in enumerate(zip(curves, grids)):
        h[i, :u.size] = w
        a0[i, :u.size] = _accel(curve, u, piece, factor)
        am[i, :u.size] = _accel(curve, u + w / 2, piece, factor)
        a1[i, :u.size] = _accel(curve, u + w, piece, factor)
    om2, c1 = omega**2, 2.0 * zeta * omega
    x = np.zeros((len(curves), omega.size))
    v = np.zeros_like(x)
    peak = np.zeros_like(x)

    def f(xx: np.ndarray, vv: np.ndarray, a: np.ndarray) -> np.ndarray:
        return -a[:, None] - c1 * vv - om2 * xx

    for k in range(n):
        hk = h[:, k][:, None]
        k1x, k1v = v, f(x, v, a0[:, k])
        k2x, k2v = v + hk / 2 * k1v, f(x + hk / 2 * k1x, v + hk / 2 * k1v, am[:, k])
        k3x, k3v = v + hk / 2 * k2v, f(x + hk / 2 * k2x, v + hk / 2 * k2v, am[:, k])
        k4x, k4v = v + hk * k3v, f(x + hk * k3x, v + hk * k3v, a1[:, k])
        xn = x + hk / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        vn = v + hk / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        turn = (v * vn < 0) & (hk > 0)
        if turn.any():
            i, j = np.nonzero(turn)
            hh = h[i, k]
            peak[i, j] = np.maximum(peak[i, j], _hermite_extreme(
                x[i, j], v[i, j], k1v[i, j], xn[i, j], vn[i, j], f(xn, vn, a1[:, k])[i, j], hh))
        x, v = xn, vn
        peak = np.maximum(peak, np.abs(x))
    return x, v, peak


def _hermite_extreme(x0, d0, s0, x1, d1, s1, h):  # type: ignore[no-untyped-def]
    """|p| at the root of p' in (0, 1) of the quintic Hermite interpolant p(θ), θ = (u − u0)/h."""
    # p(θ) = Σ c_k θ^k with p(0) = x0, p'(0) = h·d0, p''(0) = h²·s0 and the same at θ = 1
    a, b, c = x0, h * d0, h * h * s0 / 2
    r0 = x1 - a - b - c
    r1 = h * d1 - b - 2 * c
    r2 = h * h * s1 - 2 * c
    c3 = 10 * r0 - 4 * r1 + r2 / 2
    c4 = -15 * r0 + 7 * r1 - r2
    c5 = 6 * r0 - 3 * r1 + r2 / 2

    def p(t):  # type: ignore[no-untyped-def]
        return a + t * (b + t * (c + t * (c3 + t * (c4 + t * c5))))

    def dp(t):  # type: ignore[no-untyped-def]
        return b + t * (2 * c + t * (3 * c3 + t * (4 * c4 + t * 5 * c5)))

    def ddp(t):  # type: ignore[no-untyped-def]
        return 2 * c + t * (6 * c3 + t * (12 * c4 + t * 20 * c5))

    theta = np.clip(d0 / (d0 - d1), 0.0, 1.0)  # where the straight line through X' crosses 0
    for _ in range(8):
        curvature = ddp(theta)
        step = np.divide(dp(theta), curvature, out=np.zeros_like(theta), where=curvature != 0)
        theta = np.clip(theta - step, 0.0, 1.0)
    return np.abs(p(theta))


def reference(curves: list[Curve], tau: np.ndarray, zeta: np.ndarray, steps_per_unit: int) -> Reference:
    """Residual amplitude and peak for every curve at every (τ, ζ) pair (cases)."""
    omega = 2 * np.pi * np.asarray(tau, dtype=float)
    zeta = np.asarray(zeta, dtype=float)
    coarse = _run(curves, omega, zeta, steps_per_unit)
    fine = _run(curves, omega, zeta, 2 * steps_per_unit)
    omega_d = omega * np.sqrt(1 - zeta**2)

    def residual(x: np.ndarray, v: np.ndarray) -> np.ndarray:
        return np.hypot(x, (v + zeta * omega * x) / omega_d)

    r_coarse, r_fine = residual(*coarse[:2]), residual(*fine[:2])
    return Reference(residual=r_fine + (r_fine - r_coarse) / 15, residual_error=np.abs(r_fine - r_coarse) / 15,
                     peak=fine[2] + (fine[2] - coarse[2]) / 15, peak_error=np.abs(fine[2] - coarse[2]) / 15,
                     final=fine[0] + (fine[0] - coarse[0]) / 15)
