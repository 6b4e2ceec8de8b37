"""A lift curve drawn by the user as a Bezier curve in the (drive angle θ, lift h) plane.

The control points b_k = (θ_k, h_k), k = 0..n, define

    P(s) = (θ(s), h(s)) = Σ b_k · C(n, k) · s^k (1 − s)^(n−k),   s ∈ [0, 1]   (eq. 1)

and the lift is the function h(θ) traced by P, which exists when θ(s) increases
strictly. Velocity and acceleration follow by the chain rule (eqs. 2, 3):
dh/dθ = (dh/ds)/(dθ/ds), d²h/dθ² = (d/ds dh/dθ)/(dθ/ds), and so on up to the
fourth derivative, which :class:`~camcore.curve.Curve` needs to find exact extrema.

The s-derivatives come from the derivative control points (forward differences
of the b_k, times n!/(n−k)!), evaluated in the Bernstein basis by de Casteljau's
algorithm, which is numerically stable. The source document's printed second
derivative is garbled and is not used.

The curve is stored dimensionless: T = (θ − θ0)/(θn − θ0), S = (h − h_min)/(h_max − h_min)
with h_min, h_max the extremes of h(s) over the whole curve (not of the control
points). :attr:`BezierCurve.scale` maps back to degrees and millimetres.

References
----------
.. [1] Valve-cam notes, "ベジエによるバルブカム設計" (docs/sources.md),
   eqs. (1)-(3): the Bezier lift curve and the chain rule for V and A.
.. [2] G. Farin, Curves and Surfaces for CAGD, 5th ed., ch. 4-5 (de Casteljau,
   derivatives of a Bezier curve by forward differences).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.polynomial import Chebyshev
from numpy.typing import ArrayLike, NDArray

from .._solvers import bracketed_newton
from ..errors import DegenerateCurveError, LimitExceededError
from .base import FloatArray, Scale
from .curve import Curve

#: largest Bezier degree accepted by default: de Casteljau costs O(n²) per point and
#: a user-drawn lift needs far fewer control points than this.
DEFAULT_MAX_DEGREE = 30

#: dθ/ds (normalised so that its mean over [0, 1] is 1) must exceed this everywhere.
#: A smaller minimum means a (near-)vertical tangent: dh/dθ would exceed 10¹² times
#: the mean slope, and at that size the value is dominated by rounding in dθ/ds.
_MIN_THETA_SLOPE = 1e-12

#: extra samples of s used, besides endpoints and polished roots, when searching for
#: the extremes of h(s) and the minimum of dθ/ds: a cheap guard against a root that
#: the colleague-matrix eigenvalue solver misplaces.
_GUARD_SAMPLES = 1025

#: parameter values evaluated per block by de Casteljau's algorithm.
_CHUNK = 2048

#: samples of θ(s) used to bracket s for a given T before Newton's iteration.
_INVERSE_TABLE = 257


# -------------------------------------------------------------------- Bernstein tools
def bernstein_eval(coef: FloatArray, s: FloatArray) -> FloatArray:
    """Value of Σ coef_k B_k^d(s) by de Casteljau's algorithm (vectorised over s).

    Parameters
    ----------
    coef : ndarray, shape (d + 1,)
        Bernstein coefficients of a polynomial of degree d [-] (camcore passes the
        normalised θ or h of a Bezier lift; the result has the coefficients' unit).
    s : ndarray
        Parameter values [-], normally in [0, 1].

    Returns
    -------
    ndarray
        The polynomial at each s, shaped like ``s`` [-]; zeros when ``coef`` is empty.

    References
    ----------
    G. Farin, Curves and Surfaces for CAGD, 5th ed., ch. 4 (de Casteljau's algorithm:
    d passes of convex combinations, numerically stable for s in [0, 1]).
    """
    s = np.asarray(s, dtype=np.float64)
    if coef.size == 0:
        return np.zeros_like(s)
    one_minus = 1.0 - s
    level = np.broadcast_to(coef.reshape((-1,) + (1,) * s.ndim), (coef.size,) + s.shape).copy()
    # each pass replaces d+1 points by d convex combinations (loop over the degree only)
    for _ in range(coef.size - 1):
        level = level[:-1] * one_minus + level[1:] * s
    return level[0]


def bernstein_derivatives(coef: FloatArray, s: FloatArray, order: int) -> list[FloatArray]:
    """Value and derivatives up to ``order`` of Σ coef_k B_k^n(s), in one de Casteljau run.

    After n − k steps of de Casteljau's algorithm k + 1 points remain, and
    P^(k)(s) = n!/(n − k)! · Δ^k of those points (Farin, §5.3): the forward differences
    of the derivative control points, taken at the level where they are needed. One
    run costs what a single evaluation costs, instead of one run per derivative.

    Parameters
    ----------
    coef : ndarray, shape (n + 1, ...)
        Bernstein coefficients [-]; trailing axes (e.g. θ and h side by side) are carried along.
    s : ndarray, shape (m,)
        Parameter values [-].
    order : int
        Highest derivative wanted [-]; derivatives above n are zero.

    Returns
    -------
    list of ndarray
        [P, dP/ds, …, d^order P/ds^order], each of shape ``coef.shape[1:] + (m,)`` [-]
        (the coefficients' unit per unit of s^k).

    References
    ----------
    G. Farin, Curves and Surfaces for CAGD, 5th ed., §5.3 (derivatives of a Bezier curve
    as forward differences of the control points) and ch. 4 (de Casteljau's algorithm).
    """
    if s.size > _CHUNK:
        # blocks that fit in cache: the n levels re-read the block n times
        parts = [bernstein_derivatives(coef, s[i : i + _CHUNK], order) for i in range(0, s.size, _CHUNK)]
        return [np.concatenate([p[k] for p in parts], axis=-1) for k in range(order + 1)]
    degree = coef.shape[0] - 1
    one_minus = 1.0 - s
    level = np.repeat(coef[..., np.newaxis], s.size, axis=-1)
    out: list[FloatArray | None] = [None] * (order + 1)
    for k in range(order, degree, -1):
        out[k] = np.zeros(coef.shape[1:] + s.shape)
    for step in range(degree + 1):
        remaining = degree - step  # the derivative of this order is read off now
        if remaining <= order:
            out[remaining] = math.perm(degree, remaining) * np.diff(level, n=remaining, axis=0)[0]
        if step < degree:
            level = level[:-1] * one_minus + level[1:] * s
    return out  # type: ignore[return-value]


def derivative_control_points(coef: FloatArray, order: int) -> FloatArray:
    """Bernstein coefficients of the ``order``-th derivative: n!/(n−k)! · Δ^k b.

    Parameters
    ----------
    coef : ndarray, shape (n + 1,)
        Bernstein coefficients b_0..b_n of a polynomial of degree n [-].
    order : int
        k, the derivative's order (≥ 0) [-].

    Returns
    -------
    ndarray, shape (n − k + 1,)
        Coefficients of d^k P/ds^k in the Bernstein basis of degree n − k [-]; empty when
        k exceeds n (the derivative is identically zero).

    References
    ----------
    G. Farin, Curves and Surfaces for CAGD, 5th ed., §5.3 (derivatives of a Bezier curve
    by forward differences).
    """
    degree = coef.size - 1
    if order > degree:
        return np.zeros(0)
    return math.perm(degree, order) * np.diff(coef, n=order)


def _real_roots_in_unit_interval(coef: FloatArray) -> FloatArray:
    """Real roots in [0, 1] of the polynomial with Bernstein coefficients ``coef``.

    The polynomial is interpolated exactly (degree d at d + 1 Chebyshev points) in the
    Chebyshev basis on [0, 1], whose colleague matrix gives well-conditioned roots
    on the interval; the power basis would not be for degrees near 30.
    """
    degree = coef.size - 1
    if degree < 1 or not np.any(coef):
        return np.zeros(0)
    cheb = Chebyshev.interpolate(lambda x: bernstein_eval(coef, x), degree, domain=[0.0, 1.0])
    try:
        roots = cheb.roots()
    except np.linalg.LinAlgError as exc:  # only for coefficients at the edge of float range
        raise DegenerateCurveError("the control points are too extreme to locate the curve's turning points.") from exc
    # a double root may come out with a tiny imaginary part: keep it as a candidate
    real = roots[np.abs(roots.imag) <= 1e-6].real
    return np.clip(real[(real >= -1e-9) & (real <= 1.0 + 1e-9)], 0.0, 1.0)


def _polish_roots(coef: FloatArray, roots: FloatArray, steps: int = 4) -> FloatArray:
    """A few Newton steps on the Bernstein polynomial ``coef``, kept inside [0, 1]."""
    slope_coef = derivative_control_points(coef, 1)
    s = roots.copy()
    for _ in range(steps):
        f = bernstein_eval(coef, s)
        df = bernstein_eval(slope_coef, s)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(df != 0, f / df, 0.0)
        s = np.clip(s - step, 0.0, 1.0)
    return s


def _extreme_candidates(slope_coef: FloatArray) -> FloatArray:
    """Parameters where a polynomial with derivative ``slope_coef`` may be extreme on [0, 1]."""
    roots = _real_roots_in_unit_interval(slope_coef)
    return np.concatenate([[0.0, 1.0], _polish_roots(slope_coef, roots), np.linspace(0.0, 1.0, _GUARD_SAMPLES)])


def _faa_di_bruno(x: list[FloatArray], y: list[FloatArray], order: int) -> list[FloatArray]:
    """d^k y/dx^k, k = 1..order (≤ 4), from the s-derivatives x_k = d^k x/ds^k, y_k.

    Differentiating y1 = V x1 repeatedly in s gives
        y2 = A x1² + V x2
        y3 = J x1³ + 3 A x1 x2 + V x3
        y4 = Q x1⁴ + 6 J x1² x2 + 3 A x2² + 4 A x1 x3 + V x4,   Q = dJ/dx,
    which are solved here for V, A, J, Q in turn.
    """
    x1 = x[1]
    out: list[FloatArray] = []
    v = y[1] / x1
    out.append(v)
    if order >= 2:
        a = (y[2] - v * x[2]) / x1**2
        out.append(a)
    if order >= 3:
        j = (y[3] - 3.0 * a * x1 * x[2] - v * x[3]) / x1**3
        out.append(j)
    if order >= 4:
        q = (y[4] - 6.0 * j * x1**2 * x[2] - 3.0 * a * x[2] ** 2 - 4.0 * a * x1 * x[3] - v * x[4]) / x1**4
        out.append(q)
    return out


def dimensional_values(curve: Curve, t: ArrayLike) -> dict[str, FloatArray]:
    """A user curve's values in its own units, from its :class:`~camcore.curves.base.Scale`.

    Parameters
    ----------
    curve : Curve
        A curve with a ``scale`` (:class:`BezierCurve`, :class:`~camcore.curves.points.PointsCurve`).
    t : array_like
        Dimensionless times T [-].

    Returns
    -------
    dict of str to ndarray
        ``theta`` [θ unit], ``h`` [h unit], ``dh_dtheta`` [h unit/θ unit],
        ``d2h_dtheta2`` [h unit/θ unit²] and ``d3h_dtheta3`` [h unit/θ unit³], each
        shaped like ``t``; for a Bezier lift these are [deg], [mm], [mm/deg], [mm/deg²] and
        [mm/deg³] (θ = θ0 + theta_span·T, h = h_min + h_span·S, dᵏh/dθᵏ = h_span/theta_spanᵏ·dᵏS/dTᵏ).

    References
    ----------
    Bezier valve-cam notes, eqs. (1)-(3): lift h(θdr) and its derivatives by the chain rule.
    """
    scale: Scale = curve.scale  # type: ignore[attr-defined]
    t_arr = np.asarray(t, dtype=np.float64)
    s, v, a, j = curve.derivatives(t_arr, 3)
    rate = scale.h_span / scale.theta_span
    return {
        "theta": scale.theta_start + scale.theta_span * t_arr,
        "h": scale.h_min + scale.h_span * s,
        "dh_dtheta": rate * v,
        "d2h_dtheta2": rate / scale.theta_span * a,
        "d3h_dtheta3": rate / scale.theta_span**2 * j,
    }


# -------------------------------------------------------------------- the curve
class BezierCurve(Curve):
    """Lift h(θ) given by a Bezier curve's control points, as a dimensionless curve.

    Parameters
    ----------
    control_points : array_like, shape (n + 1, 2)
        ``[[theta, h], ...]``: drive angle θ [deg] and lift h [mm] of each control
        point, n + 1 ≥ 2. θ(s) must increase strictly along the curve.
    max_degree : int
        Largest accepted degree n (default 30).

    Raises
    ------
    DegenerateCurveError
        Non-finite or badly shaped input, θ not strictly increasing along the curve,
        or constant lift.
    LimitExceededError
        The degree n exceeds ``max_degree``.

    Attributes
    ----------
    scale : Scale
        θ = θ0 + theta_span·T [deg], h = h_min + h_span·S [mm].
    degree : int
        n.
    """

    def __init__(self, control_points: ArrayLike | Sequence[Sequence[float]], max_degree: int = DEFAULT_MAX_DEGREE):
        points = self._validated_points(control_points, max_degree)
        self.degree = points.shape[0] - 1
        self.control_points = points
        theta, h = points[:, 0], points[:, 1]
        theta_span = float(theta[-1] - theta[0])
        if not (np.isfinite(theta_span) and theta_span > 0):
            raise DegenerateCurveError(
                "the last control point's θ must be greater than the first one's: the drive "
                "angle has to increase from the start of the lift to its end."
            )
        # a span lost in the rounding of the control points' own size (found by fuzzing:
        # a subnormal span overflowed the normalisation) is no drive angle at all
        if theta_span <= 1e-9 * max(1.0, float(np.max(np.abs(theta)))):
            raise DegenerateCurveError(
                f"the drive angle spans only {theta_span!r}° from the first to the last control point; "
                "a lift curve needs a span of at least 1e-9 of the angles' size."
            )
        # θ normalised to [0, 1]; the mean of dθ/ds is then 1, so slopes compare to 1
        x_coef = (theta - theta[0]) / theta_span
        x_coef[-1] = 1.0
        self._check_theta_increasing(x_coef)
        h_min, h_max = self._lift_extremes(h)
        h_span = h_max - h_min
        # h varying only by rounding of its own size is a constant lift in disguise
        if not (h_span > 8 * np.finfo(float).eps * float(np.max(np.abs(h)))):
            raise DegenerateCurveError(
                "all control points give the same lift h, so there is no lift to follow; "
                "give at least one control point a different h."
            )
        y_coef = (h - h_min) / h_span
        self.scale = Scale(
            theta_start=float(theta[0]),
            theta_span=theta_span,
            h_min=h_min,
            h_span=h_span,
            units={"theta": "deg", "h": "mm"},
        )
        self._x_coef = x_coef
        # de Casteljau's rounding error is at most ~2n ulp of the largest coefficient
        # (each of its n levels adds one rounding of a convex combination)
        self._theta_noise = 2.0 * max(self.degree, 2) * np.finfo(float).eps * float(np.max(np.abs(x_coef)))
        self._xy_coef = np.column_stack([x_coef, y_coef])  # de Casteljau on both at once
        s_table = np.linspace(0.0, 1.0, _INVERSE_TABLE)
        self._s_table = s_table
        self._t_table = bernstein_eval(x_coef, s_table)
        self.piece_starts = np.array([0.0])
        self.t_end = 1.0

    # ---------------------------------------------------------------- validation
    @staticmethod
    def _validated_points(control_points: ArrayLike, max_degree: int) -> FloatArray:
        try:
            points = np.array(control_points, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise DegenerateCurveError(
                "control points must be a list of [theta, h] pairs of numbers."
            ) from exc
        if points.ndim != 2 or points.shape[1] != 2:
            raise DegenerateCurveError("control points must be a list of [theta, h] pairs of numbers.")
        if points.shape[0] < 2:
            raise DegenerateCurveError("a Bezier lift curve needs at least 2 control points.")
        degree = points.shape[0] - 1
        if degree > max_degree:
            raise LimitExceededError("Bezier degree", degree, max_degree, field=("control_points",))
        bad = ~np.isfinite(points)
        if bad.any():
            i, j = (int(k) for k in np.argwhere(bad)[0])
            name = ("theta", "h")[j]
            raise DegenerateCurveError(
                f"control point {i} has {name} = {float(points[i, j])!r}; every coordinate must be a finite number."
            )
        return points

    @staticmethod
    def _check_theta_increasing(x_coef: FloatArray) -> None:
        """Raise unless dθ/ds > 0 on the closed interval [0, 1].

        The minimum of dθ/ds lies at s = 0, s = 1 or a root of d²θ/ds².
        """
        slope = derivative_control_points(x_coef, 1)
        if x_coef.size > 2:
            candidates = _extreme_candidates(derivative_control_points(x_coef, 2))
        else:
            candidates = np.array([0.0, 1.0])  # a line: dθ/ds is constant
        slopes = bernstein_eval(slope, candidates)
        worst = int(np.argmin(slopes))
        if slopes[worst] > _MIN_THETA_SLOPE:
            return
        # report the first place where θ stops increasing
        first = float(np.min(candidates[slopes <= _MIN_THETA_SLOPE]))
        if slopes[worst] < -_MIN_THETA_SLOPE:
            raise DegenerateCurveError(
                f"the control points make the curve turn back in θ near s = {first:.2f}, so the "
                "lift is not a function of the drive angle; keep θ increasing along the control polygon."
            )
        raise DegenerateCurveError(
            f"the curve has a vertical tangent (θ stops increasing) near s = {first:.2f}, where the "
            "lift rate dh/dθ would be infinite; move the control points so that θ keeps increasing."
        )

    @staticmethod
    def _lift_extremes(h: FloatArray) -> tuple[float, float]:
        """min and max of h(s) over s ∈ [0, 1]: at the ends or at roots of dh/ds."""
        if np.all(h == h[0]):
            return float(h[0]), float(h[0])
        candidates = _extreme_candidates(derivative_control_points(h, 1))
        values = bernstein_eval(h, candidates)
        return float(np.min(values)), float(np.max(values))

    # ---------------------------------------------------------------- evaluation
    def parameter_at(self, t: ArrayLike) -> FloatArray:
        """Bezier parameter s with θ(s) = θ0 + T·theta_span, to machine precision.

        Safeguarded Newton iteration (vectorised), started by linear interpolation in
        a table of θ(s) and kept inside the table's bracket; θ(s) increases strictly.
        """
        t_arr = np.asarray(t, dtype=np.float64)
        target = np.clip(t_arr.reshape(-1), 0.0, 1.0)
        table_t, table_s = self._t_table, self._s_table
        k = np.clip(np.searchsorted(table_t, target, side="right"), 1, len(table_t) - 1)
        lo, hi = table_s[k - 1].copy(), table_s[k].copy()
        frac = (target - table_t[k - 1]) / (table_t[k] - table_t[k - 1])
        s = lo + (hi - lo) * np.clip(frac, 0.0, 1.0)

        def theta_and_slope(x: FloatArray) -> tuple[FloatArray, FloatArray]:
            theta, slope = bernstein_derivatives(self._x_coef, x, 1)
            return theta, slope

        # θ is known only to its rounding error, so a residual that small is exact
        s = bracketed_newton(theta_and_slope, target, s, lo, hi, noise=self._theta_noise)
        # the ends map exactly: θ(0) = θ0 and θ(1) = θn
        s = np.where(target == 0.0, 0.0, np.where(target == 1.0, 1.0, s))
        return s.reshape(t_arr.shape)

    def at_parameter(self, s: ArrayLike, order: int = 2) -> list[FloatArray]:
        """[T, S, V, A, J, dJ/dT][: order + 2] at Bezier parameters s ∈ [0, 1].

        Dimensionless; see :attr:`scale` (or :meth:`dimensional`) for degrees and mm.
        """
        s_arr = np.asarray(s, dtype=np.float64)
        both = bernstein_derivatives(self._xy_coef, s_arr.reshape(-1), order)
        x = [d[0].reshape(s_arr.shape) for d in both]
        y = [d[1].reshape(s_arr.shape) for d in both]
        return [x[0], y[0]] + (_faa_di_bruno(x, y, order) if order >= 1 else [])

    def eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        return self.at_parameter(self.parameter_at(t), order)[1:]

    def dimensional(self, t: ArrayLike) -> dict[str, FloatArray]:
        """θ [deg], h [mm], dh/dθ [mm/deg], d²h/dθ² [mm/deg²], d³h/dθ³ [mm/deg³] at T."""
        return dimensional_values(self, t)
