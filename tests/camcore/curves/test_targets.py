"""Makino's curves designed from a target (1977, §5.1 and §5.3): curve 4 from Vm, curve 1
from V7/V3. The solved parameters are checked against the paper's printed numbers and
against the built curve's Vm found by its extrema (an independent method: the closed form
of camcore.curves.targets is not used there)."""

from __future__ import annotations

import pytest

from camcore import makino_curve
from camcore.curves.targets import curve_4_from_vm, curve_4_slope, curve_4_vm_range
from camcore.errors import InvalidParameterError
from tests.camcore.curves.test_makino import APPENDIX_3_2, HALF_DIGIT


def test_vm_of_curve_27_gives_back_its_break_points() -> None:
    """Appendix 3-1: curve 27 (T1 = 1/16, T3 = 1/4) has VM = 1.27526. Designed from its
    exact Vm, curve 4 gives back 1/16, 1/4 to rounding; from the printed Vm, to the print's
    precision: T3(Vm) = (1 − 1/Vm)/c moves by δ/(c·Vm²) when Vm moves by δ ≤ half a digit."""
    exact_vm = makino_curve(27).characteristics.vm.value
    curve = makino_curve(4, vm=exact_vm)
    # 1/Vm and (1 − 1/Vm)/c each round once: a few ulp of 1/4
    assert curve.t[1] == pytest.approx(1 / 16, abs=1e-15) and curve.t[3] == pytest.approx(1 / 4, abs=1e-15)
    printed = makino_curve(4, vm=1.27526)
    c = curve_4_slope(0.25)
    tolerance = HALF_DIGIT / (c * 1.27526 * (1.27526 - HALF_DIGIT))  # the print's half digit, carried to T3
    assert abs(printed.t[3] - 0.25) <= tolerance and abs(printed.t[1] - 1 / 16) <= tolerance / 4
    assert abs(printed.t[3] - 0.25) > 1e-9  # the printed Vm is rounded: T3 is not exactly 1/4
    assert printed.t[1] == pytest.approx(printed.t[3] / 4, rel=1e-15)


@pytest.mark.parametrize("row", APPENDIX_3_2, ids=lambda r: f"T3={r[0]}/32-T1={r[1]}/64")
def test_appendix_3_2_vm_gives_back_t3(row: tuple) -> None:
    """Every printed row (T3 = I/32, T1 = J/64, VM): its Vm with T1/T3 = J/(2I) gives back
    its T3 (the row T3 = 1/16, T1 = 1/64 is Makino's T1 = T3/4 itself). Tolerance: VM is
    printed F15.5, so the true Vm is within half a digit δ of it; T3(Vm) = (1 − 1/Vm)/c
    moves by at most δ/(c·Vm·(Vm − δ)) over that interval."""
    i, j, _t3_p, _t1_p, vm_p, _am_p = row
    k = j / (2 * i)
    t1, t3 = curve_4_from_vm(vm_p, k)
    tolerance = HALF_DIGIT / (curve_4_slope(k) * vm_p * (vm_p - HALF_DIGIT))
    assert abs(t3 - i / 32) <= tolerance, f"T3 = {t3!r}, printed row T3 = {i}/32"
    assert abs(t1 - j / 64) <= k * tolerance + 1e-16


@pytest.mark.parametrize("k", [0.01, 0.25, 0.5, 0.75, 1.0])
@pytest.mark.parametrize("fraction", [1e-6, 0.1, 0.5, 0.9, 1.0])
def test_solved_curve_has_the_target_vm(k: float, fraction: float) -> None:
    """Independent check over the whole attainable range: the built curve's Vm, found by its
    extrema (section-wise roots, not the closed form), is the target to rounding (1e-14
    relative: Amp solved from eq. (11) and Vm's sum carry a few ulp)."""
    low, high = curve_4_vm_range(k)
    vm = low + fraction * (high - low)
    curve = makino_curve(4, vm=vm, t1_over_t3=k)
    assert curve.characteristics.vm.value == pytest.approx(vm, rel=1e-14)
    assert curve.t[1] == pytest.approx(k * curve.t[3], rel=1e-15)
    assert 0 < curve.t[3] <= 0.5


def test_vm_grows_with_t3() -> None:
    """The monotonicity the unique solution rests on: c > 0 for every 0 < k ≤ 1 (c is linear
    in k with ends 2 − 4/π and 4/π), and Vm of the built curves grows with T3."""
    for k in (1e-9, 0.25, 0.5, 1.0):
        assert curve_4_slope(k) > 0.7
        vms = [makino_curve(4, t1=k * t3, t3=t3).characteristics.vm.value for t3 in (0.05, 0.2, 0.35, 0.5)]
        assert vms == sorted(vms) and len(set(vms)) == 4


@pytest.mark.parametrize("vm, k, match", [
    (1.0, 0.25, r"reaches 1 < Vm ≤ 1\.7596"), (0.9, 0.25, "out of reach"), (2.2, 0.25, "out of reach"),
    (1.5, 0.0, "0 < T1/T3 ≤ 1"), (1.5, 1.5, "0 < T1/T3 ≤ 1")])
def test_vm_out_of_reach(vm: float, k: float, match: str) -> None:
    """Vm ≤ 1 (T3 → 0 is the limit, not a curve) and Vm above the value at T3 = 0.5 are
    refused with the attainable range; so is T1/T3 outside (0, 1]."""
    with pytest.raises(InvalidParameterError, match=match):
        makino_curve(4, vm=vm, t1_over_t3=k)


def test_vm_range_ends() -> None:
    """The top of the range is curve 4 at T3 = 0.5: built there, its Vm is the range's end."""
    for k in (0.25, 1.0):
        _, high = curve_4_vm_range(k)
        assert makino_curve(4, t1=k * 0.5, t3=0.5).characteristics.vm.value == pytest.approx(high, rel=1e-14)
        # 1/Vm and (1 − 1/Vm)/c round: T3 lands within a few ulp below 0.5
        assert makino_curve(4, vm=high, t1_over_t3=k).t[3] == pytest.approx(0.5, abs=1e-15)


def test_v_ratio_gives_z_and_eq_16() -> None:
    """v_ratio = 0.1: z = 0.9, and the curve itself has V3 = 10·V7 (Makino eq. 16: the
    cutting feed V7 = (1 − z)·V3), with T3 = 1/(1 + z)."""
    curve = makino_curve(1, v_ratio=0.1)
    assert curve.t[3] == pytest.approx(1 / 1.9, rel=1e-15)
    v3 = float(curve.evaluate(curve.t[3]).v)
    v7 = float(curve.evaluate(1.0).v)
    assert v3 == pytest.approx(10 * v7, rel=1e-13)  # V from closed-form sections: rounding only
    assert curve.t == makino_curve(1, z=0.9).t


@pytest.mark.parametrize("number, params, match", [
    (4, {"vm": 1.3, "t1": 0.05}, "not both"), (4, {"t1_over_t3": 0.25, "t1": 0.05, "t3": 0.2}, "goes with vm"),
    (1, {"v_ratio": 0.1, "z": 0.9}, "not both"), (1, {"v_ratio": 1.0}, "0 ≤ v_ratio < 1"),
    (26, {"vm": 1.3}, "no target vm"), (4, {"v_ratio": 0.1}, "no target v_ratio")])
def test_target_misuse(number: int, params: dict, match: str) -> None:
    with pytest.raises(InvalidParameterError, match=match):
        makino_curve(number, **params)
