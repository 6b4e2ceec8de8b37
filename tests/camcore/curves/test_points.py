"""PointsCurve: measured lift points interpolated by a C2 spline, limited where it would overshoot.

Sources: de Boor, A Practical Guide to Splines (2001), ch. IV (slope equations,
not-a-knot conditions: the spline reproduces cubics); Fritsch & Carlson, SIAM J. Numer.
Anal. 17 (1980) (monotone cubic Hermite pieces); Hall & Meyer, "Optimal error bounds for
cubic spline interpolation", J. Approx. Theory 16 (1976) (‖f − s‖ ≤ 5/384·h⁴‖f⁗‖,
‖f′ − s′‖ ≤ 1/24·h³‖f⁗‖, ‖f″ − s″‖ ≤ 3/8·h²‖f⁗‖); the INDEXMAN modified sine (MS)
curve from camcore's catalog, itself checked against Makino (1977) in test_mp_reference.py.
"""

from __future__ import annotations

import numpy as np
import pytest

import camcore
from camcore.curves.points import PointsCurve, c2_spline_slopes, hermite_piece_is_monotone
from camcore.errors import DegenerateCurveError, LimitExceededError, NonMonotoneError

EPS = np.finfo(float).eps


def one_sided(curve: PointsCurve, knot: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """[S, V, A, J] at an interior knot from the piece on its left and on its right."""
    at = np.array([curve.knots_t[knot]])
    left = curve.eval_pieces(at, np.array([knot - 1]), order)
    right = curve.eval_pieces(at, np.array([knot]), order)
    return np.array([x[0] for x in left]), np.array([x[0] for x in right])


# a smooth, non-monotone data set on uneven abscissae (no knot needs limiting)
SMOOTH_T = np.array([0.0, 0.7, 1.1, 2.0, 2.4, 3.3, 4.0, 5.2, 6.0])
SMOOTH_S = np.sin(SMOOTH_T) + 0.3 * SMOOTH_T


def test_interpolates_the_data_exactly() -> None:
    # at a knot the left end of its piece returns S_i itself; at the right end the cubic
    # sums four terms ≤ ~1, so a few ulp (4·eps) is the most rounding can do.
    curve = PointsCurve(SMOOTH_T, SMOOTH_S, units={"theta": "deg", "h": "mm"})
    dim = curve.dimensional(curve.knots_t)
    assert np.max(np.abs(dim["theta"] - SMOOTH_T)) <= 4 * EPS * SMOOTH_T.max()
    assert np.max(np.abs(dim["h"] - SMOOTH_S)) <= 4 * EPS * np.abs(SMOOTH_S).max()
    assert curve.scale.units == {"theta": "deg", "h": "mm"}
    s_right_ends = curve.eval_pieces(curve.knots_t[1:], np.arange(len(SMOOTH_T) - 1), 0)[0]
    assert np.max(np.abs(s_right_ends - curve.knots_s[1:])) <= 4 * EPS


def test_c2_at_every_knot_when_nothing_was_limited() -> None:
    curve = PointsCurve(SMOOTH_T, SMOOTH_S)
    assert curve.limited_knots.size == 0
    peak_a = np.max(np.abs(curve.knot_slopes)) / np.min(np.diff(curve.knots_t))
    for knot in range(1, len(SMOOTH_T) - 1):
        left, right = one_sided(curve, knot, 3)
        # S, V, A continuous: A = 2c2 is formed from slopes solved to ~eps, divided by an
        # interval (≥ 0.067 here); 1e-12 of max|V|/min h is ~1000× that rounding, and a
        # spline that is only C1 jumps in A by O(1) of that scale.
        assert np.max(np.abs(left[:3] - right[:3])) <= 1e-12 * peak_a, knot
    # not-a-knot: J is also continuous at the second and last-but-one knots
    for knot in (1, len(SMOOTH_T) - 2):
        left, right = one_sided(curve, knot, 3)
        assert abs(left[3] - right[3]) <= 1e-10 * peak_a / np.min(np.diff(curve.knots_t)), knot
    # and it is genuinely a cubic spline, not a global polynomial: J jumps elsewhere
    left, right = one_sided(curve, 3, 3)
    assert abs(left[3] - right[3]) > 1e-3


def test_reproduces_a_cubic() -> None:
    # not-a-knot splines reproduce cubics (de Boor ch. IV). s = 1 + 2t − 3t² + 5t³ is
    # increasing (s' = 2 − 6t + 15t² > 0), so the exact cubic is monotone and no knot is
    # limited. Tolerance: slopes from a tridiagonal solve, errors ~10 eps of the values.
    t = np.array([0.0, 0.1, 0.35, 0.5, 0.9, 1.0])
    s = 1 + 2 * t - 3 * t**2 + 5 * t**3
    curve = PointsCurve(t, s)
    assert curve.limited_knots.size == 0
    tt = np.linspace(0, 1, 1001)
    dim = curve.dimensional(tt)
    assert np.max(np.abs(dim["h"] - (1 + 2 * tt - 3 * tt**2 + 5 * tt**3))) <= 1e-13
    assert np.max(np.abs(dim["dh_dtheta"] - (2 - 6 * tt + 15 * tt**2))) <= 1e-12
    assert np.max(np.abs(dim["d2h_dtheta2"] - (-6 + 30 * tt))) <= 1e-10
    assert np.max(np.abs(dim["d3h_dtheta3"] - 30)) <= 1e-8


def test_three_points_give_the_parabola_and_two_the_line() -> None:
    # (0, 0), (1, 1), (3, 0): the parabola s = t(3 − t)/2 (check: s(1) = 1, s(3) = 0)
    curve = PointsCurve([0.0, 1.0, 3.0], [0.0, 1.0, 0.0])
    tt = np.linspace(0, 1, 31)
    dim = curve.dimensional(tt)
    x = dim["theta"]
    assert np.max(np.abs(dim["h"] - x * (3 - x) / 2)) <= 1e-14
    assert np.max(np.abs(dim["d2h_dtheta2"] + 1.0)) <= 1e-13
    line = PointsCurve([2.0, 4.0], [1.0, 0.0])
    s, v, a = line.derivatives(tt, 2)
    assert np.max(np.abs(s - (1 - tt))) <= 1e-15 and np.all(v == -1.0) and np.all(a == 0.0)


# ----------------------------------------------------------------------------- monotone data
# dwell – sharp rise – dwell, sampled at integers: data non-decreasing everywhere
STEP_T = np.arange(11.0)
STEP_S = np.array([0, 0, 0, 0, 0, 0.5, 1, 1, 1, 1, 1.0])


def test_the_plain_c2_spline_overshoots_a_dwell_rise_dwell() -> None:
    # the unlimited spline, built as a Hermite curve with the C2 slopes, rings at the corners
    plain = PointsCurve(STEP_T, STEP_S, v=c2_spline_slopes(STEP_T, STEP_S))
    ch = plain.characteristics
    # measured: 1.0395 and −0.0395, i.e. ±4 % of the stroke
    assert ch.s_max.value > 1.03 and ch.s_min.value < -0.03


def test_monotone_data_stay_monotone_and_flat_stays_flat() -> None:
    curve = PointsCurve(STEP_T, STEP_S)
    ch = curve.characteristics
    # exact extrema: no overshoot above the top dwell or below the bottom one, V never < 0
    # (1e-15: the rounding of S = S_i + 0·τ…, and of V near 0)
    assert ch.s_max.value <= 1.0 + 1e-15 and ch.s_min.value >= -1e-15
    assert ch.v_min.value >= -1e-15
    # flat intervals: S is exactly the data value and V exactly 0 throughout
    tt = np.linspace(0, 1, 2001)
    s, v = curve.derivatives(tt, 1)
    low = tt <= curve.knots_t[4]
    high = tt >= curve.knots_t[6]
    assert np.all(s[low] == 0.0) and np.all(v[low] == 0.0)
    assert np.all(s[high] == 1.0) and np.all(v[high] == 0.0)
    assert set(curve.limited_knots.tolist()) >= {3, 4, 6, 7}


def test_limiting_on_a_steep_rise_without_flats() -> None:
    # a ramp of slope 0.1 with a jump of 1 between t = 6 and 7, sampled at the integers:
    # strictly increasing data, but the C2 spline turns back on both sides of the jump
    # (measured V_min = −0.79); the knots around the jump get limited, the far ones stay C2.
    t = np.arange(16.0)
    s = 0.1 * t + np.where(t >= 7, 1.0, 0.0)
    plain = PointsCurve(t, s, v=c2_spline_slopes(t, s))
    assert plain.characteristics.v_min.value < -0.5
    curve = PointsCurve(t, s)
    assert set(curve.limited_knots.tolist()) <= set(range(4, 10))
    # V may touch 0 at a knot whose slope was raised to 0; −1e-15 allows its rounding
    assert curve.characteristics.v_min.value >= -1e-15
    # every piece passes the exact Fritsch–Carlson monotonicity test
    delta = np.diff(curve.knots_s) / np.diff(curve.knots_t)
    assert np.all(hermite_piece_is_monotone(curve.knot_slopes[:-1] / delta, curve.knot_slopes[1:] / delta))
    peak_a = np.max(np.abs(curve.derivatives(np.linspace(0, 1, 2001), 2)[2]))
    jumps = []
    for knot in range(1, len(t) - 1):
        left, right = one_sided(curve, knot, 2)
        # V continuous everywhere (C1); slopes are shared by both pieces, ~eps
        assert abs(left[1] - right[1]) <= 1e-13
        jumps.append(abs(left[2] - right[2]) / peak_a)
    jumps_arr = np.array(jumps)
    limited_inside = np.isin(np.arange(1, len(t) - 1), curve.limited_knots)
    unlimited_inside = ~limited_inside & ~np.isin(np.arange(1, len(t) - 1) - 1, curve.limited_knots) & ~np.isin(
        np.arange(1, len(t) - 1) + 1, curve.limited_knots
    )
    # A jumps at some limited knot (only C1 there) …
    assert np.max(jumps_arr[limited_inside]) > 1e-3
    # … and a knot whose own slope and neighbours' slopes are all the C2 spline's keeps
    # A continuous (1e-12 of the peak: ~1000× the rounding of 2c2 = (6δ − 4m − 2m')/h)
    assert unlimited_inside.sum() >= 6
    assert np.max(jumps_arr[unlimited_inside]) <= 1e-12


def test_butland_limiter_is_also_monotone() -> None:
    curve = PointsCurve(STEP_T, STEP_S, slope_limiter="fritsch-butland")
    ch = curve.characteristics
    assert ch.s_max.value <= 1.0 + 1e-15 and ch.s_min.value >= -1e-15 and ch.v_min.value >= -1e-15
    with pytest.raises(ValueError):
        PointsCurve(STEP_T, STEP_S, slope_limiter="akima")


def test_data_extremum_may_overshoot_between_samples() -> None:
    # rise then fall: the intervals next to the top are not monotone data, so the curve
    # may (and for a sampled smooth peak should) rise above the largest sample. sin on
    # [0, 3] at 8 points misses the peak sin(π/2) = 1 (largest sample sin(12/7) ≈ 0.9897).
    t = np.linspace(0, 3, 8)
    curve = PointsCurve(t, np.sin(t))
    assert curve.limited_knots.size == 0
    peak = curve.characteristics.s_max.value
    assert peak > 1.0
    # the true peak in normalised units is 1/h_span (h_min = sin 0 = 0); Hall–Meyer:
    # |error| ≤ 5/384·h⁴·sup|sin⁗| = 5/384·(3/7)⁴ [data units], measured 9e-5 < 4.4e-4
    assert abs(peak - 1.0 / curve.scale.h_span) <= 5 / 384 * (3 / 7) ** 4 / curve.scale.h_span


# ----------------------------------------------------------------------------- accuracy
@pytest.mark.parametrize("n_points", [41, 81])
def test_reproduces_the_modified_sine_curve(n_points: int) -> None:
    # MS has J jumps at T = 1/8 and 7/8, which fall on knots of both grids (5h, 35h for
    # h = 1/40), so between knots it is analytic and the Hall–Meyer bounds apply piece by
    # piece with ‖S⁗‖ = sup|dJ/dT| = Am·(4π)² (first section, A = Am·sin 4πT). They are
    # proved for complete end conditions; ours are not-a-knot with the end slope clamped
    # to 0, which is the exact V(0) of MS. Measured for 41 points: 1.5e-6, 1.8e-4, 0.049
    # against bounds 4.4e-6, 5.7e-4, 0.20.
    ms = camcore.named_curve("MS")
    t = np.linspace(0, 1, n_points)
    curve = PointsCurve(t, ms.derivatives(t, 0)[0])
    h = 1 / (n_points - 1)
    d4 = ms.characteristics.am * (4 * np.pi) ** 2
    fine = np.linspace(0, 1, 20001)
    ours = curve.derivatives(fine, 2)
    exact = ms.derivatives(fine, 2)
    bounds = (5 / 384 * h**4 * d4, 1 / 24 * h**3 * d4, 3 / 8 * h**2 * d4)
    for k in range(3):
        assert np.max(np.abs(ours[k] - exact[k])) <= bounds[k], k


def test_error_falls_as_h_to_the_fourth() -> None:
    # halving h must cut the displacement error by ~16 (fourth order); a limiter that
    # disturbed the spline more (e.g. the Fritsch–Butland harmonic mean at knot 1) drops
    # to third order (8): require > 12 to tell them apart.
    ms = camcore.named_curve("MS")
    fine = np.linspace(0, 1, 20001)
    errors = []
    for n_points in (41, 81):
        t = np.linspace(0, 1, n_points)
        curve = PointsCurve(t, ms.derivatives(t, 0)[0])
        errors.append(np.max(np.abs(curve.derivatives(fine, 0)[0] - ms.derivatives(fine, 0)[0])))
    assert errors[0] / errors[1] > 12


def test_given_slopes_give_the_hermite_cubic() -> None:
    # with the exact slopes of a cubic, the cubic Hermite interpolant is that cubic
    # (rounding as in test_reproduces_a_cubic); data in mm over degrees, slopes in mm/deg
    t = np.array([10.0, 25.0, 40.0, 70.0, 100.0])
    x = (t - 10.0) / 90.0

    def s_of(t_deg: np.ndarray) -> np.ndarray:
        u = (t_deg - 10.0) / 90.0
        return 4 * (3 * u**2 - 2 * u**3) - u  # rise with a small fall at the start

    v = (4 * (6 * x - 6 * x**2) - 1) / 90.0
    curve = PointsCurve(t, s_of(t), v=v)
    assert curve.limited_knots.size == 0
    tt = np.linspace(0, 1, 501)
    dim = curve.dimensional(tt)
    assert np.max(np.abs(dim["h"] - s_of(dim["theta"]))) <= 1e-13
    at_knots = curve.dimensional(curve.knots_t)
    assert np.max(np.abs(at_knots["dh_dtheta"] - v)) <= 1e-15


# ----------------------------------------------------------------------------- inverse
def test_inverse_on_a_monotone_points_curve() -> None:
    # strictly increasing smooth data: inverse(S(T)) = T to ~eps/V (V ≥ 0.5 on this grid)
    t = np.linspace(0, 1, 21)
    curve = PointsCurve(t, t + 0.1 * np.sin(2 * np.pi * t))
    tt = np.linspace(0.01, 0.99, 99)
    assert np.max(np.abs(curve.inverse(curve.derivatives(tt, 0)[0]) - tt)) <= 1e-13


def test_inverse_refuses_a_rise_then_fall() -> None:
    curve = PointsCurve([0, 1, 2, 3, 4], [0, 1, 2, 1, 0])
    with pytest.raises(NonMonotoneError):
        curve.inverse(np.array([0.5]))


# ----------------------------------------------------------------------------- errors
def test_non_increasing_t_names_the_index() -> None:
    with pytest.raises(DegenerateCurveError, match=r"t\[3\] = 2\.0 does not exceed t\[2\] = 2\.0"):
        PointsCurve([0, 1, 2, 2, 3], [0, 1, 2, 3, 4])
    with pytest.raises(DegenerateCurveError, match=r"t\[1\]"):
        PointsCurve([0, -1, 2], [0, 1, 2])


def test_mismatched_lengths() -> None:
    with pytest.raises(DegenerateCurveError, match="t has 3, s has 2"):
        PointsCurve([0, 1, 2], [0, 1])
    with pytest.raises(DegenerateCurveError, match="v has 2"):
        PointsCurve([0, 1, 2], [0, 1, 2], v=[0, 1])


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_non_finite_values(bad: float) -> None:
    with pytest.raises(DegenerateCurveError, match=r"s\[1\]"):
        PointsCurve([0, 1, 2], [0, bad, 2])
    with pytest.raises(DegenerateCurveError, match=r"t\[2\]"):
        PointsCurve([0, 1, bad], [0, 1, 2])
    with pytest.raises(DegenerateCurveError, match=r"v\[0\]"):
        PointsCurve([0, 1, 2], [0, 1, 2], v=[bad, 0, 0])


def test_too_many_points() -> None:
    t = np.arange(10001.0)
    with pytest.raises(LimitExceededError) as info:
        PointsCurve(t, np.sqrt(t))
    assert (info.value.what, info.value.requested, info.value.limit) == ("number of points", 10001, 10000)
    with pytest.raises(LimitExceededError):
        PointsCurve([0, 1, 2, 3], [0, 1, 2, 3], max_points=3)
    assert PointsCurve(t[:-1], np.sqrt(t[:-1])).n_pieces == 9999


def test_constant_s_and_too_few_points() -> None:
    with pytest.raises(DegenerateCurveError, match="same s"):
        PointsCurve([0, 1, 2], [5, 5, 5])
    with pytest.raises(DegenerateCurveError, match="at least 2"):
        PointsCurve([0], [1])
