"""BezierCurve: a lift h(θ) drawn with Bezier control points in the (θ [deg], h [mm]) plane.

Sources (docs/sources.md): valve-cam notes, "ベジエによるバルブカム設計", eqs.
(1)-(3) (Bezier curve, V = (dh/ds)/(dθ/ds), A = (dV/ds)/(dθ/ds)); Farin, Curves and
Surfaces for CAGD, ch. 4-5 (Bernstein form, derivative control points). The expected
values of the hand-worked cases are derived in the comments from the Bernstein basis
B_k^3(s) = C(3, k) s^k (1 − s)^(3−k), not from camcore.
"""

from __future__ import annotations

from fractions import Fraction as F

import mpmath
import numpy as np
import pytest

from camcore.curves.bezier import BezierCurve
from camcore.errors import DegenerateCurveError, LimitExceededError, NonMonotoneError

EPS = np.finfo(float).eps

# ----------------------------------------------------------------------------- hand-worked
# Case 1, θ linear in s. Control points (0, 0), (30, 0), (60, 10), (90, 10):
#   θ(s) = 30·3s(1−s)² + 60·3s²(1−s) + 90s³ = 90s   (equally spaced θ_k: linear precision)
#   h(s) = 10·3s²(1−s) + 10s³ = 30s² − 20s³
# so T = θ/90 = s, dθ/ds = 90, dh/ds = 60s − 60s², d²h/ds² = 60 − 120s, and
#   dh/dθ = (60s − 60s²)/90 = (2/3)(s − s²)          [mm/deg]
#   d²h/dθ² = (60 − 120s)/90² = (1 − 2s)/135          [mm/deg²]
#   d³h/dθ³ = −120/90³ = −4/24300                       [mm/deg³]
# h(s) is increasing on [0, 1] (dh/ds ≥ 0), so h_min = 0, h_max = 10.
LINEAR_THETA = [[0, 0], [30, 0], [60, 10], [90, 10]]
LINEAR_THETA_EXPECTED = {
    # s: (θ, h, dh/dθ, d²h/dθ²)
    F(0): (F(0), F(0), F(0), F(1, 135)),
    F(1, 4): (F(45, 2), F(25, 16), F(1, 8), F(1, 270)),
    F(1, 2): (F(45), F(5), F(1, 6), F(0)),
    F(3, 4): (F(135, 2), F(135, 16), F(1, 8), F(-1, 270)),
    F(1): (F(90), F(10), F(0), F(-1, 135)),
}

# Case 2, θ not linear in s. Control points (0, 0), (10, 0), (60, 10), (90, 10):
#   θ(s) = 10·3s(1−s)² + 60·3s²(1−s) + 90s³ = 30s + 120s² − 60s³
#   dθ/ds = 30 + 240s − 180s² (≥ 30 on [0, 1]),  d²θ/ds² = 240 − 360s
#   h(s) = 30s² − 20s³ as in case 1, dh/ds = 60s − 60s², d²h/ds² = 60 − 120s
# and by the chain rule (eqs. 2, 3 of the reference):
#   dh/dθ = h'/θ',   d²h/dθ² = (h'' − (dh/dθ)·θ'')/θ'²
# s = 1/4: θ = 225/16, h = 25/16, θ' = 315/4, h' = 45/4, θ'' = 150, h'' = 30
#          dh/dθ = 1/7, d²h/dθ² = (30 − 150/7)/(315/4)² = 64/46305
# s = 1/2: θ = 75/2, h = 5, θ' = 105, h' = 15, θ'' = 60, h'' = 0
#          dh/dθ = 1/7, d²h/dθ² = (0 − 60/7)/105² = −4/5145
# s = 3/4: θ = 1035/16, h = 135/16, θ' = 435/4, h' = 45/4, θ'' = −30, h'' = −30
#          dh/dθ = 3/29, d²h/dθ² = (−780/29)/(435/4)² = −12480/5487525 = −832/365835
CURVED_THETA = [[0, 0], [10, 0], [60, 10], [90, 10]]


def _curved_expected(s: F) -> tuple[F, F, F, F]:
    """Case 2 from the polynomials written out above (exact rational arithmetic)."""
    theta = 30 * s + 120 * s**2 - 60 * s**3
    h = 30 * s**2 - 20 * s**3
    d_theta, dd_theta = 30 + 240 * s - 180 * s**2, 240 - 360 * s
    d_h, dd_h = 60 * s - 60 * s**2, 60 - 120 * s
    slope = d_h / d_theta
    return theta, h, slope, (dd_h - slope * dd_theta) / d_theta**2


def test_curved_expected_matches_the_hand_values() -> None:
    # guards the helper above against typos: the three hand-worked points
    assert _curved_expected(F(1, 4)) == (F(225, 16), F(25, 16), F(1, 7), F(64, 46305))
    assert _curved_expected(F(1, 2)) == (F(75, 2), F(5), F(1, 7), F(-4, 5145))
    assert _curved_expected(F(3, 4)) == (F(1035, 16), F(135, 16), F(3, 29), F(-832, 365835))


# The hand values are exact rationals; camcore evaluates them in float64 through
# de Casteljau (a handful of roundings of numbers ≤ 90) and, when given T, through a
# Newton solve of θ(s) = θ0 + T·span converged to the spacing of floats. 1e-13
# relative to each quantity's scale (90 deg, 10 mm, 10/90 mm/deg, 10/90² mm/deg²)
# is ~500 ulp: far above that rounding, far below any algebra slip (≥ 1e-3 here).
HAND_RTOL = 1e-13
SCALES = (90.0, 10.0, 10.0 / 90.0, 10.0 / 90.0**2)


def _dimensional_at_parameter(curve: BezierCurve, s: float) -> tuple[float, float, float, float]:
    t, s_norm, v, a = (float(x) for x in curve.at_parameter(np.array(s), order=2))
    sc = curve.scale
    rate = sc.h_span / sc.theta_span
    return (sc.theta_start + sc.theta_span * t, sc.h_min + sc.h_span * s_norm, rate * v, rate / sc.theta_span * a)


@pytest.mark.parametrize("s", list(LINEAR_THETA_EXPECTED))
def test_hand_cubic_with_linear_theta(s: F) -> None:
    curve = BezierCurve(LINEAR_THETA)
    assert curve.scale.h_min == 0.0 and curve.scale.h_span == 10.0
    expected = LINEAR_THETA_EXPECTED[s]
    got = _dimensional_at_parameter(curve, float(s))
    for g, e, scale in zip(got, expected, SCALES):
        assert abs(g - float(e)) <= HAND_RTOL * scale
    # θ is linear, so T = s and the T-based evaluation must agree
    via_t = curve.dimensional(np.array(float(s)))
    for key, e, scale in zip(("theta", "h", "dh_dtheta", "d2h_dtheta2"), expected, SCALES):
        assert abs(float(via_t[key]) - float(e)) <= HAND_RTOL * scale
    assert abs(float(via_t["d3h_dtheta3"]) - (-4 / 24300)) <= HAND_RTOL * 10 / 90**3


@pytest.mark.parametrize("s", [F(0), F(1, 4), F(1, 2), F(3, 4), F(1)])
def test_hand_cubic_with_curved_theta(s: F) -> None:
    curve = BezierCurve(CURVED_THETA)
    expected = _curved_expected(s)
    got = _dimensional_at_parameter(curve, float(s))
    for g, e, scale in zip(got, expected, SCALES):
        assert abs(g - float(e)) <= HAND_RTOL * scale
    # through T = θ(s)/90: exercises the solve for s
    via_t = curve.dimensional(np.array(float(expected[0]) / 90.0))
    for key, e, scale in zip(("theta", "h", "dh_dtheta", "d2h_dtheta2"), expected, SCALES):
        assert abs(float(via_t[key]) - float(e)) <= HAND_RTOL * scale
    assert float(curve.parameter_at(np.array(float(expected[0]) / 90.0))) == pytest.approx(float(s), abs=1e-14)


def test_lift_extremes_come_from_the_curve_not_the_control_polygon() -> None:
    # (0, 0), (45, 20), (90, 0): h(s) = 20·2s(1−s) = 40s(1−s), largest at s = 1/2: 10 mm,
    # while the middle control point sits at 20 mm. 1e-13 mm: rounding of a few terms ≤ 20.
    curve = BezierCurve([[0, 0], [45, 20], [90, 0]])
    assert curve.scale.h_min == 0.0
    assert abs(curve.scale.h_span - 10.0) <= 1e-13
    ch = curve.characteristics
    assert abs(ch.s_max.value - 1.0) <= 1e-15 and abs(ch.s_max.t - 0.5) <= 1e-8


# ----------------------------------------------------------------------------- a harder curve
# Degree 6, θ spaced unevenly (so θ(s) is not linear), h rising, overshooting and
# coming back down: V, A, J all change sign, extremes of h lie inside the curve.
GENERAL = [[-20, 1.0], [0, 1.0], [35, 2.0], [40, 9.0], [70, 11.5], [100, 4.0], [130, 4.5]]


def _mp_reference(points: list[list[float]], theta: mpmath.mpf, order: int) -> list[mpmath.mpf]:
    """h and d^k h/dθ^k (k ≤ order) at θ, in 40-digit arithmetic, independent of camcore.

    The Bernstein sums are written out directly, s(θ) is found by mpmath.findroot and the
    θ-derivatives by mpmath.diff (high-precision finite differences).
    """
    n = len(points) - 1
    th = [mpmath.mpf(p[0]) for p in points]
    hh = [mpmath.mpf(p[1]) for p in points]

    def bern(c: list[mpmath.mpf], s: mpmath.mpf) -> mpmath.mpf:
        return mpmath.fsum(c[k] * mpmath.binomial(n, k) * s**k * (1 - s) ** (n - k) for k in range(n + 1))

    def lift(angle: mpmath.mpf) -> mpmath.mpf:
        guess = (angle - th[0]) / (th[-1] - th[0])
        s = mpmath.findroot(lambda x: bern(th, x) - angle, guess)
        return bern(hh, s)

    return [mpmath.diff(lift, theta, k) for k in range(order + 1)]


def test_derivatives_against_a_40_digit_reference() -> None:
    curve = BezierCurve(GENERAL)
    sc = curve.scale
    t = np.array([0.0, 0.013, 0.2, 0.37, 0.5, 0.61, 0.8, 0.999, 1.0])
    ours = curve.derivatives(t, 4)
    dense = curve.derivatives(np.linspace(0, 1, 2001), 4)
    with mpmath.workdps(40):
        for i, ti in enumerate(t):
            theta = mpmath.mpf(sc.theta_start) + mpmath.mpf(sc.theta_span) * mpmath.mpf(ti)
            ref = _mp_reference(GENERAL, theta, 4)
            for k in range(5):
                # dimensionless k-th derivative: d^k h/dθ^k · span^k / h_span
                expected = float(ref[k] * mpmath.mpf(sc.theta_span) ** k / mpmath.mpf(sc.h_span))
                if k == 0:
                    expected = float((ref[0] - mpmath.mpf(sc.h_min)) / mpmath.mpf(sc.h_span))
                # float64 error ≈ a few ulp of the quantity's peak, amplified by the
                # chain rule's 1/(dθ/ds)^k (dθ/ds ≥ 0.8 here, normalised): measured
                # worst 4e-15 of the peak; 1e-11 leaves room for other platforms and
                # is still 10^6 below the effect of a wrong term in the formulas.
                peak = float(np.max(np.abs(dense[k])))
                assert abs(ours[k][i] - expected) <= 1e-11 * peak, (k, ti)


def test_derivatives_against_central_differences() -> None:
    # V vs differences of S, A vs differences of V, J vs differences of A, dJ vs of J.
    # Central difference error ≤ δ²/6·sup|X'''| (truncation) + 2·eps·sup|X|/δ (rounding
    # of X, which is accurate to ~eps of its peak). sup|X'''| is bounded by the sampled
    # maximum of the derivative three orders up (computed below for S, V; the top two
    # orders use a differenced estimate) times 2 as margin for the sampling.
    curve = BezierCurve(GENERAL)
    t = np.linspace(0.002, 0.998, 499)
    step = 1e-4
    fine = np.linspace(0, 1, 20001)
    vals = curve.derivatives(fine, 4)
    # derivative 5 and 6 of S (not provided) from differences of dJ/dT: a sup estimate
    d5 = np.gradient(vals[4], fine)
    d6 = np.gradient(d5, fine)
    sups = [float(np.max(np.abs(x))) for x in (*vals, d5, d6)]
    here = curve.derivatives(t, 4)
    plus = curve.derivatives(t + step, 4)
    minus = curve.derivatives(t - step, 4)
    for k in range(4):
        central = (plus[k] - minus[k]) / (2 * step)
        tol = step**2 / 6 * 2 * sups[k + 3] + 2 * 10 * EPS * sups[k] / step
        assert np.max(np.abs(central - here[k + 1])) <= tol, k


def test_characteristics_bound_a_dense_sample() -> None:
    # Sampled peaks never exceed the exact ones (up to rounding, 1e-12 of the peak) and
    # come within the grid error: a peak of X between samples Δ apart is missed by at
    # most Δ²/8·sup|X''| (Taylor about the peak, where X' = 0).
    curve = BezierCurve(GENERAL)
    ch = curve.characteristics
    grid = np.linspace(0, 1, 100001)
    delta = grid[1] - grid[0]
    s, v, a, j, dj = curve.derivatives(grid, 4)
    fine_sup = {"s": np.max(np.abs(a)), "v": np.max(np.abs(j)), "a": np.max(np.abs(dj))}
    for name, data, exact_max, exact_min in (
        ("s", s, ch.s_max.value, ch.s_min.value),
        ("v", v, ch.v_max.value, ch.v_min.value),
        ("a", a, ch.am_pos.value, ch.am_neg.value),
    ):
        peak = max(abs(exact_max), abs(exact_min))
        slack = 1e-12 * peak
        grid_err = delta**2 / 8 * 2 * fine_sup[name] + slack
        assert np.max(data) <= exact_max + slack, name
        assert np.max(data) >= exact_max - grid_err, name
        assert np.min(data) >= exact_min - slack, name
        assert np.min(data) <= exact_min + grid_err, name
    # S is normalised on the exact extremes of h(s): its range is [0, 1]
    assert abs(ch.s_max.value - 1.0) <= 1e-14 and abs(ch.s_min.value) <= 1e-14
    # the extremes lie inside, not at the ends (the test would be weak otherwise)
    assert 0.05 < ch.s_max.t < 0.95


def test_inverse_undoes_forward_on_a_rising_curve() -> None:
    # |ΔT| ≤ |ΔS|/V: S is exact to a few eps, and V ≥ 0.3 on [0.05, 0.95] for this
    # cubic (V = 6T(1−T) in case 1), so 1e-13 is ~100 times the rounding.
    curve = BezierCurve(CURVED_THETA)
    t = np.linspace(0.05, 0.95, 181)
    s = curve.derivatives(t, 0)[0]
    assert np.max(np.abs(curve.inverse(s) - t)) <= 1e-13
    assert curve.inverse(np.array([0.0, 1.0])).tolist() == [0.0, 1.0]


def test_inverse_refuses_a_rise_and_fall() -> None:
    with pytest.raises(NonMonotoneError):
        BezierCurve(GENERAL).inverse(np.array([0.5]))


def test_dimensionless_range_and_line_case() -> None:
    # two control points: a straight line h = 2 + 3(θ − 10)/50, V = 1, A = J = dJ = 0 exactly
    # up to rounding of numbers ≤ 1 (1e-14).
    curve = BezierCurve([[10, 2], [60, 5]])
    t = np.linspace(0, 1, 11)
    s, v, a, j, dj = curve.derivatives(t, 4)
    assert np.max(np.abs(s - t)) <= 1e-15
    assert np.max(np.abs(v - 1.0)) <= 1e-14
    assert np.max(np.abs(np.concatenate([a, j, dj]))) <= 1e-14
    dim = curve.dimensional(t)
    assert np.max(np.abs(dim["dh_dtheta"] - 3 / 50)) <= 1e-15


# ----------------------------------------------------------------------------- errors
def test_turning_back_is_rejected_with_its_location() -> None:
    # θ_k = 0, 100, −10, 90, forward differences 100, −110, 100:
    #   (1/3)·dθ/ds = 100(1−s)² − 110·2s(1−s) + 100s² = 420s² − 420s + 100,
    # negative between its roots s = 1/2 ± √8400/840 ≈ 0.391, 0.609: θ turns back from
    # s ≈ 0.39 on, and the message says so.
    with pytest.raises(DegenerateCurveError, match=r"turn back in θ near s = 0\.39"):
        BezierCurve([[0, 0], [100, 1], [-10, 2], [90, 3]])


@pytest.mark.parametrize(
    ("points", "where"),
    [
        # θ_0 = θ_1: dθ/ds = 3(θ_1 − θ_0) = 0 at s = 0
        ([[0, 0], [0, 5], [60, 8], [90, 10]], "0.00"),
        # θ_k = 0, 90, 0, 90: (1/3)·dθ/ds = 90(1−s)² − 180s(1−s) + 90s² = 90(2s − 1)², zero at s = 1/2
        ([[0, 0], [90, 1], [0, 2], [90, 3]], "0.50"),
    ],
)
def test_vertical_tangent_is_rejected(points: list[list[float]], where: str) -> None:
    with pytest.raises(DegenerateCurveError, match=rf"vertical tangent .* s = {where}"):
        BezierCurve(points)


def test_theta_not_increasing_end_to_end_is_rejected() -> None:
    with pytest.raises(DegenerateCurveError, match="drive angle has to increase"):
        BezierCurve([[90, 0], [60, 1], [0, 2]])


def test_constant_lift_is_rejected() -> None:
    with pytest.raises(DegenerateCurveError, match="same lift"):
        BezierCurve([[0, 3.0], [40, 3.0], [90, 3.0]])


def test_degree_over_the_limit() -> None:
    points = np.column_stack([np.linspace(0, 90, 32), np.linspace(0, 1, 32)])  # degree 31
    with pytest.raises(LimitExceededError) as info:
        BezierCurve(points)
    assert (info.value.what, info.value.requested, info.value.limit) == ("Bezier degree", 31, 30)
    with pytest.raises(LimitExceededError):
        BezierCurve(points[:5], max_degree=3)
    # the limit itself is allowed
    BezierCurve(points[:31])


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_control_points(bad: float) -> None:
    with pytest.raises(DegenerateCurveError, match=r"control point 1 has h"):
        BezierCurve([[0, 0], [30, bad], [90, 1]])


@pytest.mark.parametrize("points", [[[0, 0]], [[0, 0, 0], [1, 1, 1]], [1, 2, 3], [["a", 0], [1, 1]]])
def test_malformed_control_points(points: object) -> None:
    with pytest.raises(DegenerateCurveError):
        BezierCurve(points)  # type: ignore[arg-type]
