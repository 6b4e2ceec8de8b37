"""Makino 1977 §5.3 (Fig. 6-9): the cutting-unit feed cam as a motion program.

The cycle: rapid feed (curve 1, z = 0.9) 40 mm over 60°, cutting feed (curve 2, T4 omitted,
``to: null``) over 120°, rapid return (curve 48 played backwards) to 0 over 90°, dwell 90°.
With h1 = 40, β = (60, 120, 90) and h2 the cutting stroke, the program must solve

    (E1)  h1·V7₁/β1 = h2·V0₂(T4)/β2                 velocity continuous at 60°
    (E2)  h2·Amm₂(T4)/β2² = (h1 + h2)·Amm₄₈/β3²      acceleration continuous at 180°

(curve 2 ends at a = −h2·Amm₂/β2²; the return N(T) = 1 − S₄₈(1 − T) from h1 + h2 to 0
starts at a = −(h1 + h2)·Amm₄₈/β3²). Curve 1 ends with A = 0 and curve 2 starts with
A = 0, both ends of the cycle are at rest, so the whole cycle is C2 — Makino's "velocity and
acceleration continuous at the joints".

The reference here is independent of camcore: each curve's acceleration is written from
its break points (curve 1: Fortran lines 34-39; curve 2: lines 45-50, its Amm and V0 *not*
taken from line 51 but solved from S(1) = 1, V(1) = 0; curve 48: table 2's break points with
Amp, Amm solved from S(1) = 1, V(1) = 0), integrated with mpmath at 30 digits, and (E1), (E2)
solved with mpmath's root finder. The article draws Fig. 6-9 without printing their numbers,
so there are no printed values to compare with; eq. (16) (V7/V3 = 1 − z) is checked instead.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from camcore.errors import InvalidParameterError
from camcore.motion import SOLVE, Law, MotionSegment, MotionSpec, resolve_motion

mp.mp.dps = 30
Z = mp.mpf("0.9")
H1 = mp.mpf(40)
B1, B2, B3, B4 = 60, 120, 90, 90


def _integrals(pieces: list[tuple[mp.mpf, mp.mpf, object]], t: mp.mpf) -> tuple[mp.mpf, mp.mpf]:
    """∫0^t a(u) du and ∫0^t (t − u)·a(u) du of a piecewise acceleration."""
    v = s = mp.mpf(0)
    for lo, hi, a in pieces:
        if t <= lo:
            break
        top = min(hi, t)
        v += mp.quad(a, [lo, top])
        s += mp.quad(lambda u, a=a: (t - u) * a(u), [lo, top])
    return v, s


# --------------------------------------------------------------------------- curve 1 (z)
T3_1 = 1 / (1 + Z)
T1_1 = T3_1 / 4
T5_1 = (3 + T3_1) / 4
CURVE1 = [(mp.mpf(0), T1_1, lambda u: mp.sin(mp.pi * u / (2 * T1_1))),
          (T1_1, T3_1, lambda u: mp.cos(mp.pi * (u - T1_1) / (2 * (T3_1 - T1_1)))),
          (T3_1, T5_1, lambda u: -mp.sin(mp.pi * (u - T3_1) / (2 * (T5_1 - T3_1)))),
          (T5_1, mp.mpf(1), lambda u: -mp.cos(mp.pi * (u - T5_1) / (2 * (1 - T5_1))))]
AMP_1 = 1 / _integrals(CURVE1, mp.mpf(1))[1]  # m = 1: S(1) = Amp·∫(1 − u)·a(u) du = 1


def curve1(t: mp.mpf) -> tuple[mp.mpf, mp.mpf]:
    v, s = _integrals(CURVE1, t)
    return AMP_1 * s, AMP_1 * v


V7_1 = curve1(mp.mpf(1))[1]


# --------------------------------------------------------------------------- curve 2 (T4)
def curve2_amplitudes(t4: mp.mpf) -> tuple[mp.mpf, mp.mpf]:
    """(V0, Amm) from V(1) = V0 − Amm·∫sin = 0 and S(1) = V0 − Amm·∫(1 − u)·sin = 1."""
    pieces = [(t4, mp.mpf(1), lambda u: mp.sin(mp.pi * (u - t4) / (2 * (1 - t4))))]
    dv, ds = _integrals(pieces, mp.mpf(1))
    amm = 1 / (dv - ds)
    return amm * dv, amm


def curve2(t4: mp.mpf, t: mp.mpf) -> tuple[mp.mpf, mp.mpf]:
    v0, amm = curve2_amplitudes(t4)
    pieces = [(t4, mp.mpf(1), lambda u: -amm * mp.sin(mp.pi * (u - t4) / (2 * (1 - t4))))]
    dv, ds = _integrals(pieces, t)
    return v0 * t + ds, v0 + dv


# --------------------------------------------------------------------------- curve 48
ACC48 = [(mp.mpf(0), mp.mpf(1) / 8, lambda u: mp.sin(mp.pi * u / (2 * mp.mpf(1) / 8))),
         (mp.mpf(1) / 8, mp.mpf(1) / 2, lambda u: mp.cos(mp.pi * (u - mp.mpf(1) / 8) / (2 * mp.mpf(3) / 8)))]
DEC48 = [(mp.mpf(1) / 2, mp.mpf(1), lambda u: -mp.sin(mp.pi * (u - mp.mpf(1) / 2) / (2 * mp.mpf(1) / 2)))]
_VA, _SA = _integrals(ACC48, mp.mpf(1))
_VD, _SD = _integrals(DEC48, mp.mpf(1))
AMP_48, AMM_48 = mp.lu_solve(mp.matrix([[_VA, _VD], [_SA, _SD]]), mp.matrix([0, 1]))


def curve48(t: mp.mpf) -> mp.mpf:
    sa = _integrals(ACC48, t)[1]
    sd = _integrals(DEC48, t)[1]
    return AMP_48 * sa + AMM_48 * sd


# --------------------------------------------------------------------------- (E1), (E2)
def cutting_stroke(t4: mp.mpf) -> mp.mpf:
    return H1 * V7_1 / B1 * B2 / curve2_amplitudes(t4)[0]  # (E1)


def e2(t4: mp.mpf) -> mp.mpf:
    h2 = cutting_stroke(t4)
    return h2 * curve2_amplitudes(t4)[1] / B2**2 - (H1 + h2) * AMM_48 / B3**2


T4_REF = mp.findroot(e2, (mp.mpf("0.5"), mp.mpf("0.999")), solver="ridder")
H2_REF = cutting_stroke(T4_REF)


def makino_cycle(spans: tuple[int, int, int, int] = (B1, B2, B3, B4)) -> MotionSpec:
    return MotionSpec([
        MotionSegment(spans[0], to=40, law=Law("makino", {"number": 1, "z": 0.9})),
        MotionSegment(spans[1], to=SOLVE, law=Law("makino", {"number": 2})),
        MotionSegment(spans[2], to=0, law=Law("named", {"name": "48"}, "return")),
        MotionSegment(spans[3], type="dwell")])


PROGRAM = resolve_motion(makino_cycle())


def test_the_reference_meets_eq_16() -> None:
    # the independent curve 1 ends at V7 = (1 − z)·V3 (Makino eq. 16) and at rest in acceleration
    v3 = AMP_1 * _integrals(CURVE1, T3_1)[0]
    assert abs(V7_1 / v3 - (1 - Z)) < mp.mpf("1e-25")
    assert 0.95 < T4_REF < 0.96  # the root found is inside (0, 1) and unique on the scan below
    assert all(e2(mp.mpf(k) / 100) < 0 for k in range(0, 95, 5)) and e2(mp.mpf("0.97")) > 0


def test_solved_t4_and_cutting_stroke_match_the_independent_solution() -> None:
    solved = PROGRAM.segments[1].solved
    # T4 is refined to a few ulp; (E2) has slope ~1e-2 mm/deg² per unit T4 here, so the
    # float64 law values (rounding ~1e-16 relative) move the root by ~1e-14: 1e-12 holds both
    assert abs(solved["t4"] - float(T4_REF)) < 1e-12
    assert abs(solved["stroke"] - float(H2_REF)) < 1e-11 * float(H2_REF)
    assert PROGRAM.segments[1].to == pytest.approx(40 + float(H2_REF), rel=1e-13)
    assert PROGRAM.segments[2].stroke == pytest.approx(-(40 + float(H2_REF)), rel=1e-13)


def test_the_whole_cycle_is_c2_at_every_join() -> None:
    joins = PROGRAM.joins
    assert [j.at_deg for j in joins] == [60, 180, 270, 360]
    for join in joins:
        assert join.continuity in ("C2", "C3"), join
    # the class is what the jumps say, against the program's scales
    s_range, v_peak, a_peak, _ = PROGRAM.scales
    for join in joins:
        assert abs(join.ds) <= 1e-9 * s_range and abs(join.dv) <= 1e-9 * v_peak and abs(join.da) <= 1e-9 * a_peak
    # curve 1 starts with a jerk (its quarter sine from rest): the cycle is C2, not C3, there
    assert joins[-1].continuity == "C2" and joins[-1].dj > 0


def test_positions_and_velocities_match_independent_curves_1_2_and_48() -> None:
    x = np.array([0, 7.5, 15, 31, 45, 59.9, 60, 75, 120, 175, 179.99, 180, 200, 225, 250, 269, 270, 300, 360])
    s, v = PROGRAM.derivatives(x, 1)
    t4, h2 = T4_REF, H2_REF
    ref_s, ref_v = [], []
    for xi in x.tolist():
        xm = mp.mpf(xi)
        if xi < 60:
            sn, vn = curve1(xm / B1)
            ref_s.append(H1 * sn)
            ref_v.append(H1 / B1 * vn)
        elif xi < 180:
            sn, vn = curve2(t4, (xm - 60) / B2)
            ref_s.append(H1 + h2 * sn)
            ref_v.append(h2 / B2 * vn)
        elif xi < 270:
            tt = (xm - 180) / B3
            top = H1 + h2
            ref_s.append(top * curve48(1 - tt))  # s_a + (0 − s_a)·(1 − S48(1 − T))
            ref_v.append(-top / B3 * _velocity48(1 - tt))
        else:
            ref_s.append(mp.mpf(0))
            ref_v.append(mp.mpf(0))
    # float64 closed forms: rounding ~1e-15 of the range (53 mm) and of the peak velocity;
    # the solved T4/h2 add ~1e-13 relative: 1e-11 of each quantity's scale leaves a margin
    s_range, v_peak = PROGRAM.scales[:2]
    assert np.max(np.abs(s - np.array(ref_s, dtype=float))) < 1e-11 * s_range
    assert np.max(np.abs(v - np.array(ref_v, dtype=float))) < 1e-11 * v_peak


def _velocity48(t: mp.mpf) -> mp.mpf:
    return AMP_48 * _integrals(ACC48, t)[0] + AMM_48 * _integrals(DEC48, t)[0]


def test_no_t4_when_the_return_starts_too_gently() -> None:
    # a short cutting feed (20°) before a slow return (260°): curve 2 decelerates harder than
    # the return starts, at every T4 (its Amm only grows towards T4 → 1)
    with pytest.raises(InvalidParameterError) as err:
        resolve_motion(makino_cycle((60, 20, 260, 20)))
    assert err.value.field == ("segments", 1, "curve", "t4")
    assert "segments[1]: no t4 in [0, 1) makes the acceleration continuous" in str(err.value)
