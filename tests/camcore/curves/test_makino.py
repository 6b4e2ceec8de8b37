"""Makino's universal cam curve against the paper's printed numbers and equations.

Source: H. Makino, "Universal Cam Curve and Its Application" (1977),
cited as Makino (1977) in docs/sources.md: eqs. (1)-(16), table 2,
appendix 1 (subroutine CURVE, Fortran line numbers quoted), appendix 3-1 and 3-2
(line-printer output of the example program, appendix 2).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import camcore
from camcore import makino_curve, universal_curve
from camcore.errors import InvalidBreakPointsError, InvalidParameterError, StrokeClosureError

PI = math.pi
#: Half a unit of the 5th decimal (FORMAT F12.5 / F15.5) plus float slack (values are
#: O(1..200); float64 error ~1e-13 at most, 10^7 below a printed digit).
HALF_DIGIT = 0.5e-5 + 1e-12

# --------------------------------------------------------------------------- appendix 3-1
#: Appendix 3-1, EXAMPLE 1, curve 27: NO, T, S, V, A, J, Q (Q = A·V, line 228).
APPENDIX_3_1 = [
    (0, 0.00000, 0.00000, 0.00000, 0.00000, 201.38070, 0.00000),
    (1, 0.00833, 0.00002, 0.00697, 1.66593, 196.98005, 0.01161),
    (2, 0.01667, 0.00015, 0.02756, 3.25905, 183.97042, 0.08983),
    (3, 0.02500, 0.00051, 0.06089, 4.70974, 162.92041, 0.28677),
    (4, 0.03333, 0.00120, 0.10549, 5.95458, 134.74999, 0.62813),
    (5, 0.04167, 0.00230, 0.15941, 6.93919, 100.69035, 1.10616),
    (6, 0.05000, 0.00388, 0.22030, 7.62051, 62.23006, 1.67876),
    (7, 0.05833, 0.00598, 0.28549, 7.96879, 21.05001, 2.27500),
    (8, 0.06667, 0.00864, 0.35219, 8.00780, -2.34270, 2.82030),
    (9, 0.07500, 0.01185, 0.41879, 7.96879, -7.01667, 3.33725),
]


@pytest.mark.parametrize("row", APPENDIX_3_1, ids=lambda r: f"I={r[0]}")
def test_appendix_3_1_curve_27_rows(row: tuple) -> None:
    """Appendix 3-1, curve 27, row I: T = I/120 (appendix 2 line 22), printed F12.5."""
    i, t_printed, *printed = row
    t = i / 120  # the program evaluates at I/LINE; the printed T is that rounded
    assert abs(t - t_printed) <= HALF_DIGIT
    vals = makino_curve(27).evaluate(t)
    computed = [vals.s, vals.v, vals.a, vals.j, vals.q_raw]
    for name, c, p in zip("SVAJQ", computed, printed):
        assert abs(float(c) - p) <= HALF_DIGIT, f"appendix 3-1 row {i} {name}: printed {p}, computed {float(c)!r}"


def test_appendix_3_1_vm_am() -> None:
    """Appendix 3-1 header: VM = 1.27526, AM = 8.01268 (PM(14), PM(15))."""
    curve = makino_curve(27)
    assert abs(curve.characteristics.vm.value - 1.27526) <= HALF_DIGIT
    assert abs(curve.amp - 8.01268) <= HALF_DIGIT
    assert abs(curve.characteristics.am_pos.value - 8.01268) <= HALF_DIGIT


# --------------------------------------------------------------------------- appendix 3-2
#: Appendix 3-2, EXAMPLE 2, curve 4: T3, T1, VM, AM (printed F15.5). The program loops
#: I = 1..16, J = 1..2I with T3 = I/32, T1 = J/64 (appendix 2 lines 44-47); the copy
#: keeps the first 13 rows.
APPENDIX_3_2 = [
    (1, 1, 0.03125, 0.01563, 1.03226, 51.88695),
    (1, 2, 0.03125, 0.03125, 1.04144, 52.34836),
    (2, 1, 0.06250, 0.01563, 1.05704, 26.56629),
    (2, 2, 0.06250, 0.03125, 1.06667, 26.80826),
    (2, 3, 0.06250, 0.04688, 1.07647, 27.05467),
    (2, 4, 0.06250, 0.06250, 1.08646, 27.30566),
    (3, 1, 0.09375, 0.01563, 1.08304, 18.14650),
    (3, 2, 0.09375, 0.03125, 1.09315, 18.31588),
    (3, 3, 0.09375, 0.04688, 1.10345, 18.48845),
    (3, 4, 0.09375, 0.06250, 1.11394, 18.66431),
    (3, 5, 0.09375, 0.07813, 1.12464, 18.84354),
    (3, 6, 0.09375, 0.09375, 1.13555, 19.02625),
    (4, 1, 0.12500, 0.01563, 1.11035, 15.95308),
]

#: Appendix 3-2, last row (T3 = 0.125, T1 = 0.01563): AM is printed 15.95308, the curve
#: gives 13.95308 — every other digit agrees, so the leading "13" was misread/misprinted
#: as "15" (docs/sources.md, known misprints). It also breaks the table's own trend: AM falls
#: roughly as 1/T3 (51.9, 26.6, 18.1 for T3 = 1/32, 2/32, 3/32, so ≈ 14 for 4/32).
APPENDIX_3_2_MISPRINTS = {(4, 1, "AM"): 13.95308}


@pytest.mark.parametrize("row", APPENDIX_3_2, ids=lambda r: f"T3={r[0]}/32-T1={r[1]}/64")
def test_appendix_3_2_curve_4_grid(row: tuple) -> None:
    """Appendix 3-2, curve 4 with T3 = I/32, T1 = J/64: VM and AM as printed."""
    i, j, t3_p, t1_p, vm_p, am_p = row
    t3, t1 = i / 32, j / 64
    # T1 = J/64 is an exact binary half-way case (1/64 = 0.015625); Fortran printed it
    # rounded up (0.01563) — so compare within half a digit, not by Python's round().
    assert abs(t3 - t3_p) <= HALF_DIGIT and abs(t1 - t1_p) <= HALF_DIGIT
    curve = makino_curve(4, t1=t1, t3=t3)
    vm, am = curve.characteristics.vm.value, curve.amp
    assert abs(vm - vm_p) <= HALF_DIGIT, f"VM printed {vm_p}, computed {vm!r}"
    assert curve.characteristics.am_pos.value == pytest.approx(am, rel=1e-15, abs=0)
    misprint = APPENDIX_3_2_MISPRINTS.get((i, j, "AM"))
    if misprint is None:
        assert abs(am - am_p) <= HALF_DIGIT, f"AM printed {am_p}, computed {am!r}"
    else:
        assert abs(am - misprint) <= HALF_DIGIT, f"AM computed {am!r}, expected the corrected {misprint}"
        assert abs(am - am_p) > 1.0, "the named misprint now matches: remove it from APPENDIX_3_2_MISPRINTS"


# --------------------------------------------------------------------------- eq. (13)-(14)
def test_trapecloid_2_eq_14() -> None:
    """Eq. (14), curve 36: Vm = 1.85, Am = Amp = Amm = 5.22, Jm = 65.6, Qmp = 7.75, Qmm = −5.34.

    Q here is Makino's A·V (line 228), so the raw Q extremes are compared.
    """
    curve = makino_curve(36)
    ch = curve.characteristics
    assert round(ch.vm.value, 2) == 1.85
    assert round(curve.amp, 2) == 5.22 and round(curve.amm, 2) == 5.22
    assert curve.amm == pytest.approx(curve.amp, rel=1e-14)  # "A_m = A_mp = A_mm"
    assert round(max(ch.jm_pos.value, -ch.jm_neg.value), 1) == 65.6
    assert round(ch.qm_raw_pos.value, 2) == 7.75
    assert round(ch.qm_raw_neg.value, 2) == -5.34


def test_trapecloid_2_eq_13_ocr_reading_is_out_of_order() -> None:
    """Eq. (13) as OCR'd reads T6 = T3 < T5: break points out of order, so that reading
    cannot be the paper's (docs/sources.md, known misprints); T6 = T5 reproduces eq. (14)."""
    t1 = 0.125
    t2 = (2 - 6 * t1 + PI * t1) / (2 + PI)
    t3 = t2 + t1
    with pytest.raises(InvalidBreakPointsError, match="T0 ≤ T1 ≤ … ≤ T7"):
        universal_curve((0, t1, t2, t3, t3, 1 - t1, t3, 1))
    assert makino_curve(36).t == pytest.approx((0, t1, t2, t3, t3, 1 - t1, 1 - t1, 1), abs=1e-16)


# --------------------------------------------------------------------------- eq. (11)
def eq11_printed(t: tuple[float, ...], m: float, v0: float = 0.0, s0: float = 0.0, s7: float = 1.0) -> float:
    """Amp from eq. (11) exactly as printed (and as Fortran lines 88-90)."""
    t0, t1, t2, t3, t4, t5, t6, t7 = t
    c1, c2, c3 = 2 * (t1 - t0) / PI, t2 - t1, 2 * (t3 - t2) / PI
    c5, c6, c7 = 2 * (t5 - t4) / PI, t6 - t5, 2 * (t7 - t6) / PI
    rhs = (
        -m * (c7 * c7 + 0.5 * c6 * c6 - c5 * c5 + c6 * (t7 - t6) + c5 * (t7 - t4))
        + c3 * c3 + 0.5 * c2 * c2 - c1 * c1 + c3 * (t7 - t3) + c2 * (t7 - t2) + c1 * (t7 - t0)
    )
    return (s7 - s0 - v0 * (t7 - t0)) / rhs


def unit_acceleration(t: tuple[float, ...], amp: float, amm: float):
    """A(T) of fig. 1 / eqs. (2)-(8), written from the section definitions."""
    t0, t1, t2, t3, t4, t5, t6, t7 = t

    def a(x: np.ndarray) -> np.ndarray:
        out = np.zeros_like(x)
        for lo, hi, f in [
            (t0, t1, lambda y: amp * np.sin(PI * (y - t0) / (2 * (t1 - t0)))),
            (t1, t2, lambda y: amp + 0 * y),
            (t2, t3, lambda y: amp * np.cos(PI * (y - t2) / (2 * (t3 - t2)))),
            (t4, t5, lambda y: -amm * np.sin(PI * (y - t4) / (2 * (t5 - t4)))),
            (t5, t6, lambda y: -amm + 0 * y),
            (t6, t7, lambda y: -amm * np.cos(PI * (y - t6) / (2 * (t7 - t6)))),
        ]:
            inside = (x >= lo) & (x < hi)
            if hi > lo and inside.any():
                out[inside] = f(x[inside])
        return out

    return a


def superposition_amp(t: tuple[float, ...], m: float, v0: float, s0: float, s7: float) -> float:
    """Amp by superposition: S7 − S0 − V0(T7 − T0) = ∫ A(τ)(T7 − τ) dτ, linear in Amp.

    The integral is done by 30-point Gauss-Legendre on each section (exact to rounding
    for these quarter-sine and constant integrands), independently of eq. (11).
    """
    a = unit_acceleration(t, 1.0, m)
    nodes, weights = np.polynomial.legendre.leggauss(30)
    total = 0.0
    for lo, hi in itertools.pairwise(t):
        if hi > lo:
            x = lo + (hi - lo) * (nodes + 1) / 2
            total += (hi - lo) / 2 * np.sum(weights * a(x) * (t[7] - x))
    return (s7 - s0 - v0 * (t[7] - t[0])) / total


EQ11_CASES = [
    ((0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1), 1.0, 0.0, 0.0, 1.0),
    ((0, 0.1, 0.3, 0.4, 0.4, 0.55, 0.85, 1), 2 / 3, 0.0, 0.0, 1.0),
    ((0.2, 0.3, 0.45, 0.6, 0.9, 1.0, 1.3, 1.5), 1.4, 0.3, 0.25, 2.0),
    ((-1.0, -0.7, -0.7, -0.2, 0.1, 0.5, 0.6, 1.2), 0.5, -0.2, 1.0, 0.5),
]


@pytest.mark.parametrize("case", EQ11_CASES, ids=range(len(EQ11_CASES)))
def test_eq_11_printed_vs_superposition(case: tuple) -> None:
    """Eq. (11) as printed = an independent superposition integral = camcore's Amp."""
    t, m, v0, s0, s7 = case
    printed = eq11_printed(t, m, v0, s0, s7)
    independent = superposition_amp(t, m, v0, s0, s7)
    curve = universal_curve(t, m=m, v0=v0, s0=s0, s7=s7)
    # Amp is O(1..30); 1e-12 relative allows for quadrature and ~10 rounded terms.
    assert printed == pytest.approx(independent, rel=1e-12)
    assert curve.amp == pytest.approx(printed, rel=1e-12)
    assert curve.amm == pytest.approx(m * printed, rel=1e-12)
    # and the curve really reaches S7 (eq. 8 end value), to rounding of O(1) sums
    assert curve.evaluate(t[7]).s == pytest.approx(s7, abs=1e-13)


# --------------------------------------------------------------------------- equal areas, m
TABLE_2 = [12, 22, 25, 26, 27, 33, 34, 35, 43, 44, 45, 46, 47, 48, 49, 50, 51, 52]


@pytest.mark.parametrize("number", TABLE_2)
def test_equal_area_rule_line_86(number: int) -> None:
    """Fortran line 86: for V7 = V0, RATIO = (C1 + C2 + C3)/(C5 + C6 + C7); V7 = V0 = 0."""
    curve = makino_curve(number)
    t0, t1, t2, t3, t4, t5, t6, t7 = curve.t
    ratio = (2 * (t3 - t2) / PI + (t2 - t1) + 2 * (t1 - t0) / PI) / (
        2 * (t7 - t6) / PI + (t6 - t5) + 2 * (t5 - t4) / PI
    )
    assert curve.m == pytest.approx(ratio, rel=1e-14)
    assert curve.amp == pytest.approx(eq11_printed(curve.t, ratio), rel=1e-14)
    end = curve.evaluate(t7)
    # V7 is a difference of O(Vm) terms: a few ulps of Vm ≈ 2 is < 1e-15
    assert abs(float(end.v)) < 1e-14, f"curve {number}: V7 = {float(end.v)!r}"
    assert float(end.s) == pytest.approx(1.0, abs=1e-14)


#: Table 2, 備考 column (m = Amm/Amp): 43 m = 1, 44 m = 2/3, 45 m = 1, 47 m = 2/3;
#: 48/49 state T1 = 1/8 with m = 1 (modified sine and trapecloid are m = 1 curves);
#: 33, 34 are Makino's asymmetric curves with m = 2/3 (their quoted break points, docs/sources.md), 35 m = 1.
STATED_M = {43: 1.0, 48: 1.0, 44: 2 / 3, 33: 2 / 3, 34: 2 / 3, 45: 1.0, 49: 1.0, 35: 1.0, 47: 2 / 3}


@pytest.mark.parametrize("number", sorted(STATED_M))
def test_table_2_stated_m(number: int) -> None:
    """Table 2: the open break points (A, B, C, D) make the equal-area m the stated m."""
    assert makino_curve(number).m == pytest.approx(STATED_M[number], rel=1e-14)


@pytest.mark.parametrize("number", [43, 44, 45, 46, 47, 48, 49])
def test_one_dwell_curves_end_at_minus_amm(number: int) -> None:
    """One-dwell curves (table 2, 片停留): V = 0 and A = −Amm at T = 1 (the return follows)."""
    curve = makino_curve(number)
    end = curve.evaluate(1.0)
    start = curve.evaluate(0.0)
    assert abs(float(end.v)) < 1e-14 and float(end.a) == pytest.approx(-curve.amm, rel=1e-14)
    assert float(start.a) == 0.0 and float(start.v) == 0.0


@pytest.mark.parametrize("number", [50, 51, 52])
def test_no_dwell_curves_start_at_plus_amp(number: int) -> None:
    """No-dwell curves (table 2, 無停留): A = +Amp at T = 0, A = −Amm at T = 1, V = 0 at both."""
    curve = makino_curve(number)
    ends = curve.evaluate([0.0, 1.0])
    assert ends.a[0] == pytest.approx(curve.amp, rel=1e-14)
    assert ends.a[1] == pytest.approx(-curve.amm, rel=1e-14)
    assert np.all(np.abs(ends.v) < 1e-14)


# --------------------------------------------------------------------------- curves 1, 2
@pytest.mark.parametrize("z", [0.1, 0.5, 0.9, 1.0])
def test_rapid_feed_eq_16(z: float) -> None:
    """Curve 1, eqs. (15)-(16): T3 = 1/(1+z), m = 1, V7/V3 = 1 − z (z = 0.9: V3 = 10 V7)."""
    curve = makino_curve(1, z=z)
    t3 = 1 / (1 + z)
    assert curve.t[3] == pytest.approx(t3, rel=1e-15) and curve.t[1] == pytest.approx(t3 / 4, rel=1e-15)
    assert curve.m == 1.0
    v3 = float(curve.evaluate(t3).v)
    v7 = float(curve.evaluate(1.0).v)
    assert v7 / v3 == pytest.approx(1 - z, abs=1e-14)
    assert float(curve.evaluate(1.0).s) == pytest.approx(1.0, abs=1e-14)


@pytest.mark.parametrize("t4", [0.0, 0.3, 0.6, 0.95])
def test_cutting_feed_curve_2(t4: float) -> None:
    """Curve 2 (lines 42-55): ends at S = 1, V = 0 with V0 = 2(1 − T4)Amm/π, Amp = 0."""
    curve = makino_curve(2, t4=t4)
    amm = PI / (4 * (1 - t4) ** 2 / PI + 2 * (1 - t4) * t4)  # line 51
    assert curve.amm == pytest.approx(amm, rel=1e-15) and curve.amp == 0.0
    ends = curve.evaluate([0.0, 1.0])
    assert ends.v[0] == pytest.approx(2 * (1 - t4) * amm / PI, rel=1e-15)  # line 54
    assert ends.s[0] == 0.0 and ends.s[1] == pytest.approx(1.0, abs=1e-14)
    assert abs(ends.v[1]) < 1e-14


# --------------------------------------------------------------------------- errors
def test_break_points_out_of_order() -> None:
    with pytest.raises(InvalidBreakPointsError, match=r"T0 ≤ T1 ≤ … ≤ T7.*T3 = 0\.2.*T2 = 0\.3"):
        universal_curve((0, 0.1, 0.3, 0.2, 0.5, 0.6, 0.7, 1))


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_break_points_not_finite(bad: float) -> None:
    with pytest.raises(InvalidBreakPointsError, match="T4 must be a finite number"):
        universal_curve((0, 0.1, 0.2, 0.3, bad, 0.6, 0.7, 1))


def test_break_points_wrong_count_and_zero_duration() -> None:
    with pytest.raises(InvalidBreakPointsError, match="8 break points"):
        universal_curve((0, 0.5, 1))
    with pytest.raises(InvalidBreakPointsError, match="T7 > T0"):
        universal_curve((0.5,) * 8)


@pytest.mark.parametrize("name,value", [("v0", math.nan), ("s7", math.inf), ("m", math.nan)])
def test_non_finite_end_conditions(name: str, value: float) -> None:
    with pytest.raises(InvalidParameterError, match="finite"):
        universal_curve((0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1), **{name: value})


def test_m_that_cannot_close_the_stroke() -> None:
    """Eq. (11) divides by zero when m = P/N: no Amp reaches S7 → StrokeClosureError."""
    t = (0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1)
    # eq11_printed(t, m) = 1/(P − m N): P and N from m = 0 and m = 1
    p = 1 / eq11_printed(t, 0.0)
    n = p - 1 / eq11_printed(t, 1.0)
    with pytest.raises(StrokeClosureError, match="eq. 11"):
        universal_curve(t, m=p / n)


def test_no_deceleration_section_cannot_close_velocity() -> None:
    """T4 = T7 leaves Amm nothing to act on, so V7 = V0 cannot be met (line 86 divides by 0)."""
    with pytest.raises(StrokeClosureError, match="T4 = T7"):
        universal_curve((0, 0.25, 0.25, 0.5, 1, 1, 1, 1))


def test_m_and_v7_together_rejected() -> None:
    with pytest.raises(InvalidParameterError, match="either m or V7"):
        universal_curve((0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1), m=1.0, v7=0.0)


@pytest.mark.parametrize(
    "number,params,match",
    [
        (1, {"z": 0.0}, "0 < z ≤ 1"),
        (1, {"z": 1.5}, "0 < z ≤ 1"),
        (1, {"z": math.nan}, "finite"),
        (1, {}, "needs z"),
        (2, {"t4": 1.0}, "0 ≤ T4 < 1"),
        (2, {"t4": -0.1}, "0 ≤ T4 < 1"),
        (4, {"t1": 0.3, "t3": 0.25}, "0 < T1 ≤ T3 ≤ 0.5"),
        (4, {"t1": 0.1, "t3": 0.6}, "0 < T1 ≤ T3 ≤ 0.5"),
        (4, {"t1": 0.0, "t3": 0.25}, "0 < T1 ≤ T3 ≤ 0.5"),
        (4, {"t3": 0.25}, "needs t1"),
        (26, {"z": 0.5}, "takes no parameter z"),
        (99, {}, "not one of"),
    ],
)
def test_bad_special_curve_parameters(number: int, params: dict, match: str) -> None:
    with pytest.raises(InvalidParameterError, match=match):
        makino_curve(number, **params)


def test_named_curve_by_makino_number() -> None:
    """The catalog answers to Makino's classification numbers (table 2)."""
    assert camcore.named_curve("27") is camcore.named_curve("mcv50")
    assert camcore.named_curve("26") is camcore.named_curve("ms")


def test_cutting_feed_ends_are_the_built_curves_own_ends() -> None:
    """A motion program solves curve 2's T4 from these closed-form ends instead of building a curve per trial
    (camcore.motion.resolve): they must be the curve's own N′(0) and N″(1), bit for bit, wherever its pieces are
    all longer than MIN_SECTION; within it of T4 = 0 or 1 a piece is merged into its neighbour and the ends move
    (by up to ~1e-9 just inside: the solver builds the curve there)."""
    import numpy as np

    from camcore.curves.makino import cutting_feed, cutting_feed_ends
    from camcore.curves.universal import MIN_SECTION
    from camcore.motion.laws import normalised_ends

    near_ends = [0.5 ** k for k in range(1, 29)] + [1.0 - 0.5 ** k for k in range(1, 29)]  # down to 3.7e-9
    for t4 in np.linspace(0.0, 0.999, 2000)[1:].tolist() + np.linspace(0.99, 1.0 - 1e-8, 2000).tolist() + near_ends:
        assert min(t4, 1.0 - t4) >= MIN_SECTION
        start, end = normalised_ends(cutting_feed(t4))
        v0, amm = cutting_feed_ends(t4)
        assert (start[1], end[2]) == (v0, -amm), t4
    # inside MIN_SECTION of 0 the constant-velocity piece is merged away: the ends are not the closed form's
    start, _ = normalised_ends(cutting_feed(0.5 * MIN_SECTION))
    assert start[1] != cutting_feed_ends(0.5 * MIN_SECTION)[0]
