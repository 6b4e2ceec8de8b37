"""Property tests (Hypothesis) of Makino's universal cam curve over random break points.

Random valid break points T0 = 0 ≤ T1 ≤ … ≤ T6 ≤ T7 = 1 (six sorted draws, snapped to
a 1/64 grid half of the time so that empty sections — T1 = T2, T3 = T4, … — are common),
with m omitted, so Amp and Amm are solved for V7 = V0 = 0, S0 = 0, S7 = 1 (Makino 1977,
eq. (11) and the equal-area rule). Properties:

- ends: S(T0) = S0, S(T7) = S7, V(T0) = V(T7) = 0;
- continuity: S, V and A are continuous at every break point (left limit from the
  previous piece's formula, right limit from the next one's, both at the break point);
  J may jump;
- monotone rise: Amp > 0, Amm > 0 and S never decreases. Why: V7 − V0 = Amp·Cp − Amm·Cn
  = 0 with Cp = C1 + C2 + C3 > 0 and Cn = C5 + C6 + C7 > 0 (there is an acceleration
  section before T3 and a deceleration section after T4), so Amm = Amp·Cp/Cn has the
  sign of Amp. A ≥ 0 on [T0, T3] (quarter sine, constant, quarter cosine of +Amp), A = 0
  on [T3, T4], A ≤ 0 on [T4, T7] (the same of −Amm). If Amp > 0, V rises from V0 = 0,
  stays, then falls monotonically to V7 = 0: never negative, so S is nondecreasing. If
  Amp ≤ 0 the same argument gives V ≤ 0 and S7 ≤ S0, which contradicts S7 − S0 = 1; so
  Amp > 0 (and then Amm > 0);
- inverse ∘ forward = identity at every T where V is not tiny (V ≥ 1e-3·Vm: there
  S determines T to about ulp(S)/V), and forward ∘ inverse = identity for every S;
- the characteristic values bound a sampled 1001-row table (S, V, A, J, Q), and the
  peaks of S, V and A are attained at the reported T;

and the same over Makino's curve 4 (non-standard modified constant velocity) with random
0 < T1 ≤ T3 ≤ 0.5, which is symmetric: Amp = Amm and S(T) + S(1 − T) = 1.

Bounded for CI (``HYPOTHESIS_CURVE_EXAMPLES``, default 60 per test), no deadline.
"""

from __future__ import annotations

import itertools
import os

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import camcore
from camcore.curves.universal import UniversalCurve

pytestmark = pytest.mark.property

EXAMPLES = int(os.environ.get("HYPOTHESIS_CURVE_EXAMPLES", "60"))
SETTINGS = settings(max_examples=EXAMPLES, deadline=None)

#: shortest acceleration span T3 − T0 and deceleration span T7 − T4 drawn: a "valid" cam
#: accelerates and decelerates over a visible part of the stroke (shorter spans only
#: scale Amp up as 1/span, which the relative tolerances below absorb anyway)
MIN_SPAN = 1 / 64
#: shortest non-empty section drawn by the main strategy
MIN_SECTION = 1e-9
#: relative tolerance for continuity and identities (peaks are O(1)..O(10^4) here; the
#: rounding of each side is a few ulps of the peak)
REL = 1e-10


# ----------------------------------------------------------------------------- strategies
unit = st.one_of(
    st.integers(0, 64).map(lambda k: k / 64),  # grid: ties (empty sections) are common
    st.floats(0.0, 1.0, allow_nan=False, allow_subnormal=False),
)


@st.composite
def break_points(draw: st.DrawFn) -> tuple[float, ...]:
    inner = sorted(draw(st.lists(unit, min_size=6, max_size=6)))
    t = (0.0, *inner, 1.0)
    assume(t[3] - t[0] >= MIN_SPAN and t[7] - t[4] >= MIN_SPAN)
    # sections are empty or at least MIN_SECTION long (shorter ones are refused: see below)
    assume(all(b == a or b - a >= MIN_SECTION for a, b in itertools.pairwise(t)))
    return t


@st.composite
def curve4_params(draw: st.DrawFn) -> tuple[float, float]:
    t3 = draw(st.floats(MIN_SPAN, 0.5, allow_nan=False))
    t1 = draw(st.floats(MIN_SPAN / 4, t3, allow_nan=False))
    return t1, t3


# ----------------------------------------------------------------------------- helpers
def peak(curve: camcore.Curve, row: int) -> float:
    """Largest |S|, |V|, |A| or |J| (row 0..3) over the curve, at least 1."""
    ch = curve.characteristics
    values = {
        0: max(abs(ch.s_max.value), abs(ch.s_min.value)),
        1: ch.vm.value,
        2: ch.am,
        3: max(abs(ch.jm_pos.value), abs(ch.jm_neg.value)),
    }
    return max(1.0, values[row])


def one_sided(curve: camcore.Curve, t: float, piece: int, order: int = 3) -> np.ndarray:
    vals = curve.eval_pieces(np.array([t]), np.array([piece], dtype=np.intp), order)
    return np.array([float(v[0]) for v in vals])


def check_ends(curve: camcore.Curve, s0: float = 0.0, s7: float = 1.0) -> None:
    (s_a, s_b), (v_a, v_b) = curve.derivatives([curve.t_start, curve.t_end], 1)
    assert curve.t_start == 0.0 and curve.t_end == 1.0
    assert s_a == pytest.approx(s0, abs=1e-12)
    assert s_b == pytest.approx(s7, abs=1e-12)
    vtol = REL * peak(curve, 1)
    assert abs(v_a) <= vtol and abs(v_b) <= vtol


def a_jumps(t: tuple[float, ...]) -> set[float]:
    """Interior break points where A of the universal curve may jump.

    A runs 0 → Amp (I), Amp (II), Amp → 0 (III), 0 (IV), 0 → −Amm (V), −Amm (VI),
    −Amm → 0 (VII): continuous, except that an empty section III leaves A at +Amp
    at T3, and an empty section V starts the deceleration at −Amm at T4
    (e.g. T1 = T3 = T4 = T6 = 1/2 is the simple harmonic motion, A jumps at 1/2).
    """
    out = set()
    if t[2] == t[3]:
        out.add(t[3])
    if t[4] == t[5]:
        out.add(t[4])
    return out


def check_continuity(curve: UniversalCurve) -> None:
    pieces = curve.pieces
    assert [p.start for p in pieces] == list(curve.break_points[:-1])
    tol = [REL * peak(curve, row) for row in range(3)]
    jumps = a_jumps(curve.t)
    for k in range(1, len(pieces)):
        b = pieces[k].start
        assert pieces[k - 1].end == b
        left = one_sided(curve, b, k - 1)
        right = one_sided(curve, b, k)
        for row, name in enumerate("SVA"):
            if name == "A" and b in jumps:
                continue
            assert abs(left[row] - right[row]) <= tol[row], (
                f"{name} jumps at break point T = {b!r}: {left[row]!r} → {right[row]!r}")


def check_monotone(curve: camcore.Curve) -> None:
    t = np.unique(np.concatenate([np.linspace(0.0, 1.0, 4097), curve.break_points]))
    s, v = curve.derivatives(t, 1)
    vtol = REL * peak(curve, 1)
    assert v.min() >= -vtol
    assert np.diff(s).min() >= -1e-12
    assert curve.characteristics.v_min.value >= -vtol
    assert curve.monotone_direction == 1


def check_inverse(curve: camcore.Curve) -> None:
    t = np.linspace(0.0, 1.0, 513)
    s, v = curve.derivatives(t, 1)
    vm = curve.characteristics.vm.value
    ok = v >= 1e-3 * vm
    assert ok.any()
    back = curve.inverse(s[ok])
    # |ΔT| ≈ |ΔS| / V ≤ a few ulps / (1e-3·Vm)
    assert np.max(np.abs(back - t[ok])) <= 1e-9
    targets = np.linspace(0.0, 1.0, 257)
    t_found = curve.inverse(targets)
    assert np.all((t_found >= 0.0) & (t_found <= 1.0))
    assert np.max(np.abs(curve.derivatives(t_found, 0)[0] - targets)) <= 1e-12


def check_characteristics_bound_table(curve: camcore.Curve) -> None:
    ch = curve.characteristics
    table = curve.table(1001)
    tol = [REL * peak(curve, row) for row in range(4)]
    assert table.s.max() <= ch.s_max.value + tol[0] and table.s.min() >= ch.s_min.value - tol[0]
    assert table.v.max() <= ch.v_max.value + tol[1] and table.v.min() >= ch.v_min.value - tol[1]
    assert np.abs(table.v).max() <= ch.vm.value + tol[1]
    assert table.a.max() <= ch.am_pos.value + tol[2] and table.a.min() >= ch.am_neg.value - tol[2]
    assert np.abs(table.a).max() <= ch.am + tol[2]
    assert table.j.max() <= ch.jm_pos.value + tol[3] and table.j.min() >= ch.jm_neg.value - tol[3]
    qtol = REL * max(1.0, ch.vm.value)
    assert table.q.max() <= ch.qm_pos.value + qtol and table.q.min() >= ch.qm_neg.value - qtol
    # the table comes as close to the exact peaks as the slopes allow: a row lies within
    # one step on the peak's side of it, and |dV/dT| ≤ Am, |dA/dT| ≤ Jm (mean value theorem)
    step = 1.0 / 1000
    jm = max(abs(ch.jm_pos.value), abs(ch.jm_neg.value))
    assert np.abs(table.v).max() >= ch.vm.value - ch.am * step - tol[1]
    assert np.abs(table.a).max() >= ch.am - jm * step - tol[2]
    # and the reported T of each peak gives the peak, from one side or the other of a
    # break point (A may jump there)
    starts = list(curve.piece_starts)
    for ext, row in ((ch.v_max, 1), (ch.am_pos, 2), (ch.am_neg, 2), (ch.s_max, 0)):
        assert 0.0 <= ext.t <= 1.0
        values = [curve.derivatives([ext.t], 2)[row][0]]
        if ext.t in starts and starts.index(ext.t) > 0:
            values.append(one_sided(curve, ext.t, starts.index(ext.t) - 1)[row])
        if ext.t == curve.t_end:
            values.append(one_sided(curve, ext.t, curve.n_pieces - 1)[row])
        assert min(abs(v - ext.value) for v in values) <= tol[row], (ext, values)


def check_all(curve: UniversalCurve) -> None:
    check_ends(curve)
    check_continuity(curve)
    check_monotone(curve)
    check_inverse(curve)
    check_characteristics_bound_table(curve)


# ----------------------------------------------------------------------------- universal curve
@SETTINGS
@given(break_points())
def test_universal_curve_rises_with_positive_amplitudes(t: tuple[float, ...]) -> None:
    curve = camcore.universal_curve(t)
    assert isinstance(curve, UniversalCurve)
    assert curve.amp > 0 and curve.amm > 0
    assert curve.v7 == pytest.approx(0.0, abs=REL * peak(curve, 1))
    assert curve.s7 == pytest.approx(1.0, abs=1e-12)


@SETTINGS
@given(break_points())
def test_universal_curve_ends_and_continuity(t: tuple[float, ...]) -> None:
    curve = camcore.universal_curve(t)
    check_ends(curve)
    check_continuity(curve)
    # the break points are the drawn ones, with empty sections dropped
    assert set(curve.break_points) <= set(t)
    assert curve.break_points[0] == t[0] and curve.break_points[-1] == t[7]


@SETTINGS
@given(break_points())
def test_universal_curve_is_monotone(t: tuple[float, ...]) -> None:
    check_monotone(camcore.universal_curve(t))


@SETTINGS
@given(break_points())
def test_universal_curve_inverse_undoes_forward(t: tuple[float, ...]) -> None:
    check_inverse(camcore.universal_curve(t))


@SETTINGS
@given(break_points())
def test_universal_curve_characteristics_bound_table(t: tuple[float, ...]) -> None:
    check_characteristics_bound_table(camcore.universal_curve(t))


@SETTINGS
@given(break_points(), st.floats(0.5, 4.0), st.floats(-5.0, 5.0))
def test_universal_curve_scales_with_stroke(t: tuple[float, ...], s7: float, s0: float) -> None:
    """S0 and S7 only shift and scale the curve: S = S0 + (S7 − S0)·S_unit."""
    unit_curve = camcore.universal_curve(t)
    curve = camcore.universal_curve(t, s0=s0, s7=s0 + s7)
    grid = np.linspace(0.0, 1.0, 129)
    s_u, v_u = unit_curve.derivatives(grid, 1)
    s, v = curve.derivatives(grid, 1)
    assert np.allclose(s, s0 + s7 * s_u, rtol=0, atol=1e-9 * (1 + abs(s0) + s7))
    assert np.allclose(v, s7 * v_u, rtol=0, atol=REL * s7 * peak(unit_curve, 1))


# ----------------------------------------------------------------------------- Makino curve 4
@SETTINGS
@given(curve4_params())
def test_makino_curve_4_properties(params: tuple[float, float]) -> None:
    t1, t3 = params
    curve = camcore.makino_curve(4, t1=t1, t3=t3)
    expected = (0.0, t1, t1, t3, 1.0 - t3, 1.0 - t1, 1.0 - t1, 1.0)
    # sections shorter than MIN_SECTION (T3 − T1 of a few ulps) are merged into their start
    assert np.allclose(curve.t, expected, rtol=0, atol=camcore.curves.universal.MIN_SECTION)
    # symmetric break points: equal areas need Amm = Amp (m = 1)
    assert curve.amm == pytest.approx(curve.amp, rel=1e-9)
    check_all(curve)
    # point symmetry about (1/2, 1/2): S(T) + S(1 − T) = 1, V(T) = V(1 − T)
    grid = np.linspace(0.0, 1.0, 257)
    s, v = curve.derivatives(grid, 1)
    s_m, v_m = curve.derivatives(1.0 - grid, 1)
    assert np.max(np.abs(s + s_m - 1.0)) <= 1e-9
    assert np.max(np.abs(v - v_m)) <= 1e-9 * peak(curve, 1)


@pytest.mark.parametrize("t1", [1e-160, 2.2250738585072014e-308, 1e-10])
def test_universal_curve_with_a_vanishing_section_merges_it(t1: float) -> None:
    # found by fuzzing: a quarter-wave section of ~1e-154 made ω² overflow (a 500). A section
    # shorter than camcore.curves.universal.MIN_SECTION of the stroke is rounding noise and is merged
    # away: the curve is the one without it (modified sine here), to rounding.
    curve = camcore.universal_curve((0.0, t1, t1, 0.5, 0.5, 0.875, 0.875, 1.0))
    assert curve.t[:3] == (0.0, 0.0, 0.0)
    ref = camcore.universal_curve((0.0, 0.0, 0.0, 0.5, 0.5, 0.875, 0.875, 1.0))
    grid = np.linspace(0.0, 1.0, 101)
    for mine, theirs in zip(curve.derivatives(grid, 3), ref.derivatives(grid, 3)):
        assert np.array_equal(mine, theirs)
    check_ends(curve)
    check_monotone(curve)


def test_makino_curve_4_matches_the_catalog_mcv_curves() -> None:
    """The strategy's family contains the catalog's MCV50 (1/16, 1/4) and MCV25 (3/32, 3/8)."""
    for name, (t1, t3) in (("MCV50", (1 / 16, 1 / 4)), ("MCV25", (3 / 32, 3 / 8))):
        ours = camcore.makino_curve(4, t1=t1, t3=t3).characteristics
        assert ours.vm.value == pytest.approx(camcore.named_curve(name).characteristics.vm.value, rel=1e-12)
