"""Indexer kinematics, position lookup, sizing and accuracy (camcore.indexer).

Every expected value is from the INDEXMAN technical guide (the section or table is named
in each test) or worked by hand in the comments.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcore import InvalidParameterError, StrokeRangeError, named_curve
from camcore.curves.reverse import ReturnCurve
from camcore.indexer import G, Indexer, Load, LoadPart, accuracy_mm, size

MS = named_curve("MS")


def example_indexer() -> Indexer:
    # Guide, section 5, worked example before 凸轮曲线的特性值一览:
    # 分度数 = 6, 分配角 = 270°, 凸轮曲线 = MS, 输入轴转速 = 60 rpm.
    return Indexer(stops=6, indexing_angle_deg=270, speed_rpm=60)


# --------------------------------------------------------------------------- timing
def test_worked_example_timing() -> None:
    # Guide, section 5 worked example: h = 360/6 = 60°, th = 270/360 × 60/60 = 0.75 s.
    # Section 3: t0 = 60/(N·z) = 1 s, so the dwell t2 = t0 − th = 0.25 s.
    ix = example_indexer()
    summ = ix.summary()
    assert summ.displacement_deg == 60.0
    assert summ.indexing_time_s == pytest.approx(0.75, rel=1e-15)
    assert summ.cycle_time_s == pytest.approx(1.0, rel=1e-15)
    assert summ.dwell_time_s == pytest.approx(0.25, rel=1e-15)
    assert summ.total_indexing_angle_deg == 270.0
    assert summ.dwell_angle_deg == 90.0


def test_multi_dwell_changes_th_and_t0() -> None:
    # Guide, section 2-3 (停留数) table: RGIS 80, 16 stops, θh = 120°, unit cycle time
    # 2 s, MS: z = 1 runs at 30 rpm, z = 2 at 15 rpm. Section 3: N = 60/(t0·z).
    one = Indexer(stops=16, indexing_angle_deg=120, dwells=1, cycle_time_s=2.0)
    two = Indexer(stops=16, indexing_angle_deg=120, dwells=2, cycle_time_s=2.0)
    assert one.rpm == pytest.approx(30.0, rel=1e-15)
    assert two.rpm == pytest.approx(15.0, rel=1e-15)
    # th = (θh/360)·(60/N): 120/360 × 2 = 0.6667 s for z = 1; 120/360 × 4 = 1.3333 s for z = 2.
    assert one.indexing_time_s == pytest.approx(2 / 3, rel=1e-15)
    assert two.indexing_time_s == pytest.approx(4 / 3, rel=1e-15)
    # t2 = t0 − th: 2 − 0.6667 = 1.3333 s and 2 − 1.3333 = 0.6667 s; θt = θh·z = 240° (section 2-4).
    assert one.dwell_time_s == pytest.approx(4 / 3, rel=1e-14)
    assert two.dwell_time_s == pytest.approx(2 / 3, rel=1e-14)
    assert two.total_indexing_angle_deg == 240.0
    # twice the indexing time → a quarter of the peak acceleration (a = (h/th²)·A), which is
    # why the guide's z = 2 unit is rated for far more output torque (133.0 vs 30.0 N·m).
    assert one.summary().alpha_rad_s2 / two.summary().alpha_rad_s2 == pytest.approx(4.0, rel=1e-14)
    # the same unit given by speed: z = 2 at 15 rpm → t0 = 60/(15·2) = 2 s
    by_speed = Indexer(stops=16, indexing_angle_deg=120, dwells=2, speed_rpm=15)
    assert by_speed.unit_cycle_time_s == pytest.approx(2.0, rel=1e-15)


def test_machine_cycle_time_with_input_stop() -> None:
    # Guide, section 3: tm = t0 + ts when the input stops at every index.
    ix = Indexer(stops=8, indexing_angle_deg=300, speed_rpm=120, input_stop_time_s=0.3)
    assert ix.unit_cycle_time_s == pytest.approx(0.5, rel=1e-15)
    assert ix.machine_cycle_time_s == pytest.approx(0.8, rel=1e-15)


def test_oscillating_unit_uses_swing_angle() -> None:
    # Guide, section 2-1: n = 360/ψ; oscillating units use ψ itself as the displacement.
    ix = Indexer(swing_angle_deg=45, indexing_angle_deg=150, dwells=2, speed_rpm=30)
    assert ix.n == 8.0
    assert ix.displacement_deg == 45.0
    # catalog short form 360/(n·θh) = ψ/θh
    assert 360 / (ix.n * ix.indexing_angle_deg) == pytest.approx(45 / 150, rel=1e-15)


# --------------------------------------------------------------------------- motion
def test_motion_summary_peaks_are_exact_characteristics() -> None:
    # Guide, section 5: v = (h/th)·V, a = (h/th²)·A, j = (h/th³)·J, h in radians.
    ix = example_indexer()
    ch = MS.characteristics
    h, th = math.pi / 3, 0.75
    summ = ix.summary()
    assert summ.omega_rad_s == pytest.approx(h / th * ch.vm.value, rel=1e-15)
    assert summ.alpha_pos_rad_s2 == pytest.approx(h / th**2 * ch.am_pos.value, rel=1e-15)
    assert summ.alpha_neg_rad_s2 == pytest.approx(h / th**2 * ch.am_neg.value, rel=1e-15)
    assert summ.jerk_pos_rad_s3 == pytest.approx(h / th**3 * ch.jm_pos.value, rel=1e-15)
    # MS: Vm at T = 0.5 (input 135°), Am+ at T = 1/8 (33.75°), Am− at 7/8 (236.25°)
    assert summ.omega_input_angle_deg == pytest.approx(135.0, abs=1e-9)
    assert summ.alpha_pos_input_angle_deg == pytest.approx(33.75, abs=1e-9)
    assert summ.alpha_neg_input_angle_deg == pytest.approx(236.25, abs=1e-9)
    assert summ.alpha_pos_time_s == pytest.approx(0.75 / 8, abs=1e-12)
    # the sampled table never exceeds the exact peak (it samples the same closed form)
    tab = ix.motion(1001).table
    assert tab.omega_rad_s.max() <= summ.omega_rad_s * (1 + 1e-14)
    assert tab.alpha_rad_s2.max() <= summ.alpha_pos_rad_s2 * (1 + 1e-14)


def test_motion_table_columns() -> None:
    # Guide, section 4 note 2 and section 5 example: time ∝ input angle, θ = θh·T.
    ix = example_indexer()
    tab = ix.motion(5).table
    np.testing.assert_allclose(tab.input_angle_deg, [0, 67.5, 135, 202.5, 270])
    np.testing.assert_allclose(tab.time_s, [0, 0.1875, 0.375, 0.5625, 0.75], rtol=1e-15)
    # MS is symmetric: half the stroke (30°) at half the index; full 60° at the end.
    np.testing.assert_allclose(tab.output_angle_deg[[0, 2, 4]], [0, 30, 60], atol=1e-12)
    # dθout/dθin = (h/θh)·V = (60/270)·V
    _s, v, _a, _j = MS.derivatives(np.array([0.25]), 3)
    assert tab.dout_din[1] == pytest.approx(60 / 270 * v[0], rel=1e-14)
    assert tab.omega_rad_s[1] == pytest.approx(math.radians(60) / 0.75 * v[0], rel=1e-14)
    assert set(tab.columns()) >= {
        "input_angle_deg", "time_s", "output_angle_deg", "omega_rad_s", "alpha_rad_s2", "jerk_rad_s3"
    }


def test_motion_at_dwell_is_stationary() -> None:
    # Guide, section 4-1: in the dwell (停留区间) the output stands still.
    ix = example_indexer()
    tab = ix.motion_at([300.0, 360.0])
    np.testing.assert_array_equal(tab.output_angle_deg, [60.0, 60.0])
    np.testing.assert_array_equal(tab.omega_rad_s, [0.0, 0.0])
    with pytest.raises(InvalidParameterError, match=r"0 ≤ θ ≤ 360/z"):
        ix.motion_at([361.0])


def test_return_curve_is_normalised() -> None:
    # A falling curve (return stroke, S: 1 → 0) still drives a forward index: normalised,
    # 1 − S(1 − T) is the MS rise mirrored, so MS (symmetric) gives the same motion.
    ix = Indexer(stops=6, indexing_angle_deg=270, speed_rpm=60, curve=ReturnCurve(MS))
    ref = example_indexer()
    a, b = ix.motion(41).table, ref.motion(41).table
    np.testing.assert_allclose(a.output_angle_deg, b.output_angle_deg, atol=1e-12)
    np.testing.assert_allclose(a.omega_rad_s, b.omega_rad_s, atol=1e-12)
    assert ix.summary().alpha_pos_rad_s2 == pytest.approx(ref.summary().alpha_pos_rad_s2, rel=1e-14)
    load = Load(inertia_kgm2=2.0, friction_torque_nm=10.0)
    assert size(ix, load).input_torque_nm == pytest.approx(size(ref, load).input_torque_nm, rel=1e-12)


# --------------------------------------------------------------------------- position
def test_worked_example_position_table_method() -> None:
    # Guide, worked example before 凸轮曲线的特性值一览: 11° → S = 11/60 = 0.1833, between
    # rows T = 0.30 (S 0.17789, V 1.32295) and 0.31 (S 0.19132, V 1.36325) of the MS table;
    # proportional interpolation gives T = 0.304, V = 1.339; θ = 270 × 0.304 = 82.08°;
    # ω = 60/0.75 × 1.339 × π/180 = 1.8696 rad/s.
    ix = example_indexer()
    pos = ix.position(11.0, method="table", table_step=0.01, table_decimals=5)
    t = float(pos.t)
    # our T is 0.30405 (the guide uses S = 0.1833; we use 11/60 = 0.183333…), printed to 3 decimals
    assert round(t, 3) == 0.304
    assert 270 * round(t, 3) == pytest.approx(82.08, abs=1e-12)
    # the unrounded input angle differs from 82.08 by 270 × (T − 0.304) = 270 × 5.3e-5 = 0.014°;
    # rounding T to 3 decimals can move it by up to 270 × 0.0005 = 0.135°.
    assert float(pos.input_angle_deg) == pytest.approx(82.08, abs=0.135)
    assert round(float(pos.v), 3) == 1.339
    # the printed ω comes from the rounded V = 1.339
    assert 60 / 0.75 * round(float(pos.v), 3) * math.pi / 180 == pytest.approx(1.8696, abs=5e-5)
    # from the unrounded V: within 80 × 0.0005 × π/180 = 7.0e-4 rad/s of the printed value
    assert float(pos.omega_rad_s) == pytest.approx(1.8696, abs=7.0e-4)
    assert float(pos.time_s) == pytest.approx(0.75 * t, rel=1e-15)


def test_worked_example_exact_vs_table() -> None:
    # Same example (guide, before 凸轮曲线的特性值一览), exact method: S(T) = 11/60 solved
    # on the closed form.
    ix = example_indexer()
    exact = ix.position([11.0], method="exact")
    table = ix.position([11.0], method="table", table_step=0.01)
    t_e, t_t = float(exact.t[0]), float(table.t[0])
    assert float(MS.derivatives(t_e, 0)[0]) == pytest.approx(11 / 60, abs=1e-15)
    # exact: T = 0.3040904, θ = 82.1044°, V = 1.339627, ω = 1.870473 rad/s
    assert t_e == pytest.approx(0.3040903772609671, abs=1e-13)
    assert float(exact.input_angle_deg[0]) == pytest.approx(82.10440186, abs=1e-7)
    assert float(exact.omega_rad_s[0]) == pytest.approx(1.87047262, abs=1e-7)
    # Why they differ: the table method replaces the curved S(T) between the rows 0.30 and
    # 0.31 by its chord. S is convex there (A ≈ 4.04 > 0), so the chord lies above the curve
    # by (A/2)·f(1−f)·Δ² at the fraction f of the row spacing Δ = 0.01, and the table reaches
    # S = 11/60 early by that over V:  ΔT ≈ (A/2)·f(1−f)·Δ²/V.
    f = (11 / 60 - 0.17788776262872125) / (0.1913201 - 0.17788776262872125)
    estimate = float(exact.a[0]) / 2 * f * (1 - f) * 0.01**2 / float(exact.v[0])
    assert estimate == pytest.approx(3.64e-5, rel=0.01)
    # the next term of the expansion is of relative order |J|·Δ/A ≈ 15.5 × 0.01/4 ≈ 4 %, times
    # a factor |1 − 2f|/3 ≈ 0.06: well under 2 %.
    assert t_e - t_t == pytest.approx(estimate, rel=0.02)
    # in input angle 270 × 3.63e-5 = 0.0098°; in ω about 2.6e-4 of the value (V is also
    # interpolated on a chord, and read at the early T)
    assert float(exact.input_angle_deg[0] - table.input_angle_deg[0]) == pytest.approx(0.0098, abs=2e-4)
    rel_omega = float(exact.omega_rad_s[0] / table.omega_rad_s[0]) - 1
    assert 2.0e-4 < rel_omega < 3.0e-4


def test_position_is_inverse_of_motion() -> None:
    # Forward then inverse on the closed form returns the input angle (section 5 example logic).
    ix = Indexer(stops=4, indexing_angle_deg=180, speed_rpm=50, curve="MT")
    theta = np.linspace(0, 180, 37)
    out = ix.motion_at(theta).output_angle_deg
    back = ix.position(out).input_angle_deg
    # the inverse is solved to float spacing in T; where V = 0 (both ends) S is flat to
    # second order, so a rounding error δS moves T by √(2δS/A): ~1e-7 in T → 1e-5°.
    np.testing.assert_allclose(back, theta, atol=1e-5)
    np.testing.assert_allclose(back[3:-3], theta[3:-3], atol=1e-9)


def test_position_out_of_range() -> None:
    ix = example_indexer()
    with pytest.raises(StrokeRangeError, match=r"output_angle_deg\[1\] = 61.0 is outside the index.*0 to h = 60.0"):
        ix.position([10.0, 61.0])
    with pytest.raises(InvalidParameterError, match="method must be 'exact' or 'table'"):
        ix.position(10.0, method="spline")  # type: ignore[arg-type]


# --------------------------------------------------------------------------- sizing
def test_sizing_disc_table_with_fixtures_and_workpieces() -> None:
    # Hand check of the load inertia (parallel-axis rule) and friction μ·m·g·R on the guide's
    # example unit (n = 6, θh = 270°, MS, 60 rpm).
    parts = [
        # table: disc D = 600 mm, 40 kg → I = m·D²/8 = 40 × 0.36/8 = 1.8 kg·m²
        LoadPart(shape="disc", mass_kg=40, diameter_mm=600),
        # 6 fixtures, blocks 100 × 80 mm, 5 kg, on a 250 mm pitch radius:
        # own m·(a²+b²)/12 = 5 × (0.01 + 0.0064)/12 = 0.0068333; m·r² = 5 × 0.0625 = 0.3125
        # → 6 × 0.3193333 = 1.916 kg·m²
        LoadPart(shape="block", mass_kg=5, a_mm=100, b_mm=80, offset_mm=250, count=6),
        # 6 workpieces as 2 kg points at 250 mm: 6 × 2 × 0.0625 = 0.75 kg·m²
        LoadPart(shape="point", mass_kg=2, offset_mm=250, count=6),
    ]
    load = Load(parts=parts, friction_coefficient=0.1, friction_radius_mm=200)
    r = size(example_indexer(), load)
    # I = 1.8 + 1.916 + 0.75 = 4.466 kg·m²; Σm = 40 + 30 + 12 = 82 kg
    assert r.inertia_kgm2 == pytest.approx(4.466, rel=1e-14)
    assert r.mass_kg == 82.0
    # Tf = μ·m·g·R = 0.1 × 82 × 9.80665 × 0.2 = 16.082906 N·m
    assert r.friction_torque_nm == pytest.approx(16.082906, rel=1e-12)
    # α max = (h/th²)·Am = (π/3)/0.5625 × 5.527957 = 10.29131 rad/s² (guide section 5, Am ±5.53)
    assert r.alpha_max_rad_s2 == pytest.approx(math.pi / 3 / 0.5625 * MS.characteristics.am, rel=1e-15)
    assert r.alpha_max_rad_s2 == pytest.approx(10.29131, abs=1e-5)
    # Ti = 4.466 × 10.29131 = 45.9610 N·m; Tt = 45.9610 + 16.0829 = 62.0439; fc·Tt = 93.0659
    assert r.inertia_torque_nm == pytest.approx(45.9610, abs=1e-4)
    assert r.output_torque_nm == pytest.approx(62.0439, abs=1e-4)
    assert r.design_output_torque_nm == pytest.approx(93.0659, abs=1e-4)
    # catalog: 360/(6 × 270) × Qm × fc × Tt = 0.222222 × 0.987300 × 93.0659 = 20.4187 N·m
    assert r.input_torque_catalog_nm == pytest.approx(20.4187, abs=1e-4)
    # exact peak: friction weighs with V (up to 1.76), not Qm (0.99), so it is larger here
    assert r.input_torque_nm > r.input_torque_catalog_nm
    assert r.input_torque_nm == pytest.approx(22.23619, abs=1e-5)
    # P = 2π·N·T/60/η = 2π × 60/60 × 22.23619/1000 = 0.139714 kW
    assert r.input_power_kw == pytest.approx(2 * math.pi * 22.23619 / 1000, rel=1e-6)
    assert r.input_torque_input_angle_deg == pytest.approx(270 * r.input_torque_t, rel=1e-15)


def test_sizing_ring_multi_dwell_work_torque_power() -> None:
    # Guide, section 2-3 unit (16 stops, θh = 120°, t0 = 2 s) with z = 2 → N = 15 rpm,
    # th = 1.3333 s, h = 22.5° = π/8 rad.
    ix = Indexer(stops=16, indexing_angle_deg=120, dwells=2, cycle_time_s=2.0)
    # ring D = 400, d = 300 mm, 10 kg: m·(D²+d²)/8 = 10 × (0.16 + 0.09)/8 = 0.3125 kg·m²,
    # plus 0.5 kg·m² given directly → 0.8125 kg·m²
    load = Load(
        inertia_kgm2=0.5,
        parts=[LoadPart(shape="ring", mass_kg=10, diameter_mm=400, inner_diameter_mm=300)],
        friction_torque_nm=2.0, work_torque_nm=3.0, service_factor=2.0, efficiency=0.8,
    )
    r = size(ix, load)
    assert r.inertia_kgm2 == pytest.approx(0.8125, rel=1e-14)
    # α = (π/8)/(4/3)² × Am = 0.220893 × 5.527957 = 1.221091 rad/s²; Ti = 0.8125 × α = 0.992136
    alpha = math.pi / 8 / (4 / 3) ** 2 * MS.characteristics.am
    assert r.alpha_max_rad_s2 == pytest.approx(alpha, rel=1e-14)
    assert r.inertia_torque_nm == pytest.approx(0.8125 * alpha, rel=1e-14)
    # Tt = 0.992136 + 2 + 3 = 5.992136; fc·Tt = 11.984272
    assert r.output_torque_nm == pytest.approx(0.8125 * alpha + 5.0, rel=1e-14)
    assert r.design_output_torque_nm == pytest.approx(2 * (0.8125 * alpha + 5.0), rel=1e-14)
    # P = 2π·N·T_in/60/η with N = 15 rpm, η = 0.8
    assert r.input_power_kw == pytest.approx(2 * math.pi * 15 * r.input_torque_nm / 60 / 0.8 / 1000, rel=1e-15)
    # catalog form 360/(n·θh)·Qm·fc·Tt = 360/(16 × 120) × Qm × 2 × Tt
    assert r.input_torque_catalog_nm == pytest.approx(
        360 / (16 * 120) * MS.characteristics.qm_pos.value * 2 * r.output_torque_nm, rel=1e-15
    )


def brute_force_input_torque(ix: Indexer, load: Load, n: int = 400_001) -> float:
    """fc·max over a grid of (h/θh)·V·[I·(h/th²)·A + Tf + Tw] through curve.derivatives."""
    c = ix.curve
    t = np.linspace(c.t_start, c.t_end, n)
    _, v, a = c.derivatives(t, 2)
    h = ix.displacement_rad
    th = ix.indexing_time_s
    ratio = h / math.radians(ix.indexing_angle_deg)
    f = ratio * v * (load.total_inertia_kgm2 * h / th**2 * a + load.total_friction_torque_nm + load.work_torque_nm)
    return float(load.service_factor * np.abs(f).max())


@pytest.mark.parametrize("name", ["MS", "MCV50", "MCV25", "MT", "TR", "cycloid", "asymmetric-cycloid"])
@pytest.mark.parametrize("friction", [0.0, 5.0, 60.0])
def test_exact_input_torque_peak_vs_brute_force(name: str, friction: float) -> None:
    # Power balance (module references [2]); the exact peak is found per smooth piece.
    ix = Indexer(stops=8, indexing_angle_deg=240, speed_rpm=40, curve=name)
    load = Load(inertia_kgm2=3.0, friction_torque_nm=friction, work_torque_nm=1.0)
    r = size(ix, load)
    scan = brute_force_input_torque(ix, load)
    # a grid can only miss the top: scan ≤ exact (1e-14 relative allows the last bits of
    # the two evaluation paths)
    assert scan <= r.input_torque_nm * (1 + 1e-14)
    # and miss it by at most ½|f''|·(Δ/2)² with Δ = 2.5e-6, (Δ/2)² = 1.6e-12. The sharpest
    # pieces here are MCV50's quarter sines of length 1/16 (frequency 8π), so |f''| ≲ (8π)²·f
    # ≈ 630 f and the miss is ≲ 5e-10 f (largest seen: 1.5e-10).
    assert scan == pytest.approx(r.input_torque_nm, rel=1e-9)
    # the reported T is where the peak is: f there equals the peak
    t = r.input_torque_t
    _, v, a = ix.curve.derivatives(np.array([t]), 2)
    h, th = ix.displacement_rad, ix.indexing_time_s
    f = h / math.radians(240) * v[0] * (3.0 * h / th**2 * a[0] + friction + 1.0)
    assert abs(1.5 * f) == pytest.approx(r.input_torque_nm, rel=1e-12)


def test_exact_peak_equals_catalog_without_friction_and_work() -> None:
    # Derivation: with Tf = Tw = 0, T_in(T) = (h/θh)·V·I·(h/th²)·A, so
    # max T_in = (h/θh)·I·(h/th²)·max(A·V) = (h/θh)·I·(h/th²)·Am·Qm = (h/θh)·Ti·Qm,
    # with Q = A·V/Am (guide section 5) and Ti = I·(h/th²)·Am. As h/θh = 360/(n·θh)
    # (h = 360/n in the same unit as θh) and Tt = Ti, this is the catalog's short form
    # 360/(n·θh)·Qm·fc·Tt, at the T of Qm (MS: T = 0.2873).
    ix = example_indexer()
    r = size(ix, Load(inertia_kgm2=2.0))
    assert r.input_torque_nm == pytest.approx(r.input_torque_catalog_nm, rel=1e-13)
    assert r.input_torque_nm == pytest.approx(1.5 * 60 / 270 * r.inertia_torque_nm * r.qm, rel=1e-13)
    assert r.input_torque_t == pytest.approx(MS.characteristics.qm_pos.t, abs=1e-9)
    # symmetric curve: the braking peak is the mirror of the driving peak
    assert r.input_torque_neg_nm == pytest.approx(-r.input_torque_pos_nm, rel=1e-12)
    # guide, characteristic table: MS Qm = ±0.99 (printed to 2 decimals)
    assert round(r.qm, 2) == 0.99
    # P = 2π × 60/60 × T_in/1000
    assert r.input_power_kw == pytest.approx(2 * math.pi * r.input_torque_nm / 1000, rel=1e-15)


def test_friction_only_peaks_at_vm() -> None:
    # With I = 0, T_in = (h/θh)·V·Tf peaks at Vm (MS: 1.76 at T = 0.5, guide's table).
    ix = example_indexer()
    r = size(ix, Load(friction_torque_nm=10.0, service_factor=1.0))
    assert r.input_torque_nm == pytest.approx(60 / 270 * MS.characteristics.vm.value * 10.0, rel=1e-14)
    assert r.input_torque_t == pytest.approx(0.5, abs=1e-9)
    assert r.input_torque_input_angle_deg == pytest.approx(135.0, abs=1e-6)


# --------------------------------------------------------------------------- accuracy
ACCURACY_TABLE = {
    # Guide, 计算分度精度 (last table): x [mm] for θ [arcsec] at r [mm], printed to 3 decimals.
    100: [0.005, 0.010, 0.015, 0.029, 0.044],
    200: [0.010, 0.019, 0.029, 0.058, 0.087],
    300: [0.015, 0.029, 0.044, 0.087, 0.131],
}
ARC_SECONDS = [10, 20, 30, 60, 90]


@pytest.mark.parametrize("radius", sorted(ACCURACY_TABLE))
def test_accuracy_table(radius: int) -> None:
    # x = 2πr·θ/(360·60·60); printed to 3 decimals, so compare rounded values exactly
    # (no entry lies within 1e-5 of a rounding boundary).
    got = accuracy_mm(ARC_SECONDS, radius)
    assert [round(float(x), 3) for x in got] == ACCURACY_TABLE[radius]
    # the guide's short constant 0.00000485 is 2π/1 296 000 = 4.8481e-6 to 3 figures
    assert accuracy_mm(1, 1) == pytest.approx(0.00000485, rel=1e-3)


def test_accuracy_in_sizing() -> None:
    r = size(example_indexer(), Load(inertia_kgm2=1.0), accuracy_arc_seconds=90, accuracy_radius_mm=300)
    assert round(r.accuracy_mm, 3) == 0.131  # type: ignore[arg-type]
    assert size(example_indexer(), Load(inertia_kgm2=1.0)).accuracy_mm is None


# --------------------------------------------------------------------------- validation
@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"stops": 0, "indexing_angle_deg": 270, "speed_rpm": 60}, r"stops must be a whole number ≥ 1, got 0"),
        ({"stops": 2.5, "indexing_angle_deg": 270, "speed_rpm": 60}, r"stops must be a whole number ≥ 1"),
        ({"indexing_angle_deg": 270, "speed_rpm": 60}, r"exactly one of stops .* and swing_angle_deg"),
        ({"stops": 6, "swing_angle_deg": 60, "indexing_angle_deg": 270, "speed_rpm": 60}, r"exactly one of stops"),
        ({"stops": 6, "indexing_angle_deg": 0, "speed_rpm": 60}, r"indexing_angle_deg must satisfy 0 < θh ≤ 360, got 0"),
        ({"stops": 6, "indexing_angle_deg": 361, "speed_rpm": 60}, r"indexing_angle_deg must satisfy 0 < θh ≤ 360"),
        ({"stops": 6, "indexing_angle_deg": float("nan"), "speed_rpm": 60}, r"indexing_angle_deg must be a finite"),
        ({"stops": 6, "indexing_angle_deg": 200, "dwells": 2, "speed_rpm": 60},
         r"θt = θh·z must not exceed 360°.*200.0 × 2 = 400.0"),
        ({"stops": 6, "indexing_angle_deg": 270, "dwells": 0, "speed_rpm": 60}, r"dwells must be a whole number ≥ 1"),
        ({"stops": 6, "indexing_angle_deg": 270}, r"exactly one of speed_rpm .* and cycle_time_s"),
        ({"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60, "cycle_time_s": 1.0}, r"exactly one of speed_rpm"),
        ({"stops": 6, "indexing_angle_deg": 270, "speed_rpm": -1}, r"speed_rpm must be greater than 0"),
        ({"stops": 6, "indexing_angle_deg": 270, "cycle_time_s": 0}, r"cycle_time_s must be greater than 0"),
        ({"swing_angle_deg": 400, "indexing_angle_deg": 270, "speed_rpm": 60}, r"swing_angle_deg must satisfy 0 < ψ ≤ 360"),
        ({"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60, "input_stop_time_s": -1},
         r"input_stop_time_s must be 0 or more"),
    ],
)
def test_indexer_validation(kwargs: dict, message: str) -> None:
    with pytest.raises(InvalidParameterError, match=message):
        Indexer(**kwargs)


def test_full_circle_indexing_is_valid() -> None:
    # θh·z = 360 exactly is allowed (no dwell: the guide's 4-4 reducer case has none)
    ix = Indexer(stops=4, indexing_angle_deg=180, dwells=2, speed_rpm=10)
    assert ix.dwell_time_s == 0.0


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: LoadPart(shape="disc", mass_kg=-1, diameter_mm=100), r"mass_kg must be 0 or more, got -1"),
        (lambda: LoadPart(shape="cone", mass_kg=1), r"shape must be one of disc, ring, block, point"),
        (lambda: LoadPart(shape="disc", mass_kg=1), r"a disc part needs diameter_mm"),
        (lambda: LoadPart(shape="ring", mass_kg=1, diameter_mm=100, inner_diameter_mm=120),
         r"inner_diameter_mm ≤ diameter_mm"),
        (lambda: LoadPart(shape="point", mass_kg=1, count=0), r"count must be a whole number ≥ 1"),
        (lambda: Load(inertia_kgm2=1, efficiency=0), r"efficiency must satisfy 0 < η ≤ 1, got 0"),
        (lambda: Load(inertia_kgm2=1, efficiency=1.2), r"efficiency must satisfy 0 < η ≤ 1, got 1.2"),
        (lambda: Load(inertia_kgm2=1, service_factor=0.9), r"service_factor must be at least 1, got 0.9"),
        (lambda: Load(inertia_kgm2=-1), r"inertia_kgm2 must be 0 or more"),
        (lambda: Load(inertia_kgm2=1, friction_coefficient=0.1), r"friction_coefficient needs friction_radius_mm"),
        (lambda: Load(inertia_kgm2=1, friction_coefficient=0.1, friction_radius_mm=100),
         r"friction_coefficient needs parts with mass_kg"),
        (lambda: Load(parts=[LoadPart(shape="point", mass_kg=1)], friction_coefficient=0.1,
                      friction_radius_mm=100, friction_torque_nm=2), r"not both"),
    ],
)
def test_load_validation(make, message: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidParameterError, match=message):
        make()


def test_gravity_constant() -> None:
    # friction torque μ·m·g·R uses standard gravity
    assert G == 9.80665
