"""The toolpath's faster paths against the ones they replaced, to the bit.

The references below are the earlier implementations, kept here as they were: the biarc built
with numpy two-vectors (``_numpy_biarc``), a biarc's distance as two :meth:`Element.distance`
calls, the element arrays that gathered one row per quantity and computed every formula for
every lane (``_RowArrays``), and the climb that scattered its whole state back every step
(``_scattering_climb``). The greedy search must pick the same grid points with the same
elements, and the measurement must give the same deviations, to the bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator
from itertools import pairwise
from typing import Any

import numpy as np
import pytest

import camcore
from camcore.profile import Follower, Segment, make_cam
from camcore.toolpath import OffsetCurve, base_curve
from camcore.toolpath import measure as measure_module
from camcore.toolpath.fit import Budget, _farthest_fit, _greedy
from camcore.toolpath.geometry import STRAIGHT, Element, biarc, biarc_of, pair_distance
from camcore.toolpath.measure import CLIMB_GAIN_MM, CLIMB_STEPS, measure
from camcore.toolpath.offset import base_stretch

MS = camcore.named_curve("MS")
CAMS = {
    "readme": make_cam(Follower(type="roller", roller_radius_mm=10), 40, segments=[
        Segment(type="rise", angle_deg=180, lift_mm=20), Segment(type="return", angle_deg=180, lift_mm=20)]),
    "ms-dwells": make_cam(Follower(type="roller", roller_radius_mm=10), 40, segments=[
        Segment(type="rise", angle_deg=120, lift_mm=20, curve=MS), Segment(type="dwell", angle_deg=60),
        Segment(type="return", angle_deg=120, lift_mm=20, curve=MS), Segment(type="dwell", angle_deg=60)]),
    "flat": make_cam(Follower(type="flat-faced"), 40, segments=[
        Segment(type="rise", angle_deg=150, lift_mm=15), Segment(type="return", angle_deg=210, lift_mm=15)]),
}


# ------------------------------------------------------------------ the earlier implementations
def _numpy_arc(start: np.ndarray, tangent: np.ndarray, end: np.ndarray, theta0: float, theta1: float) -> Element:
    chord = end - start
    c2 = float(chord @ chord)
    cross = float(tangent[0] * chord[1] - tangent[1] * chord[0])
    s, e = (float(start[0]), float(start[1])), (float(end[0]), float(end[1]))
    if c2 == 0.0 or abs(cross) <= STRAIGHT * c2:
        return Element(s, e, None, True, theta0, theta1)
    curvature = 2.0 * cross / c2
    cx = float(start[0]) - tangent[1] / curvature
    cy = float(start[1]) + tangent[0] / curvature
    return Element(s, e, (float(cx), float(cy)), curvature > 0, theta0, theta1)


def _numpy_biarc(p0: np.ndarray, t0: np.ndarray, p1: np.ndarray, t1: np.ndarray, theta0: float = 0.0,
                 theta1: float = 0.0) -> tuple[Element, Element] | None:
    v, t = p1 - p0, t0 + t1
    vt, vv = float(v @ t), float(v @ v)
    if vv == 0.0:
        return None
    four_minus_tt = 4.0 - float(t @ t)
    root = math.sqrt(vt * vt + max(four_minus_tt, 0.0) * vv)
    if vt > 0.0:
        d = vv / (vt + root)
    elif four_minus_tt > 1e-14:
        d = (root - vt) / four_minus_tt
    else:
        return None
    if not (math.isfinite(d) and d > 0.0):
        return None
    q0, q1 = p0 + d * t0, p1 - d * t1
    joint, leg = 0.5 * (q0 + q1), q1 - q0
    norm = math.hypot(float(leg[0]), float(leg[1]))
    if norm == 0.0:
        return None
    tm = leg / norm
    mid = 0.5 * (theta0 + theta1)
    first = _numpy_arc(p0, t0, joint, theta0, mid)
    second = _numpy_arc(p1, -t1, joint, theta1, mid).reversed()
    if second.centre is None:
        dx, dy = second.end[0] - second.start[0], second.end[1] - second.start[1]
    else:
        rx, ry = second.start[0] - second.centre[0], second.start[1] - second.centre[1]
        dx, dy = (-ry, rx) if second.ccw else (ry, -rx)
    return (first, second) if dx * tm[0] + dy * tm[1] > 0.0 else None


class _RowArrays:
    """Elements as one array per quantity, every formula for every lane."""

    def __init__(self, elements: list[Element]):
        self.sx = np.array([e.start[0] for e in elements])
        self.sy = np.array([e.start[1] for e in elements])
        self.ex = np.array([e.end[0] for e in elements])
        self.ey = np.array([e.end[1] for e in elements])
        self.arc = np.array([e.centre is not None for e in elements], dtype=bool)
        self.cx = np.array([e.centre[0] if e.centre is not None else 0.0 for e in elements])
        self.cy = np.array([e.centre[1] if e.centre is not None else 0.0 for e in elements])
        self.r = np.array([e.radius_mm if e.centre is not None else 0.0 for e in elements])
        self.a0 = np.arctan2(self.sy - self.cy, self.sx - self.cx)
        self.sweep = np.array([e.sweep_rad for e in elements])

    def distance_slope(self, lane: np.ndarray, x: np.ndarray, y: np.ndarray, vx: np.ndarray, vy: np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray]:
        sx, sy, ex, ey = self.sx[lane], self.sy[lane], self.ex[lane], self.ey[lane]
        dx, dy = ex - sx, ey - sy
        length2 = dx * dx + dy * dy
        with np.errstate(invalid="ignore", divide="ignore"):
            u = np.clip(np.where(length2 > 0, ((x - sx) * dx + (y - sy) * dy) / length2, 0.0), 0.0, 1.0)
        fx, fy = x - (sx + u * dx), y - (sy + u * dy)
        line = np.hypot(fx, fy)
        cx, cy, sweep = self.cx[lane], self.cy[lane], self.sweep[lane]
        rel = np.mod((np.arctan2(y - cy, x - cx) - self.a0[lane]) * np.where(sweep < 0, -1.0, 1.0), 2 * math.pi)
        to_start, to_end = np.hypot(x - sx, y - sy), np.hypot(x - ex, y - ey)
        start_nearer = to_start <= to_end
        to_ends = np.minimum(to_start, to_end)
        on_arc = rel <= np.abs(sweep)
        rx, ry = x - cx, y - cy
        radius = np.hypot(rx, ry)
        arc = np.where(on_arc, np.abs(radius - self.r[lane]), to_ends)
        is_arc = self.arc[lane]
        distance = np.where(is_arc, arc, line)
        with np.errstate(invalid="ignore", divide="ignore"):
            radial = np.sign(radius - self.r[lane]) * (rx * vx + ry * vy) / radius
            end = np.where(start_nearer, (x - sx) * vx + (y - sy) * vy, (x - ex) * vx + (y - ey) * vy) / to_ends
            slope = np.where(is_arc & on_arc, radial, np.where(is_arc, end, (fx * vx + fy * vy) / line))
        return distance, np.where(distance > 0, slope, 0.0)

    def along(self, lane: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, ...]:
        a = self.a0[lane] + u * self.sweep[lane]
        r, arc = self.r[lane], self.arc[lane]
        rs = r * self.sweep[lane]
        sx, sy, ex, ey = self.sx[lane], self.sy[lane], self.ex[lane], self.ey[lane]
        return (np.where(arc, self.cx[lane] + r * np.cos(a), sx + u * (ex - sx)),
                np.where(arc, self.cy[lane] + r * np.sin(a), sy + u * (ey - sy)),
                np.where(arc, -rs * np.sin(a), ex - sx), np.where(arc, rs * np.cos(a), ey - sy))


def _scattering_climb(a: Any, b: Any, slope_a: Any, slope_b: Any, aux_a: Any, aux_b: Any,
                      probe: Callable[..., Generator[Any, Any, Any]]) -> Generator[Any, Any, np.ndarray]:
    a, b, sa, sb, aux_a, aux_b = (np.array(v, dtype=np.float64) for v in (a, b, slope_a, slope_b, aux_a, aux_b))
    best = np.full(a.size, -np.inf)
    kept = np.zeros(a.size, dtype=np.int8)
    active = np.arange(a.size)
    for _ in range(CLIMB_STEPS):
        if not active.size:
            break
        aa, bb, fa, fb = a[active], b[active], sa[active], sb[active]
        with np.errstate(invalid="ignore", divide="ignore"):
            x = bb - fb * (bb - aa) / (fb - fa)
        x = np.where((x > aa) & (x < bb), x, 0.5 * (aa + bb))
        value, slope, aux = yield from probe(x, active, aa, bb, aux_a[active], aux_b[active])
        best[active] = np.fmax(best[active], value)
        down, up = slope < 0, slope > 0
        sa[active] = np.where(down & (kept[active] == -1), 0.5 * fa, np.where(up, slope, fa))
        sb[active] = np.where(up & (kept[active] == 1), 0.5 * fb, np.where(down, slope, fb))
        a[active], b[active] = np.where(up, x, aa), np.where(down, x, bb)
        aux_a[active] = np.where(up, aux, aux_a[active])
        aux_b[active] = np.where(down, aux, aux_b[active])
        kept[active] = np.where(down, -1, np.where(up, 1, 0))
        done = ~(np.abs(slope) * (b[active] - a[active]) > CLIMB_GAIN_MM)
        active = active[~done]
    return best


# ------------------------------------------------------------------ helpers
def _bits(elements: tuple[Element, ...] | None) -> str:
    """The elements' every number, -0.0 and the types included."""
    return repr(None if elements is None else [(e.start, e.end, e.centre, e.ccw, e.theta0_rad, e.theta1_rad)
                                               for e in elements])


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.array_equal(a, b, equal_nan=True) and np.array_equal(np.signbit(a), np.signbit(b)))


def _grid(spec: camcore.profile.CamSpec, tool_mm: float, a_deg: float, b_deg: float
          ) -> tuple[OffsetCurve, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The greedy fit's grid over a stretch: angles, points and unit travel tangents."""
    curve = OffsetCurve(spec, -spec.model.roller_radius_mm + tool_mm)
    theta = np.linspace(math.radians(a_deg), math.radians(b_deg), 600)
    x, y, tx, ty, _ = curve.travel(theta)
    return curve, theta, np.column_stack([x, y]), np.column_stack([tx, ty]), np.array([x, y])


# ------------------------------------------------------------------ tests
def test_the_biarc_is_the_numpy_biarcs_to_the_bit() -> None:
    # random ends and tangents, and near-degenerate ones: ends a micrometre apart, tangents 1e-8 rad apart
    rng = np.random.default_rng(11)
    nones = 0
    for k in range(20000):
        scale = 10 ** rng.uniform(-3, 3)
        p0, p1 = rng.normal(size=2) * scale, rng.normal(size=2) * scale
        if k % 3 == 0:
            p1 = p0 + rng.normal(size=2) * scale * 1e-6
        a0, a1 = rng.uniform(-math.pi, math.pi, 2)
        if k % 5 == 0:
            a1 = a0 + rng.normal() * 1e-8
        t0, t1 = np.array([math.cos(a0), math.sin(a0)]), np.array([math.cos(a1), math.sin(a1)])
        theta0, theta1 = rng.uniform(0.0, 6.0, 2).tolist()
        reference = _numpy_biarc(p0, t0, p1, t1, theta0, theta1)
        assert _bits(biarc(p0, t0, p1, t1, theta0, theta1)) == _bits(reference)
        nones += reference is None
        if reference is not None:
            x, y = rng.normal(size=(2, 50)) * scale + p0[:, None]
            two_calls = np.minimum(reference[0].distance(x, y), reference[1].distance(x, y))
            assert _same(pair_distance(reference, x, y), two_calls)
            found = biarc_of(p0, t0, p1, t1)
            assert found is not None and _same(found.distance(x, y), two_calls)
    assert 0 < nones < 5000  # both kinds were met


@pytest.mark.parametrize("name", CAMS)
def test_the_greedy_search_picks_the_one_by_one_searchs_points(name: str) -> None:
    # every start of a stretch's grid, a first guess of 1 to 200 steps and two aims: the search over the
    # biarcs' numbers (elements made for the one kept) against the one-by-one search over elements
    spec = CAMS[name]
    _, theta, pts, tan, (px, py) = _grid(spec, 6.0 if spec.model.roller_radius_mm else 3.0, 20.0, 200.0)
    n = theta.size - 1

    def new(i: int, j: int) -> tuple[Any, float]:
        fit = biarc_of(pts[i], tan[i], pts[j], tan[j])
        return (None, math.inf) if fit is None else (fit, float(fit.distance(px[i:j + 1], py[i:j + 1]).max()))

    def old(i: int, j: int) -> tuple[Any, float]:
        pair = _numpy_biarc(pts[i], tan[i], pts[j], tan[j], float(theta[i]), float(theta[j]))
        return (None, math.inf) if pair is None else (pair, float(pair_distance(pair, px[i:j + 1], py[i:j + 1]).max()))

    rng = np.random.default_rng(5)
    for i in range(0, n - 1, 7):
        for aim_mm in (2e-3, 2e-5):
            guess = int(rng.integers(1, 200))
            good, fit = _farthest_fit(new, i, n, guess, aim_mm)
            good_old, fit_old = _farthest_fit(old, i, n, guess, aim_mm)
            assert good == good_old
            assert _bits(None if fit is None else fit.elements(float(theta[i]), float(theta[good]))) == _bits(fit_old)


@pytest.mark.parametrize("name", CAMS)
def test_the_measurement_is_the_row_arrays_and_scattering_climbs_to_the_bit(
        name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    # the spans of fits at three tolerances (and of a coarse fit, whose spans deviate far more), measured
    # with the one-table arrays and the compact climb, and with the earlier ones
    spec = CAMS[name]
    curve, theta, pts, tan, _ = _grid(spec, 6.0 if spec.model.roller_radius_mm else 3.0, 20.0, 200.0)
    for tolerance_mm, step in ((0.05, 0.02), (0.005, 0.003), (5e-4, 0.003)):
        spans = _greedy(curve, float(theta[0]), float(theta[-1]), (pts[0], tan[0]), (pts[-1], tan[-1]),
                        tolerance_mm, step, Budget(10**6))
        fast = measure(curve, spans)
        with monkeypatch.context() as patched:
            patched.setattr(measure_module, "ElementArrays", _RowArrays)
            patched.setattr(measure_module, "_climb", _scattering_climb)
            reference = measure(curve, spans)
        assert _same(fast, reference)


def test_lines_and_mixed_elements_are_measured_as_before(monkeypatch: pytest.MonkeyPatch) -> None:
    # the element arrays' line-only and mixed paths (a fit of arcs never takes them): chords of a
    # stretch, and chords between biarcs
    curve, theta, pts, tan, _ = _grid(CAMS["readme"], 6.0, 30.0, 120.0)
    cuts = list(range(0, theta.size, 40)) + [theta.size - 1]
    chords = [Element(tuple(pts[a]), tuple(pts[b]), None, True, float(theta[a]), float(theta[b]))
              for a, b in pairwise(cuts)]
    lines = [measure_module.Span(e.theta0_rad, e.theta1_rad, (e,)) for e in chords]
    mixed = []
    for k, (a, b) in enumerate(pairwise(cuts)):
        pair = biarc(pts[a], tan[a], pts[b], tan[b], float(theta[a]), float(theta[b]))
        elements = (chords[k],) if k % 2 or pair is None else pair
        mixed.append(measure_module.Span(float(theta[a]), float(theta[b]), elements))
    for spans in (lines, mixed):
        fast = measure(curve, spans)
        arrays = measure_module.ElementArrays([e for s in spans for e in s.elements])
        assert arrays.kinds == ("lines" if spans is lines else "both")
        rows = _RowArrays([e for s in spans for e in s.elements])
        lane = np.arange(len(rows.sx)).repeat(7)
        rng = np.random.default_rng(2)
        x, y = rows.sx[lane] + rng.normal(size=lane.size), rows.sy[lane] + rng.normal(size=lane.size)
        vx, vy = rng.normal(size=(2, lane.size))
        u = rng.uniform(0.0, 1.0, lane.size)
        for got, want in zip((*arrays.distance_slope(lane, x, y, vx, vy), *arrays.along(lane, u)),
                             (*rows.distance_slope(lane, x, y, vx, vy), *rows.along(lane, u))):
            assert _same(got, want)
        with monkeypatch.context() as patched:
            patched.setattr(measure_module, "ElementArrays", _RowArrays)
            patched.setattr(measure_module, "_climb", _scattering_climb)
            assert _same(fast, measure(curve, spans))


@pytest.mark.parametrize("follower", [
    Follower(type="roller", roller_radius_mm=10, offset_mm=3.0), Follower(type="flat-faced"),
    Follower(type="roller", roller_radius_mm=5, motion="oscillating", pivot_distance_mm=80, arm_length_mm=60),
    Follower(type="flat-faced", motion="oscillating", pivot_distance_mm=90)], ids=["roller", "flat", "arm", "flat-arm"])
def test_the_wall_scans_coefficients_are_the_base_curves(follower: Follower) -> None:
    # base_stretch (the check grid's scans) leaves out the point and the normal, not a bit of a or b
    swing = follower.motion == "oscillating"
    spec = make_cam(follower, 40, rotation="cw", segments=[
        Segment(type="rise", angle_deg=170, **({"swing_deg": 12} if swing else {"lift_mm": 15}), curve=MS),
        Segment(type="return", angle_deg=190, **({"swing_deg": 12} if swing else {"lift_mm": 15}))])
    theta = np.concatenate([np.random.default_rng(1).uniform(0.0, 2 * math.pi, 3000), np.linspace(0.0, 6.0, 7)])
    a, b = base_stretch(spec, theta)
    whole = base_curve(spec, theta)
    assert _same(a, whole.a) and _same(b, whole.b)
