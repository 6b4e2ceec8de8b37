"""The INDEXMAN catalog curves against the catalog's own printed numbers.

Source: INDEXMAN guide (docs/sources.md), the catalog's technical section 技术说明,
section 5 "凸轮曲线":
- the 0.01-step tables "凸轮曲线特性表" of MS, MC (MCV50), MCV25, MT and TR, copied to
  ``tests/data/indexman_<name>.csv`` (columns T, S, V, A, J, Q = A·V/Am; 101 rows each,
  printed to 5 decimals);
- the characteristic-value table "凸轮曲线的特性值一览";
- the closed-form displacement expressions "位移表达式" and constants "常数表达式"
  of MS, MC, MT and TR.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import camcore

DATA = Path(__file__).resolve().parents[3] / "tests" / "data"
CURVES = ["MS", "MCV50", "MCV25", "MT", "TR"]
COLUMNS = ["S", "V", "A", "J", "Q"]

#: Half a unit in the 5th decimal: the largest error of a correctly rounded printed value.
HALF_DIGIT = 0.5e-5
#: Float slack on top of HALF_DIGIT: our float64 values carry ~1e-14 absolute error (J is
#: up to ~200, so a few ulps of 200 is ~1e-13) and parsing "0.57795" to a double adds
#: ~1e-17. 1e-12 covers both and is 10^7 times smaller than a printed digit, so it cannot
#: hide a misprint.
FLOAT_SLACK = 1e-12

#: Printing errors in the catalog tables, by (curve, T, column). Each was identified by
#: the table's own symmetry: MS is point-symmetric about T = 0.5, so V(T) = V(1 − T) and
#: the mirror row prints the value that the closed form gives.
MISPRINTS: dict[tuple[str, float, str], dict[str, float | str]] = {
    ("MS", 0.15, "V"): {
        "printed": 0.57795,
        "mirror_t": 0.85,
        "mirror_printed": 0.57785,
        "why": "MS table row T = 0.15 prints V = 0.57795; the closed form gives 0.577847 and the "
        "mirror row T = 0.85 prints 0.57785: the 4th decimal 8 was printed as 9.",
    },
    ("MS", 0.96, "V"): {
        "printed": 0.05541,
        "mirror_t": 0.04,
        "mirror_printed": 0.05441,
        "why": "MS table row T = 0.96 prints V = 0.05541; the closed form gives 0.054413 and the "
        "mirror row T = 0.04 prints 0.05441: the 3rd decimal 4 was printed as 5.",
    },
}


def load_table(name: str) -> dict[str, np.ndarray]:
    raw = np.loadtxt(DATA / f"indexman_{name}.csv", delimiter=",", skiprows=1)
    return {col: raw[:, i] for i, col in enumerate(["T", *COLUMNS])}


def computed_columns(name: str, t: np.ndarray) -> dict[str, np.ndarray]:
    vals = camcore.named_curve(name).evaluate(t)
    return {"S": vals.s, "V": vals.v, "A": vals.a, "J": vals.j, "Q": vals.q}


@pytest.mark.parametrize("name", CURVES)
def test_table_shape(name: str) -> None:
    """Each table has rows T = 0.00, 0.01, …, 1.00 (101 rows)."""
    table = load_table(name)
    assert table["T"].shape == (101,), f"{name}: expected 101 rows, got {table['T'].shape}"
    np.testing.assert_array_equal(table["T"], np.round(np.arange(101) / 100, 2))


@pytest.mark.parametrize("name", CURVES)
def test_table_reproduced_to_every_printed_digit(name: str) -> None:
    """INDEXMAN guide, 凸轮曲线特性表 of ``name``: all 101 rows × S, V, A, J, Q.

    Every cell except the named misprints equals the computed value correctly rounded
    to 5 decimals; the misprint cells must NOT match, so the MISPRINTS list stays honest.
    """
    table = load_table(name)
    t = table["T"]
    comp = computed_columns(name, t)
    failures = []
    for col in COLUMNS:
        for i, ti in enumerate(t):
            key = (name, round(float(ti), 2), col)
            err = abs(comp[col][i] - table[col][i])
            ok = err <= HALF_DIGIT + FLOAT_SLACK
            if key in MISPRINTS:
                assert not ok, f"{key} is listed as a misprint but matches the computed value {comp[col][i]!r}"
            elif not ok:
                failures.append(f"T = {ti:.2f} {col}: printed {table[col][i]:.5f}, computed {comp[col][i]:.8f}")
    assert not failures, f"{name}: {len(failures)} cells off by more than half a printed digit:\n" + "\n".join(failures)


@pytest.mark.parametrize("key", sorted(MISPRINTS), ids=lambda k: f"{k[0]}-T{k[1]}-{k[2]}")
def test_misprint_explained_by_mirror_row(key: tuple[str, float, str]) -> None:
    """A misprint is named by row: the computed value rounds to the mirror row's print."""
    name, t, col = key
    info = MISPRINTS[key]
    table = load_table(name)
    rows = {round(float(x), 2): i for i, x in enumerate(table["T"])}
    assert table[col][rows[t]] == info["printed"], f"{key}: the CSV copy does not hold the printed value"
    assert table[col][rows[info["mirror_t"]]] == info["mirror_printed"], f"{key}: mirror row differs from the note"
    computed = computed_columns(name, np.array([t]))[col][0]
    # the computed value at the misprinted row, rounded as printed, is the mirror row's print
    assert abs(computed - info["mirror_printed"]) <= HALF_DIGIT + FLOAT_SLACK, (computed, info["why"])
    # and is more than one printed digit away from the misprint
    assert abs(computed - info["printed"]) > 1e-5, (computed, info["why"])


# INDEXMAN guide, 凸轮曲线的特性值一览 (characteristic values). Vm, Am, Qm printed to
# 2 decimals, Jm to 1 decimal; MT and TR print "±Jm" (one magnitude for both signs).
CHARACTERISTIC_TABLE = {
    #         Vm    Am    Jm+    Jm−    Qm
    "MS": (1.76, 5.53, 69.5, -23.2, 0.99),
    "MCV50": (1.28, 8.01, 201.4, -67.1, 0.72),
    "MCV25": (1.48, 6.19, 103.8, -34.6, 0.83),
    "MT": (2.00, 4.89, 61.4, -61.4, 1.65),
    "TR": (2.18, 6.17, 77.5, -77.5, 1.76),
}


#: The characteristic-value table's one inconsistency: MT Qm is printed ±1.65, but the exact
#: peak of A·V/Am is 1.655028 (at T = 0.39252), which rounds to 1.66. The printed value is
#: what one reads off the 0.01-step MT table (largest printed Q = 1.65408 at T = 0.39) or
#: gets by truncating; the other four curves' Qm are correctly rounded exact values
#: (MS 0.98730 → 0.99 where the table's max 0.98711 also gives 0.99, MCV25 0.82973 → 0.83).
CHARACTERISTIC_MISPRINTS = {("MT", "Qm+"): 1.66, ("MT", "Qm-"): -1.66}


def test_characteristic_misprint_mt_qm() -> None:
    """INDEXMAN guide, 特性值一览, row MT, column Qm: printed ±1.65, exact 1.65503."""
    curve = camcore.named_curve("MT")
    ch = curve.characteristics
    assert round(ch.qm_pos.value, 2) == 1.66 and round(ch.qm_neg.value, 2) == -1.66
    assert abs(ch.qm_pos.value - 1.655028) < 1e-6
    table_max = load_table("MT")["Q"].max()
    assert table_max == 1.65408 and round(table_max, 2) == CHARACTERISTIC_TABLE["MT"][4]


@pytest.mark.parametrize("name", CURVES)
def test_characteristic_value_table(name: str) -> None:
    """INDEXMAN guide, 凸轮曲线的特性值一览, row ``name``: exact values rounded as printed."""
    vm, am, jp, jn, qm = CHARACTERISTIC_TABLE[name]
    ch = camcore.named_curve(name).characteristics
    got = {
        "Vm": (round(ch.vm.value, 2), vm),
        "Am+": (round(ch.am_pos.value, 2), am),
        "Am-": (round(ch.am_neg.value, 2), -am),
        "Jm+": (round(ch.jm_pos.value, 1), jp),
        "Jm-": (round(ch.jm_neg.value, 1), jn),
        "Qm+": (round(ch.qm_pos.value, 2), qm),
        "Qm-": (round(ch.qm_neg.value, 2), -qm),
    }
    for column, expected in CHARACTERISTIC_MISPRINTS.items():
        if column[0] == name:
            assert got[column[1]][0] == expected, f"{column}: misprint note is stale"
            del got[column[1]]
    bad = {k: v for k, v in got.items() if v[0] != v[1]}
    assert not bad, f"{name}: (computed rounded, printed) differ: {bad}"
    assert ch.am == max(ch.am_pos.value, -ch.am_neg.value)


# --------------------------------------------------------------------------- closed forms
# The catalog's own formulas (常数表达式 / 位移表达式), written out independently of
# camcore. MCV25 uses the MC formulas with Ta = 3/32, Tb = 3/8 (T1 = T3/4, the MCV family).
PI = math.pi


def ms_closed(t: np.ndarray, ta: float = 1 / 8) -> tuple[np.ndarray, dict[str, float]]:
    am = 1 / (2 * ta / PI + (2 - 8 * ta) / PI**2)
    va = 2 * ta * am / PI
    sa = 2 * ta**2 * am / PI - 4 * ta**2 * am / PI**2
    sb = 1 - sa
    s = np.where(
        t <= ta,
        2 * ta * am / PI * t - 4 * ta**2 * am / PI**2 * np.sin(PI * t / (2 * ta)),
        np.where(
            t <= 1 - ta,
            (1 - 2 * ta) ** 2 * am / PI**2 * (1 - np.cos(PI * (t - ta) / (1 - 2 * ta))) + va * (t - ta) + sa,
            4 * ta**2 * am / PI**2 * (np.cos(PI * (t - 1 + ta) / (2 * ta)) - 1) + va * (t - 1 + ta) + sb,
        ),
    )
    return s, {"Am": am, "Va": va, "Sa": sa, "Sb": sb, "Ta": ta}


def mc_closed(t: np.ndarray, ta: float = 1 / 16, tb: float = 1 / 4) -> tuple[np.ndarray, dict[str, float]]:
    am = 1 / (2 / PI * ((2 - 8 / PI) * ta * tb + (4 / PI - 2) * tb**2 + tb))
    va = 2 * ta * am / PI
    sa = 2 * ta**2 * am / PI - 4 * ta**2 * am / PI**2
    vm = 2 * tb * am / PI
    sb = 4 * (tb - ta) ** 2 * am / PI**2 + va * (tb - ta) + sa
    sc = 1 - sb
    sd = 1 - sa
    k = 4 * (tb - ta) ** 2 * am / PI**2
    s1 = 2 * ta * am / PI * t - 4 * ta**2 * am / PI**2 * np.sin(PI * t / (2 * ta))
    s2 = k * (1 - np.cos(PI * (t - ta) / (2 * (tb - ta)))) + va * (t - ta) + sa
    s3 = vm * (t - tb) + sb
    u = t - 1 + tb
    s4 = k * np.sin(PI * u / (2 * (tb - ta))) - 2 * (tb - ta) * am / PI * u + vm * u + sc
    s5 = 4 * ta**2 * am / PI**2 * (np.cos(PI * (t - 1 + ta) / (2 * ta)) - 1) + va * (t - 1 + ta) + sd
    s = np.select([t <= ta, t <= tb, t <= 1 - tb, t <= 1 - ta], [s1, s2, s3, s4], s5)
    return s, {"Am": am, "Va": va, "Sa": sa, "Vm": vm, "Sb": sb, "Ta": ta, "Tb": tb}


def mt_closed(
    t: np.ndarray, ta: float = 1 / 8, as_printed: bool = False
) -> tuple[np.ndarray, dict[str, float]]:
    """MT as in the guide, except section V (see MT_SECTION_V_MISPRINT) unless ``as_printed``."""
    am = 1 / (0.25 - ta + 2 / PI * ta)
    va = 2 * ta * am / PI
    sa = 2 * ta**2 * am / PI - 4 * ta**2 * am / PI**2
    vb = am * (0.5 - 2 * ta) + va
    sb = am / 2 * (0.5 - 2 * ta) ** 2 + va * (0.5 - 2 * ta) + sa
    sc = 1 - sb
    sd = 1 - sa
    k = 4 * ta**2 * am / PI**2
    s1 = 2 * ta * am / PI * t - k * np.sin(PI * t / (2 * ta))
    s2 = am / 2 * (t - ta) ** 2 + va * (t - ta) + sa
    s3 = k * (1 - np.cos(PI * (t - 0.5 + ta) / (2 * ta))) + vb * (t - 0.5 + ta) + sb
    s4 = -am / 2 * (t - 0.5 - ta) ** 2 + vb * (t - 0.5 - ta) + sc
    v_end = vb if as_printed else va
    s5 = k * (np.cos(PI * (t - 1 + ta) / (2 * ta)) - 1) + v_end * (t - 1 + ta) + sd
    s = np.select([t <= ta, t <= 0.5 - ta, t <= 0.5 + ta, t <= 1 - ta], [s1, s2, s3, s4], s5)
    return s, {"Am": am, "Va": va, "Sa": sa, "Vb": vb, "Sb": sb, "Ta": ta}


def tr_closed(t: np.ndarray, ta: float = 1 / 8) -> tuple[np.ndarray, dict[str, float]]:
    tb = (2 - 6 * ta + PI * ta) / (2 + PI)
    tc = (2 - 2 * ta + 3 * PI * ta) / (2 + PI)
    am = 1 / (
        (-1.5 + 4 / PI + 4 / PI**2) * ta**2
        + (1 + 2 / PI) * ta * tb
        + 0.5 * tb**2
        + (2 / PI - 4 / PI**2) * (1 - tc) ** 2
    )
    va = 2 * ta * am / PI
    sa = 2 * ta**2 * am / PI - 4 * ta**2 * am / PI**2
    vb = am * (tb - ta) + va
    sb = am / 2 * (tb - ta) ** 2 + va * (tb - ta) + sa
    sc = 8 * ta**2 * am / PI**2 + 2 * vb * ta + sb
    s1 = 2 * ta * am / PI * t - 4 * ta**2 * am / PI**2 * np.sin(PI * t / (2 * ta))
    s2 = am / 2 * (t - ta) ** 2 + va * (t - ta) + sa
    s3 = 4 * ta**2 * am / PI**2 * (1 - np.cos(PI * (t - tb) / (2 * ta))) + vb * (t - tb) + sb
    s4 = 4 * (1 - tc) ** 2 * am / PI**2 * (np.cos(PI * (t - tc) / (2 * (1 - tc))) - 1) + vb * (t - tc) + sc
    s = np.select([t <= ta, t <= tb, t <= tc], [s1, s2, s3], s4)
    return s, {"Am": am, "Va": va, "Sa": sa, "Vb": vb, "Sb": sb, "Sc": sc, "Ta": ta, "Tb": tb, "Tc": tc}


#: INDEXMAN guide, MT 位移表达式, 区间 V (1 − Ta < T ≤ 1) prints
#:     S = 4Ta²Am/π² {cos(π(T − 1 + Ta)/2Ta) − 1} + Vb(T − 1 + Ta) + Sd.
#: The velocity entering section V is Va (the mirror of section I), not Vb (the peak
#: velocity at T = 0.5): as printed, S is continuous at T = 1 − Ta but V jumps from Va
#: to Vb, and S(1) = Sd − 4Ta²Am/π² + Ta·Vb = 1.1528 ≠ 1. With Va the curve ends at S = 1
#: and matches the table; the test below keeps the printed form to show the misprint.
MT_SECTION_V_MISPRINT = "MT section V: 'Vb(T − 1 + Ta)' should read 'Va(T − 1 + Ta)'"

CLOSED_FORMS = {
    "MS": lambda t: ms_closed(t),
    "MCV50": lambda t: mc_closed(t),
    "MCV25": lambda t: mc_closed(t, 3 / 32, 3 / 8),
    "MT": lambda t: mt_closed(t),
    "TR": lambda t: tr_closed(t),
}

def test_mt_section_v_formula_misprint() -> None:
    """INDEXMAN guide, MT 区间 V: the printed Vb does not close the stroke; Va does."""
    t = np.array([1 - 1 / 8, 1.0])
    printed, k = mt_closed(t, as_printed=True)
    corrected, _ = mt_closed(t)
    # as printed: S(1) = Sd − 4Ta²Am/π² + Ta·Vb = 1.15275…, not 1 (MT_SECTION_V_MISPRINT)
    ta, am = k["Ta"], k["Am"]
    assert abs(printed[1] - (1 - k["Sa"] - 4 * ta**2 * am / PI**2 + ta * k["Vb"])) < 1e-14
    assert printed[1] > 1.15, MT_SECTION_V_MISPRINT
    assert abs(corrected[1] - 1.0) < 1e-14, MT_SECTION_V_MISPRINT
    # at T = 1 − Ta both forms give Sd, so the slip only shows inside section V
    assert abs(printed[0] - corrected[0]) < 1e-15


#: S is of order 1 and each closed form sums a handful of O(1..10) terms, so both sides
#: carry a few ulps (~2e-16 each) of rounding; 1e-14 is ~50 ulps, far below anything a
#: wrong formula or constant would produce (those show up at 1e-3 and above).
CLOSED_FORM_TOL = 1e-14


@pytest.mark.parametrize("name", CURVES)
def test_catalog_displacement_formulas_match_universal_curve(name: str) -> None:
    """INDEXMAN guide, 位移表达式 of ``name`` vs camcore's universal-curve implementation."""
    t = np.unique(np.concatenate([np.linspace(0, 1, 4001), camcore.named_curve(name).break_points]))
    s_closed, _ = CLOSED_FORMS[name](t)
    s = camcore.named_curve(name).evaluate(t).s
    err = np.abs(s - s_closed)
    i = int(np.argmax(err))
    assert err[i] <= CLOSED_FORM_TOL, f"{name}: |S_camcore − S_catalog| = {err[i]:.3e} at T = {t[i]!r}"


@pytest.mark.parametrize("name", CURVES)
def test_catalog_constants_match_universal_curve(name: str) -> None:
    """INDEXMAN guide, 常数表达式 of ``name``: Am, Va = V(Ta), Sa = S(Ta), Vb, Sb, Vm …"""
    curve = camcore.named_curve(name)
    _, k = CLOSED_FORMS[name](np.array([0.5]))
    checks = {"Am": (curve.characteristics.am, k["Am"])}
    ta = k["Ta"]
    at_ta = curve.evaluate(ta)
    checks["Va"] = (float(at_ta.v), k["Va"])
    checks["Sa"] = (float(at_ta.s), k["Sa"])
    if name in ("MCV50", "MCV25"):
        at_tb = curve.evaluate(k["Tb"])
        checks["Vm"] = (curve.characteristics.vm.value, k["Vm"])
        checks["Sb"] = (float(at_tb.s), k["Sb"])
    if name == "MT":
        at = curve.evaluate(0.5 - ta)
        checks["Vb"] = (float(at.v), k["Vb"])
        checks["Sb"] = (float(at.s), k["Sb"])
    if name == "TR":
        at_tb = curve.evaluate(k["Tb"])
        at_tc = curve.evaluate(k["Tc"])
        checks["Vb"] = (float(at_tb.v), k["Vb"])
        checks["Sb"] = (float(at_tb.s), k["Sb"])
        checks["Sc"] = (float(at_tc.s), k["Sc"])
        # Tc = Tb + 2Ta: the catalog's TR is Makino's 35 with break points (0, Ta, Tb, Tb+Ta, …)
        checks["Tb"] = (curve.break_points[2], k["Tb"])
        checks["Tc"] = (k["Tb"] + 2 * ta, k["Tc"])
    # constants are O(1..10): 1e-14 relative is ~50 ulps (see CLOSED_FORM_TOL)
    bad = {n: v for n, v in checks.items() if abs(v[0] - v[1]) > CLOSED_FORM_TOL * max(1.0, abs(v[1]))}
    assert not bad, f"{name}: (camcore, catalog formula) differ: {bad}"
