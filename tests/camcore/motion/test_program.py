"""Motion programs (camcore.motion): matching, joins, evaluation, characteristic values, errors.

Each expected value is computed here independently of camcore.motion: polynomials from their
own 6×6 systems, jumps of named laws from their closed forms, cam lifts from the existing
rise/dwell/return schedule of camcore.profile.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camcore.errors import CamError, InvalidParameterError
from camcore.motion import SOLVE, Law, MotionSegment, MotionSpec, resolve_motion
from camcore.profile import CamSpec, Follower, MotionLift, Segment, compute_profile, make_cam
from camcore.profile.lift import LiftSchedule

POLY = Law("polynomial", {})
CV = Law("named", {"name": "constant-velocity"})
SH = Law("named", {"name": "simple-harmonic"})


def move(span: float, law: Law | None = None, **kw: object) -> MotionSegment:
    return MotionSegment(span, law=law, **kw)  # type: ignore[arg-type]


def dwell(span: float) -> MotionSegment:
    return MotionSegment(span, type="dwell")


# ----------------------------------------------------------------------------- matched quintics
REST_CV_REST = MotionSpec([dwell(30), move(60, POLY, to=10), move(120, CV, to=50), move(60, POLY, to=60), dwell(30),
                           move(60, to=0)])


def quintic(conditions: list[float]) -> np.ndarray:
    """Coefficients of p(T) = Σ c_k T^k from p, p', p'' at T = 0 and T = 1 (own 6×6 system)."""
    rows = [[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0],
            [1, 1, 1, 1, 1, 1], [0, 1, 2, 3, 4, 5], [0, 0, 2, 6, 12, 20]]
    return np.linalg.solve(np.array(rows, dtype=float), np.array(conditions, dtype=float))


def test_rest_constant_velocity_rest_with_matched_quintics() -> None:
    program = resolve_motion(REST_CV_REST)
    v_feed = 40 / 120  # mm/deg in the constant-velocity segment
    # C2 at every join of the matched quintics; the jerk jumps (a quintic is not C3 to a dwell)
    assert [j.continuity for j in program.joins[:4]] == ["C2", "C2", "C2", "C2"]
    # exact constant velocity in the middle: v to the last bit, a and j zero
    x = np.linspace(90, 210, 241)[:-1]
    _, v, a, j = program.derivatives(x)
    assert np.all(np.abs(v - v_feed) <= 2 * np.spacing(v_feed)) and np.all(a == 0) and np.all(j == 0)
    # the first quintic against its own system, in the local time T = (x − 30)/60:
    # p(0) = 0, p'(0) = p''(0) = 0, p(1) = 10, p'(1) = 60·v_feed, p''(1) = 0
    c = quintic([0, 0, 0, 10, 60 * v_feed, 0])
    t = np.linspace(0, 1, 25)
    s, v, a, _ = program.derivatives(30 + 60 * t)
    p = np.polynomial.Polynomial(c)
    # float64 solves of a 6×6 system and a power sum of degree 5: rounding ~1e-14 of 10 mm
    assert np.max(np.abs(s - p(t))) < 1e-12
    assert np.max(np.abs(v - p.deriv()(t) / 60)) < 1e-13
    assert np.max(np.abs(a - p.deriv(2)(t) / 60**2)) < 1e-14
    assert program.segments[1].solved == pytest.approx({"degree": 5, "v_start": 0, "a_start": 0, "v_end": v_feed,
                                                        "a_end": 0})


def test_septic_matches_the_jerk_too() -> None:
    spec = MotionSpec([dwell(30), move(60, POLY, to=10, match="jerk"), move(120, SH, to=50), move(150, to=0)])
    program = resolve_motion(spec)
    assert program.joins[0].continuity == "C3"  # dwell → septic: s, v, a, j all continuous
    assert program.joins[1].continuity == "C3"  # septic → simple harmonic (whose jerk at its start is 0, a is not)
    assert program.segments[1].solved["degree"] == 7


# ----------------------------------------------------------------------------- named laws: jumps
def test_named_laws_leave_an_acceleration_jump_reported_as_c1() -> None:
    h, beta = 10.0, 90.0
    program = resolve_motion(MotionSpec([move(beta, SH, to=h), dwell(90), move(beta, SH, to=0), dwell(90)]))
    # simple harmonic S = (1 − cos πT)/2: A = π²/2 at T = 0 and −π²/2 at T = 1, V = 0 at both;
    # in real units a = h/β²·A, so each join jumps by ±h·π²/(2β²) in acceleration
    jump = h * math.pi**2 / (2 * beta**2)
    expected = [+jump, -jump, -jump, +jump]  # 90° (rise ends), 180° (fall starts), 270°, 360° (rise starts)
    assert [j.at_deg for j in program.joins] == [90, 180, 270, 360]
    for join, da in zip(program.joins, expected):
        assert join.continuity == "C1"
        assert join.da == pytest.approx(da, rel=1e-14)
        assert abs(join.ds) < 1e-14 and abs(join.dv) < 1e-15


def test_a_velocity_jump_is_c0_and_a_position_jump_none() -> None:
    # an indexer's output: 90° over 120° of input, then a dwell; the output never comes back
    cv = resolve_motion(MotionSpec([move(120, CV, stroke=90), dwell(240)], unit="deg"))
    assert [j.continuity for j in cv.joins] == ["C0", "none"]
    assert cv.joins[0].dv == pytest.approx(-90 / 120) and cv.joins[1].ds == pytest.approx(-90)


# ----------------------------------------------------------------------------- evaluation
def test_wrap_around_advances_by_the_net_stroke_and_time_columns_scale_by_omega() -> None:
    program = resolve_motion(MotionSpec([move(120, Law("named", {"name": "MS"}), stroke=90), dwell(240)], unit="deg"))
    x = np.array([30.0, 100.0])
    s, v, a, j = program.derivatives(x)
    s2, v2, a2, j2 = program.derivatives(x + 720)
    assert np.allclose(s2, s + 180, rtol=0, atol=1e-12) and np.array_equal(v2, v) and np.array_equal(a2, a)
    assert np.array_equal(j2, j)
    assert program.derivatives([360.0], 0)[0][0] == 90.0  # x = period belongs to the last segment
    assert program.derivatives([-360.0], 0)[0][0] == -90.0
    table = program.table(x, speed_rpm=10.0)
    omega = 60.0  # deg/s at 10 rpm
    assert np.allclose(table.time_s, x / omega) and np.allclose(table.v_per_s, v * omega)
    assert np.allclose(table.a_per_s2, a * omega**2) and np.allclose(table.j_per_s3, j * omega**3)
    assert set(program.table(x).columns()) == {"x_deg", "s", "v", "a", "j"}


def test_characteristics_are_exact_and_mapped_to_real_units() -> None:
    h, beta = 12.0, 80.0
    program = resolve_motion(MotionSpec([dwell(100), move(beta, to=h), dwell(100), move(beta, to=0)]))
    ch = program.characteristics
    # cycloid: V peaks at 2 in the middle, A at ±2π at T = 1/4, 3/4, J at 4π² at the ends
    assert ch.v_peak == pytest.approx(2 * h / beta, rel=1e-14) and ch.v_peak_at_deg == pytest.approx(100 + beta / 2)
    assert ch.v_min == pytest.approx(-2 * h / beta, rel=1e-14) and ch.v_min_at_deg == pytest.approx(280 + beta / 2)
    assert ch.a_max == pytest.approx(2 * math.pi * h / beta**2, rel=1e-14)
    assert ch.a_max_at_deg == pytest.approx(100 + beta / 4, abs=1e-9)
    assert ch.j_max == pytest.approx(4 * math.pi**2 * h / beta**3, rel=1e-13)
    assert (ch.s_max, ch.s_min) == (pytest.approx(h), 0.0)
    # no sample exceeds the exact extremes
    s, v, a, j = program.derivatives(np.linspace(0, 360, 7201))
    assert v.max() <= ch.v_max * (1 + 1e-15) and a.min() >= ch.a_min * (1 + 1e-15)
    assert j.max() <= ch.j_max * (1 + 1e-15) and s.max() <= ch.s_max


# ----------------------------------------------------------------------------- universal, half-matched
def test_universal_with_omitted_v0_takes_the_previous_velocity() -> None:
    t = [0, 0.1, 0.1, 0.3, 0.5, 0.75, 0.75, 1]  # a quarter-sine bump, a stretch at constant V, a stop
    spec = MotionSpec([dwell(60), move(60, CV, to=20), move(120, Law("universal", {"t": t, "v7": 0}), to=40),
                       move(120, to=0)])
    program = resolve_motion(spec)
    v_feed = 20 / 60
    # V0 in the law's own units: v·β/h·(S7 − S0)/(T7 − T0) = (1/3)·120/20 = 2
    assert program.segments[2].solved == pytest.approx({"v0": v_feed * 120 / 20}, rel=1e-15)
    # the universal curve starts with a quarter sine from A = 0: C2 where it meets the feed
    assert abs(program.joins[1].dv) < 1e-15 and program.joins[1].continuity == "C2"
    # played backwards, the segment starts with the law's end: the matched velocity is its v7
    back = MotionSpec([dwell(60), move(60, CV, to=20), move(120, Law("universal", {"t": t, "v0": 0}, "return"), to=40),
                       move(120, to=0)])
    program = resolve_motion(back)
    assert program.segments[2].solved == pytest.approx({"v7": v_feed * 120 / 20}, rel=1e-15)
    assert abs(program.joins[1].dv) < 1e-15 and program.joins[1].continuity in ("C1", "C2")


def test_half_matched_polynomial_keeps_its_given_start() -> None:
    law = Law("polynomial", {"start": {"s": 0, "v": 0, "a": 0}})
    program = resolve_motion(MotionSpec([dwell(60), move(60, law, to=10), move(120, CV, to=50), move(120, to=0)]))
    assert program.joins[1].continuity == "C2" and program.segments[1].solved["degree"] == 5


@st.composite
def matched_programs(draw: st.DrawFn) -> MotionSpec:
    """Dwells and matched polynomials (quintic or septic) at random spans and positions,
    ending where they start; a named law may anchor one segment."""
    n = draw(st.integers(2, 8))
    weights = draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n))
    spans = [360.0 * w / sum(weights) for w in weights]
    spans[-1] = 360.0 - sum(spans[:-1])
    kinds = draw(st.lists(st.sampled_from(["poly", "poly", "septic", "dwell", "cycloid"]), min_size=n, max_size=n))
    if "poly" not in kinds and "septic" not in kinds:
        kinds[0] = "poly"
    last_move = max(i for i, kind in enumerate(kinds) if kind != "dwell")
    segments = []
    for i, (span, kind) in enumerate(zip(spans, kinds)):
        to = 0.0 if i == last_move else draw(st.floats(-50, 50).map(lambda v: round(v, 3)))
        if kind == "dwell":
            segments.append(dwell(span))
        elif kind == "cycloid":
            segments.append(move(span, to=to))
        else:
            segments.append(move(span, POLY, to=to, match="jerk" if kind == "septic" else "acceleration"))
    return MotionSpec(segments)


@pytest.mark.property
@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(spec=matched_programs())
def test_random_programs_of_matched_polynomials_are_c2_and_close(spec: MotionSpec) -> None:
    # a dwell or the cycloid starts and ends at rest (v = a = 0); every matched polynomial meets
    # its neighbours' s, v, a, so every join is at least C2 (the wrap-around included), unless
    # the program is refused with a sentence (a cycloid asked to move by 0)
    try:
        program = resolve_motion(spec)
    except CamError as err:
        assert str(err).startswith("segments[") and "a stroke of 0 with the law 'cycloid'" in str(err), str(err)
        return
    assert all(join.continuity in ("C2", "C3") for join in program.joins), program.joins
    # s(360) = 0 up to the rounding of the polynomials' solve and evaluation, which scales with the
    # largest derivative a segment meets in its own units (M = max |d^k s/dx^k|·span^k at its ends;
    # a 5° cycloid's jerk makes it ~1e6 mm) times the polynomial's monomial coefficients per unit
    # of those (35 + 84 + 70 + 20 = 209 for the septic 1 -> 0): the largest residual seen is 192 eps
    # of M (a 1 mm septic, 4.3e-14 mm), so 1024 eps of M (1e-9 mm absolute failed at 3.4e-9 mm)
    starts = np.concatenate([[0.0], np.cumsum([segment.span_deg for segment in spec.segments])])
    scale = 1.0
    for a, b in itertools.pairwise(starts.tolist()):
        for x in (a + 1e-12 * (b - a), b - 1e-12 * (b - a)):
            values = program.derivatives(np.array([x]), 3)
            scale = max(scale, *(abs(float(values[k][0])) * (b - a) ** k for k in range(4)))
    end = program.derivatives(np.array([360.0]), 0)[0][0]
    assert program.advance == 0.0 and end == pytest.approx(0.0, abs=1024 * np.finfo(float).eps * scale)


# ----------------------------------------------------------------------------- a program as a cam's lift
def test_a_closed_program_is_a_cam_lift_like_the_segment_schedule() -> None:
    program = resolve_motion(MotionSpec([move(120, to=20), dwell(60), move(120, to=0), dwell(60)]))
    schedule = LiftSchedule([Segment("rise", 120, 20), Segment("dwell", 60), Segment("return", 120, 20),
                             Segment("dwell", 60)])
    lift = MotionLift(program)
    # off the break points, where a rounding of the angle decides which side answers
    theta = np.radians(np.arange(0.25, 360, 0.5))
    for ours, theirs in zip(lift.derivatives(theta, 3), schedule.derivatives(theta, 3)):
        assert np.allclose(ours, theirs, rtol=1e-12, atol=1e-12)
    assert np.allclose(np.sort(lift.breaks_rad), np.sort(schedule.breaks_rad))
    follower = Follower(type="roller", roller_radius_mm=10)
    ours_p = compute_profile(CamSpec(follower, 40, lift), np.arange(0, 360, 5.0))
    theirs_p = compute_profile(CamSpec(follower, 40, schedule), np.arange(0, 360, 5.0))
    assert np.allclose(ours_p.x_mm, theirs_p.x_mm, atol=1e-10)
    assert np.allclose(ours_p.pressure_angle_deg, theirs_p.pressure_angle_deg, atol=1e-10)
    with pytest.raises(InvalidParameterError, match="does not close"):
        MotionLift(resolve_motion(MotionSpec([move(180, to=20), move(180, to=10)])))


def test_a_program_of_half_a_turn_makes_a_two_lobe_cam() -> None:
    # master angle = drive angle: a 180° program repeats twice per cam turn (γ = 1), and with
    # γ = 0.5 (the cam turns once per two drive turns) a 720° program is one cam turn; the
    # chain rule dᵏh/dθᵏ = (180/(π·γ))ᵏ·dᵏs/dxᵏ is checked against the 360° schedule
    half = resolve_motion(MotionSpec([move(60, to=20), dwell(30), move(60, to=0), dwell(30)], period_deg=180))
    lift = MotionLift(half)
    theta = np.radians(np.arange(0.25, 180, 0.5))
    for first, second in zip(lift.derivatives(theta, 2), lift.derivatives(theta + np.pi, 2)):
        # θ + π rounds: the angles differ by ~1e-16 rad, the lift by that times its slope
        assert np.allclose(first, second, rtol=1e-12, atol=1e-12)
    assert len(lift.breaks_rad) == 2 * len(half.breaks_deg)
    slow = resolve_motion(MotionSpec([move(240, to=20), dwell(120), move(240, to=0), dwell(120)], period_deg=720))
    schedule = LiftSchedule([Segment("rise", 120, 20), Segment("dwell", 60), Segment("return", 120, 20),
                             Segment("dwell", 60)])
    for ours, theirs in zip(MotionLift(slow, rotation_ratio=0.5).derivatives(theta * 2, 3),
                            schedule.derivatives(theta * 2, 3)):
        assert np.allclose(ours, theirs, rtol=1e-12, atol=1e-12)
    with pytest.raises(InvalidParameterError, match="whole number") as raised:
        MotionLift(resolve_motion(MotionSpec([move(150, to=20), move(150, to=0)], period_deg=300)))
    # with no γ given (a barrel cam, a machine's camshaft) the period is the field at fault; with γ, γ
    assert raised.value.field == ("period_deg",)
    tiny = resolve_motion(MotionSpec([move(0.15, to=20), move(0.15, to=0)], period_deg=0.3))
    with pytest.raises(InvalidParameterError, match="more than 1000 periods") as raised:
        MotionLift(tiny)
    assert raised.value.field == ("period_deg",)
    with pytest.raises(InvalidParameterError, match="raise rotation_ratio") as raised:
        MotionLift(tiny, rotation_ratio=1.0)
    assert raised.value.field == ("rotation_ratio",)
    assert len(MotionLift(tiny, rotation_ratio=2.4).breaks_rad) == 500 * len(tiny.breaks_deg)  # 150° a turn


def test_make_cam_takes_a_program_in_the_follower_unit() -> None:
    program = resolve_motion(MotionSpec([move(120, to=20), dwell(60), move(120, to=0), dwell(60)]))
    cam = make_cam(Follower("roller", roller_radius_mm=10), 40, motion=program)
    assert isinstance(cam.lift, MotionLift)
    swing = Follower("roller", "oscillating", roller_radius_mm=5, arm_length_mm=50, pivot_distance_mm=70)
    with pytest.raises(InvalidParameterError, match="follower is in 'deg'") as err:
        make_cam(swing, 30, motion=program)
    assert err.value.field == ("motion", "unit")
    with pytest.raises(InvalidParameterError, match="one of them"):
        make_cam(Follower("roller", roller_radius_mm=10), 40, motion=program,
                 segments=[Segment("rise", 180, 20), Segment("return", 180, 20)])


# ----------------------------------------------------------------------------- errors
def error_of(spec: MotionSpec) -> CamError:
    with pytest.raises(CamError) as err:
        resolve_motion(spec)
    return err.value


@pytest.mark.parametrize(("spec", "field", "words"), [
    (MotionSpec([move(100, to=1), dwell(200)]), ("segments",), "add up to 300"),
    (MotionSpec([move(180, to=1, stroke=1), dwell(180)]), ("segments", 0), "not both"),
    (MotionSpec([move(180), dwell(180)]), ("segments", 0), "needs to"),
    (MotionSpec([dwell(90), move(90, to=0), dwell(180)]), ("segments", 1, "to"), "a stroke of 0 with the law 'cycloid'"),
    (MotionSpec([move(180, Law("polynomial", {"start": {"s": 0.2}}), to=5), move(180, to=0)]), ("segments", 0, "curve"),
     "contradict"),
    (MotionSpec([move(180, Law("polynomial", {"start": {"s": 0}, "end": {"s": 0, "v": 1}}), to=5), move(180, to=0)]),
     ("segments", 0, "curve"), "contradict"),
    (MotionSpec([dwell(90), move(90, SH, to=SOLVE), move(180, to=0)]), ("segments", 1, "to"), "starts at rest"),
    (MotionSpec([dwell(90), move(90, CV, to=SOLVE), move(180, to=0)]), ("segments", 1, "to"), "ends at rest"),
    (MotionSpec([move(90, CV, to=SOLVE), move(90, CV, stroke=5), move(180, to=0)]), ("segments", 0), "cannot be resolved"),
    (MotionSpec([move(90, CV, to=5), move(90, POLY, to=SOLVE), move(180, to=0)]), ("segments", 1, "to"),
     "given in full"),
    (MotionSpec([move(120, Law("makino", {"number": 2}), to=5), move(120, POLY, to=10), move(120, to=0)]),
     ("segments", 1), "each take their conditions from the other"),
    (MotionSpec([move(120, CV, to=5), move(120, SH, to=10, match="jerk"), move(120, to=0)]), ("segments", 1, "match"),
     "match applies"),
    (MotionSpec([move(180, Law("named", {"name": "no-such-curve"}), to=5), move(180, to=0)]),
     ("segments", 0, "curve", "name"), "No curve named"),
])
def test_unsolvable_programs_name_the_segment_and_say_why(spec: MotionSpec, field: tuple[object, ...],
                                                          words: str) -> None:
    err = error_of(spec)
    assert err.field == field, err
    assert words in str(err)
    if field[:1] == ("segments",) and len(field) > 1:
        assert str(err).startswith(f"segments[{field[1]}]")
