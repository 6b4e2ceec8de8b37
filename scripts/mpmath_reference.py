#!/usr/bin/env python
"""High-precision reference values of the sine-family cam curves (mpmath, 40 digits).

Independent of camcore: nothing here imports it. Two sources are ported:

1. Makino (1977), appendix 1, subroutine CURVE — a line-by-line port of the common
   constants (lines 75-124: C1..C7, the equal-area RATIO of line 86, AMP of lines 88-90,
   V1..V7, S1..S7) and of the variable part (lines 146-221: sections 401-407).
   Break points of the table-2 curves are those quoted in docs/sources.md; the open values
   (35: A, 45: B, 47: C, 49: D) are found here *numerically* (mp.findroot) from the
   defining condition "line-86 RATIO = stated m", not from camcore's closed forms.
   Curve 46 uses T5 = 0.625 (the copy's ".675" is flagged doubtful; 0.625 is the
   1/8 transition of the modified-trapezoid family, camcore's reading).
   Curve 36 uses eq. (13) with T6 = T5 (the OCR's T6 = T3 is out of order).
   Curves 1 (z = 0.9), 2 (T4 = 0.6) and 4 (T1 = 0.05, T3 = 0.2) follow lines 30-65.
2. The INDEXMAN guide's displacement expressions (位移表达式) for MS, MC = MCV50,
   MCV25 (MC formulas with Ta = 3/32, Tb = 3/8), MT (section V with Va: the guide
   prints Vb, a misprint) and TR; V, A, J by mpmath's numerical differentiation
   (mp.diffs) of each section's own analytic formula at 40 digits.

Convention at break points (docs/api.md, Conventions): the section that starts there (Fortran's
``T.GE.Tk .AND. T.LT.Tk+1``); at T = T7 the last non-empty section (where the Fortran
goes to section VIII, line 161, and prints A = J = 0 — the catalog tables do not).
A float T that *is* a break point as a float (T = 0.6 for T4 = 0.6, whose exact value
lies 2e-17 above the float) selects its section as if it were exactly the break point:
the section is chosen with the break point, the formula is evaluated at the float T.

Run ``python scripts/mpmath_reference.py`` to regenerate
``tests/data/mp_reference.csv`` (curve, T, S, V, A, J; 25 significant digits).
"""

from __future__ import annotations

import csv
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

from mpmath import cos, findroot, mp, mpf, nstr, pi, sin

mp.dps = 40
#: the start speed V0 of a curve that starts at rest
AT_REST = mpf(0)

OUT = Path(__file__).resolve().parent.parent / "tests" / "data" / "mp_reference.csv"
DIGITS = 25
GRID = 400  # T = k/400, k = 0..400, plus break points and break points ± OFFSET
OFFSET = mpf("1e-9")


# --------------------------------------------------------------------------- Makino CURVE
class MakinoCurve:
    """Subroutine CURVE, common part (lines 75-124) and variable part (lines 146-221)."""

    def __init__(self, no: int, t: list, ratio=None, amp=None, amm=None, v0=AT_REST):
        # lines 16-25: defaults T0 = 0, T7 = 1, V0 = V7 = 0, S0 = 0, S7 = 1, RATIO = 1
        self.T = [mpf(x) for x in t]
        T0, T1, T2, T3, T4, T5, T6, T7 = self.T
        V0, V7, S0, S7 = mpf(v0), mpf(0), mpf(0), mpf(1)
        RATIO = mpf(1) if ratio is None else mpf(ratio)
        C1 = 2 * (T1 - T0) / pi  # lines 76-82
        C2 = T2 - T1
        C3 = 2 * (T3 - T2) / pi
        C4 = T4 - T3
        C5 = 2 * (T5 - T4) / pi
        C6 = T6 - T5
        C7 = 2 * (T7 - T6) / pi
        if no != 2:  # line 83
            if V7 - V0 == 0 and no != 1:  # lines 84-85
                RATIO = (C3 + C2 + C1) / (C7 + C6 + C5)  # line 86
            AMP = (S7 - S0 - V0 * (T7 - T0)) / (  # lines 88-90
                -RATIO * (C7 * C7 + mpf("0.5") * C6 * C6 - C5 * C5 + (T6 - T5) * (T7 - T6) + C5 * (T7 - T4))
                + C3 * C3 + mpf("0.5") * C2 * C2 - C1 * C1 + C3 * (T7 - T3) + (T2 - T1) * (T7 - T2) + C1 * (T7 - T0)
            )
            AMM = RATIO * AMP  # line 91
        else:
            AMP, AMM = mpf(amp), mpf(amm)
        V1 = C1 * AMP + V0  # lines 93-100
        V2 = C2 * AMP + V1
        V3 = C3 * AMP + V2
        V4 = V3
        V5 = -C5 * AMM + V4
        V6 = -C6 * AMM + V5
        V7 = -C7 * AMM + V6
        S1 = -C1 * C1 * AMP + V1 * (T1 - T0) + S0  # lines 101-108
        S2 = mpf("0.5") * C2 * C2 * AMP + C2 * V1 + S1
        S3 = C3 * C3 * AMP + V2 * (T3 - T2) + S2
        S4 = C4 * V3 + S3
        S5 = C5 * C5 * AMM + V5 * (T5 - T4) + S4
        S6 = -mpf("0.5") * C6 * C6 * AMM + C6 * V5 + S5
        S7 = -C7 * C7 * AMM + V6 * (T7 - T6) + S6
        self.__dict__.update(locals())
        del self.__dict__["self"]

    def section(self, t) -> int:
        """Lines 153-161 with the last non-empty section at T = T7 (see module doc)."""
        T = self.T
        t = snap(t, T)
        for k in range(7):
            if T[k] <= t < T[k + 1]:
                return k + 1
        if t == T[7]:
            return max(k + 1 for k in range(7) if T[k] < T[k + 1])
        return 0 if t < T[0] else 8

    def evaluate(self, t) -> tuple:
        d = self
        t = mpf(t)
        sec = self.section(t)
        if sec == 1:  # lines 168-174
            P = (t - d.T0) / d.C1
            return (-d.C1 * d.C1 * d.AMP * sin(P) + d.V1 * (t - d.T0) + d.S0, -d.C1 * d.AMP * cos(P) + d.V1,
                    d.AMP * sin(P), d.AMP * cos(P) / d.C1)
        if sec == 2:  # lines 175-181
            P = t - d.T1
            return mpf("0.5") * d.AMP * P * P + d.V1 * P + d.S1, d.AMP * P + d.V1, d.AMP, mpf(0)
        if sec == 3:  # lines 182-188
            P = (t - d.T2) / d.C3
            return (-d.C3 * d.C3 * d.AMP * (cos(P) - 1) + d.V2 * (t - d.T2) + d.S2, d.C3 * d.AMP * sin(P) + d.V2,
                    d.AMP * cos(P), -d.AMP * sin(P) / d.C3)
        if sec == 4:  # lines 189-194
            return d.V3 * (t - d.T3) + d.S3, d.V3, mpf(0), mpf(0)
        if sec == 5:  # lines 195-201
            P = (t - d.T4) / d.C5
            return (d.C5 * d.C5 * d.AMM * sin(P) + d.V5 * (t - d.T4) + d.S4, d.C5 * d.AMM * cos(P) + d.V5,
                    -d.AMM * sin(P), -d.AMM * cos(P) / d.C5)
        if sec == 6:  # lines 202-208
            P = t - d.T5
            return -mpf("0.5") * d.AMM * P * P + d.V5 * P + d.S5, -d.AMM * P + d.V5, -d.AMM, mpf(0)
        if sec == 7:  # lines 209-215
            P = (t - d.T6) / d.C7
            return (d.C7 * d.C7 * d.AMM * (cos(P) - 1) + d.V6 * (t - d.T6) + d.S6, -d.C7 * d.AMM * sin(P) + d.V6,
                    -d.AMM * cos(P), d.AMM * sin(P) / d.C7)
        if sec == 0:  # lines 162-167
            return d.S0, d.V0, mpf(0), mpf(0)
        return d.S7 + d.V7 * (t - d.T7), d.V7, mpf(0), mpf(0)  # lines 216-221


def ratio_of(t: list) -> mpf:
    """Line 86: RATIO = (C3 + C2 + C1)/(C7 + C6 + C5)."""
    T0, T1, T2, T3, T4, T5, T6, T7 = t
    return (2 * (T3 - T2) / pi + (T2 - T1) + 2 * (T1 - T0) / pi) / (2 * (T7 - T6) / pi + (T6 - T5) + 2 * (T5 - T4) / pi)


def solve_open(shape: Callable[[mpf], list], m: mpf) -> list:
    """The open break point X of a table-2 curve: line-86 RATIO(X) = stated m."""
    x = findroot(lambda x: ratio_of(shape(x)) - m, mpf("0.35"))
    return shape(x)


e = mpf(1) / 8
TABLE_2: dict[int, list] = {
    11: [0, 0, mpf("0.5"), mpf("0.5"), mpf("0.5"), mpf("0.5"), 1, 1],
    12: [0, 0, 0, mpf("0.5"), mpf("0.5"), 1, 1, 1],
    22: [0, mpf("0.25"), mpf("0.25"), mpf("0.5"), mpf("0.5"), mpf("0.75"), mpf("0.75"), 1],
    25: [0, e, 3 * e, mpf("0.5"), mpf("0.5"), 5 * e, 7 * e, 1],
    26: [0, e, e, mpf("0.5"), mpf("0.5"), 7 * e, 7 * e, 1],
    27: [0, mpf(1) / 16, mpf(1) / 16, mpf("0.25"), mpf("0.75"), mpf(15) / 16, mpf(15) / 16, 1],
    33: [0, mpf("0.2"), mpf("0.2"), mpf("0.4"), mpf("0.4"), mpf("0.7"), mpf("0.7"), 1],
    34: [0, mpf("0.1"), mpf("0.3"), mpf("0.4"), mpf("0.4"), mpf("0.55"), mpf("0.85"), 1],
    35: solve_open(lambda a: [0, e, a, a + e, a + e, a + 2 * e, a + 2 * e, 1], mpf(1)),
    43: [0, mpf("0.25"), mpf("0.25"), mpf("0.5"), mpf("0.5"), 1, 1, 1],
    44: [0, mpf("0.2"), mpf("0.2"), mpf("0.4"), mpf("0.4"), 1, 1, 1],
    45: solve_open(lambda b: [0, e, b, b + e, b + e, b + 2 * e, 1, 1], mpf(1)),
    46: [0, e, 3 * e, mpf("0.5"), mpf("0.5"), 5 * e, 1, 1],
    47: solve_open(lambda c: [0, e, c, c + e, c + e, c + mpf(5) / 24, 1, 1], mpf(2) / 3),
    48: [0, e, e, mpf("0.5"), mpf("0.5"), 1, 1, 1],
    49: solve_open(lambda d: [0, e, d, d + e, d + e, 1, 1, 1], mpf(1)),
    50: [0, 0, 0, mpf("0.5"), mpf("0.5"), 1, 1, 1],
    51: [0, 0, mpf("0.25"), mpf("0.5"), mpf("0.5"), mpf("0.75"), 1, 1],
    52: [0, 0, 0, mpf("0.25"), mpf("0.75"), 1, 1, 1],
}


def curve_36() -> MakinoCurve:
    t1 = e  # eq. (13), T6 = T5
    t2 = (2 - 6 * t1 + pi * t1) / (2 + pi)
    return MakinoCurve(36, [0, t1, t2, t2 + t1, t2 + t1, 1 - t1, 1 - t1, 1])


def curve_1(z: mpf) -> MakinoCurve:
    t3 = 1 / (1 + z)  # lines 33-40
    t5 = (3 + t3) / 4
    return MakinoCurve(1, [0, t3 / 4, t3 / 4, t3, t3, t5, t5, 1], ratio=1)


def curve_2(t4: mpf) -> MakinoCurve:
    amm = pi / (4 * (1 - t4) ** 2 / pi + 2 * (1 - t4) * t4)  # lines 45-54
    return MakinoCurve(2, [0, 0, 0, 0, t4, 1, 1, 1], amp=0, amm=amm, v0=2 * (1 - t4) * amm / pi)


def curve_4(t1: mpf, t3: mpf) -> MakinoCurve:
    return MakinoCurve(4, [0, t1, t1, t3, 1 - t3, 1 - t1, 1 - t1, 1])  # lines 59-64


# --------------------------------------------------------------------------- INDEXMAN formulas
def snap(t: mpf, breaks: list) -> mpf:
    """The break point b when float(t) == float(b), else t (for choosing a section only)."""
    for b in breaks:
        if float(t) == float(b):
            return mpf(b)
    return t


class ClosedForm:
    """A catalog displacement expression: sections (start, S(T) formula); derivatives by mp.diffs."""

    def __init__(self, sections: list[tuple[mpf, Callable]]):
        self.sections = sections
        self.T = [s for s, _ in sections] + [mpf(1)]

    def evaluate(self, t) -> tuple:
        t = mpf(t)
        ts = snap(t, self.T)
        k = max(i for i, (start, _) in enumerate(self.sections) if start <= ts) if ts < 1 else len(self.sections) - 1
        return tuple(mp.diffs(self.sections[k][1], t, 3))


def indexman_ms(ta=e) -> ClosedForm:
    am = 1 / (2 * ta / pi + (2 - 8 * ta) / pi**2)
    va = 2 * ta * am / pi
    sa = 2 * ta**2 * am / pi - 4 * ta**2 * am / pi**2
    sb = 1 - sa
    return ClosedForm([
        (mpf(0), lambda t: 2 * ta * am / pi * t - 4 * ta**2 * am / pi**2 * sin(pi * t / (2 * ta))),
        (ta, lambda t: (1 - 2 * ta) ** 2 * am / pi**2 * (1 - cos(pi * (t - ta) / (1 - 2 * ta))) + va * (t - ta) + sa),
        (1 - ta, lambda t: 4 * ta**2 * am / pi**2 * (cos(pi * (t - 1 + ta) / (2 * ta)) - 1) + va * (t - 1 + ta) + sb),
    ])


def indexman_mc(ta, tb) -> ClosedForm:
    am = 1 / (2 / pi * ((2 - 8 / pi) * ta * tb + (4 / pi - 2) * tb**2 + tb))
    va = 2 * ta * am / pi
    sa = 2 * ta**2 * am / pi - 4 * ta**2 * am / pi**2
    vm = 2 * tb * am / pi
    sb = 4 * (tb - ta) ** 2 * am / pi**2 + va * (tb - ta) + sa
    sc, sd = 1 - sb, 1 - sa
    k = 4 * (tb - ta) ** 2 * am / pi**2
    return ClosedForm([
        (mpf(0), lambda t: 2 * ta * am / pi * t - 4 * ta**2 * am / pi**2 * sin(pi * t / (2 * ta))),
        (ta, lambda t: k * (1 - cos(pi * (t - ta) / (2 * (tb - ta)))) + va * (t - ta) + sa),
        (tb, lambda t: vm * (t - tb) + sb),
        (1 - tb, lambda t: k * sin(pi * (t - 1 + tb) / (2 * (tb - ta))) - 2 * (tb - ta) * am / pi * (t - 1 + tb)
         + vm * (t - 1 + tb) + sc),
        (1 - ta, lambda t: 4 * ta**2 * am / pi**2 * (cos(pi * (t - 1 + ta) / (2 * ta)) - 1) + va * (t - 1 + ta) + sd),
    ])


def indexman_mt(ta=e) -> ClosedForm:
    am = 1 / (mpf(1) / 4 - ta + 2 / pi * ta)
    va = 2 * ta * am / pi
    sa = 2 * ta**2 * am / pi - 4 * ta**2 * am / pi**2
    vb = am * (mpf("0.5") - 2 * ta) + va
    sb = am / 2 * (mpf("0.5") - 2 * ta) ** 2 + va * (mpf("0.5") - 2 * ta) + sa
    sc, sd = 1 - sb, 1 - sa
    k = 4 * ta**2 * am / pi**2
    h = mpf("0.5")
    return ClosedForm([
        (mpf(0), lambda t: 2 * ta * am / pi * t - k * sin(pi * t / (2 * ta))),
        (ta, lambda t: am / 2 * (t - ta) ** 2 + va * (t - ta) + sa),
        (h - ta, lambda t: k * (1 - cos(pi * (t - h + ta) / (2 * ta))) + vb * (t - h + ta) + sb),
        (h + ta, lambda t: -am / 2 * (t - h - ta) ** 2 + vb * (t - h - ta) + sc),
        # the guide prints Vb here; Va is the velocity entering section V (see the tests)
        (1 - ta, lambda t: k * (cos(pi * (t - 1 + ta) / (2 * ta)) - 1) + va * (t - 1 + ta) + sd),
    ])


def indexman_tr(ta=e) -> ClosedForm:
    tb = (2 - 6 * ta + pi * ta) / (2 + pi)
    tc = (2 - 2 * ta + 3 * pi * ta) / (2 + pi)
    am = 1 / ((-mpf(3) / 2 + 4 / pi + 4 / pi**2) * ta**2 + (1 + 2 / pi) * ta * tb + tb**2 / 2
              + (2 / pi - 4 / pi**2) * (1 - tc) ** 2)
    va = 2 * ta * am / pi
    sa = 2 * ta**2 * am / pi - 4 * ta**2 * am / pi**2
    vb = am * (tb - ta) + va
    sb = am / 2 * (tb - ta) ** 2 + va * (tb - ta) + sa
    sc = 8 * ta**2 * am / pi**2 + 2 * vb * ta + sb
    return ClosedForm([
        (mpf(0), lambda t: 2 * ta * am / pi * t - 4 * ta**2 * am / pi**2 * sin(pi * t / (2 * ta))),
        (ta, lambda t: am / 2 * (t - ta) ** 2 + va * (t - ta) + sa),
        (tb, lambda t: 4 * ta**2 * am / pi**2 * (1 - cos(pi * (t - tb) / (2 * ta))) + vb * (t - tb) + sb),
        (tc, lambda t: 4 * (1 - tc) ** 2 * am / pi**2 * (cos(pi * (t - tc) / (2 * (1 - tc))) - 1) + vb * (t - tc) + sc),
    ])


def curves() -> dict[str, MakinoCurve | ClosedForm]:
    """Every reference curve by the id written to the CSV."""
    out: dict[str, MakinoCurve | ClosedForm] = {f"makino-{n}": MakinoCurve(n, t) for n, t in TABLE_2.items()}
    out["makino-36"] = curve_36()
    out["makino-1-z0.9"] = curve_1(mpf("0.9"))
    out["makino-2-t4-0.6"] = curve_2(mpf("0.6"))
    out["makino-4-t1-0.05-t3-0.2"] = curve_4(mpf("0.05"), mpf("0.2"))
    out["indexman-MS"] = indexman_ms()
    out["indexman-MCV50"] = indexman_mc(mpf(1) / 16, mpf(1) / 4)
    out["indexman-MCV25"] = indexman_mc(mpf(3) / 32, mpf(3) / 8)
    out["indexman-MT"] = indexman_mt()
    out["indexman-TR"] = indexman_tr()
    return out


def sample_times(curve: MakinoCurve | ClosedForm) -> list[float]:
    """k/400, every interior break point b as a float, and b ± 1e-9 (as floats)."""
    ts = {float(mpf(k) / GRID) for k in range(GRID + 1)}
    for b in curve.T[1:-1]:
        b = mpf(b)
        ts.add(float(b - OFFSET))
        ts.add(float(b + OFFSET))
        ts.add(float(b))
    return sorted(t for t in ts if 0.0 <= t <= 1.0)


def row(curve_id: str, curve: MakinoCurve | ClosedForm, t: float) -> list[str]:
    """One CSV row: the float T written exactly (repr), S, V, A, J to DIGITS digits."""
    return [curve_id, repr(t), *(nstr(x, DIGITS, min_fixed=-30, max_fixed=30) for x in curve.evaluate(mpf(t)))]


def rows() -> Iterator[list[str]]:
    for curve_id, curve in curves().items():
        for t in sample_times(curve):
            yield row(curve_id, curve, t)


def self_check() -> None:
    """The two independent ports must agree where they describe the same curve."""
    cs = curves()
    for a, b in [("indexman-MS", "makino-26"), ("indexman-MCV50", "makino-27"), ("indexman-MT", "makino-25"),
                 ("indexman-TR", "makino-35")]:
        worst = max(abs(x - y) for t in sample_times(cs[b]) for x, y in zip(cs[a].evaluate(t), cs[b].evaluate(t)))
        assert worst < mpf("1e-25"), (a, b, worst)


def main() -> int:
    self_check()
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w", newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(["curve", "T", "S", "V", "A", "J"])
        n = 0
        for r in rows():
            writer.writerow(r)
            n += 1
    print(f"wrote {n} rows to {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
