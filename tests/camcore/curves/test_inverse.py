"""Inverse lookup S → T: the exact method and the catalog's table method.

Sources: docs/api.md (POST /v1/curves/inverse); INDEXMAN guide, 凸轮曲线特性表及其
使用方法, worked example (n = 6, θh = 270°, MS, 60 rpm, output at 11°).

Conditioning: near a solution, dT = dS / V. S(T) in float64 carries an absolute error
δS of a few ulps of its terms (see S_TOL), so T can only be recovered to δS/|V| plus
the spacing of T itself; where V → 0 (dwell ends, flat polynomial ends) T is not
determined by S at all and only the residual |S(T') − S(T)| ≤ δS is meaningful.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcore
from camcore import CATALOG, ReturnCurve, universal_curve
from camcore.errors import NonMonotoneError, StrokeRangeError

EPS = np.finfo(float).eps
POLY = {"constant-velocity", "3-4-5", "4-5-6-7"}


def s_tol(name: str) -> float:
    """Absolute float error δS of evaluating S.

    Sine family: S is a sum of ~5 terms of size ≤ 2 → 32 eps (7e-15) covers it.
    Polynomials: the monomial sum Σ c_k T^k has terms up to |c_k| (84 for 4-5-6-7) that
    cancel to ≤ 1, so δS ≈ Σ|c_k| · eps; 2 Σ|c_k| · eps (9e-14 for 4-5-6-7).
    """
    if name.removeprefix("return-") in POLY:
        coef = CATALOG[name.removeprefix("return-")].parameters["coefficients"]
        return 2 * sum(abs(c) for c in coef) * EPS
    return 32 * EPS


CASES = [(n, camcore.named_curve(n)) for n in sorted(CATALOG)]
CASES += [(f"return-{n}", ReturnCurve(camcore.named_curve(n))) for n in ["MS", "TR", "MCV50", "4-5-6-7"]]
IDS = [n for n, _ in CASES]


@pytest.mark.parametrize("name,curve", CASES, ids=IDS)
def test_inverse_of_forward_is_identity(name: str, curve: camcore.Curve) -> None:
    """inverse(S(T)) = T to δS/|V| where V is not small; S(T') = S(T) to δS everywhere."""
    t = np.linspace(curve.t_start, curve.t_end, 20001)
    vals = curve.evaluate(t)
    lo, hi = sorted((curve.s_start, curve.s_end))
    # float S may step a rounding error past its end value near a flat end (4-5-6-7)
    s = np.clip(vals.s, lo, hi)
    t_back = curve.inverse(s)
    tol_s = s_tol(name)
    resid = np.abs(curve.evaluate(t_back).s - s)
    k = int(np.argmax(resid))
    assert resid[k] <= tol_s, f"{name}: |S(T') − S| = {resid[k]:.2e} at S = {s[k]!r}"
    fast = np.abs(vals.v) >= 0.5
    err = np.abs(t_back - t)[fast]
    bound = tol_s / np.abs(vals.v[fast]) + 4 * EPS
    k = int(np.argmax(err - bound))
    assert err[k] <= bound[k], f"{name}: |T' − T| = {err[k]:.2e} > {bound[k]:.2e} at T = {t[fast][k]!r}"
    if name.removeprefix("return-") not in POLY:
        # the brief's figure: 1e-14 in T wherever V ≥ 0.5 (δS/0.5 + 4 eps < 1.5e-14 → 1e-14 holds
        # with the measured δS of ~2e-15)
        assert err.max() <= 1e-14, f"{name}: max |T' − T| = {err.max():.2e} where V ≥ 0.5"


def test_inverse_through_constant_velocity_stretch_mcv50() -> None:
    """MCV50 on [0.25, 0.75]: S = Sb + Vm(T − 0.25), so T = 0.25 + (S − Sb)/Vm exactly."""
    curve = camcore.named_curve("MCV50")
    sb = float(curve.evaluate(0.25).s)
    vm = curve.characteristics.vm.value
    t = np.linspace(0.25, 0.75, 501)
    s = sb + vm * (t - 0.25)
    # dT = δS/Vm with Vm = 1.275: well inside 1e-14
    assert np.max(np.abs(curve.inverse(s) - t)) <= 1e-14
    assert np.max(np.abs(curve.evaluate(curve.inverse(s)).v - vm)) == 0.0


@pytest.mark.parametrize("name,curve", CASES, ids=IDS)
def test_inverse_at_dwell_ends_own_end_values(name: str, curve: camcore.Curve) -> None:
    """The curve's own S(T0) → T0 and S(T7) → T7 (the first T reaching it is the end)."""
    assert curve.inverse(curve.s_start) == curve.t_start
    assert curve.inverse(curve.s_end) == curve.t_end


#: S(T7) is summed section by section and lands 1 ulp off the nominal 1 for some curves
#: (S(T7) = 0.9999999999999999 for MCV25, 33, 45, 47; 1.0000000000000002 for 34, 36, 49):
#: the inverse treats a target within a few ulps of an end as that end, so S = 1 → T7 for all.
@pytest.mark.parametrize("name", sorted(CATALOG))
def test_inverse_nominal_stroke_ends(name: str) -> None:
    """S = 0 → T0 and S = 1 → T7 for every catalog rise (the dwell ends)."""
    curve = camcore.named_curve(name)
    assert curve.inverse(0.0) == curve.t_start
    assert curve.inverse(1.0) == curve.t_end


@pytest.mark.parametrize("name", ["MS", "TR", "one-dwell-modified-sine"])
def test_inverse_of_return_stroke(name: str) -> None:
    """A return falls from 1 to 0: inverse of the decreasing S; it mirrors the rise's inverse."""
    rise = camcore.named_curve(name)
    ret = ReturnCurve(rise)
    s = np.linspace(0.05, 0.95, 91)
    t_ret = ret.inverse(s)
    assert np.all(np.diff(t_ret) < 0), "higher S comes earlier on a return"
    # S_ret(T) = S(1 − T): T_ret(s) = 1 − T_rise(s); the two inverses differ by rounding
    # of 1 − T and δS/V (V ≥ 0.1 on [0.05, 0.95] for these curves) → 1e-13
    assert np.max(np.abs(t_ret - (1 - rise.inverse(s)))) <= 1e-13
    assert ret.inverse(1.0) == 0.0 and ret.inverse(0.0) == 1.0


@pytest.mark.parametrize("name,curve", CASES, ids=IDS)
def test_inverse_does_not_depend_on_the_order_of_the_targets(name: str, curve: camcore.Curve) -> None:
    """Targets are solved in blocks, grouped by piece: any order gives the same T, bit for bit."""
    lo, hi = sorted((curve.s_start, curve.s_end))
    s = np.linspace(lo, hi, 30001)  # several blocks of camcore.curves.inverse.BLOCK, both end cells
    order = np.random.default_rng(11).permutation(s.size)
    assert np.array_equal(curve.inverse(s)[order], curve.inverse(s[order]))


@pytest.mark.parametrize("name", ["MS", "MCV50", "cycloid", "4-5-6-7"])
def test_inverse_in_the_dwell_end_cells(name: str) -> None:
    """Near T0 and T7 (V → 0, S − S_end ∝ τ^k) the inverse still reaches δS/|V|.

    camcore.curves.inverse iterates on (S − S_end)^(1/k) in the first and last of its 8192
    cells; this holds it to the same conditioning bound as everywhere else.
    """
    curve = camcore.named_curve(name)
    t = np.concatenate([np.linspace(2e-3, 0.03, 2001), np.linspace(0.97, 1 - 2e-3, 2001)])
    vals = curve.evaluate(t)
    t_back = curve.inverse(vals.s)
    bound = s_tol(name) / np.abs(vals.v) + 4 * EPS
    k = int(np.argmax(np.abs(t_back - t) - bound))
    assert abs(t_back[k] - t[k]) <= bound[k], f"{name}: |T' − T| = {abs(t_back[k] - t[k]):.2e} at T = {t[k]!r}"
    assert np.max(np.abs(curve.evaluate(t_back).s - vals.s)) <= s_tol(name)


def test_inverse_keeps_shape() -> None:
    curve = camcore.named_curve("MS")
    grid = np.array([[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]])
    out = curve.inverse(grid)
    assert out.shape == (2, 3)
    assert np.array_equal(out.reshape(-1), curve.inverse(grid.reshape(-1)))
    scalar = curve.inverse(0.5)
    assert np.shape(scalar) == () and float(scalar) == pytest.approx(0.5, abs=1e-15)  # MS is point-symmetric
    table = curve.inverse_table(grid, 0.01)
    assert table.t.shape == (2, 3) and table.v.shape == (2, 3)


# --------------------------------------------------------------------------- worked example
def test_table_method_reproduces_catalog_worked_example() -> None:
    """INDEXMAN guide, worked example: n = 6, θh = 270°, MS, N = 60 rpm, output at 11°.

    h = 360/6 = 60°, th = 270/360 × 60/60 = 0.75 s, S = 11/60 = 0.1833 (printed); the MS
    table rows T = 0.30, 0.31 have S = 0.17789, 0.19132 and V = 1.32295, 1.36325;
    proportional interpolation gives T = 0.304, V = 1.339, θ = 82.08°, v = 1.8696 rad/s.
    """
    curve = camcore.named_curve("MS")
    rows = curve.evaluate([0.30, 0.31])
    assert np.array_equal(np.round(rows.s, 5), [0.17789, 0.19132])
    assert np.array_equal(np.round(rows.v, 5), [1.32295, 1.36325])
    res = curve.inverse_table(0.1833, 0.01, decimals=5)
    frac = (0.1833 - 0.17789) / (0.19132 - 0.17789)
    # the same arithmetic as printed; only the order of float operations differs
    assert float(res.t) == pytest.approx(0.3 + (0.31 - 0.3) * frac, abs=1e-15)
    assert float(res.v) == pytest.approx(1.32295 + (1.36325 - 1.32295) * frac, abs=1e-14)
    assert round(float(res.t), 3) == 0.304 and round(float(res.v), 3) == 1.339
    h, th = 360 / 6, 270 / 360 * 60 / 60
    assert th == 0.75
    assert round(270 * round(float(res.t), 3), 2) == 82.08
    assert round(h / th * round(float(res.v), 3) * math.pi / 180, 4) == 1.8696
    # the exact inverse of S = 11/60 lies within the table method's interpolation error
    t_exact = float(curve.inverse(11 / 60))
    assert abs(t_exact - float(res.t)) < 1e-3 and round(t_exact, 3) == 0.304


# --------------------------------------------------------------------------- errors
@pytest.mark.parametrize("bad", [1.5, -0.1, math.nan, math.inf])
def test_stroke_range_error_names_value(bad: float) -> None:
    curve = camcore.named_curve("MS")
    with pytest.raises(StrokeRangeError, match=rf"s\[0\] = {re_float(bad)} is outside the stroke"):
        curve.inverse(bad)
    with pytest.raises(StrokeRangeError, match=rf"s\[1\] = {re_float(bad)}"):
        curve.inverse_table([0.5, bad], 0.01)


def re_float(x: float) -> str:
    return {"nan": "nan", "inf": "inf"}.get(repr(x), repr(x).replace(".", r"\."))


def test_return_stroke_range_error() -> None:
    with pytest.raises(StrokeRangeError, match="from S = 1.0 to S = 0.0"):
        ReturnCurve(camcore.named_curve("MS")).inverse(1.2)


@pytest.mark.parametrize("v0", [3.0, -1.0, 2.5])
def test_non_monotone_universal_curve(v0: float) -> None:
    """A universal curve with V0 = V7 = v0 far from the mean velocity 1: V changes sign, so
    S runs ahead (v0 = 3, 2.5: S rises, falls back, rises again) or starts backwards
    (v0 = −1) and S does not determine T → NonMonotoneError (exact and table methods)."""
    pts = (0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1)
    curve = universal_curve(pts, v0=v0)
    ch = curve.characteristics
    assert ch.v_min.value < 0 < ch.v_max.value, "the construction must really reverse"
    s = curve.evaluate(np.linspace(0, 1, 2001)).s
    assert np.any(np.diff(s) < -1e-6) and np.any(np.diff(s) > 1e-6), "S must go both ways"
    with pytest.raises(NonMonotoneError, match="not monotone"):
        curve.inverse(0.5)
    with pytest.raises(NonMonotoneError, match="not monotone"):
        curve.inverse_table(0.5, 0.01)


def test_constant_displacement_is_not_invertible() -> None:
    """S7 = S0 with no motion at all: S does not determine T."""
    curve = universal_curve((0, 0.125, 0.125, 0.5, 0.5, 0.875, 0.875, 1), s7=0.0)
    with pytest.raises(NonMonotoneError):
        curve.inverse(0.0)


@pytest.mark.parametrize("name,curve", CASES, ids=IDS)
def test_rates_from_the_solve_are_the_curve_at_the_answer(name: str, curve: camcore.Curve) -> None:
    """Issue 21: V and A come out of the solve (the last Newton evaluation carried over the last
    step by Taylor) instead of a second evaluation; they equal the curve evaluated afresh at the
    same T. Random targets (unsorted), both stroke ends and the dwell-end cells."""
    lo, hi = sorted((curve.s_start, curve.s_end))
    rng = np.random.default_rng(21)
    s = np.concatenate([rng.uniform(lo, hi, 20_000), [lo, hi], lo + (hi - lo) * np.logspace(-16, -3, 40),
                        hi - (hi - lo) * np.logspace(-16, -3, 40)])
    t, v, a = curve.inverse_with_rates(s)
    np.testing.assert_array_equal(t, curve.inverse(s))  # the same answers as without the rates
    _s, v_direct, a_direct = curve.derivatives(t, 2)
    ch = curve.characteristics
    # the Taylor terms left out are below 1e-15 of the peaks (|δ| ≤ 1e-9); what remains is
    # the rounding of evaluating V and A at two different T. Sine family: measured ≤ 1.1e-15
    # of Vm and Am, so 4e-15 (about 18 ulp of a unit peak). Polynomials: the monomial sums
    # Σ k·c_k·T^(k−1) and Σ k(k−1)·c_k·T^(k−2) cancel from terms of up to Σ k|c_k| (1120 for
    # 4-5-6-7), so twice that many eps, as s_tol does for S
    v_tol, a_tol = 4e-15 * ch.vm.value, 4e-15 * max(ch.am, 1.0)
    if name.removeprefix("return-") in POLY:
        coef = CATALOG[name.removeprefix("return-")].parameters["coefficients"]
        v_tol = 2 * EPS * sum(k * abs(c) for k, c in enumerate(coef))  # coefficients from T⁰ up
        a_tol = 2 * EPS * sum(k * (k - 1) * abs(c) for k, c in enumerate(coef))
    assert np.abs(v - v_direct).max() <= v_tol
    assert np.abs(a - a_direct).max() <= a_tol
