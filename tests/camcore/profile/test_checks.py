"""The checks' exact extremes, refined all together by local grids (issue 21), against an
independent refinement of each quantity alone: a scalar golden-section search (Kiefer 1953)
between the same grid neighbours, and a dense brute-force scan of the whole turn."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from camcore._maxima import golden_max
from camcore.curves import build_curve
from camcore.profile import Follower, Segment, kinematics, make_cam, profile_checks, size_base_circle
from camcore.profile.checks import check_grid, lift_check_grid, lift_corners, lift_grid

MS = build_curve("named", {"name": "MS"})
CA = build_curve("named", {"name": "constant-acceleration"})

FOLLOWERS = [
    Follower("knife-edge", offset_mm=4.0),
    Follower("roller", offset_mm=-3.0, roller_radius_mm=6.0),
    Follower("flat-faced"),
    Follower("roller", motion="oscillating", roller_radius_mm=5.0, arm_length_mm=60.0, pivot_distance_mm=75.0),
]


def cam(follower: Follower, rotation: str = "ccw"):
    unit = 12.0 if follower.motion == "translating" else 10.0  # mm, or degrees of swing
    kind = "lift_mm" if follower.motion == "translating" else "swing_deg"
    segs = [Segment("rise", 110, curve=MS, **{kind: unit}), Segment("dwell", 70),
            Segment("return", 130, curve=CA, **{kind: unit}), Segment("dwell", 50)]
    return make_cam(follower, 40.0, segments=segs, rotation=rotation)


def golden_extreme(spec, quantity) -> float:
    """The largest value of one quantity: the best grid point, then golden section on both
    neighbouring cells, one quantity at a time (the pre-issue-21 method)."""
    grid = check_grid(spec)
    vals = quantity(kinematics(spec, grid))
    vals = np.where(np.isfinite(vals), vals, -np.inf)
    i = int(np.argmax(vals))
    lo = grid[i - 1] if i > 0 else grid[-1] - 2 * math.pi
    hi = grid[i + 1] if i + 1 < grid.size else grid[0] + 2 * math.pi
    _, v = golden_max(lambda t: quantity(kinematics(spec, t)), np.array([lo, grid[i]]), np.array([grid[i], hi]),
                      width=1e-12)
    return max(float(vals[i]), float(v.max()))


@pytest.mark.parametrize("follower", FOLLOWERS, ids=lambda f: f"{f.type}-{f.motion}")
@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_extremes_match_golden_section_and_a_dense_scan(follower: Follower, rotation: str) -> None:
    spec = cam(follower, rotation)
    got = profile_checks(spec)
    pressure = math.radians(got.max_pressure_angle_deg)
    # a maximum located to 1e-9 rad is within ½|f''|·1e-18 of the true one: the values agree
    # to rounding (1e-12 relative leaves room for the two methods' different last points)
    assert pressure == pytest.approx(golden_extreme(spec, lambda k: np.abs(k.pressure)), rel=1e-12)
    if follower.type == "flat-faced":
        rho = -golden_extreme(spec, lambda k: -k.rho_cam)
        assert got.min_radius_of_curvature_mm == pytest.approx(rho, rel=1e-12)
        off_max = golden_extreme(spec, lambda k: k.offset)
        assert got.face_max_mm == pytest.approx(off_max, rel=1e-12)
    else:
        kappa = golden_extreme(spec, lambda k: k.kappa_pitch)
        assert got.min_pitch_radius_of_curvature_mm == pytest.approx(1.0 / kappa, rel=1e-12)
    # no angle of a dense scan (2e5 points) beats the refined extreme
    dense = kinematics(spec, np.linspace(0.0, 2 * math.pi, 200_001))
    assert np.abs(dense.pressure).max() <= pressure * (1 + 1e-14)


@pytest.mark.parametrize("follower", FOLLOWERS[:2] + FOLLOWERS[3:], ids=lambda f: f"{f.type}-{f.motion}")
def test_base_circle_with_the_grid_reused_equals_the_checks_at_its_answer(follower: Follower) -> None:
    """Sizing evaluates the lift on the grid once and only the limited extreme per radius; at
    its answer the full checks (their own grid, every quantity) meet both limits exactly."""
    spec = cam(follower)
    res = size_base_circle(spec, max_pressure_angle_deg=28.0, min_radius_of_curvature_mm=3.0)
    at = profile_checks(replace(spec, base_radius_mm=res.base_radius_mm))
    if res.active_constraint == "pressure_angle":
        assert at.max_pressure_angle_deg == pytest.approx(28.0, abs=1e-7)  # radius to 1e-10 relative
    else:
        assert at.min_radius_of_curvature_mm == pytest.approx(3.0, abs=1e-6)
    assert at.max_pressure_angle_deg <= 28.0 + 1e-9
    assert at.min_radius_of_curvature_mm >= 3.0 - 1e-6
    assert res.max_pressure_angle_deg == at.max_pressure_angle_deg


def test_lift_grid_is_the_lift_on_the_check_grid() -> None:
    spec = cam(FOLLOWERS[1])
    grid = lift_grid(spec)
    np.testing.assert_array_equal(grid.theta, check_grid(spec))
    for mine, direct in zip(grid.lift, spec.lift.derivatives(check_grid(spec), 2)):
        np.testing.assert_array_equal(mine, direct)
    # the checks with a grid handed in are the checks without one, bit for bit
    assert profile_checks(spec, grid) == profile_checks(spec)


class _Breaks:
    """A lift with given break points only (what lift_check_grid reads)."""

    def __init__(self, breaks_rad: np.ndarray):
        self.breaks_rad = breaks_rad


def test_the_check_grid_is_np_unique_of_its_angles() -> None:
    # the base grid with the breaks and their left neighbours inserted is np.unique of all of them: breaks
    # on the grid, at 0, repeated, unsorted, a left neighbour landing on a grid angle
    rng = np.random.default_rng(4)
    for _ in range(3000):
        n = int(rng.choice([7200, 720, 13, 2, 1, 0]))
        base = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
        breaks = rng.uniform(0.0, 2 * math.pi, int(rng.integers(0, 12)))
        if breaks.size and n:
            breaks[: breaks.size // 2] = base[rng.integers(0, n, breaks.size // 2)]
            breaks = np.concatenate([breaks, breaks[:2], [0.0, base[-1] + 1e-10]])  # repeated, unsorted
        expected = np.unique(np.concatenate([base, breaks, np.mod(breaks - 1e-10, 2 * math.pi)]))
        np.testing.assert_array_equal(lift_check_grid(_Breaks(breaks), n), expected)


def _corners_with_the_grid_always(lift) -> list[float]:
    """lift_corners as it was: the scale from a 720-point grid whatever the jumps."""
    br = np.asarray(lift.breaks_rad, dtype=np.float64)
    if br.size == 0:
        return []
    right, left = lift.derivatives(br, 1), lift.derivatives(br - 1e-9, 1)
    h1 = lift.derivatives(lift_check_grid(lift, 720), 1)[1]
    scale = max(1.0, float(np.abs(h1).max()))
    return [float(np.degrees(b)) for b in br[np.abs(right[1] - left[1]) > 1e-6 * scale]]


@pytest.mark.parametrize(("curve", "jumps"), [(None, False), (MS, False), (CA, False),
                                               (build_curve("named", {"name": "constant-velocity"}), True)],
                         ids=["cycloid", "MS", "constant-acceleration", "constant-velocity"])
def test_corners_skip_the_grid_only_where_no_jump_could_count(curve, jumps: bool) -> None:
    # a jump must pass 1e-6 times a scale of at least 1: below 1e-6 everywhere there is no corner, the
    # grid's lift unasked; a velocity that jumps (constant velocity) still gets the grid's scale
    for lift_mm in (0.001, 12.0, 400.0):
        spec = make_cam(Follower("roller", roller_radius_mm=6.0), 40.0 + lift_mm, segments=[
            Segment(type="rise", angle_deg=100, lift_mm=lift_mm, curve=curve), Segment(type="dwell", angle_deg=80),
            Segment(type="return", angle_deg=120, lift_mm=lift_mm, curve=curve), Segment(type="dwell", angle_deg=60)])
        found = lift_corners(spec.lift)
        assert found == _corners_with_the_grid_always(spec.lift)
        assert bool(found) == jumps, found


def test_angles_already_in_one_turn_are_their_own_remainder() -> None:
    # the lift reduces its angles to [0, 2π) with np.mod unless a long array already lies there: np.mod
    # leaves such an angle's bits as they are; −0 (np.mod gives +0), 2π and NaN are reduced
    spec = cam(FOLLOWERS[1])
    rng = np.random.default_rng(9)
    inside = np.concatenate([rng.uniform(0.0, 2 * math.pi, 5000), [0.0, 5e-324, np.nextafter(2 * math.pi, 0.0)]])
    np.testing.assert_array_equal(np.mod(inside, 2 * math.pi), inside)
    assert not np.signbit(np.mod(inside, 2 * math.pi)).any()
    for odd in (-0.0, 2 * math.pi, -1e-300, math.nan):
        theta = np.concatenate([inside[:400], [odd]])
        for mine, reduced in zip(spec.lift.derivatives(theta, 2), spec.lift.derivatives(np.mod(theta, 2 * math.pi), 2)):
            np.testing.assert_array_equal(mine, reduced)
