"""Plate-cam design (camcore.profile.design): the answer against independent routes.

- (a) a brute-force grid over the free variables, every grid point judged by the existing checks
  (:func:`profile_checks`, :func:`follower_dynamics`), never finds a feasible cam smaller than the answer
  by more than the search's tolerance, and the answer itself passes those checks;
- (b) every limit that decides a variable is at its limit: a base radius 1e-7 smaller breaks it;
- (c) with only the base radius free the answer is sizeBaseCircle's number, to the last digit;
- (d) a problem no design meets names the limit and the best value the bounds reach;
- (e) the softest spring holds the margin at every speed of the range, a slightly softer one with the
  largest preload does not.

The dense versions of (a) are marked ``property`` (tests/camcore/profile/test_design_dense.py).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from camcore.errors import InvalidParameterError
from camcore.profile import CamSpec, Follower, Segment, make_cam, profile_checks, size_base_circle
from camcore.profile.design import DesignLimits, DesignProblem, FollowerLoad, ProfileDesign, design_profile
from camcore.profile.dynamics import RollerMaterials, follower_dynamics
from camcore.profile.dynamics.load import TranslatingLoad

#: a steep rise (30 mm in 80°) so the curvature limit binds at the nose, not at the base circle
STEEP = [Segment("rise", 80, 30.0), Segment("dwell", 100), Segment("return", 100, 30.0), Segment("dwell", 80)]
OSCILLATING = [Segment("rise", 100, 0.0, swing_deg=20.0), Segment("dwell", 40),
               Segment("return", 120, 0.0, swing_deg=20.0), Segment("dwell", 100)]
ROLLER = Follower("roller", roller_radius_mm=10.0)
ARM = Follower("roller", "oscillating", roller_radius_mm=6.0, arm_length_mm=45.0, pivot_distance_mm=60.0)


def cam(follower: Follower = ROLLER, segments: list[Segment] = STEEP, rb: float = 40.0) -> CamSpec:
    return make_cam(follower, rb, segments=segments)


def at(result: ProfileDesign, name: str) -> tuple[float, float, float, bool]:
    row = next(c for c in result.constraints if c.name == name)
    return row.value, row.limit, row.margin, row.active


def meets(spec: CamSpec, limits: DesignLimits) -> bool:
    """The geometric limits by profile_checks, the independent judge (rounding of the limit itself allowed:
    1e-12 of it, far below any step of a grid)."""
    try:
        checks = profile_checks(spec)
    except InvalidParameterError:
        return False
    if checks.undercut:
        return False
    ok = True
    if limits.max_pressure_angle_deg is not None:
        ok &= checks.max_pressure_angle_deg <= limits.max_pressure_angle_deg * (1 + 1e-12)
    req = max(limits.min_radius_of_curvature_mm or 0.0,
              (limits.min_radius_of_curvature_roller_multiple or 0.0) * spec.follower.roller_radius_mm)
    return bool(ok and checks.min_radius_of_curvature_mm >= req * (1 - 1e-12))


def smallest_on_grid(spec: CamSpec, limits: DesignLimits, radii: np.ndarray) -> float:
    """The smallest radius of a sorted grid whose cam meets the limits (bisection over the grid: the geometric
    limits of a translating follower are met above a radius and not below it); inf where none does."""
    if not meets(replace(spec, base_radius_mm=float(radii[-1])), limits):
        return math.inf
    lo, hi = -1, radii.size - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if meets(replace(spec, base_radius_mm=float(radii[mid])), limits):
            hi = mid
        else:
            lo = mid
    return float(radii[hi])


# ----------------------------------------------------------------------------- (a) against a grid
@pytest.mark.parametrize("limits", [
    DesignLimits(max_pressure_angle_deg=30, min_radius_of_curvature_mm=20),  # they trade: a ridge in (e, Rr)
    DesignLimits(max_pressure_angle_deg=25, min_radius_of_curvature_roller_multiple=1.5),
], ids=["pressure-curvature", "roller-multiple"])
def test_no_grid_point_is_a_smaller_feasible_cam(limits: DesignLimits) -> None:
    free = {"base_radius_mm": (10.0, 200.0), "offset_mm": (-30.0, 30.0), "roller_radius_mm": (5.0, 20.0)}
    result = design_profile(DesignProblem(cam(), free, limits))
    rb = result.design.base_radius_mm
    assert meets(result.cam, limits)  # the answer is feasible by the checks themselves
    # the grid: offsets and rollers around the answer (the search's neighbourhood, 0.5 mm and 0.25 mm steps)
    # and over the whole box (7.5 mm steps); radii every 0.01 mm below the answer + 0.2 mm
    e0, r0 = result.design.offset_mm, result.design.roller_radius_mm
    assert e0 is not None and r0 is not None
    points = [(e, r) for e in np.linspace(-30, 30, 9) for r in np.linspace(5, 20, 4)]
    points += [(e, r) for e in e0 + np.linspace(-1, 1, 5) for r in np.clip(r0 + np.linspace(-0.5, 0.5, 5), 5, 20)]
    radii = np.arange(10.0, rb + 0.2, 0.01)
    best = min(smallest_on_grid(replace(result.cam, follower=replace(ROLLER, offset_mm=float(e), roller_radius_mm=float(r))),
                                limits, radii) for e, r in points)
    # no grid point beats the answer: the search locates its optimum to 1e-5 of each range, and the grid's
    # own radii are 0.01 mm apart, so a grid cam smaller by more than 1e-3 mm would be a miss
    assert best >= rb - 1e-3, (best, rb)
    # and the grid's best is no better than the answer by its step: it is the answer, rounded up to the grid
    assert best <= rb + 0.01 + 0.05, (best, rb)  # 0.05: the grid's (e, Rr) steps cost at most that near the answer


def test_a_knife_edge_offset_against_a_grid() -> None:
    knife = Follower("knife-edge")
    limits = DesignLimits(max_pressure_angle_deg=30, max_return_pressure_angle_deg=40)
    result = design_profile(DesignProblem(cam(knife), {"base_radius_mm": (5.0, 200.0), "offset_mm": (-20.0, 20.0)},
                                          limits))
    rb, e0 = result.design.base_radius_mm, result.design.offset_mm
    assert e0 is not None
    checks = profile_checks(result.cam)  # the rise and return limits, by the signed extremes of the checks
    assert checks.max_pressure_angle_deg <= 40 * (1 + 1e-12)
    for e in np.concatenate([np.linspace(-20, 20, 9), e0 + np.linspace(-0.2, 0.2, 3)]):
        spec = replace(result.cam, follower=replace(knife, offset_mm=float(e)))
        # each offset's own smallest radius, solved by size_base_circle's route for each sign of φ: the grid
        # point is never a smaller cam than the answer (1e-4 mm: the offset located to 4e-4 mm, the radius's
        # slope in the offset about 0.2 there)
        need = _split_pressure_radius(spec, 30, 40)
        assert need >= rb - 1e-4, (e, need, rb)


def _arm_smallest_radius(spec: CamSpec, limit_deg: float, top_mm: float) -> float:
    """An arm's smallest base radius with every pressure angle ≤ limit_deg, by profile_checks alone (the
    independent judge): the largest pressure angle is unimodal in the base radius (it falls as the cam
    grows, then rises as the arm nears folding), so its least value is found by bounded Brent, and the
    smallest radius meeting the limit by bisection below it; inf where even the least exceeds the limit."""
    from scipy.optimize import minimize_scalar

    def largest(rb: float) -> float:
        try:
            return profile_checks(replace(spec, base_radius_mm=rb)).max_pressure_angle_deg
        except InvalidParameterError:  # the arm cannot be assembled or swung at this radius
            return math.inf

    floor = abs(spec.follower.pivot_distance_mm - spec.follower.arm_length_mm) - spec.follower.roller_radius_mm
    lo = max(floor, 0.0) + 1e-6
    least = minimize_scalar(largest, bounds=(lo, top_mm), method="bounded", options={"xatol": 1e-6})
    if least.fun > limit_deg:
        return math.inf
    hi = float(least.x)
    while hi - lo > 1e-6:  # the largest pressure angle falls from lo to the least's radius
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if largest(mid) <= limit_deg else (mid, hi)
    return hi


def test_a_free_pivot_against_a_grid_of_pivots() -> None:
    # the arm's pivot distance d searched with the base radius: each pivot of a grid over the whole box and
    # beside the answer, sized by profile_checks alone, is never a smaller feasible cam. The smallest cam
    # lies where the pressure angle's least value over the base radius just reaches the limit (a smaller
    # d: none meets it), so the grid beside the answer straddles that edge
    limits = DesignLimits(max_pressure_angle_deg=30)
    free = {"base_radius_mm": (5.0, 80.0), "pivot_distance_mm": (30.0, 120.0)}
    result = design_profile(DesignProblem(cam(ARM, OSCILLATING, rb=20.0), free, limits))
    rb, d0 = result.design.base_radius_mm, result.design.pivot_distance_mm
    assert d0 is not None and result.cam.follower.pivot_distance_mm == d0
    assert profile_checks(result.cam).max_pressure_angle_deg <= 30 * (1 + 1e-9)  # feasible by the checks
    assert at(result, "max_pressure_angle_deg")[3]  # the pressure angle is active
    def need(d: float) -> float:
        return _arm_smallest_radius(replace(result.cam, follower=replace(ARM, pivot_distance_mm=d)), 30.0, 80.0)

    # 1e-5 mm: the judge's bisection stops within 1e-6 mm, the answer's radius is solved to 1e-10
    for d in np.linspace(30.0, 120.0, 7):
        assert need(float(d)) >= rb - 1e-5, (float(d), need(float(d)), rb)
    # the edge: 2e-3 mm below the answer's pivot no radius meets the limit (the pivot is located to 1e-5 of
    # its 90 mm range, 9e-4 mm); at it, the judge's radius is the answer's; beyond it, the radius grows by
    # about 1.07 mm per mm of d (measured: +0.0107 mm at d0 + 0.01), so no smaller cam lies on that side
    assert need(d0 - 2e-3) == math.inf
    assert need(d0) == pytest.approx(rb, abs=1e-5)
    assert rb < need(d0 + 0.01) <= rb + 1.2 * 0.01
    assert rb < need(d0 + 0.5) <= rb + 1.2 * 0.5


def _split_pressure_radius(spec: CamSpec, rise: float, ret: float) -> float:
    """The smallest radius with the largest φ ≤ rise and the largest −φ ≤ return, by bisection on
    profile_checks' signed pressure angle at its maximum and a dense scan of φ (independent of the design's
    signed maxima)."""
    def ok(rb: float) -> bool:
        s = replace(spec, base_radius_mm=rb)
        from camcore.profile import kinematics
        phi = np.degrees(kinematics(s, np.linspace(0, 2 * np.pi, 20001)).pressure)
        return bool(phi.max() <= rise and (-phi).max() <= ret)
    lo, hi = abs(spec.follower.offset_mm) + 1e-9, 200.0
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    return hi


# ----------------------------------------------------------------------------- (b) active limits
@pytest.mark.parametrize("limits", [
    DesignLimits(max_pressure_angle_deg=30, min_radius_of_curvature_mm=20),
    DesignLimits(max_pressure_angle_deg=30, min_radius_of_curvature_mm=5),
], ids=["kink", "pressure"])
def test_the_limit_that_sets_the_base_radius_is_at_it(limits: DesignLimits) -> None:
    free = {"base_radius_mm": (10.0, 200.0), "offset_mm": (-30.0, 30.0), "roller_radius_mm": (5.0, 20.0)}
    result = design_profile(DesignProblem(cam(), free, limits))
    deciding = [c for c in result.constraints if "base_radius_mm" in c.sets and not c.name.startswith("free.")]
    assert deciding, result.constraints
    for c in result.constraints:
        if c.active and not c.name.startswith("free."):
            # active: within 1e-4 of its limit (a limit the search balanced against the deciding one)
            assert abs(c.margin) <= 1e-4 * max(abs(c.limit), 1.0), c
    for c in deciding:
        # the radius is solved to 1e-10: its margin is rounding of the checks, and 1e-7 less radius breaks it
        assert abs(c.margin) <= 1e-8 * max(abs(c.limit), 1.0), c
    smaller = replace(result.cam, base_radius_mm=result.design.base_radius_mm * (1 - 1e-7))
    assert not meets(smaller, limits)


# ----------------------------------------------------------------------------- (c) sizeBaseCircle
@pytest.mark.parametrize(("follower", "pressure", "curvature"), [
    (ROLLER, 30.0, 15.0), (ROLLER, 25.0, None), (Follower("knife-edge", offset_mm=5.0), 30.0, None),
    (Follower("flat-faced"), None, 5.0)], ids=["roller", "roller-pressure", "knife-edge", "flat-faced"])
def test_one_variable_is_size_base_circle_to_the_last_digit(follower: Follower, pressure: float | None,
                                                             curvature: float | None) -> None:
    spec = cam(follower, rb=10.0)
    result = design_profile(DesignProblem(spec, {"base_radius_mm": (10.0, 300.0)},
                                          DesignLimits(max_pressure_angle_deg=pressure,
                                                       min_radius_of_curvature_mm=curvature)))
    # a roller without a curvature limit must still not undercut: size_base_circle with 0 (it adds nothing here)
    req = curvature if curvature is not None or follower.type == "knife-edge" else 0.0
    expected = size_base_circle(spec, pressure, req).base_radius_mm
    assert expected > 10.0  # a case where the limits, not the bound, decide
    assert result.design.base_radius_mm == expected  # the same solver on the same margins, from the same start


def test_an_oscillating_one_variable_agrees_with_size_base_circle() -> None:
    # an arm's radius is bracketed by its assembly range, not doubled from a start as size_base_circle
    # does, so the Illinois steps differ: both stop within 1e-10 of the root (relative), hence 3e-10
    spec = cam(ARM, OSCILLATING, rb=25.0)
    result = design_profile(DesignProblem(spec, {"base_radius_mm": (5.0, 50.0)},
                                          DesignLimits(max_pressure_angle_deg=45, min_radius_of_curvature_mm=2)))
    expected = size_base_circle(replace(spec, base_radius_mm=5.0), 45, 2).base_radius_mm
    assert result.design.base_radius_mm == pytest.approx(expected, rel=3e-10)


# ----------------------------------------------------------------------------- (d) no design
def test_an_unreachable_pressure_angle_names_it_and_the_best_value() -> None:
    free = {"base_radius_mm": (10.0, 30.0), "offset_mm": (-30.0, 30.0)}
    with pytest.raises(InvalidParameterError) as err:
        design_profile(DesignProblem(cam(), free, DesignLimits(max_pressure_angle_deg=30)))
    assert err.value.field == ("limits", "max_pressure_angle_deg")
    message = str(err.value)
    assert "the smallest reachable within the bounds is" in message
    best = float(message.split("bounds is ")[1].split("°")[0])
    # the best the bounds reach: at the largest radius, over the offset, by the checks on a scan (every
    # 0.5 mm, then every 2.5 µm around its best: the worst angle's slope in the offset is about 0.5°/mm, so
    # the scan is within 1e-3° of its least); the message rounds to 4 digits (5e-3° here)
    def worst(e: float) -> float:
        return profile_checks(replace(cam(), base_radius_mm=30.0, follower=replace(ROLLER, offset_mm=e))
                              ).max_pressure_angle_deg
    coarse = np.linspace(-30, 30, 121)
    e_best = coarse[int(np.argmin([worst(float(e)) for e in coarse]))]
    scan = min(worst(float(e)) for e in e_best + np.linspace(-0.5, 0.5, 401))
    assert best == pytest.approx(scan, abs=5e-3)
    assert best > 30


def test_an_unreachable_margin_names_the_stiffest_spring() -> None:
    load = FollowerLoad(0.5, (3000.0, 3000.0))
    free = {"base_radius_mm": (10.0, 200.0), "spring_rate_n_mm": (0.5, 2.0), "preload_n": (0.0, 20.0)}
    with pytest.raises(InvalidParameterError) as err:
        design_profile(DesignProblem(cam(), free, DesignLimits(max_pressure_angle_deg=30, safety_margin_n=5), load))
    assert err.value.field == ("limits", "safety_margin_n")
    value = float(str(err.value).split("within the bounds is ")[1].split(" N")[0])
    stiffest = follower_dynamics(cam(), TranslatingLoad(0.5, 2.0, 20.0), 3000.0, safety_margin_n=5)
    assert value == pytest.approx(stiffest.summary.min_contact_force_n, rel=1e-3)  # 4 digits in the message


@pytest.mark.parametrize(("free", "where"), [
    ({"base_radius_mm": (20.0, 10.0)}, ("free", "base_radius_mm")),
    ({"base_radius_mm": (10.0, 20.0), "roller_radius_mm": (5.0, 6.0)}, ("free", "roller_radius_mm")),
    ({"base_radius_mm": (10.0, 20.0), "pivot_distance_mm": (50.0, 60.0)}, ("free", "pivot_distance_mm")),
    ({"base_radius_mm": (10.0, 20.0), "arm_length_mm": (50.0, 60.0)}, ("free", "arm_length_mm")),
    ({"offset_mm": (-5.0, 5.0)}, ("free",)),
    ({"base_radius_mm": (10.0, 20.0), "spring_rate_n_mm": (1.0, 2.0)}, ("mass_kg",)),
], ids=["lo-above-hi", "knife-has-no-roller", "pivot-of-a-translating-follower", "arm-not-searched",
        "nothing-to-minimise", "spring-without-mass"])
def test_bad_problems_name_the_field(free: dict[str, tuple[float, float]], where: tuple[str, ...]) -> None:
    with pytest.raises(InvalidParameterError) as err:
        design_profile(DesignProblem(cam(Follower("knife-edge")), free, DesignLimits(max_pressure_angle_deg=30)))
    assert err.value.field == where, str(err.value)


# ----------------------------------------------------------------------------- (e) the spring
def test_the_softest_spring_holds_and_a_softer_one_does_not() -> None:
    load = FollowerLoad(0.5, (400.0, 900.0), damping=0.002)
    free = {"base_radius_mm": (10.0, 200.0), "spring_rate_n_mm": (0.5, 50.0), "preload_n": (0.0, 60.0)}
    result = design_profile(DesignProblem(cam(), free, DesignLimits(max_pressure_angle_deg=30, safety_margin_n=5),
                                          load))
    k, f0 = result.design.spring_rate_n_mm, result.design.preload_n
    assert k is not None and f0 is not None and 0.5 < k < 50 and f0 == pytest.approx(60.0, abs=1e-9)
    value, _limit, margin, active = at(result, "safety_margin_n")
    assert active and abs(margin) <= 1e-9 * 100  # the root to 1e-10 of k; forces of ~100 N
    # at every speed of the range the follower keeps the margin (follower_dynamics, the existing check), and
    # somewhere in it only just: the least over a dense set of speeds is the answer's value
    least = math.inf
    for rpm in np.linspace(400.0, 900.0, 26):
        run = follower_dynamics(result.cam, TranslatingLoad(0.5, k, f0, damping_n_s_mm=0.002), float(rpm),
                                safety_margin_n=5)
        assert run.summary.min_contact_force_n >= 5 - 1e-9 * 100, rpm  # rounding of forces of ~100 N
        least = min(least, run.summary.min_contact_force_n)
    assert least == pytest.approx(value, abs=1e-6)  # the top speed decides here (the range's ends are on the scan)
    # 1e-6 softer, even with the largest preload, the margin is lost at the top speed
    softer = follower_dynamics(result.cam, TranslatingLoad(0.5, k * (1 - 1e-6), 60.0, damping_n_s_mm=0.002), 900.0,
                               safety_margin_n=5)
    assert softer.summary.min_preload_n is not None and softer.summary.min_preload_n > 60.0


def test_the_stress_trades_against_the_spring() -> None:
    # a preload lower bound of 0 leaves room for a stiffer spring with less preload, which presses less at
    # low lift where the rise's acceleration peaks: the softest spring would break 220 MPa at the smallest cam
    roller = RollerMaterials(12.0)
    load = FollowerLoad(0.5, (600.0, 600.0), roller=roller)
    free = {"base_radius_mm": (10.0, 200.0), "offset_mm": (-30.0, 30.0), "roller_radius_mm": (5.0, 20.0),
            "spring_rate_n_mm": (0.5, 50.0), "preload_n": (0.0, 500.0)}
    limits = DesignLimits(max_pressure_angle_deg=30, min_radius_of_curvature_mm=15, safety_margin_n=5,
                          allowed_stress_mpa=220)
    result = design_profile(DesignProblem(cam(), free, limits, load))
    geometry_only = design_profile(DesignProblem(cam(), {k: v for k, v in free.items() if "spring" not in k
                                                          and "preload" not in k},
                                                 DesignLimits(max_pressure_angle_deg=30, min_radius_of_curvature_mm=15)))
    # the geometry's own optimum is kept: a lower bound, reached
    assert result.design.base_radius_mm == pytest.approx(geometry_only.design.base_radius_mm, rel=1e-9)
    k, f0 = result.design.spring_rate_n_mm, result.design.preload_n
    assert k is not None and f0 is not None and k > 0.5
    check = follower_dynamics(result.cam, TranslatingLoad(0.5, k, f0), 600.0, safety_margin_n=5, roller=roller)
    assert check.summary.max_contact_stress_mpa is not None
    assert check.summary.max_contact_stress_mpa <= 220 * (1 + 1e-9)  # the golden sections' rounding
    assert not check.summary.separates
    # the softest spring that fits: 1e-6 softer (its preload the smallest that holds) breaks 220 MPa
    softer = k * (1 - 1e-6)
    preload = follower_dynamics(result.cam, TranslatingLoad(0.5, softer, 0.0), 600.0, safety_margin_n=5
                                ).summary.min_preload_n
    assert preload is not None
    worse = follower_dynamics(result.cam, TranslatingLoad(0.5, softer, preload), 600.0, safety_margin_n=5, roller=roller)
    assert worse.summary.max_contact_stress_mpa is not None and worse.summary.max_contact_stress_mpa > 220


# ----------------------------------------------------------------------------- the search's evaluator
@pytest.mark.parametrize("follower", [Follower("roller", offset_mm=4.0, roller_radius_mm=12.0), ARM],
                         ids=["translating", "oscillating"])
def test_the_closed_forms_are_the_followers_own_kinematics(follower: Follower) -> None:
    # the search's closed forms (one array for many candidates) against each follower model's own
    # kinematics evaluated candidate by candidate: the same formulas, so equal to rounding (1e-12);
    # an arm's lanes each with a pivot distance of its own (a free pivot)
    from camcore.profile.design.evaluate import Lanes, SearchCam

    segments = OSCILLATING if follower.motion == "oscillating" else STEEP
    spec = cam(follower, segments, rb=25.0)
    limits = DesignLimits(max_pressure_angle_deg=40, min_radius_of_curvature_mm=2)
    fast = SearchCam(spec, limits, None, 5.0)
    slow = SearchCam(spec, limits, None, 5.0)
    slow.closed_form = slow.oscillating_point = False  # the model's own kinematics, one candidate at a time
    place = (follower.offset_mm + np.zeros(4) if follower.motion == "translating"
             else (follower.pivot_distance_mm or 0.0) + np.array([0.0, 4.0, -2.0, 8.0]))
    lanes = Lanes(place, np.array([5.0, 6.0, 8.0, 12.0]), np.full(4, np.nan), np.full(4, np.nan))
    rb = np.array([20.0, 25.0, 30.0, 40.0])
    a, valid_a = fast.extremes(lanes, rb)
    b, valid_b = slow.extremes(lanes, rb)
    assert valid_a.tolist() == valid_b.tolist() == [True] * 4
    for name in ("rise", "return", "kappa"):
        assert a[name] == pytest.approx(b[name], rel=1e-12, abs=1e-12), name


def test_the_estimate_counts_the_searchs_own_grids() -> None:
    # camcore.work.design counts the search's candidates from its constants, which the search module sets
    from camcore.profile.design import search
    from camcore.work import design as work

    assert (work.NESTED_OUTER, work.NESTED_INNER) == (search.NESTED_OUTER_POINTS, search.NESTED_INNER_POINTS)
    assert work.LOCATION_TOLERANCE == search.LOCATION_TOLERANCE
    assert work.golden_steps(13) == search.golden_steps(13)
    for variables in (0, 1, 2):
        result = design_profile(DesignProblem(
            cam(), {"base_radius_mm": (10.0, 200.0), "offset_mm": (-30.0, 30.0), "roller_radius_mm": (5.0, 20.0)}
            if variables == 2 else {"base_radius_mm": (10.0, 200.0), "roller_radius_mm": (5.0, 20.0)} if variables
            else {"base_radius_mm": (10.0, 200.0)}, DesignLimits(max_pressure_angle_deg=30)))
        assert result.search.evaluations == work.search_candidates(variables, False)


def test_an_arm_near_folding_is_bracketed_below_it() -> None:
    # an arm's pressure angle falls and then rises again as the arm nears folding (α0 → π): with the upper
    # bound beyond the fold the design is still found (the margin unimodal), and it meets the limit by the checks
    arm = Follower("roller", "oscillating", roller_radius_mm=10.0, arm_length_mm=80.0, pivot_distance_mm=100.0)
    segments = [Segment("rise", 120, 0.0, swing_deg=20.0), Segment("dwell", 60),
                Segment("return", 120, 0.0, swing_deg=20.0), Segment("dwell", 60)]
    result = design_profile(DesignProblem(cam(arm, segments, rb=40.0), {"base_radius_mm": (10.0, 200.0)},
                                          DesignLimits(max_pressure_angle_deg=30)))
    checks = profile_checks(result.cam)
    assert checks.max_pressure_angle_deg == pytest.approx(30.0, abs=1e-8)  # the root to 1e-10 of the radius
    # just below it, and near the fold (where the angle rises again), the limit is broken
    below = profile_checks(replace(result.cam, base_radius_mm=result.design.base_radius_mm * (1 - 1e-6)))
    assert below.max_pressure_angle_deg > 30
    # the arm folds at Rb + Rr = √(d² + L² + 2dL·cos 20°) = 177.3 mm: at 165 mm the angle is far past the limit
    near_fold = profile_checks(replace(result.cam, base_radius_mm=165.0))
    assert near_fold.max_pressure_angle_deg > 60
