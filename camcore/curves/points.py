"""A lift curve given as measured points, interpolated by a shape-preserving cubic spline.

The points (t_i, s_i) are normalised to T = (t − t0)/(tn − t0) and
S = (s − s_min)/(s_max − s_min); each data interval is one piece, a cubic in Hermite
form fixed by the values and the slopes m_i at its two knots. The slopes are

* those of the C2 cubic spline through the points (not-a-knot end conditions; the
  parabola through 3 points; the straight line through 2), except
* at knots where that spline would overshoot on an interval where the data are
  monotone: there the slope is limited into Fritsch–Carlson's square 0 ≤ m/δ ≤ 3
  (the spline's slope cut to 3·min|δ| or raised to 0 — Hyman's filter), or, on
  request, replaced by the Fritsch–Butland harmonic mean. The curve is C1 at those
  knots only (listed in :attr:`PointsCurve.limited_knots`); a flat data interval
  keeps both slopes zero.

If the user gives the slopes v_i, the curve is the cubic Hermite through the points
with those slopes, unchanged. J is constant on each piece and dJ/dT = 0.

References
----------
.. [1] C. de Boor, A Practical Guide to Splines (2001), ch. IV (cubic spline
   interpolation, the slope equations, not-a-knot end conditions).
.. [2] F. N. Fritsch, R. E. Carlson, "Monotone piecewise cubic interpolation",
   SIAM J. Numer. Anal. 17 (1980) 238-246: the monotonicity region of a cubic
   Hermite piece in (α, β) = (m_i/δ_i, m_{i+1}/δ_i), including the sufficient square
   0 ≤ α, β ≤ 3.
.. [3] F. N. Fritsch, J. Butland, "A method for constructing local monotone piecewise
   cubic interpolants", SIAM J. Sci. Stat. Comput. 5 (1984) 300-304, with Brodlie's
   weighting for uneven spacing (the slope rule of MATLAB's / SciPy's PCHIP).
.. [4] J. M. Hyman, "Accurate monotonicity preserving cubic interpolation", SIAM J.
   Sci. Stat. Comput. 4 (1983) 645-654: limiting a spline's slopes into that square.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import DegenerateCurveError, LimitExceededError
from .base import FloatArray, Scale
from .curve import Curve

#: limited slopes are kept this far inside Fritsch–Carlson's bound m/δ ≤ 3, so that the
#: ratio recomputed in floating point cannot land a rounding error above 3.
_INSIDE_BOUND = 3.0 * (1.0 - 8.0 * np.finfo(float).eps)

#: largest number of points accepted by default (the slope system is solved in O(n),
#: but the exact characteristics inspect every piece).
DEFAULT_MAX_POINTS = 10000


def _as_vector(name: str, values: ArrayLike) -> FloatArray:
    try:
        arr = np.array(values, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise DegenerateCurveError(f"{name} must be a list of numbers.") from exc
    if arr.ndim != 1:
        raise DegenerateCurveError(f"{name} must be a flat list of numbers.")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.nonzero(bad)[0][0])
        raise DegenerateCurveError(f"{name}[{i}] = {float(arr[i])!r}; every value must be a finite number.")
    return arr


def _solve_tridiagonal(lower: FloatArray, diag: FloatArray, upper: FloatArray, rhs: FloatArray) -> FloatArray:
    """Thomas algorithm; row i reads lower[i]·x[i−1] + diag[i]·x[i] + upper[i]·x[i+1] = rhs[i].

    Without pivoting: every pivot of the slope system below stays ≥ the interval
    lengths (the interior rows are diagonally dominant and the not-a-knot rows are
    eliminated into them), so no pivot vanishes.
    """
    n = diag.size
    c = np.empty(n)
    d = np.empty(n)
    c[0] = upper[0] / diag[0]
    d[0] = rhs[0] / diag[0]
    for i in range(1, n):
        pivot = diag[i] - lower[i] * c[i - 1]
        c[i] = upper[i] / pivot if i < n - 1 else 0.0
        d[i] = (rhs[i] - lower[i] * d[i - 1]) / pivot
    x = np.empty(n)
    x[-1] = d[-1]
    for i in range(n - 2, -1, -1):
        x[i] = d[i] - c[i] * x[i + 1]
    return x


def c2_spline_slopes(t: FloatArray, s: FloatArray) -> FloatArray:
    """Knot slopes of the C2 cubic spline through (t, s): not-a-knot (n ≥ 4 points),
    the parabola through 3 points, the line through 2.

    The interior equations (continuity of the second derivative at knot i) are
        h_i m_{i−1} + 2 (h_{i−1} + h_i) m_i + h_{i−1} m_{i+1} = 3 (h_i δ_{i−1} + h_{i−1} δ_i)
    with h_i = t_{i+1} − t_i, δ_i = (s_{i+1} − s_i)/h_i; the end rows make the third
    derivative continuous at the second and the last-but-one knot (de Boor, ch. IV).

    Parameters
    ----------
    t : ndarray
        Knots, strictly increasing, ≥ 2 of them [-] (normalised T).
    s : ndarray
        Values at the knots [-] (normalised S).

    Returns
    -------
    ndarray
        The slope ds/dt at each knot [-].

    References
    ----------
    C. de Boor, A Practical Guide to Splines (2001), ch. IV (the slope equations of the
    cubic spline, not-a-knot end conditions).
    """
    h = np.diff(t)
    delta = np.diff(s) / h
    n = t.size
    if n == 2:
        return np.array([delta[0], delta[0]])
    if n == 3:
        # the parabola through the 3 points: its slope at each knot
        c2 = (delta[1] - delta[0]) / (h[0] + h[1])
        return np.array([delta[0] - c2 * h[0], delta[0] + c2 * h[0], delta[1] + c2 * h[1]])
    lower = np.zeros(n)
    diag = np.zeros(n)
    upper = np.zeros(n)
    rhs = np.zeros(n)
    lower[1:-1] = h[1:]
    diag[1:-1] = 2.0 * (h[:-1] + h[1:])
    upper[1:-1] = h[:-1]
    rhs[1:-1] = 3.0 * (h[1:] * delta[:-1] + h[:-1] * delta[1:])
    d0 = h[0] + h[1]
    diag[0], upper[0] = h[1], d0
    rhs[0] = ((h[0] + 2.0 * d0) * h[1] * delta[0] + h[0] ** 2 * delta[1]) / d0
    d1 = h[-1] + h[-2]
    lower[-1], diag[-1] = d1, h[-2]
    rhs[-1] = (h[-1] ** 2 * delta[-2] + (2.0 * d1 + h[-1]) * h[-2] * delta[-1]) / d1
    return _solve_tridiagonal(lower, diag, upper, rhs)


def hermite_piece_is_monotone(alpha: FloatArray, beta: FloatArray) -> NDArray[np.bool_]:
    """Fritsch–Carlson (1980): is a cubic Hermite piece with slope ratios α, β monotone?

    α = m_i/δ_i, β = m_{i+1}/δ_i for a piece with δ_i ≠ 0. Monotone iff α, β ≥ 0 and
    (α + β ≤ 2, or 2α + β ≤ 3, or α + 2β ≤ 3, or φ = α − (2α + β − 3)²/(3(α + β − 2)) ≥ 0).

    Parameters
    ----------
    alpha : ndarray
        α = m_i/δ_i of each piece, the left slope over the secant [-].
    beta : ndarray
        β = m_{i+1}/δ_i of each piece, the right slope over the secant [-].

    Returns
    -------
    ndarray of bool
        True where the piece is monotone.

    References
    ----------
    F. N. Fritsch, R. E. Carlson, "Monotone piecewise cubic interpolation", SIAM J. Numer.
    Anal. 17 (1980) 238-246: the monotonicity region in (α, β).
    """
    total = alpha + beta - 2.0
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = alpha - (2.0 * alpha + beta - 3.0) ** 2 / (3.0 * total)
    inside = (total <= 0) | (2.0 * alpha + beta <= 3.0) | (alpha + 2.0 * beta <= 3.0) | (phi >= 0)
    return (alpha >= 0) & (beta >= 0) & inside


def _fritsch_butland(h: FloatArray, delta: FloatArray) -> FloatArray:
    """Limited slopes at the interior knots 1..n−2 (Brodlie's weighted harmonic mean).

    0 where the neighbouring secants differ in sign or one is zero; otherwise a value
    of their sign with 0 < m/δ ≤ 3 for both neighbouring δ, inside the square that
    Fritsch–Carlson prove sufficient for monotonicity.
    """
    h_left, h_right = h[:-1], h[1:]
    d_left, d_right = delta[:-1], delta[1:]
    w_left = 2.0 * h_right + h_left
    w_right = h_right + 2.0 * h_left
    same_sign = d_left * d_right > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = (w_left + w_right) / (w_left / d_left + w_right / d_right)
    return np.where(same_sign, mean, 0.0)


def _fritsch_carlson_clamp(slope: FloatArray, delta: FloatArray) -> FloatArray:
    """Interior knots 1..n−2: the C2 slope moved the least into 0 ≤ m/δ ≤ 3 on both sides.

    Fritsch–Carlson's sufficient square applied to the spline's own slopes (Hyman's
    filter): a slope already inside is kept, a larger one is cut to 3·min|δ|, one of the
    wrong sign becomes 0. 0 where the neighbouring secants differ in sign or one is zero.
    """
    d_left, d_right = delta[:-1], delta[1:]
    same_sign = d_left * d_right > 0
    direction = np.sign(d_left)
    bound = _INSIDE_BOUND * np.minimum(np.abs(d_left), np.abs(d_right))
    clamped = direction * np.clip(direction * slope, 0.0, bound)
    return np.where(same_sign, clamped, 0.0)


def _clamp_end_slope(slope: float, delta: float) -> float:
    """Fritsch–Carlson bound at an end knot: m of δ's sign with |m| ≤ 3|δ|."""
    if delta == 0 or slope * delta <= 0:
        return 0.0
    return float(np.sign(delta) * min(abs(slope), _INSIDE_BOUND * abs(delta)))


def monotone_limited_slopes(
    t: FloatArray, s: FloatArray, slopes: FloatArray, limiter: str = "fritsch-carlson"
) -> tuple[FloatArray, NDArray[np.intp]]:
    """Limit the knot slopes so every interval where the data are monotone stays monotone.

    An interval is *monotone data* when its ΔS and its neighbours' ΔS are each of one
    sign or zero. Flat intervals get zero slopes at both ends. On other monotone
    intervals whose cubic would overshoot (exact Fritsch–Carlson test), the knots with
    a slope ratio outside [0, 3] are replaced by limited slopes; this repeats until
    all such intervals pass. Every pass limits at least one new knot, because a
    limited knot has ratios in [0, 3] on both sides and a failing piece has a ratio
    outside, so at most n passes are made.

    Parameters
    ----------
    t : ndarray
        Knots, strictly increasing [-].
    s : ndarray
        Values at the knots [-].
    slopes : ndarray
        Starting slopes ds/dt at the knots [-], e.g. :func:`c2_spline_slopes`.
    limiter : {"fritsch-carlson", "fritsch-butland"}
        The replacement slope: the starting slope cut into 0 ≤ m/δ ≤ 3 (Hyman's filter), or
        the Fritsch–Butland weighted harmonic mean of the neighbouring secants.

    Returns
    -------
    slopes : ndarray
        The final knot slopes [-].
    limited : ndarray of int
        Indices of the knots whose slope differs from the input slope [-].

    References
    ----------
    Fritsch and Carlson (1980), the monotonicity test and the sufficient square 0 ≤ α, β ≤ 3;
    Hyman (1983), limiting a spline's slopes into it; Fritsch and Butland (1984) with
    Brodlie's weights, the harmonic-mean slopes.
    """
    h = np.diff(t)
    ds = np.diff(s)
    delta = ds / h
    sign = np.sign(ds)
    left_sign = np.concatenate([[0.0], sign[:-1]])
    right_sign = np.concatenate([sign[1:], [0.0]])
    monotone_data = (sign == 0) | ((left_sign * sign >= 0) & (right_sign * sign >= 0))
    flat = sign == 0

    limited_value = np.empty(t.size)
    if limiter == "fritsch-butland":
        limited_value[1:-1] = _fritsch_butland(h, delta)
    elif limiter == "fritsch-carlson":
        limited_value[1:-1] = _fritsch_carlson_clamp(slopes[1:-1], delta)
    else:
        raise ValueError(f"unknown slope limiter {limiter!r}")
    limited_value[0] = _clamp_end_slope(slopes[0], delta[0])
    limited_value[-1] = _clamp_end_slope(slopes[-1], delta[-1])

    m = slopes.copy()
    is_limited = np.zeros(t.size, dtype=bool)
    # a flat stretch of data stays flat
    flat_knots = np.zeros(t.size, dtype=bool)
    flat_knots[:-1] |= flat
    flat_knots[1:] |= flat
    m[flat_knots] = 0.0
    is_limited |= flat_knots
    check = monotone_data & ~flat
    for _ in range(t.size + 1):
        with np.errstate(divide="ignore", invalid="ignore"):
            alpha = np.where(check, m[:-1] / delta, 0.0)
            beta = np.where(check, m[1:] / delta, 0.0)
        failing = check & ~hermite_piece_is_monotone(alpha, beta)
        if not failing.any():
            break
        out_left = failing & ((alpha < 0) | (alpha > 3.0))
        out_right = failing & ((beta < 0) | (beta > 3.0))
        knots = np.zeros(t.size, dtype=bool)
        knots[:-1] |= out_left
        knots[1:] |= out_right
        knots &= ~is_limited
        if not knots.any():
            # only rounding-level misses remain (ratios within eps of the square)
            break
        m[knots] = limited_value[knots]
        is_limited |= knots
    changed = is_limited & (m != slopes)
    return m, np.nonzero(changed)[0].astype(np.intp)


class PointsCurve(Curve):
    """A lift curve through measured points (t_i, s_i), optionally with slopes v_i.

    Parameters
    ----------
    t : array_like
        Abscissae (e.g. cam angle [deg] or time [s]), strictly increasing, ≥ 2 values.
    s : array_like
        Lift at each t (e.g. [mm]), same length; not all equal.
    v : array_like, optional
        Slopes ds/dt at each point [s unit/t unit]; if given, the curve is the cubic
        Hermite interpolant with these slopes.
    max_points : int
        Largest accepted number of points (default 10000).
    units : dict, optional
        Names of the units of t and s, stored in :attr:`scale` (``{"theta": …, "h": …}``).
    slope_limiter : {"fritsch-carlson", "fritsch-butland"}
        How a knot slope that makes monotone data overshoot is replaced: cut into the
        Fritsch–Carlson square 0 ≤ m/δ ≤ 3 (default; keeps the spline's slope when it
        is already inside, so it disturbs the C2 curve least), or replaced by the
        Fritsch–Butland harmonic mean of the neighbouring secants.

    Raises
    ------
    DegenerateCurveError
        Non-finite values, mismatched lengths, fewer than 2 points, t not strictly
        increasing, or all s equal.
    LimitExceededError
        More points than ``max_points``.

    Attributes
    ----------
    scale : Scale
        t = t0 + theta_span·T, s = h_min + h_span·S.
    knots_t, knots_s, knot_slopes : ndarray
        Normalised knots T_i, S_i and slopes dS/dT at them.
    limited_knots : ndarray of int
        Knots where the C2 spline's slope was limited to keep monotone data monotone
        (the curve is only C1 there). Empty when ``v`` is given.
    """

    def __init__(
        self,
        t: ArrayLike,
        s: ArrayLike,
        v: ArrayLike | None = None,
        max_points: int = DEFAULT_MAX_POINTS,
        units: dict[str, str] | None = None,
        slope_limiter: str = "fritsch-carlson",
    ):
        t_arr = _as_vector("t", t)
        # the limit is checked before any O(n) work beyond reading the input
        if t_arr.size > max_points:
            raise LimitExceededError("number of points", int(t_arr.size), max_points, field=("t",))
        s_arr = _as_vector("s", s)
        v_arr = _as_vector("v", v) if v is not None else None
        if s_arr.size != t_arr.size or (v_arr is not None and v_arr.size != t_arr.size):
            sizes = f"t has {t_arr.size}, s has {s_arr.size}" + (f", v has {v_arr.size}" if v_arr is not None else "")
            raise DegenerateCurveError(f"t, s (and v) must have one value per point; {sizes}.")
        if t_arr.size < 2:
            raise DegenerateCurveError("a lift curve from points needs at least 2 points.")
        step = np.diff(t_arr)
        if np.any(step <= 0):
            i = int(np.nonzero(step <= 0)[0][0]) + 1
            raise DegenerateCurveError(
                f"t must increase strictly: t[{i}] = {float(t_arr[i])!r} does not exceed "
                f"t[{i - 1}] = {float(t_arr[i - 1])!r}."
            )
        t_span = float(t_arr[-1] - t_arr[0])
        s_min, s_max = float(np.min(s_arr)), float(np.max(s_arr))
        s_span = s_max - s_min
        if not s_span > 0:
            raise DegenerateCurveError("all points have the same s, so there is no lift to follow.")
        if not (np.isfinite(t_span) and np.isfinite(s_span)):
            raise DegenerateCurveError("the range of t or of s overflows; rescale the data.")
        knots_t = (t_arr - t_arr[0]) / t_span
        knots_t[-1] = 1.0
        if np.any(np.diff(knots_t) <= 0):
            i = int(np.nonzero(np.diff(knots_t) <= 0)[0][0]) + 1
            raise DegenerateCurveError(
                f"t[{i - 1}] and t[{i}] are too close to tell apart relative to the range of t."
            )
        knots_s = (s_arr - s_min) / s_span
        if v_arr is not None:
            # dS/dT = (ds/dt)·t_span/s_span
            slopes = v_arr * (t_span / s_span)
            limited = np.zeros(0, dtype=np.intp)
        else:
            c2 = c2_spline_slopes(knots_t, knots_s)
            slopes, limited = monotone_limited_slopes(knots_t, knots_s, c2, slope_limiter)
        self.scale = Scale(
            theta_start=float(t_arr[0]), theta_span=t_span, h_min=s_min, h_span=s_span, units=dict(units or {})
        )
        self.knots_t = knots_t
        self.knots_s = knots_s
        self.knot_slopes = slopes
        self.limited_knots = limited
        self.piece_starts = knots_t[:-1].copy()
        self.t_end = 1.0
        # power form on each piece about its left knot: S = S_i + m_i τ + c2 τ² + c3 τ³
        h = np.diff(knots_t)
        delta = np.diff(knots_s) / h
        m_left, m_right = slopes[:-1], slopes[1:]
        self._c2 = (3.0 * delta - 2.0 * m_left - m_right) / h
        self._c3 = (m_left + m_right - 2.0 * delta) / h**2

    def eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        tau = t - self.knots_t[piece]
        m = self.knot_slopes[piece]
        c2 = self._c2[piece]
        c3 = self._c3[piece]
        out = [self.knots_s[piece] + tau * (m + tau * (c2 + tau * c3))]
        if order >= 1:
            out.append(m + tau * (2.0 * c2 + 3.0 * c3 * tau))
        if order >= 2:
            out.append(2.0 * c2 + 6.0 * c3 * tau)
        if order >= 3:
            out.append(6.0 * c3 + 0.0 * tau)
        if order >= 4:
            out.append(np.zeros_like(tau))
        return out

    def dimensional(self, t: ArrayLike) -> dict[str, FloatArray]:
        """t, s, ds/dt, d²s/dt², d³s/dt³ in the data's units at T (keys as in Bezier)."""
        from .bezier import dimensional_values

        return dimensional_values(self, t)
