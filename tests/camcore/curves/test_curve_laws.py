"""Laws every catalog curve must obey: continuity, end values, the right-limit
convention at break points, and exact characteristic values.

Sources: Makino (1977) fig. 1 and eqs. (2)-(9) (S and V continuous by construction,
A continuous "全区間を通じて連続" for the standard curves); docs/api.md, Conventions (break-point
convention, one-dwell and no-dwell ends); INDEXMAN guide, MCV50 table (凸轮曲线特性表),
rows T = 0.25, 0.75, 1.00.
"""

from __future__ import annotations

import numpy as np
import pytest

import camcore
from camcore import CATALOG, ReturnCurve

ALL = sorted(CATALOG)
#: curves whose A jumps at an interior break point: constant acceleration (T = 0.5,
#: A goes from +Amp to −Amm). Every other entry's A is continuous inside (T0, T7).
A_JUMPS_INSIDE = {"constant-acceleration"}
#: curves whose A is not 0 at T0 and/or T7 (so A jumps against the dwell there):
#: simple harmonic (12), the no-dwell curves (50-52), constant acceleration (11)
#: at both ends; the one-dwell curves (43-49) at T7 only (A = −Amm: their break points, camcore/curves/universal.py).
A_NONZERO_START = {"simple-harmonic", "constant-acceleration", "no-dwell-simple-harmonic",
                   "no-dwell-modified-trapezoid", "no-dwell-modified-constant-velocity"}
ONE_DWELL = {k for k, e in CATALOG.items() if e.family == "one-dwell"}
A_NONZERO_END = A_NONZERO_START | ONE_DWELL

#: Returns of a symmetric, an asymmetric, a one-dwell and a polynomial curve.
RETURN_OF = ["MS", "TR", "asymmetric-modified-trapezoid", "one-dwell-modified-trapezoid-m2-3", "3-4-5"]


def curves() -> list[tuple[str, camcore.Curve]]:
    out = [(name, camcore.named_curve(name)) for name in ALL]
    out += [(f"return-{name}", ReturnCurve(camcore.named_curve(name))) for name in RETURN_OF]
    return out


CURVES = curves()
IDS = [name for name, _ in CURVES]


def base_name(name: str) -> str:
    return name.removeprefix("return-")


def scale(curve: camcore.Curve, row: int) -> float:
    """Peak |quantity| of row 0..3 (S, V, A, J) on a fine grid, at least 1."""
    vals = curve.derivatives(np.linspace(curve.t_start, curve.t_end, 2001), 3)
    return max(1.0, float(np.max(np.abs(vals[row]))))


#: Left vs right limit at a break point b: the left limit is evaluated one ulp below b
#: (np.nextafter), which selects the previous piece; the right limit at b. A quantity
#: continuous at b then differs by |next derivative| × 1 ulp (< 1e-13 even for J ~ 10^4
#: times 2e-16) plus the rounding of each side (a few ulps of the quantity's peak).
#: 1e-12 × peak leaves room for both and is far below any real jump (≥ 1e-1 here).
CONT_TOL = 1e-12


@pytest.mark.parametrize("name,curve", CURVES, ids=IDS)
def test_continuity_at_interior_break_points(name: str, curve: camcore.Curve) -> None:
    """S and V (and A, except where a jump is part of the law) at every interior break point."""
    inner = curve.piece_starts[1:]
    if inner.size == 0:
        return  # a single smooth piece (polynomials) has nothing to join
    right = curve.derivatives(inner, 2)
    left = curve.derivatives(np.nextafter(inner, -np.inf), 2)
    rows = [0, 1] if base_name(name) in A_JUMPS_INSIDE else [0, 1, 2]
    for row in rows:
        tol = CONT_TOL * scale(curve, row)
        jump = np.abs(right[row] - left[row])
        k = int(np.argmax(jump))
        assert jump[k] <= tol, f"{name}: {'SVA'[row]} jumps by {jump[k]:.3e} at T = {inner[k]!r}"
    if base_name(name) in A_JUMPS_INSIDE:
        # and the jump really is there (the exclusion is not hiding anything else)
        assert np.max(np.abs(right[2] - left[2])) > 1.0


@pytest.mark.parametrize("name,curve", CURVES, ids=IDS)
def test_end_values(name: str, curve: camcore.Curve) -> None:
    """S(T0) = S0, S(T7) = S7 (0 → 1 for a rise, 1 → 0 for its return); V and A at the ends."""
    ends = curve.evaluate([curve.t_start, curve.t_end])
    rise = not name.startswith("return-")
    s0, s7 = (0.0, 1.0) if rise else (1.0, 0.0)
    # S is a sum of O(1) terms: 1e-14 is ~50 ulps
    assert abs(ends.s[0] - s0) <= 1e-14 and abs(ends.s[1] - s7) <= 1e-14, (name, ends.s)
    assert curve.s_start == pytest.approx(s0, abs=1e-14) and curve.s_end == pytest.approx(s7, abs=1e-14)
    base = base_name(name)
    v_end = 1.0 if base == "constant-velocity" else 0.0
    v_end = v_end if rise else -v_end
    # V at the ends is a difference of O(Vm) terms: ~10 ulps of Vm ≤ 2.2 is < 1e-14
    assert np.all(np.abs(ends.v - v_end) <= 1e-14), (name, ends.v)
    # at the dwell ends A = 0 unless the law starts/ends on a peak (see the sets above)
    start_base, end_base = (A_NONZERO_START, A_NONZERO_END)
    a_start, a_end = (ends.a[0], ends.a[1]) if rise else (ends.a[1], ends.a[0])
    am = curve.characteristics.am
    if base not in start_base:
        assert abs(a_start) <= 1e-13 * max(am, 1), (name, a_start)
    else:
        assert abs(a_start) > 0.1 * am
    if base not in end_base:
        assert abs(a_end) <= 1e-13 * max(am, 1), (name, a_end)
    else:
        assert abs(a_end) > 0.1 * am


@pytest.mark.parametrize("name", RETURN_OF)
def test_return_stroke_is_the_rise_reversed(name: str) -> None:
    """Makino CURVE lines 147-151, 223-226 (INIT = 2): T → 1 − T, V and J change sign."""
    rise = camcore.named_curve(name)
    ret = ReturnCurve(rise)
    # off the break points (where the one-sided choice differs by design)
    t = np.linspace(0, 1, 1001)[1:-1] + 1e-7
    r = ret.evaluate(t)
    f = rise.evaluate(1 - t)
    # same formulas at mirrored T; the only difference is the rounding of 1 − T (1 ulp),
    # times the derivative: < 1e-12 relative to each quantity's peak
    for got, want, row in [(r.s, f.s, 0), (r.v, -f.v, 1), (r.a, f.a, 2), (r.j, -f.j, 3)]:
        assert np.max(np.abs(got - want)) <= 1e-12 * scale(rise, row), (name, "SVAJ"[row])


def test_right_limit_convention_catalog_mcv50() -> None:
    """INDEXMAN MCV50 table: T = 0.25 prints J = 0.00000 (constant-velocity section starts),
    T = 0.75 prints J = −67.12690 (deceleration starts), T = 0 and 1 print J = 201.38070
    (first and last section)."""
    curve = camcore.named_curve("MCV50")
    j = curve.evaluate([0.0, 0.25, 0.75, 1.0]).j
    printed = [201.38070, 0.0, -67.12690, 201.38070]
    assert np.all(np.abs(j - printed) <= 0.5e-5 + 1e-12), j
    # the left limits are the other sections' values
    left = curve.evaluate(np.nextafter([0.25, 0.75], -np.inf)).j
    assert left[0] == pytest.approx(-67.12690, abs=0.5e-5) and abs(left[1]) < 1e-12


def test_right_limit_convention_return_stroke() -> None:
    """A return stroke takes, at a break point, the piece that starts there in its own time."""
    ret = ReturnCurve(camcore.named_curve("MCV50"))
    j = ret.evaluate([0.25, 0.75]).j
    # at 0.25 the constant-velocity piece starts (J = 0); at 0.75 the mirrored
    # acceleration-end piece starts: J = −(−67.1269) = +67.1269
    assert abs(j[0]) < 1e-12 and j[1] == pytest.approx(67.12690, abs=0.5e-5)


def test_right_limit_convention_ms_ends() -> None:
    """INDEXMAN MS table rows T = 0 and T = 1: J = 69.46636 (first and last sections)."""
    j = camcore.named_curve("MS").evaluate([0.0, 1.0]).j
    assert np.all(np.abs(j - 69.46636) <= 0.5e-5 + 1e-12), j


EXTREMA = [
    ("vm", "absv"), ("v_max", "v"), ("v_min", "v"), ("am_pos", "a"), ("am_neg", "a"),
    ("jm_pos", "j"), ("jm_neg", "j"), ("qm_raw_pos", "q_raw"), ("qm_raw_neg", "q_raw"),
    ("qm_pos", "q"), ("qm_neg", "q"), ("s_max", "s"), ("s_min", "s"),
]


@pytest.mark.parametrize("name,curve", CURVES, ids=IDS)
def test_characteristics_bound_dense_table_and_are_attained(name: str, curve: camcore.Curve) -> None:
    """Exact characteristic values (docs/api.md, characteristics): no sample of a dense table beyond them,
    each attained at its T (as a right or a left limit), and a dense table gets close."""
    ch = curve.characteristics
    bp = curve.break_points
    t = np.unique(np.concatenate([np.linspace(curve.t_start, curve.t_end, 20001), bp,
                                  np.nextafter(bp[1:], -np.inf)]))
    vals = curve.evaluate(t)
    cols = {"s": vals.s, "v": vals.v, "absv": np.abs(vals.v), "a": vals.a, "j": vals.j,
            "q": vals.q, "q_raw": vals.q_raw}
    for attr, col in EXTREMA:
        ext = getattr(ch, attr)
        data = cols[col]
        peak = max(1.0, float(np.max(np.abs(data))))
        # bound: the closed-form extremum can only be beaten by rounding (1e-12 × peak)
        is_max = attr in ("vm", "v_max", "am_pos", "jm_pos", "qm_raw_pos", "qm_pos", "s_max")
        beyond = (data.max() - ext.value) if is_max else (ext.value - data.min())
        assert beyond <= 1e-12 * peak, f"{name}.{attr} = {ext.value!r}, a sample goes {beyond:.3e} beyond"
        # close: a 1/20000 grid misses a smooth interior peak by ≤ f''·h²/8 ≈ 1e5 · 3e-10;
        # 1e-4 × peak bounds that for every quantity here (J's curvature is the largest)
        gap = (ext.value - data.max()) if is_max else (data.min() - ext.value)
        assert gap <= 1e-4 * peak, f"{name}.{attr}: dense table peak differs by {gap:.3e}"
        # attained at ext.t, as the right-limit value or the left limit of the piece ending there
        here = curve.evaluate(np.array([ext.t, np.nextafter(ext.t, -np.inf)]))
        got = {"s": here.s, "v": here.v, "absv": np.abs(here.v), "a": here.a, "j": here.j,
               "q": here.q, "q_raw": here.q_raw}[col]
        assert np.min(np.abs(got - ext.value)) <= 1e-12 * peak, f"{name}.{attr} not attained at T = {ext.t!r}"
    assert ch.am == max(ch.am_pos.value, -ch.am_neg.value)
