"""Follower dynamics (camcore.profile.dynamics) against hand-derived values.

Every expected number here is computed in the test from formulas written out here (the
cycloid's closed form, the geometry of an eccentric circle cam, the Hertz formula in Roark's
form), solved or integrated with mpmath at 30 digits where it has no closed form: nothing
is taken from camcore's own evaluation of the same quantity.

Sources
-------
[N] Norton, Cam Design and Manufacturing Handbook: F = m·a + c·v + k·x + F_pl, jump, T·ω = F·v.
[J] Johnson (1985), Contact Mechanics, §4.2: p0 = sqrt(P'·E*/(π·R)), 1/E* = Σ(1 − ν²)/E.
[R] Roark's Formulas for Stress and Strain, 7th ed., table 14.1 (cylinder on cylinder):
    σc = 0.798·sqrt(p/(K_D·C_E)), K_D = D1·D2/(D1 + D2), C_E = Σ(1 − ν²)/E.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import camcore
from camcore.errors import GeometryError, InvalidParameterError
from camcore.profile import CamSpec, Follower, Segment, compute_profile, kinematics, make_cam, validate
from camcore.profile.dynamics import (
    OscillatingLoad,
    RollerMaterials,
    TranslatingLoad,
    effective_modulus_mpa,
    follower_dynamics,
)

mpmath.mp.dps = 30

# ============================================================================ the cycloid cam
# rise H over 120°, dwell 60°, return H over 180°: the rise decelerates harder (its span is
# shorter), so the contact force is smallest on the rise
H, BETA_RISE, BETA_RETURN = 20.0, 2 * math.pi / 3, math.pi
MASS, RATE, PRELOAD = 0.5, 2.0, 30.0  # kg, N/mm, N


def cycloid_cam(follower: Follower | None = None) -> CamSpec:
    return make_cam(follower or Follower("roller", roller_radius_mm=10.0), 40.0, segments=[
        Segment("rise", 120, H), Segment("dwell", 60), Segment("return", 180, H)])


def omega_of(rpm: float) -> float:
    return 2 * math.pi * rpm / 60


def hand_min_force_on_rise(rpm: float, preload: float = PRELOAD) -> tuple[float, float]:
    """The minimum of F on the rise, by hand.

    Cycloid: s = H·(T − sin 2πT/(2π)), T = θ/β, so s'' = (2πH/β²)·sin 2πT [mm/rad²], and
    F(T) = m·ω²·s''/1000 + k·s + F0 = P·sin x + k·H·(T − sin x/(2π)) + F0 with x = 2πT and
    P = m·ω²·2πH/(1000·β²) [N]. dF/dT = 2πP·cos x + k·H·(1 − cos x) = 0 gives
    cos x* = −kH/(2πP − kH); the minimum is the root with sin x* < 0 (deceleration), x* in (π, 3π/2).
    Returns (F_min [N], θ* [deg])."""
    p = MASS * omega_of(rpm) ** 2 * 2 * math.pi * H / (1000 * BETA_RISE**2)
    kh = RATE * H
    x = 2 * math.pi - math.acos(-kh / (2 * math.pi * p - kh))
    t = x / (2 * math.pi)
    force = p * math.sin(x) + kh * (t - math.sin(x) / (2 * math.pi)) + preload
    return force, math.degrees(t * BETA_RISE)


def test_min_contact_force_matches_the_hand_derivation():
    cam = cycloid_cam()
    for rpm in (500.0, 600.0, 800.0):
        expected, at_deg = hand_min_force_on_rise(rpm)
        s = follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), rpm).summary
        # the force is ~10-100 N; the refined minimum is exact to rounding (~1e-13 N)
        assert s.min_contact_force_n == pytest.approx(expected, abs=1e-9)
        # at a smooth minimum the angle is determined only to ~sqrt(rounding/|F''|) ≈ 1e-6°
        assert s.min_contact_force_at_deg == pytest.approx(at_deg, abs=1e-5)


def test_a_case_that_holds_and_one_that_separates():
    cam = cycloid_cam()
    # 600 rpm: P = 0.5·62.83²·2π·20/(1000·2.094²) = 56.55 N, cos x* = −40/(355.3 − 40) → x* = 4.5852,
    # F_min = 56.55·sin x* + 40·(0.72975 + 0.15787) + 30 = −56.09 + 35.50 + 30 = 9.41 N > 0: it holds
    holds, _ = hand_min_force_on_rise(600.0)
    assert holds == pytest.approx(9.41, abs=0.01)
    s600 = follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), 600.0).summary
    assert not s600.separates and s600.min_contact_force_n > 0
    # ... but not with a 10 N margin
    assert follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), 600.0, safety_margin_n=10).summary.separates
    # 800 rpm: P grows by (800/600)² to 100.53 N, cos x* = −40/(631.7 − 40) → x* = 4.6447,
    # F_min = 100.53·sin x* + 40·(0.73923 + 0.15879) + 30 = −100.30 + 35.92 + 30 = −34.38 N < 0: it jumps
    lost, _ = hand_min_force_on_rise(800.0)
    assert lost == pytest.approx(-34.38, abs=0.01)
    s800 = follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), 800.0).summary
    assert s800.separates and s800.min_contact_force_n == pytest.approx(lost, abs=1e-9)
    table = follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), 800.0, samples=721).table
    assert table.contact_force_n.min() < 0 and table.contact_force_n.min() >= s800.min_contact_force_n


def hand_jump_speed(margin: float = 0.0) -> float:
    """The undamped jump speed [rpm], by hand.

    At each angle F = m·ω²·s''/1000 + k·s + F0 = margin gives ω² = N(T)/D(T) with N = k·s + F0 − margin
    and D = −m·s''/1000 > 0 where the follower decelerates. Rise: s = H·S(T), S(T) = T − sin x/(2π),
    x = 2πT, s'' = c·sin x, c = 2πH/β², T in (1/2, 1); return (the rise played backwards):
    s = H·(1 − S(T)), s'' = −c·sin x, T in (0, 1/2). The ratio is smallest where N'·D = N·D', with
    N' = ±k·H·(1 − cos x) and D' = ∓(m·c/1000)·2π·cos x, solved by mpmath (30 digits) in a bracket;
    the jump speed is the smaller of the two minima."""
    best = mpmath.inf
    for beta, sign, bracket in ((BETA_RISE, 1, (0.55, 0.95)), (BETA_RETURN, -1, (0.05, 0.45))):
        c = 2 * mpmath.pi * H / mpmath.mpf(beta) ** 2

        def num(t, sign=sign):
            cyc = t - mpmath.sin(2 * mpmath.pi * t) / (2 * mpmath.pi)
            return RATE * H * (cyc if sign > 0 else 1 - cyc) + PRELOAD - margin

        def den(t, sign=sign, c=c):
            return -sign * MASS * c * mpmath.sin(2 * mpmath.pi * t) / 1000

        def slope(t, sign=sign, c=c):
            x = 2 * mpmath.pi * t
            num1 = sign * RATE * H * (1 - mpmath.cos(x))
            den1 = -sign * MASS * c * 2 * mpmath.pi * mpmath.cos(x) / 1000
            return num1 * den(t) - num(t) * den1

        t = mpmath.findroot(slope, bracket, solver="anderson")
        best = min(best, num(t) / den(t))
    return float(mpmath.sqrt(best) * 60 / (2 * mpmath.pi))


def test_jump_speed_matches_the_hand_derivation():
    cam = cycloid_cam()
    for margin in (0.0, 10.0):
        expected = hand_jump_speed(margin)
        s = follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), 300.0, safety_margin_n=margin).summary
        # accuracy claimed by the summary: 1e-9 relative
        assert s.jump_speed_rpm == pytest.approx(expected, rel=1e-9)
        # at the jump speed the smallest contact force is the margin (to the force's rounding)
        at_jump = follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), s.jump_speed_rpm,
                                    safety_margin_n=margin).summary
        assert at_jump.min_contact_force_n == pytest.approx(margin, abs=1e-9)


def hand_min_force_damped(rpm: float, damping: float) -> tuple[float, float]:
    """The smallest F with damping, by hand: F = m·ω²·s''/1000 + c·ω·s' + k·s + F0, minimised over the
    rise's and the return's deceleration by mpmath. Rise: s = H·S, s' = (H/β)(1 − cos x),
    s'' = (2πH/β²)·sin x; return: s = H·(1 − S), s' = −(H/β)(1 − cos x), s'' = −(2πH/β²)·sin x
    (x = 2πT). Returns (F_min [N], its cam angle [deg])."""
    w = mpmath.mpf(omega_of(rpm))
    best = (mpmath.inf, 0.0)
    for beta, sign, start_deg, bracket in ((BETA_RISE, 1, 0.0, (0.55, 0.95)), (BETA_RETURN, -1, 180.0, (0.05, 0.45))):
        beta = mpmath.mpf(beta)
        p = MASS * w**2 * 2 * mpmath.pi * H / (1000 * beta**2)

        def force(t, beta=beta, sign=sign, p=p):
            x = 2 * mpmath.pi * t
            cyc = t - mpmath.sin(x) / (2 * mpmath.pi)
            return sign * (p * mpmath.sin(x) + damping * w * H / beta * (1 - mpmath.cos(x))) \
                + RATE * H * (cyc if sign > 0 else 1 - cyc) + PRELOAD

        def slope(t, beta=beta, sign=sign, p=p):
            x = 2 * mpmath.pi * t
            return sign * (2 * mpmath.pi * p * mpmath.cos(x) + 2 * mpmath.pi * damping * w * H / beta * mpmath.sin(x)
                           + RATE * H * (1 - mpmath.cos(x)))

        t = mpmath.findroot(slope, bracket, solver="anderson")
        if force(t) < best[0]:
            best = (force(t), start_deg + float(t) * math.degrees(float(beta)))
    return float(best[0]), best[1]


def test_jump_speed_with_damping_is_where_the_force_first_reaches_the_margin():
    """With damping the condition at each angle is a quadratic in ω; checked here against its
    definition: at the jump speed the smallest force (minimised by hand) equals the margin, and
    just below it the force stays above the margin."""
    cam = cycloid_cam()
    damping, margin = 0.05, 5.0  # N·s/mm: c·|v| peaks at 0.05·2·(20/π)·ω ≈ 40 N on the return at 600 rpm
    load = TranslatingLoad(MASS, RATE, PRELOAD, damping_n_s_mm=damping)
    s = follower_dynamics(cam, load, 300.0, safety_margin_n=margin).summary
    # on the return the follower moves towards the cam centre (v < 0): damping resists that and so pulls
    # it off the cam, and the return's deceleration (T < 1/2, at high lift) now comes first
    assert s.jump_speed_rpm < hand_jump_speed(margin)
    assert s.jump_at_deg is not None and 180 < s.jump_at_deg < 270
    force, at_deg = hand_min_force_damped(s.jump_speed_rpm, damping)
    assert force == pytest.approx(margin, abs=1e-8)  # F ~ 50 N: 1e-8 N is the rounding of the mp→float chain
    assert at_deg == pytest.approx(s.jump_at_deg, abs=1e-4)
    assert hand_min_force_damped(s.jump_speed_rpm * (1 - 1e-6), damping)[0] > margin


def test_min_preload_makes_the_min_contact_force_equal_the_margin():
    cam = cycloid_cam()
    for margin, rpm in ((0.0, 800.0), (15.0, 800.0), (5.0, 600.0)):
        s = follower_dynamics(cam, TranslatingLoad(MASS, RATE, PRELOAD), rpm, safety_margin_n=margin).summary
        assert s.min_preload_n is not None
        again = follower_dynamics(cam, TranslatingLoad(MASS, RATE, s.min_preload_n), rpm,
                                  safety_margin_n=margin).summary
        # the force is linear in F0: exact to its rounding; meeting the margin is not separating
        assert again.min_contact_force_n == pytest.approx(margin, abs=1e-9) and not again.separates
        # closed form on the cycloid: F0_min = F0 + margin − F_min (the minimum lies on the rise)
        assert s.min_preload_n == pytest.approx(PRELOAD + margin - hand_min_force_on_rise(rpm)[0], abs=1e-9)


# ============================================================================ a circle-arc cam
class EccentricCircleLift:
    """In-line roller on an eccentric circle cam (circle radius Rc, centre ε from the cam axis):
    the roller centre stays R = Rc + Rr from the circle's centre C(θ) = (−ε·sin θ, ε·cos θ), so on
    the line x = 0 it sits at y = ε·cos θ + sqrt(g), g = R² − ε²·sin²θ, and the lift is
    s = y − (R − ε) (the base circle is Rc − ε). Derivatives by hand: g' = −ε²·sin 2θ,
    g'' = −2ε²·cos 2θ, (√g)' = g'/(2√g), (√g)'' = g''/(2√g) − g'²/(4·g^1.5)."""

    unit = "mm"
    breaks_rad = np.array([0.0])

    def __init__(self, circle_mm: float, ecc_mm: float, roller_mm: float):
        self.rc, self.ecc, self.big = circle_mm, ecc_mm, circle_mm + roller_mm

    def derivatives(self, theta, order=2):
        t = np.asarray(theta, dtype=float)
        e, big = self.ecc, self.big
        g = big**2 - (e * np.sin(t)) ** 2
        g1, g2 = -e * e * np.sin(2 * t), -2 * e * e * np.cos(2 * t)
        root = np.sqrt(g)
        s = e * np.cos(t) + root - (big - e)
        s1 = -e * np.sin(t) + g1 / (2 * root)
        s2 = -e * np.cos(t) + g2 / (2 * root) - g1**2 / (4 * g**1.5)
        return [s, s1, s2, np.zeros_like(t)][: order + 1]

    def cos_pressure_angle(self, theta):
        """The normal runs from C to the roller centre (ε·sin θ, sqrt(g)): cos φ = sqrt(g)/R."""
        return np.sqrt(self.big**2 - (self.ecc * np.sin(theta)) ** 2) / self.big


RC, ECC, RR, WIDTH = 30.0, 8.0, 10.0, 12.0  # mm
E_ROLLER, NU_ROLLER, E_CAM, NU_CAM = 206_000.0, 0.3, 110_000.0, 0.27  # steel roller, cast-iron cam [MPa]


def eccentric_cam(rotation: str = "ccw") -> tuple[CamSpec, EccentricCircleLift]:
    lift = EccentricCircleLift(RC, ECC, RR)
    spec = CamSpec(Follower("roller", roller_radius_mm=RR), RC - ECC, lift, rotation)
    validate(spec)
    return spec, lift


def roark_line_contact_mpa(normal_n, width_mm, d1_mm, d2_mm, constant=0.798):
    """[R] table 14.1, cylinder on cylinder: σc = 0.798·sqrt(p/(K_D·C_E)), p = load per length."""
    k_d = d1_mm * d2_mm / (d1_mm + d2_mm)
    c_e = (1 - NU_ROLLER**2) / E_ROLLER + (1 - NU_CAM**2) / E_CAM
    return constant * np.sqrt((normal_n / width_mm) / (k_d * c_e))


def test_hertz_stress_on_a_circle_arc_cam_matches_the_textbook_formula():
    spec, lift = eccentric_cam()
    theta_deg = np.linspace(0, 360, 73)
    # the cam surface is the circle itself: ρ = Rc everywhere (its geometry, independently)
    rho = compute_profile(spec, theta_deg).radius_of_curvature_mm
    assert np.allclose(rho, RC, rtol=1e-9)  # curvature from analytic 2nd derivatives: ~1e-12
    load = TranslatingLoad(mass_kg=2.0, spring_rate_n_mm=10.0, preload_n=200.0)
    roller = RollerMaterials(WIDTH, E_ROLLER, NU_ROLLER, E_CAM, NU_CAM)
    rpm = 300.0
    result = follower_dynamics(spec, load, rpm, 73, roller=roller)
    table, summary = result.table, result.summary
    # contact force by hand: F = m·ω²·s''/1000 + k·s + F0, normal force F/cos φ with cos φ = sqrt(g)/R
    th = np.radians(theta_deg)
    s, _, s2 = lift.derivatives(th)
    force = 2.0 * omega_of(rpm) ** 2 * s2 / 1000 + 10.0 * s + 200.0
    normal = force / lift.cos_pressure_angle(th)
    assert np.allclose(table.contact_force_n, force, rtol=1e-12, atol=1e-10)
    assert np.allclose(table.normal_force_n, normal, rtol=1e-12, atol=1e-10)
    assert force.min() > 0  # in contact all round: the stress is defined everywhere
    # Roark's 0.798 is sqrt(2/π) = 0.797885 to three digits: with it the two forms agree to 1e-4,
    # with sqrt(2/π) itself to rounding
    d_roller, d_cam = 2 * RR, 2 * RC
    assert np.allclose(table.contact_stress_mpa, roark_line_contact_mpa(normal, WIDTH, d_roller, d_cam), rtol=2e-4)
    exact = roark_line_contact_mpa(normal, WIDTH, d_roller, d_cam, constant=math.sqrt(2 / math.pi))
    assert np.allclose(table.contact_stress_mpa, exact, rtol=1e-12)
    # E* of steel on cast iron, by hand: 1/(0.91/206000 + 0.9271/110000) = 1/(4.4175e-6 + 8.4282e-6) = 77 847.3 MPa
    assert summary.effective_modulus_mpa == pytest.approx(1 / (0.91 / 206_000 + 0.9271 / 110_000), rel=1e-14)
    assert summary.effective_modulus_mpa == pytest.approx(77_847.3, abs=0.1)
    # the largest stress: above every sample, and the hand formula's maximum there (no slope either side)
    assert summary.max_contact_stress_mpa >= table.contact_stress_mpa.max()
    at = math.radians(summary.max_contact_stress_at_deg)

    def hand_stress(theta):
        s_, _, s2_ = lift.derivatives(np.asarray(theta))
        f = (2.0 * omega_of(rpm) ** 2 * s2_ / 1000 + 10.0 * s_ + 200.0) / lift.cos_pressure_angle(theta)
        return roark_line_contact_mpa(f, WIDTH, d_roller, d_cam, constant=math.sqrt(2 / math.pi))

    assert summary.max_contact_stress_mpa == pytest.approx(float(hand_stress(at)), rel=1e-12)
    assert float(hand_stress(at + 1e-4)) <= summary.max_contact_stress_mpa
    assert float(hand_stress(at - 1e-4)) <= summary.max_contact_stress_mpa


def test_hertz_stress_on_concave_flanks_uses_the_signed_radius():
    """A roller inside a concave flank: 1/R = 1/Rr + 1/ρ with ρ < 0 (the profile's own signed
    radius column, computed apart from the dynamics' pitch curvature)."""
    spec = make_cam(Follower("roller", roller_radius_mm=5.0), 20.0, segments=[
        Segment("rise", 90, 25), Segment("dwell", 30), Segment("return", 90, 25), Segment("dwell", 150)])
    roller = RollerMaterials(8.0)
    result = follower_dynamics(spec, TranslatingLoad(1.0, 5.0, 100.0), 100.0, 721, roller=roller)
    rho = compute_profile(spec, result.table.cam_angle_deg).radius_of_curvature_mm
    concave = rho < 0
    assert concave.sum() > 10  # the test needs concave flanks
    e_star = effective_modulus_mpa(206_000, 0.3, 206_000, 0.3)
    assert e_star == pytest.approx(206_000 / (2 * 0.91), rel=1e-14)
    radius = 1 / (1 / 5.0 + 1 / rho[concave])
    assert (radius > 5.0).all()  # a concave flank embraces the roller: a larger relative radius
    expected = np.sqrt(result.table.normal_force_n[concave] * e_star / (math.pi * 8.0 * radius))
    assert np.allclose(result.table.contact_stress_mpa[concave], expected, rtol=1e-9)


def test_roller_undercut_and_impacts_are_refused():
    # a 20 mm lift out and back over 80°: the pitch curve's nose radius is 6.3 mm, under the 8 mm roller
    sharp = make_cam(Follower("roller", roller_radius_mm=8.0), 10.0, segments=[
        Segment("rise", 40, 20), Segment("return", 40, 20), Segment("dwell", 280)])
    assert camcore.profile.profile_checks(sharp).undercut
    with pytest.raises(GeometryError, match="undercuts"):
        follower_dynamics(sharp, TranslatingLoad(1.0, 5.0, 10.0), 100.0, roller=RollerMaterials(10.0))
    # without a roller's materials no stress is asked for: the forces are still defined
    assert follower_dynamics(sharp, TranslatingLoad(1.0, 5.0, 10.0), 100.0).summary.max_contact_stress_mpa is None
    cv = camcore.named_curve("constant-velocity")
    stepped = make_cam(Follower("knife-edge"), 30.0, segments=[Segment("rise", 180, 20, cv),
                                                               Segment("return", 180, 20, cv)])
    with pytest.raises(GeometryError, match="velocity jumps at 0°, 180°"):
        follower_dynamics(stepped, TranslatingLoad(1.0, 5.0, 10.0), 100.0)


# ============================================================================ camshaft torque
def hand_torque(rpm: float):
    """T(θ) = F·s'/1000 [N·m] on the cycloid cam, written out (0 on the dwell): rise
    s' = (H/β)(1 − cos x), return s' = −(H/β')(1 − cos x), with F as in hand_min_force_on_rise."""
    w = mpmath.mpf(omega_of(rpm))

    def on(beta, sign):
        beta = mpmath.mpf(beta)

        def torque(theta):
            t = theta / beta
            x = 2 * mpmath.pi * t
            cyc = t - mpmath.sin(x) / (2 * mpmath.pi)
            s = H * (cyc if sign > 0 else 1 - cyc)
            s1 = sign * H / beta * (1 - mpmath.cos(x))
            s2 = sign * 2 * mpmath.pi * H / beta**2 * mpmath.sin(x)
            return (MASS * w**2 * s2 / 1000 + RATE * s + PRELOAD) * s1 / 1000
        return torque

    return on(BETA_RISE, 1), on(BETA_RETURN, -1)


def test_rms_and_peak_torque_against_an_independent_integration():
    rpm = 600.0
    rise, ret = hand_torque(rpm)
    # mpmath.quad (tanh-sinh, 30 digits) on each smooth piece; the dwell adds nothing (s' = 0)
    integral = mpmath.quad(lambda u: rise(u) ** 2, [0, BETA_RISE]) + mpmath.quad(lambda u: ret(u) ** 2, [0, BETA_RETURN])
    rms = float(mpmath.sqrt(integral / (2 * mpmath.pi)))
    s = follower_dynamics(cycloid_cam(), TranslatingLoad(MASS, RATE, PRELOAD), rpm).summary
    # 8-point Gauss-Legendre on ≤ 1° cells of a smooth piece: exact to rounding
    assert s.rms_camshaft_torque_nm == pytest.approx(rms, rel=1e-12)
    # peaks: the hand torque's own extremes, by its slope's root (mpmath) next to the best of a fine grid

    def extreme(fun, beta, sign):
        grid = np.linspace(0, beta, 2001)
        values = [sign * float(fun(u)) for u in grid]
        i = int(np.argmax(values))
        theta = mpmath.findroot(lambda u: mpmath.diff(fun, u), float(grid[i]), tol=1e-25)
        return float(fun(theta)), math.degrees(float(theta))

    t_max, at_max = extreme(rise, BETA_RISE, 1)
    t_min, at_min = extreme(ret, BETA_RETURN, -1)
    assert s.max_camshaft_torque_nm == pytest.approx(t_max, rel=1e-12)
    assert s.min_camshaft_torque_nm == pytest.approx(t_min, rel=1e-12)
    assert s.max_camshaft_torque_at_deg == pytest.approx(at_max, abs=1e-5)
    assert s.min_camshaft_torque_at_deg == pytest.approx(180 + at_min, abs=1e-5)
    assert s.peak_camshaft_torque_nm == pytest.approx(max(abs(t_max), abs(t_min)), rel=1e-12)
    # the mean torque over a turn is the work per turn: zero for a conservative spring and no damping
    table = follower_dynamics(cycloid_cam(), TranslatingLoad(MASS, RATE, PRELOAD), rpm, samples=3601).table
    assert abs(np.trapezoid(table.camshaft_torque_nm, np.radians(table.cam_angle_deg))) < 1e-6 * s.peak_camshaft_torque_nm


def contact_moment_nm(spec: CamSpec, table, normal_in_fixed_frame) -> np.ndarray:
    """The camshaft torque from the geometry: the follower pushes the cam with −F_n·n̂ at the contact
    point P (fixed frame), whose moment about the cam axis is M = P × (−F_n·n̂); at constant speed the
    drive balances it in the sense of rotation: T = −σ·M [N·mm → N·m]."""
    theta = np.radians(table.cam_angle_deg)
    kin = kinematics(spec, theta)
    px, py = kin.contact
    nx, ny = normal_in_fixed_frame(kin, theta)
    moment = px * (-table.normal_force_n * ny) - py * (-table.normal_force_n * nx)
    return -spec.sigma * moment / 1000


def roller_normal(kin, theta):
    """From the contact to the roller centre: the direction of the cam's push on the follower."""
    dx, dy = kin.pitch[0] - kin.contact[0], kin.pitch[1] - kin.contact[1]
    length = np.hypot(dx, dy)
    return dx / length, dy / length


OSC_SEGMENTS = [Segment("rise", 100, swing_deg=20), Segment("dwell", 40), Segment("return", 120, swing_deg=20),
                Segment("dwell", 100)]


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("motion", ["translating", "oscillating"])
def test_camshaft_torque_by_virtual_work_equals_the_moment_of_the_normal_force(motion, rotation):
    """T = Q·dq/dθ (virtual work) against the moment of the normal force about the cam axis, for an
    offset translating roller and an oscillating roller: checks F_n = F/cos φ, the oscillating arm's
    F = Q/L and the torque at once."""
    if motion == "translating":
        follower = Follower("roller", offset_mm=6.0, roller_radius_mm=8.0)
        spec = make_cam(follower, 30.0, rotation=rotation, segments=[
            Segment("rise", 100, 18), Segment("dwell", 40), Segment("return", 120, 18), Segment("dwell", 100)])
        load = TranslatingLoad(0.8, 3.0, 40.0, external_force_n=5.0, damping_n_s_mm=0.02)
    else:
        follower = Follower("roller", "oscillating", roller_radius_mm=6.0, arm_length_mm=45.0, pivot_distance_mm=60.0)
        spec = make_cam(follower, 25.0, rotation=rotation, segments=OSC_SEGMENTS)
        load = OscillatingLoad(0.004, 20.0, 3.0, external_torque_nm=0.2, damping_nm_s_rad=0.001)
    table = follower_dynamics(spec, load, 400.0, samples=181).table
    expected = contact_moment_nm(spec, table, roller_normal)
    scale = np.abs(table.camshaft_torque_nm).max()
    assert np.allclose(table.camshaft_torque_nm, expected, rtol=1e-9, atol=1e-12 * scale)


def test_flat_faced_followers_push_at_the_contact_offset():
    """Flat faces have φ = 0: F_n = F. Translating: the normal force is vertical at the contact x = σ·s'
    (valve-cam notes eq. 11), so T = F·s'/1000 is also its moment. Oscillating: the normal force is
    perpendicular to the face through the pivot, at the contact's distance from the pivot: F = Q/r."""
    flat = make_cam(Follower("flat-faced"), 30.0, segments=[
        Segment("rise", 120, 10), Segment("dwell", 60), Segment("return", 120, 10), Segment("dwell", 60)])
    table = follower_dynamics(flat, TranslatingLoad(0.3, 2.0, 20.0), 500.0, samples=181).table
    assert np.array_equal(table.normal_force_n, table.contact_force_n)
    expected = contact_moment_nm(flat, table, lambda kin, th: (np.zeros_like(th), np.ones_like(th)))
    assert np.allclose(table.camshaft_torque_nm, expected, rtol=1e-9, atol=1e-12)

    pivot_mm, base_mm = 70.0, 30.0
    swing = make_cam(Follower("flat-faced", "oscillating", pivot_distance_mm=pivot_mm), base_mm, segments=OSC_SEGMENTS)
    load = OscillatingLoad(0.002, 10.0, 2.0)
    result = follower_dynamics(swing, load, 300.0, samples=181)
    theta = np.radians(result.table.cam_angle_deg)
    psi, psi1, psi2 = (np.radians(x) for x in swing.lift.derivatives(theta, 2))
    w = omega_of(300.0)
    torque = 0.002 * psi2 * w**2 + 10.0 * psi + 2.0  # I·ψ̈ + k·ψ + T0 [N·m]
    assert np.allclose(result.table.contact_torque_nm, torque, rtol=1e-12, atol=1e-12)
    kin = kinematics(swing, theta)
    arm_m = np.hypot(kin.contact[0] - pivot_mm, kin.contact[1]) / 1000
    assert np.allclose(result.table.contact_force_n, torque / arm_m, rtol=1e-12)
    assert np.allclose(result.table.camshaft_torque_nm, torque * psi1, rtol=1e-12, atol=1e-14)

    # the face's outward normal (sin α, cos α), α = asin(Rb/d) + ψ: the push on the follower
    def face_normal(kin, th):
        alpha = math.asin(base_mm / pivot_mm) + np.radians(swing.lift.derivatives(th, 0)[0])
        return np.sin(alpha), np.cos(alpha)

    expected = contact_moment_nm(swing, result.table, face_normal)
    assert np.allclose(result.table.camshaft_torque_nm, expected, rtol=1e-9, atol=1e-12)
    assert result.summary.min_preload_nm is not None and result.summary.min_preload_n is None


def test_oscillating_follower_margin_jump_and_preload():
    """About the pivot: Q = I·ψ̈ + c·ψ̇ + k·ψ + T0 + T_ext, contact force Q/L at the roller; the margin is
    a force at the roller (Q ≥ F_m·L). At the jump speed the smallest contact force is the margin, and
    the minimum preload torque makes it so at the given speed."""
    follower = Follower("roller", "oscillating", roller_radius_mm=6.0, arm_length_mm=45.0, pivot_distance_mm=60.0)
    spec = make_cam(follower, 25.0, segments=OSC_SEGMENTS)
    load = OscillatingLoad(0.004, 20.0, 3.0, damping_nm_s_rad=0.002)
    margin = 20.0  # N at the roller = 0.9 N·m about the pivot
    s = follower_dynamics(spec, load, 200.0, safety_margin_n=margin).summary
    assert s.jump_speed_rpm is not None and s.min_preload_n is None
    at_jump = follower_dynamics(spec, load, s.jump_speed_rpm, safety_margin_n=margin).summary
    # contact force ~100 N: exact to the rounding of Q/L
    assert at_jump.min_contact_force_n == pytest.approx(margin, abs=1e-9)
    fast = follower_dynamics(spec, load, 2 * s.jump_speed_rpm, safety_margin_n=margin).summary
    assert fast.separates and fast.min_preload_nm is not None and fast.min_preload_nm > load.preload_nm
    held = OscillatingLoad(0.004, 20.0, fast.min_preload_nm, damping_nm_s_rad=0.002)
    again = follower_dynamics(spec, held, 2 * s.jump_speed_rpm, safety_margin_n=margin).summary
    assert again.min_contact_force_n == pytest.approx(margin, abs=1e-9) and not again.separates


def test_a_cam_without_motion_never_jumps():
    still = make_cam(Follower("roller", roller_radius_mm=5.0), 20.0, segments=[Segment("dwell", 360)])
    s = follower_dynamics(still, TranslatingLoad(1.0, 1.0, 10.0), 1000.0).summary
    assert s.jump_speed_rpm is None and s.jump_at_deg is None
    assert s.min_contact_force_n == 10.0 and s.rms_camshaft_torque_nm == 0.0
    # a spring that cannot hold the follower at rest: the jump speed is 0
    weak = follower_dynamics(cycloid_cam(), TranslatingLoad(MASS, RATE, 1.0), 100.0, safety_margin_n=5.0).summary
    assert weak.jump_speed_rpm == 0.0 and weak.separates


@pytest.mark.parametrize(("call", "message"), [
    (lambda: TranslatingLoad(0.0, 1.0), "mass_kg must be greater than 0"),
    (lambda: TranslatingLoad(1.0, -2.0), "spring_rate_n_mm must be greater than 0"),
    (lambda: TranslatingLoad(1.0, 1.0, damping_n_s_mm=-0.1), "damping_n_s_mm must be 0 or more"),
    (lambda: OscillatingLoad(0.0, 1.0), "inertia_kgm2 must be greater than 0"),
    (lambda: OscillatingLoad(1.0, 0.0), "spring_rate_nm_rad must be greater than 0"),
    (lambda: TranslatingLoad(1.0, 1.0, preload_n=math.nan), "preload_n must be a finite number"),
    (lambda: RollerMaterials(0.0), "roller width_mm must be greater than 0"),
    (lambda: RollerMaterials(5.0, poisson_ratio=0.6), "roller poisson_ratio must lie between 0 and 0.5"),
    (lambda: follower_dynamics(cycloid_cam(), TranslatingLoad(1.0, 1.0), 0.0), "speed_rpm must be greater than 0"),
    # the smallest normal double is accepted as a number, but 2π·N/60 is subnormal and the time column's
    # θ/ω overflows (a fuzzed body found the 500)
    (lambda: follower_dynamics(cycloid_cam(), TranslatingLoad(1.0, 1.0), 2.225073858507202e-308),
     "speed_rpm=2.225073858507202e-308 is too slow"),
    (lambda: follower_dynamics(cycloid_cam(), TranslatingLoad(1.0, 1.0), 100.0, 1), "samples must be"),
    (lambda: follower_dynamics(cycloid_cam(), TranslatingLoad(1.0, 1.0), 100.0, safety_margin_n=-1),
     "safety_margin_n must be 0 or more"),
    (lambda: follower_dynamics(cycloid_cam(), OscillatingLoad(1.0, 1.0), 100.0), "mass_kg and spring_rate_n_mm"),
    (lambda: follower_dynamics(cycloid_cam(Follower("knife-edge")), TranslatingLoad(1.0, 1.0), 100.0,
                               roller=RollerMaterials(5.0)), "needs a roller follower"),
])
def test_bad_input_is_refused_with_a_sentence(call, message):
    with pytest.raises(InvalidParameterError, match=message):
        call()
