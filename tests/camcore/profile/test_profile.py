"""Plate-cam profiles (camcore.profile) and contour export (camcore.export).

Sources
-------
[S] S. Shinzato, M. Kunigami, "Utilization of a Microcomputer in Mechanism Education (1):
    Drawing and Calculation of Cam Pressure Angle" (1988), cited as Shinzato (1988)
    in docs/sources.md: eq. (6), table 1, program lists 1 and 2.
[V] Valve-cam notes, "ベジエによるバルブカム設計" (docs/sources.md):
    rotation ratio (eqs. 4, 5, 12), flat tappet contact offset (eq. 11), convexity test.
Exact geometry (eccentric circle cams, hand-derived base-circle minima) is derived in the
tests themselves.
"""

from __future__ import annotations

import io
import math
from dataclasses import replace
from typing import Any

import ezdxf
import numpy as np
import pytest

import camcore
from camcore.curves import build_curve
from camcore.errors import GeometryError, InvalidParameterError
from camcore.export import contour_csv, contour_dxf, contour_xyz
from camcore.profile import (
    CamSpec,
    CurveLift,
    Follower,
    LiftSchedule,
    Segment,
    chord_convexity,
    compute_profile,
    make_cam,
    pressure_angle_from_lift_samples,
    pressure_angle_from_points,
    profile_checks,
    sample_profile,
    size_base_circle,
)

CV = camcore.named_curve("constant-velocity")
CYC = camcore.named_curve("cycloid")
SH = camcore.named_curve("simple-harmonic")


def paper_cam(lift: float = 20.0) -> CamSpec:
    """[S] table 1: knife-edge, in-line, base circle D = 30 mm, uniform rise over 180°,
    uniform return over 180°."""
    segs = [Segment("rise", 180, lift, CV), Segment("return", 180, lift, CV)]
    return make_cam(Follower("knife-edge"), 15.0, segments=segs)


# ============================================================================ [S] table 1
TABLE1 = {10: 21.56, 30: 19.15, 45: 17.66, 120: 12.66}


def test_table1_analytic_eq6():
    # eq. (6): β = atan((l − D/2)/(θ·l)), l = y + D/2, for the uniform rise y = hθ/π.
    # Table 1 states D = 30 mm and lift 20 mm; the program list's S = 10*10 plotter units
    # (0.1 mm) would be a 10 mm lift and gives 11.56° at 10°, not 21.56° (checked below),
    # so the printed table was computed with the 20 mm lift.
    for deg, printed in TABLE1.items():
        th = math.radians(deg)
        ell = 20.0 * th / math.pi + 15.0
        beta = math.degrees(math.atan((ell - 15.0) / (th * ell)))
        assert round(beta, 2) == printed
    res = compute_profile(paper_cam(), list(TABLE1))
    # our analytic pressure angle atan2(s', Rb + s) is the same formula: printed 2 decimals
    assert np.round(res.pressure_angle_deg, 2).tolist() == list(TABLE1.values())
    # 270°: table 1 gives only the numerical value, −14.29; the analytic one rounds the same
    assert round(float(compute_profile(paper_cam(), [270.0]).pressure_angle_deg[0]), 2) == -14.29
    # the 10 mm reading of the program list does not reproduce the table
    assert round(float(compute_profile(paper_cam(10.0), [10.0]).pressure_angle_deg[0]), 2) == 11.56


def paper_list1_points(s_units: float = 200.0, pai: float = 3.1416):
    """Program list 1, lines 70 and 120-190, verbatim (plotter units, 0.1 mm).

    Note line 140: I = 0 falls to line 160, so H(0) = S − S·(0 − PAI)/PAI = 2S, a slip in
    the paper; it only affects the angles 0, 1, 359 and 360, which table 1 does not use.
    """
    d1 = 30 * 10
    h = np.empty(361)
    x = np.empty(361)
    y = np.empty(361)
    for i in range(361):
        sita = i * pai / 180
        h[i] = s_units * sita / pai if 0 < i <= 180 else s_units - s_units * (sita - pai) / pai
        dd1 = d1 / 2 + h[i]
        x[i], y[i] = dd1 * math.cos(sita), dd1 * math.sin(sita)
    return x, y


def paper_round(value: float) -> float:
    """The program's 3-decimal print, then the table's 2 decimals (half away from zero)."""
    from decimal import ROUND_HALF_UP, Decimal

    three = Decimal(value).quantize(Decimal("0.001"), rounding=ROUND_HALF_UP)
    return float(three.quantize(Decimal("0.01"), rounding=ROUND_HALF_UP))


def test_table1_numerical_method_on_paper_points():
    # [S] list 1 with PAI = 3.1416 and the 20 mm lift (S = 200 units): the tangent through
    # the neighbouring points (lines 420-430), the radius at the integer angle PHAI as the
    # stroke line. The paper uses X(PHAI±1) directly: closed=False.
    x, y = paper_list1_points()
    ang = np.arange(361.0)
    beta = pressure_angle_from_points(x, y, ang, closed=False)
    for deg, printed in {**TABLE1, 270: -14.29}.items():
        # The program prints with PRINT USING "#####.###" (line 2010), three decimals, and
        # table 1 shows two: at 45° we get 17.65496°, printed 17.655, shown 17.66 — a double
        # rounding (one-step rounding would give 17.65). The paper's own degree conversion
        # (G = ATN(…)·180/PAI, PAI = 3.1416) shifts its value by only ~1.5e-4°, and 17.65496
        # is 4.5e-4° from the nearest three-decimal boundary, so the printed 17.655 is certain.
        assert paper_round(float(beta[deg])) == printed, deg
    assert round(float(beta[45]), 3) == 17.655


def test_table1_numerical_method_exact_pi_and_lift_samples():
    # The same method with π exact and the lift from our schedule gives the same table:
    # the 1° chord's error (~0.002°) and PAI = 3.1416 (relative 2e-6) are both below 0.005°.
    cam = paper_cam()
    ang = np.arange(361.0)
    h = cam.lift.derivatives(np.radians(ang), 0)[0]
    beta = pressure_angle_from_lift_samples(h, 15.0, ang)
    for deg, printed in {**TABLE1, 270: -14.29}.items():
        assert round(float(beta[deg]), 2) == printed


def test_straight_flank_list2_gives_40_deg_at_320():
    # [S] list 2: rise as list 1 up to 180°, then H = S − (S − 62.13)(θ − π)/(3π/4) to 315°
    # (H(315) = 62.13 units, so the radius is 150 + 62.13 = 150·√2 and X(315) = 150.0 = D/2),
    # then the straight flank X = X(315), Y = X(315)·tan θ from 316° to 360°. (Line 170 is
    # OCR'd "DDI(I) = DI1 / 2 * H(I)"; it is list 1's DD1(I) = D1/2 + H(I).)
    pai, s_units, d1 = 3.1416, 200.0, 300.0
    x = np.empty(361)
    y = np.empty(361)
    for i in range(316):
        sita = i * pai / 180
        h = s_units * sita / pai if 0 < i <= 180 else s_units - (s_units - 62.13) * (sita - pai) / (3 * pai / 4)
        dd1 = d1 / 2 + h
        x[i], y[i] = dd1 * math.cos(sita), dd1 * math.sin(sita)
    for i in range(316, 361):
        sita = i * pai / 180
        x[i] = x[315]
        y[i] = x[315] * (math.sin(sita) / math.cos(sita))
    assert x[315] == pytest.approx(150.0, abs=0.01)  # 62.13 is 150(√2 − 1) to 2 decimals
    beta = pressure_angle_from_points(x, y, np.arange(361.0), closed=False)
    # the flank is vertical (x = const), the stroke line at 320° makes 40° with its normal.
    # The paper says "40°"; its program (line 1220, B = −(90 − (PHAI2 − |G|)) with G = 0)
    # prints −40: the follower is falling (the paper's sign: negative on the return).
    # The tangent is exactly vertical, so the result is exact to rounding.
    assert beta[320] == pytest.approx(-40.0, abs=1e-9)


def test_contour_matches_paper_convention():
    # The paper's contour (x, y) = l(cos θ, sin θ) is a cam turning clockwise with the
    # follower along +x; ours has the follower along +y, so a cw cam is the paper's
    # contour turned by +90°: (−l sin θ, l cos θ). Exact up to rounding (1e-12 mm).
    cam = CamSpec(Follower("knife-edge"), 15.0, paper_cam().lift, rotation="cw")
    ang = np.arange(0.0, 360.0, 7.0)
    res = compute_profile(cam, ang)
    th = np.radians(ang)
    ell = 15.0 + np.where(ang <= 180, 20 * ang / 180, 20 * (360 - ang) / 180)
    np.testing.assert_allclose(res.x_mm, -ell * np.sin(th), atol=1e-12)
    np.testing.assert_allclose(res.y_mm, ell * np.cos(th), atol=1e-12)


# ============================================================================ eccentric circle
class FunctionLift:
    """A test lift from a closed-form function of the cam angle, with derivatives by the
    5-point central difference at step 1e-3 rad: truncation ~ h⁴·f⁽⁵⁾/30 ≈ 3e-14·f and
    rounding ~ 1e-16·|f|/h² ≈ 1e-8 (2nd derivative), so derived radii carry ~1e-7 error."""

    def __init__(self, fun, unit="mm", breaks=()):
        self.fun = fun
        self.unit = unit
        self.breaks_rad = np.asarray(breaks, dtype=float)

    def derivatives(self, theta, order=2):
        t = np.asarray(theta, dtype=float)
        h = 1e-3
        f = [self.fun(t + k * h) for k in (-2, -1, 0, 1, 2)]
        d1 = (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)
        d2 = (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * h * h)
        d3 = (-f[0] + 2 * f[1] - 2 * f[3] + f[4]) / (2 * h**3)
        return [f[2], d1, d2, d3][: order + 1]


R_CIRCLE, ECC, RR, OFFSET, PIVOT, ARM = 25.0, 5.0, 6.0, 4.0, 60.0, 45.0
RB = R_CIRCLE - ECC  # the base circle: the circle's nearest point to the cam centre


def centre(theta, sigma):
    """Circle centre (0, −ε) of the cam frame, seen in the fixed frame: R(σθ)(0, −ε)."""
    a = sigma * theta
    return ECC * np.sin(a), -ECC * np.cos(a)


def eccentric_spec(ftype, motion, rotation):
    sigma = 1.0 if rotation == "ccw" else -1.0
    rr = RR if ftype == "roller" else 0.0
    q = R_CIRCLE + rr
    if motion == "translating":
        follower = Follower(ftype, "translating", offset_mm=OFFSET if ftype != "flat-faced" else 0.0,
                            roller_radius_mm=rr)
        if ftype == "flat-faced":
            # face at y = cy + R: s = R − ε cos θ − (R − ε) = ε(1 − cos θ) exactly
            lift = FunctionLift(lambda t: ECC * (1 - np.cos(t)))
        else:
            s0 = math.sqrt((RB + rr) ** 2 - OFFSET**2)

            def lift_fn(t):
                cx, cy = centre(t, sigma)
                return cy + np.sqrt(q * q - (OFFSET - cx) ** 2) - s0

            lift = FunctionLift(lift_fn)
    else:
        follower = Follower(ftype, "oscillating", roller_radius_mm=rr, arm_length_mm=ARM, pivot_distance_mm=PIVOT)
        if ftype == "flat-faced":
            a0 = math.asin(RB / PIVOT)

            def lift_fn(t):
                # face through A = (d, 0) with normal (sin α, cos α): (d − cx) sin α − cy cos α = R
                cx, cy = centre(t, sigma)
                m = np.hypot(PIVOT - cx, cy)
                return np.degrees(np.arctan2(cy, PIVOT - cx) + np.arcsin(R_CIRCLE / m) - a0)
        else:
            r0 = RB + rr
            a0 = math.acos((PIVOT**2 + ARM**2 - r0**2) / (2 * PIVOT * ARM))

            def lift_fn(t):
                # |B(α) − C| = Q with B = (d − L cos α, L sin α): (d − cx) cos α + cy sin α = K
                cx, cy = centre(t, sigma)
                k = ((PIVOT - cx) ** 2 + cy**2 + ARM**2 - q * q) / (2 * ARM)
                m = np.hypot(PIVOT - cx, cy)
                delta = np.arctan2(cy, PIVOT - cx)
                return np.degrees(delta + np.arccos(k / m) - a0)
        lift = FunctionLift(lift_fn, unit="deg")
    return CamSpec(follower, RB, lift, rotation)


CASES = [(f, m, r) for f in ("knife-edge", "roller", "flat-faced") for m in ("translating", "oscillating")
         for r in ("ccw", "cw")]


@pytest.mark.parametrize("ftype,motion,rotation", CASES)
def test_eccentric_circle_cam(ftype, motion, rotation):
    spec = eccentric_spec(ftype, motion, rotation)
    ang = np.linspace(0.0, 360.0, 73)
    res = compute_profile(spec, ang)
    # the lift never goes below the base circle, and touches it (its minimum is 0)
    assert res.lift.min() > -1e-9 and res.lift.min() < 0.05
    # cam surface = the circle of radius R about (0, −ε) in the cam frame (rounding, 1e-9 mm,
    # and the finite-difference lift derivative which moves the contact along the circle)
    dist = np.hypot(res.x_mm - 0.0, res.y_mm + ECC)
    np.testing.assert_allclose(dist, R_CIRCLE, atol=1e-7)
    # radius of curvature of the surface is R everywhere (finite-difference lift: ~1e-7)
    np.testing.assert_allclose(res.radius_of_curvature_mm, R_CIRCLE, rtol=1e-6)
    if ftype == "roller":
        np.testing.assert_allclose(res.pitch_radius_of_curvature_mm, R_CIRCLE + RR, rtol=1e-6)
        np.testing.assert_allclose(np.hypot(res.pitch_x_mm, res.pitch_y_mm + ECC), R_CIRCLE + RR, atol=1e-9)
    ch = res.checks
    assert ch.convex and not ch.undercut
    assert ch.min_radius_of_curvature_mm == pytest.approx(R_CIRCLE, rel=1e-6)
    if ftype == "flat-faced":
        assert np.all(res.pressure_angle_deg == 0.0)
    elif motion == "translating":
        # the common normal is the line from the circle centre to the pitch point, so
        # |sin φ| = |e − cx|/Q (exact geometry; 1e-9° of rounding)
        sigma = 1.0 if rotation == "ccw" else -1.0
        cx, _ = centre(np.radians(ang), sigma)
        expect = np.degrees(np.arcsin(np.abs(OFFSET - cx) / (R_CIRCLE + (RR if ftype == "roller" else 0.0))))
        np.testing.assert_allclose(np.abs(res.pressure_angle_deg), expect, atol=1e-7)


def test_flat_faced_contact_offset_is_ds_dtheta():
    # [V] eq. (11): the tappet contact point sits dh/dθ from the stem axis; for the
    # eccentric, s' = ε sin θ, so the face must span 2ε (exact to the 1e-9 of the FD lift).
    spec = eccentric_spec("flat-faced", "translating", "ccw")
    ang = np.linspace(0, 360, 37)
    res = compute_profile(spec, ang)
    np.testing.assert_allclose(res.contact_offset_mm, ECC * np.sin(np.radians(ang)), atol=1e-9)
    assert res.checks.face_width_mm == pytest.approx(2 * ECC, abs=1e-9)


# ============================================================================ curvature vs polyline
def circumradius(x, y):
    ax, ay = x[:-2], y[:-2]
    bx, by = x[1:-1], y[1:-1]
    cx, cy = x[2:], y[2:]
    a = np.hypot(bx - cx, by - cy)
    b = np.hypot(ax - cx, ay - cy)
    c = np.hypot(ax - bx, ay - by)
    cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    return a * b * c / (2 * cross)  # signed: positive for a ccw turn


def mixed_cam(ftype="roller", rotation="ccw", offset=3.0):
    segs = [Segment("rise", 120, 12.0, CYC), Segment("dwell", 60), Segment("return", 120, 12.0, CYC),
            Segment("dwell", 60)]
    return make_cam(Follower(ftype, offset_mm=offset if ftype != "flat-faced" else 0.0,
                             roller_radius_mm=5.0 if ftype == "roller" else 0.0),
                    30.0, segments=segs, rotation=rotation)


@pytest.mark.parametrize("ftype", ["knife-edge", "roller", "flat-faced"])
@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_curvature_against_three_point_circles(ftype, rotation):
    spec = mixed_cam(ftype, rotation)
    ang = np.linspace(0.0, 360.0, 14401)
    res = compute_profile(spec, ang)
    r3 = circumradius(res.x_mm, res.y_mm)
    # orientation: a ccw cam runs its contour clockwise (circumradius negative where convex)
    sign = -1.0 if rotation == "ccw" else 1.0
    rho = res.radius_of_curvature_mm[1:-1]
    # three-point circle through points 0.025° apart: error O(Δ²) ≈ 1e-6 relative where the
    # contour is smooth. At a segment end the cycloid's jerk jumps, so the curvature has a
    # kink there and a circle centred on it is off by O(Δ) (measured 1.2e-4 at 300°):
    # those middle points (0°, 120°, 180°, 300°, 360°) are left out.
    keep = ~np.isin(ang[1:-1], [0.0, 120.0, 180.0, 300.0, 360.0])
    np.testing.assert_allclose((sign * r3)[keep], rho[keep], rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_contour_is_kinematic_inversion(rotation):
    spec = mixed_cam("roller", rotation, offset=3.0)
    ang = np.linspace(0.0, 360.0, 97)
    res = compute_profile(spec, ang)
    th = np.radians(ang)
    sigma = 1.0 if rotation == "ccw" else -1.0
    s = spec.lift.derivatives(th, 0)[0]
    s0 = math.sqrt(35.0**2 - 3.0**2)
    # roller centre (e, s0 + s) in the fixed frame, turned back by the cam angle
    px = np.cos(-sigma * th) * 3.0 - np.sin(-sigma * th) * (s0 + s)
    py = np.sin(-sigma * th) * 3.0 + np.cos(-sigma * th) * (s0 + s)
    np.testing.assert_allclose(res.pitch_x_mm, px, atol=1e-12)
    np.testing.assert_allclose(res.pitch_y_mm, py, atol=1e-12)
    # the surface is one roller radius from the centre, along the pitch curve's normal
    np.testing.assert_allclose(np.hypot(res.x_mm - px, res.y_mm - py), 5.0, rtol=1e-12)
    h = 1e-6
    a = compute_profile(spec, ang + h)
    b = compute_profile(spec, ang - h)
    tx, ty = a.pitch_x_mm - b.pitch_x_mm, a.pitch_y_mm - b.pitch_y_mm
    cosang = (tx * (res.x_mm - px) + ty * (res.y_mm - py)) / (np.hypot(tx, ty) * 5.0)
    np.testing.assert_allclose(cosang, 0.0, atol=1e-6)  # central difference O(h²) + rounding
    # and the surface lies inside the pitch curve (the roller is outside the cam)
    assert np.all(np.hypot(res.x_mm, res.y_mm) < np.hypot(px, py))


def test_lift_derivatives_chain_rule():
    # dh/dθ = (lift/β)·V, d²h/dθ² = (lift/β²)·A, d³ = (lift/β³)·J (β in rad), checked against
    # a central difference (h = 1e-5 rad: O(h²) ≈ 1e-9 relative, rounding ≈ 1e-7).
    spec = mixed_cam()
    th = np.radians(np.array([10.0, 60.0, 110.0, 200.0, 250.0, 290.0]))
    d = spec.lift.derivatives(th, 3)
    hh = 1e-5
    for k in range(3):
        fd = (spec.lift.derivatives(th + hh, 3)[k] - spec.lift.derivatives(th - hh, 3)[k]) / (2 * hh)
        np.testing.assert_allclose(d[k + 1], fd, rtol=1e-6, atol=1e-5)
    beta = math.radians(120)
    assert d[1][0] == pytest.approx(12 / beta * CYC.derivatives(10 / 120, 1)[1], rel=1e-14)
    # the return mirrors the rise: lift at 200° (80° into the return) = lift at 40° of the rise
    assert spec.lift.derivatives(math.radians(260.0), 0)[0] == pytest.approx(
        spec.lift.derivatives(math.radians(40.0), 0)[0], rel=1e-13)


def _lift_by_masks(lift: LiftSchedule, theta: np.ndarray, order: int) -> list[np.ndarray]:
    """A schedule's lift the plain way: every angle's piece by np.searchsorted, each piece's angles
    by a mask (the method before a few angles were placed by bisection and sorted ones by slices)."""
    flat = np.mod(theta.reshape(-1), 2 * math.pi)
    idx = np.searchsorted(lift._starts, flat, side="right") - 1
    out = list(np.zeros((order + 1, flat.size)))
    for k, p in enumerate(lift._pieces):
        sel = idx == k
        if not sel.any():
            continue
        if p.curve is None:
            out[0][sel] = p.level
            continue
        c = p.curve
        rate = (c.t_end - c.t_start) / p.span
        u = np.minimum(np.maximum((flat[sel] - p.start) / p.span, 0.0), 1.0)
        vals = c.derivatives(c.t_start + (c.t_end - c.t_start) * u, order)
        gain = p.amount / (p.s1 - p.s0)
        out[0][sel] = p.level + gain * (vals[0] - p.s0)
        for o in range(1, order + 1):
            out[o][sel] = gain * rate**o * vals[o]
    return [o.reshape(theta.shape) for o in out]


def test_the_lift_of_a_few_or_sorted_angles_is_the_masks_lift_to_the_bit():
    # LiftSchedule places up to 8 angles by bisection and sorted angles by slices; the curve gets the
    # same T in the same order either way, so every number must be equal, not close (the recorded
    # answers hold them to the bit). Angles: random, sorted, on the piece starts, past a turn,
    # negative, -0.0, NaN, one and none
    # the constant-velocity rise's V jumps at its start and end: an angle on a piece start placed on
    # the piece before would differ there
    jumps = LiftSchedule([Segment("rise", 100, 10.0, CV), Segment("dwell", 80), Segment("return", 100, 10.0, SH),
                          Segment("dwell", 80)])
    rng = np.random.default_rng(38)
    cases: list[tuple[LiftSchedule, np.ndarray]] = []
    for lift in (mixed_cam().lift, jumps):
        starts = lift._starts
        lift_cases = [np.zeros(0), np.array([1.0]), np.array([-0.0]), np.array([np.nan, 1.0]), starts.copy(),
                      np.concatenate([starts, starts + 1e-15]), np.sort(rng.uniform(0, 2 * math.pi, 500)),
                      np.sort(np.concatenate([starts, starts, rng.uniform(0, 2 * math.pi, 20)])),
                      np.linspace(0.0, 2 * math.pi, 361), np.linspace(-7.0, 13.0, 50), np.array([2.0, 2.0, 2.0])]
        for n in (2, 5, 8, 9, 30, 200):
            for _ in range(20):
                lift_cases.append(rng.uniform(-10.0, 20.0, n))
                lift_cases.append(np.sort(rng.uniform(0.0, 2 * math.pi, n)))
                lift_cases.append(rng.choice(np.concatenate([starts, rng.uniform(0, 7, 4)]), n))
                lift_cases.append(np.sort(lift_cases[-1]))
        cases += [(lift, theta) for theta in lift_cases]
    for lift, theta in cases:
        for order in (0, 2, 3):
            got, want = lift.derivatives(theta, order), _lift_by_masks(lift, theta, order)
            assert len(got) == order + 1
            for g, w in zip(got, want):
                assert g.shape == theta.shape
                np.testing.assert_array_equal(np.ascontiguousarray(g).view(np.int64),
                                              np.ascontiguousarray(w).view(np.int64))  # bits: -0.0 ≠ 0.0
    # a matrix of angles keeps its shape
    assert lift.derivatives(np.ones((2, 3)), 1)[1].shape == (2, 3)


# ============================================================================ rotation ratio
class PeriodicCurve(camcore.Curve):
    """A closed user lift: S = (1 − cos 2πT)/2 over T ∈ [0, 1], with a scale like a Bezier
    curve's (drive angle 30..210°, lift 2 + 8·S mm)."""

    def __init__(self):
        self.piece_starts = np.array([0.0])
        self.t_end = 1.0
        self.scale = camcore.curves.base.Scale(theta_start=30.0, theta_span=180.0, h_min=2.0, h_span=8.0)

    def eval_pieces(self, t, piece, order):
        w = 2 * math.pi
        out = [(1 - np.cos(w * t)) / 2, w * np.sin(w * t) / 2, w * w * np.cos(w * t) / 2,
               -(w**3) * np.sin(w * t) / 2, -(w**4) * np.cos(w * t) / 2]
        return out[: order + 1]


def test_curve_lift_with_rotation_ratio():
    # [V] eqs. (5), (12): θcam = γ θdr, dh/dθcam = (1/γ) dh/dθdr. With γ = 2 one cam turn is
    # 180° of drive, exactly the curve's span.
    lift = CurveLift(PeriodicCurve(), rotation_ratio=2.0)
    cam_deg = np.array([0.0, 45.0, 100.0, 300.0])
    drive = cam_deg / 2.0
    tau = np.mod((drive - 30.0) / 180.0, 1.0)
    h, h1 = lift.derivatives(np.radians(cam_deg), 1)
    np.testing.assert_allclose(h, 2 + 8 * (1 - np.cos(2 * np.pi * tau)) / 2, rtol=1e-14)
    dh_ddrive = 8 * math.pi * np.sin(2 * np.pi * tau) / math.radians(180.0)
    np.testing.assert_allclose(h1, dh_ddrive / 2.0, rtol=1e-12, atol=1e-12)
    with pytest.raises(InvalidParameterError, match="whole number"):
        CurveLift(PeriodicCurve(), rotation_ratio=1.5)
    # One cam turn holds 360/(γ·180°) periods: 1000 at γ = 1/500 is the most; fewer cam turns per
    # drive turn (down to 5e-324, where 360/γ overflows) are refused before the periods are laid out.
    assert len(CurveLift(PeriodicCurve(), rotation_ratio=1 / 500).breaks_rad) > 1000
    for ratio in (1 / 500.5, 5e-324):
        with pytest.raises(InvalidParameterError, match="more than 1000 periods"):
            CurveLift(PeriodicCurve(), rotation_ratio=ratio)


# ============================================================================ base circle
def test_base_circle_knife_edge_constant_velocity():
    # tan φ = (h/β)/(Rb + s) is largest at s = 0: Rb_min = (h/β)/tan φmax (hand-derived).
    segs = [Segment("rise", 180, 20.0, CV), Segment("return", 180, 20.0, CV)]
    spec = make_cam(Follower("knife-edge"), 15.0, segments=segs)
    res = size_base_circle(spec, max_pressure_angle_deg=30.0)
    expect = (20.0 / math.pi) / math.tan(math.radians(30.0))
    # the closed form s0 = max(s'/tan α − s) of the checks' own maximum: to rounding (measured equal)
    assert res.base_radius_mm == pytest.approx(expect, rel=1e-14)
    assert res.active_constraint == "pressure_angle"
    # roller: the pitch base radius Rb + Rr takes that role
    spec_r = make_cam(Follower("roller", roller_radius_mm=4.0), 15.0, segments=segs)
    assert size_base_circle(spec_r, max_pressure_angle_deg=30.0).base_radius_mm == pytest.approx(
        expect - 4.0, rel=1e-14)


@pytest.mark.parametrize("follower", [Follower("knife-edge", offset_mm=7.5), Follower("roller", offset_mm=-12.0,
                                                                                     roller_radius_mm=10.0)])
@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("limit_deg", [20.0, 30.0, 45.0])
def test_the_pressure_closed_form_is_the_root_of_the_checked_angle(follower: Follower, rotation: str,
                                                                 limit_deg: float) -> None:
    # a translating follower's radius for a pressure limit, s0 = max_θ(|s' − σe|/tan α − s), against the
    # Illinois root of the checks' own largest pressure angle (the route an arm still takes): they agree to
    # the root's 1e-10 (measured 1.4e-11 at most over 72 cams), and the closed form's cam meets the limit
    # to rounding (7e-15° measured)
    from camcore.profile import base_circle
    from camcore.profile.checks import check_maxima, lift_grid

    spec = make_cam(follower, 40.0, segments=[Segment("rise", 80, 30.0), Segment("dwell", 100),
                                              Segment("return", 100, 30.0), Segment("dwell", 80)], rotation=rotation)
    grid = lift_grid(spec)
    closed = base_circle._translating_pressure_radius(spec, grid, limit_deg)
    root = base_circle._solve_radius(
        spec, lambda s: limit_deg - math.degrees(check_maxima(s, grid, ("pressure",))["pressure"][1]), "pressure")
    assert closed == pytest.approx(root, rel=1e-10)
    assert profile_checks(replace(spec, base_radius_mm=closed)).max_pressure_angle_deg == pytest.approx(
        limit_deg, abs=1e-12)


def test_base_circle_pressure_limit_is_met_exactly():
    spec = mixed_cam("roller", "ccw", offset=6.0)
    res = size_base_circle(spec, max_pressure_angle_deg=25.0)
    from dataclasses import replace

    at = profile_checks(replace(spec, base_radius_mm=res.base_radius_mm))
    assert at.max_pressure_angle_deg == pytest.approx(25.0, abs=1e-7)
    below = profile_checks(replace(spec, base_radius_mm=res.base_radius_mm * (1 - 1e-6)))
    assert below.max_pressure_angle_deg > 25.0
    # the exact max beats any sampled grid (golden-section refinement)
    samp = compute_profile(replace(spec, base_radius_mm=res.base_radius_mm), np.linspace(0, 360, 3601))
    assert np.abs(samp.pressure_angle_deg).max() <= at.max_pressure_angle_deg + 1e-12


def test_base_circle_flat_faced_curvature():
    # simple-harmonic rise h over β = 120°, dwell, return, dwell: s = h/2·(1 − cos(πθ/β)),
    # s + s'' = h/2 + h/2·((π/β)² − 1)·cos(πθ/β); with π/β = 3/2 the least value is at the
    # top of the rise: h/2 − h/2·1.25 = −h/8. So Rb = ρreq + h/8 (hand-derived).
    h = 16.0
    segs = [Segment("rise", 120, h, SH), Segment("dwell", 60), Segment("return", 120, h, SH), Segment("dwell", 60)]
    spec = make_cam(Follower("flat-faced"), 30.0, segments=segs)
    res = size_base_circle(spec, min_radius_of_curvature_mm=5.0)
    assert res.base_radius_mm == pytest.approx(5.0 + h / 8, rel=1e-12)
    assert res.active_constraint == "radius_of_curvature"
    # full-turn harmonic: s + s'' = h/2 constant, so ρ = Rb + h/2 everywhere
    segs2 = [Segment("rise", 180, h, SH), Segment("return", 180, h, SH)]
    spec2 = make_cam(Follower("flat-faced"), 30.0, segments=segs2)
    assert size_base_circle(spec2, min_radius_of_curvature_mm=20.0).base_radius_mm == pytest.approx(
        20.0 - h / 2, rel=1e-12)


def test_base_circle_roller_curvature():
    spec = mixed_cam("roller", "ccw", offset=0.0)
    res = size_base_circle(spec, min_radius_of_curvature_mm=8.0, max_pressure_angle_deg=40.0)
    from dataclasses import replace

    ch = profile_checks(replace(spec, base_radius_mm=res.base_radius_mm))
    assert ch.min_radius_of_curvature_mm >= 8.0 - 1e-6
    assert ch.max_pressure_angle_deg <= 40.0 + 1e-6
    assert res.active_constraint in ("pressure_angle", "radius_of_curvature")


# ============================================================================ checks
def test_undercut_and_convexity():
    # a steep cycloid on a small base circle: pitch curvature radius below the roller radius
    segs = [Segment("rise", 60, 20.0, CYC), Segment("return", 60, 20.0, CYC), Segment("dwell", 240)]
    spec = make_cam(Follower("roller", roller_radius_mm=15.0), 10.0, segments=segs)
    ch = sample_profile(spec, 361).checks
    assert ch.undercut and not ch.convex
    big = make_cam(Follower("roller", roller_radius_mm=2.0), 80.0, segments=segs)
    assert not profile_checks(big).undercut
    # flat-faced on a small base circle: ρ = Rb + s + s'' < 0 somewhere, not convex
    flat = make_cam(Follower("flat-faced"), 10.0, segments=segs)
    fc = profile_checks(flat)
    assert fc.min_radius_of_curvature_mm < 0 and not fc.convex


def test_chord_convexity_valve_document():
    t = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    assert chord_convexity(np.cos(t), np.sin(t))
    assert chord_convexity(np.cos(t)[::-1], np.sin(t)[::-1])  # either traversal direction
    r = 1 + 0.3 * np.cos(3 * t)  # a trefoil with concave stretches
    assert not chord_convexity(r * np.cos(t), r * np.sin(t))


# ============================================================================ export
def test_dxf_export_round_trip():
    spec = mixed_cam("roller")
    res = sample_profile(spec, 361)
    data = contour_dxf(res.x_mm, res.y_mm, spline=True, base_radius_mm=30.0)
    assert isinstance(data, bytes)
    doc = ezdxf.read(io.StringIO(data.decode("utf-8")))
    assert doc.dxfversion == "AC1024"  # R2010
    assert doc.units == ezdxf.units.MM
    msp = doc.modelspace()
    (pl,) = msp.query("LWPOLYLINE")
    assert pl.closed
    assert len(pl) == 360  # 361 samples over 0–360° with both ends: the closing point is dropped
    pts = np.array(list(pl.vertices()))
    # DXF text keeps full precision (repr-style floats): 1e-9 mm
    assert pts[:, 0].min() == pytest.approx(res.x_mm.min(), abs=1e-9)
    assert pts[:, 0].max() == pytest.approx(res.x_mm.max(), abs=1e-9)
    assert pts[:, 1].min() == pytest.approx(res.y_mm.min(), abs=1e-9)
    assert pts[:, 1].max() == pytest.approx(res.y_mm.max(), abs=1e-9)
    assert len(msp.query("SPLINE")) == 1 and len(msp.query("CIRCLE")) == 1


def test_csv_and_xyz_export():
    x, y = np.array([1.0, 0.0, -1.0]), np.array([0.0, 1.0, 0.0])
    text = contour_csv(x, y, [0.0, 90.0, 180.0], with_z=True)
    lines = text.splitlines()
    assert lines[0] == "cam_angle_deg,x_mm,y_mm,z_mm"
    assert lines[2] == "90.0,0.0,1.0,0.0"
    xyz = contour_xyz(x, y).splitlines()
    assert xyz[0] == "1.0 0.0 0.0" and xyz[-1] == xyz[0] and len(xyz) == 4


# ============================================================================ validation
def test_validation_errors():
    with pytest.raises(InvalidParameterError, match="add to 350"):
        LiftSchedule([Segment("rise", 170, 10, CV), Segment("return", 180, 10, CV)])
    with pytest.raises(InvalidParameterError, match="does not close"):
        LiftSchedule([Segment("rise", 180, 10, CV), Segment("return", 180, 8, CV)])
    with pytest.raises(GeometryError, match="below the base circle"):
        LiftSchedule([Segment("return", 180, 10, CV), Segment("rise", 180, 10, CV)])
    segs = [Segment("rise", 180, 10, CV), Segment("return", 180, 10, CV)]
    with pytest.raises(GeometryError, match="roller radius > 0"):
        make_cam(Follower("roller", roller_radius_mm=0.0), 20.0, segments=segs)
    with pytest.raises(GeometryError, match="must exceed the offset"):
        make_cam(Follower("knife-edge", offset_mm=25.0), 20.0, segments=segs)
    with pytest.raises(GeometryError, match="base radius must be positive"):
        make_cam(Follower("knife-edge"), -1.0, segments=segs)
    swing = [Segment("rise", 180, swing_deg=10, curve=CV), Segment("return", 180, swing_deg=10, curve=CV)]
    with pytest.raises(GeometryError, match="cannot be assembled"):
        make_cam(Follower("roller", "oscillating", roller_radius_mm=5, arm_length_mm=20, pivot_distance_mm=100),
                 20.0, segments=swing)
    with pytest.raises(InvalidParameterError, match="as segments, as one lift curve or as a motion program"):
        make_cam(Follower("knife-edge"), 20.0)


def test_oscillating_schedule_runs():
    swing = [Segment("rise", 120, swing_deg=15, curve=CYC), Segment("dwell", 60),
             Segment("return", 120, swing_deg=15, curve=CYC), Segment("dwell", 60)]
    spec = make_cam(Follower("roller", "oscillating", roller_radius_mm=5, arm_length_mm=50, pivot_distance_mm=70),
                    30.0, segments=swing)
    res = sample_profile(spec, 721)
    assert "swing_deg" in res.columns()
    # at zero swing the roller centre is on the circle Rb + Rr (assembly geometry)
    np.testing.assert_allclose(np.hypot(res.pitch_x_mm[0], res.pitch_y_mm[0]), 35.0, rtol=1e-12)
    r3 = circumradius(res.x_mm, res.y_mm)
    # three-point circles 0.5° apart: O(Δ²) ≈ 1e-4 relative; segment ends (a kink in the
    # curvature, see above) are left out
    ang = res.cam_angle_deg[1:-1]
    keep = ~np.isin(ang, [0.0, 120.0, 180.0, 300.0, 360.0])
    np.testing.assert_allclose(-r3[keep], res.radius_of_curvature_mm[1:-1][keep], rtol=5e-4)


def test_flat_faced_convexity_is_not_fooled_by_break_point_neighbours() -> None:
    """A cycloid rise/dwell/return/dwell with ρ ≥ 34.7 mm everywhere is convex.

    The exact-extremum grid holds each break point and its left neighbour an ulp apart;
    the valve-cam chord test (cos φ > 0, sin φ > 0) on such chords was rounding noise and
    called this cam not convex. The chord test now runs on an even grid. A cam whose
    ρ = Rb + s + s'' dips below zero (Rb = 3 mm) must still be caught.
    """
    from camcore import named_curve
    from camcore import profile as P

    segs = [P.Segment("rise", 120, 10, named_curve("cycloid")), P.Segment("dwell", 60),
            P.Segment("return", 120, 10, named_curve("cycloid")), P.Segment("dwell", 60)]
    follower = P.Follower(type="flat-faced")
    good = P.profile_checks(P.make_cam(follower, 40, segments=segs))
    assert good.convex and good.min_radius_of_curvature_mm > 34
    bad = P.profile_checks(P.make_cam(follower, 3, segments=segs))
    assert not bad.convex and bad.min_radius_of_curvature_mm < 0


# ------------------------------------------------------- base-circle solver at the extremes
@pytest.mark.parametrize("limits", [(89.9999, None), (0.01, None), (None, 0.0), (None, 1e6), (30.0, 5.0)])
@pytest.mark.parametrize("start_radius_mm", [1.0, 1e4])
def test_base_circle_solver_converges_within_its_caps_at_the_extremes(
        monkeypatch: pytest.MonkeyPatch, limits: tuple[float | None, float | None], start_radius_mm: float) -> None:
    """Issue 15: the solver's caps (a 60-step doubling bracket, 200 Illinois steps) are far
    from binding at the extremes of the limits and of the starting radius: each limit took at
    most 49 evaluations of the limited extreme when measured; the answer is tight (1e-9 smaller
    fails the limit)."""
    from camcore.profile import Follower, Segment, base_circle, make_cam, profile_checks, size_base_circle
    calls: list[int] = []
    real = base_circle.check_maxima

    def counted(*args: Any) -> Any:
        calls.append(1)
        return real(*args)

    monkeypatch.setattr(base_circle, "check_maxima", counted)
    ms = build_curve("named", {"name": "MS"})
    follower = Follower(type="roller", motion="translating", offset_mm=0.0, roller_radius_mm=10.0,
                        arm_length_mm=None, pivot_distance_mm=None)
    cam = make_cam(follower, start_radius_mm, segments=[
        Segment(type="rise", angle_deg=120, lift_mm=20, curve=ms), Segment(type="dwell", angle_deg=60),
        Segment(type="return", angle_deg=120, lift_mm=20, curve=ms), Segment(type="dwell", angle_deg=60)])
    pressure, curvature = limits
    result = size_base_circle(cam, pressure, curvature)
    solved = sum(limit is not None for limit in limits)
    # a translating roller's pressure limit is a closed form (no root solve, no call) unless the geometry's
    # floor decides; each root solve takes at most 50 calls
    assert len(calls) <= 50 * solved
    rb = result.base_radius_mm
    checks = profile_checks(replace(cam, base_radius_mm=rb))
    if pressure is not None:
        assert checks.max_pressure_angle_deg <= pressure + 1e-9
    if curvature is not None:
        assert checks.min_radius_of_curvature_mm >= curvature - 1e-6 * max(1.0, curvature)
    smaller = rb - 1e-9 * max(1.0, rb) * 10
    if smaller > 0 and result.active_constraint != "geometry":
        c = profile_checks(replace(cam, base_radius_mm=smaller))
        fails = (pressure is not None and c.max_pressure_angle_deg > pressure) or (
            curvature is not None and c.min_radius_of_curvature_mm < curvature)
        assert fails, (rb, result)
