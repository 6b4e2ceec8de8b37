"""The plates' exact contours (camcore.cams.parallel.trace and .polyline) against independent routes.

* A brute-force envelope: every roller of a plate at 200 000 cam angles a turn, placed by the index
  law written out here (φ = h·S(θ/θh) of the catalog curve, B = (C − Rp·cos α, Rp·sin α), turned
  into the cam's frame); scipy's k-d tree finds each contour point's nearest centre. A point of the
  exact contour is at Rr from the nearest roller position and no roller comes nearer.
* The plates as camcore drew them before (tests/parallel_shapely_reference.py: Shapely's union of
  the swept bands taken from a disc), within that method's own error.
* The pieces' ends and the chords between the points, from the pieces themselves.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

import camcore
from camcore.cams.parallel import (
    CHORD_SHARE,
    ParallelCam,
    ParallelResult,
    contour_points,
    make_parallel_cam,
    sample_parallel,
    trace_factor,
)
from camcore.cams.parallel.crossings import COVER_SHARE, CROSSING_SHARE
from camcore.cams.parallel.trace import TooCoarse, trace_plate
from tests.parallel_shapely_reference import shapely_contour

MS = camcore.named_curve("MS")
#: the brute-force envelope's cam angles a turn: a 160 mm/rad path moves 5e-3 mm between them
DENSE = 200_000


@dataclass(frozen=True)
class Case:
    stops: int
    plates: int
    c: float
    rp: float
    rr: float
    theta_h: float
    samples: int

    def cam(self) -> ParallelCam:
        return make_parallel_cam(self.stops, self.c, self.rp, self.rr, self.theta_h, "MS", plates=self.plates)


CASES = [Case(4, 3, 100.0, 60.0, 12.0, 120.0, 181), Case(8, 3, 100.0, 60.0, 10.0, 120.0, 1441),
         Case(6, 2, 100.0, 60.0, 8.0, 120.0, 361)]


@pytest.fixture(scope="module", params=CASES, ids=lambda c: f"{c.stops}stops-{c.plates}plates-{c.samples}")
def traced(request: pytest.FixtureRequest) -> tuple[Case, ParallelResult]:
    case = request.param
    return case, sample_parallel(case.cam(), case.samples)


def dense_centres(case: Case, start_deg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every roller's centre at DENSE cam angles, in the cam's frame, from the index law written out."""
    theta = np.arange(DENSE) * (2 * math.pi / DENSE)
    h = 2 * math.pi / case.stops
    phi = h * MS.derivatives(np.minimum(theta / math.radians(case.theta_h), 1.0), 0)[0]
    alpha = np.radians(start_deg)[:, None] + phi[None, :]
    bx, by = case.c - case.rp * np.cos(alpha), case.rp * np.sin(alpha)
    return np.cos(theta) * bx + np.sin(theta) * by, -np.sin(theta) * bx + np.cos(theta) * by


def test_every_point_is_on_the_brute_force_envelope(traced: tuple[Case, ParallelResult]) -> None:
    case, result = traced
    eps = COVER_SHARE * case.c
    for plate in result.plates:
        cx, cy = dense_centres(case, plate.roller_start_angle_deg)
        d, _ = cKDTree(np.column_stack([cx.ravel(), cy.ravel()])).query(np.column_stack([plate.x_mm, plate.y_mm]))
        # the nearest of the dense positions misses the exact one by at most half their spacing: a
        # sagitta of (spacing/2)²/(2·Rr) beyond Rr
        spacing = float(np.hypot(np.diff(cx, axis=1), np.diff(cy, axis=1)).max())
        assert spacing < 0.01
        assert d.max() <= case.rr + (spacing / 2) ** 2 / (2 * case.rr) + 1e-9
        # and no nearer than Rr less ε: a point counts as free down to Rr − ε, and where two envelopes
        # run together the hand-over may sit that deep in the other roller (1e-5 mm here)
        assert d.min() >= case.rr - eps


def test_no_roller_enters_the_polyline(traced: tuple[Case, ParallelResult]) -> None:
    """No roller at any of the dense cam angles comes nearer the contour's polyline than Rr − δ − ε:
    a chord stands off the exact contour by δ at most (concave stretches bulge into the rollers)."""
    case, result = traced
    delta, eps = CHORD_SHARE * case.rr, COVER_SHARE * case.c
    for plate in result.plates:
        cx, cy = dense_centres(case, plate.roller_start_angle_deg)
        vertices = np.column_stack([plate.x_mm, plate.y_mm])
        pts = np.column_stack([cx.ravel(), cy.ravel()])
        # only centres within reach of a vertex can be near a chord (chords are short)
        gaps = np.hypot(np.diff(plate.x_mm, append=plate.x_mm[0]), np.diff(plate.y_mm, append=plate.y_mm[0]))
        near = cKDTree(vertices).query(pts)[0] < case.rr + gaps.max()
        # each centre's distance to its nearest chord: the distance to the closed polyline, found by
        # Shapely's tree of the chords (the same numbers as to the ring, checked: 2-2.5× faster)
        chords = shapely.linestrings(np.stack([vertices, np.roll(vertices, -1, axis=0)], axis=1))
        _, d = shapely.STRtree(chords).query_nearest(shapely.points(pts[near]), return_distance=True, all_matches=False)
        assert d.min() >= case.rr - delta - eps, (d.min(), case.rr - delta - eps)


def test_the_pieces_meet_exactly() -> None:
    """Each piece starts where the one before ends: at a corner, a crossing of the two envelopes
    (within CROSSING_SHARE·C); where two envelopes run together, a hand-over within 2ε."""
    case = CASES[1]
    cam = case.cam()
    for plate in range(case.plates):
        contour, _ = trace_plate(cam, plate, case.samples)
        n = len(contour.pieces)
        corners = 0
        for k in range(n):
            end = contour.at(k, np.array([contour.pieces[k].tau_end_rad]))
            nxt = contour.at((k + 1) % n, np.array([contour.pieces[(k + 1) % n].tau_start_rad]))
            gap = math.hypot(float(end.x[0] - nxt.x[0]), float(end.y[0] - nxt.y[0]))
            if contour.pieces[(k + 1) % n].corner:
                corners += 1
                assert gap <= CROSSING_SHARE * case.c
                # both rollers touch the corner: their centres Rr away
                for e in (end, nxt):
                    assert math.hypot(float(e.x[0] - e.px[0]), float(e.y[0] - e.py[0])) == pytest.approx(case.rr,
                                                                                                           abs=1e-12)
            else:
                assert gap <= 2 * COVER_SHARE * case.c
        assert corners >= 1


def test_the_chords_stay_within_the_chord_tolerance(traced: tuple[Case, ParallelResult]) -> None:
    """Between two consecutive points of one piece the exact contour (7 points along the step) stands
    off their chord by δ = CHORD_SHARE·Rr at most."""
    case, result = traced
    delta = CHORD_SHARE * case.rr
    finer = trace_factor(case.samples)
    for contour in result.contours:
        pts = contour_points(contour, 2 * math.pi / (case.samples * finer))
        same = np.flatnonzero(pts.piece[1:] == pts.piece[:-1])
        frac = np.linspace(0.0, 1.0, 9)[1:-1]
        worst = 0.0
        for k in np.unique(pts.piece[same]):
            i = same[pts.piece[same] == k]
            tau = pts.tau[i, None] + frac[None, :] * (pts.tau[i + 1] - pts.tau[i])[:, None]
            e = contour.at(int(k), tau.ravel())
            ax, ay = pts.x[i, None], pts.y[i, None]
            bx, by = pts.x[i + 1, None], pts.y[i + 1, None]
            ex, ey = e.x.reshape(tau.shape), e.y.reshape(tau.shape)
            cross = (bx - ax) * (ey - ay) - (by - ay) * (ex - ax)
            worst = max(worst, float((np.abs(cross) / np.hypot(bx - ax, by - ay)).max()))
        assert 0 < worst <= delta, (worst, delta)


def test_each_point_is_its_envelope_at_its_cam_angle_to_the_bit(traced: tuple[Case, ParallelResult]) -> None:
    """contour_points takes a point already computed at the same cam angle rather than computing it
    again: every point is still the envelope at its τ, the same floats."""
    case, result = traced
    finer = trace_factor(case.samples)
    for contour in result.contours:
        pts = contour_points(contour, 2 * math.pi / (case.samples * finer))
        for k in np.unique(pts.piece):
            mine = pts.piece == k
            e = contour.at(int(k), pts.tau[mine])
            for got, want in ((pts.x, e.x), (pts.y, e.y), (pts.pressure_deg, e.pressure_deg), (pts.drives, e.drives),
                              (pts.rho, e.rho)):
                assert np.array_equal(got[mine], want)


def test_the_contour_is_the_shapely_one_within_its_error() -> None:
    """The plates as Shapely's boolean operations drew them (8 path points per sampled cam angle) and
    the exact contour are the same curve: each polyline's points lie within the other's chord
    error of it — the old polyline's chords cut into a roller by (its spacing)²/(8·Rr), the new one's
    by δ."""
    for case in (CASES[0], CASES[2]):
        cam = case.cam()
        new = sample_parallel(cam, case.samples)
        for p in range(case.plates):
            ox, oy, _roller, _theta = shapely_contour(cam, p, case.samples)
            nx, ny = new.plates[p].x_mm, new.plates[p].y_mm
            spacing = np.hypot(np.diff(ox, append=ox[0]), np.diff(oy, append=oy[0])).max()
            old_error = spacing**2 / (8 * case.rr)
            bound = old_error + CHORD_SHARE * case.rr
            old_to_new = shapely.distance(shapely.points(ox, oy), shapely.LinearRing(np.column_stack([nx, ny])))
            new_to_old = shapely.distance(shapely.points(nx, ny), shapely.LinearRing(np.column_stack([ox, oy])))
            assert max(old_to_new.max(), new_to_old.max()) <= bound, (p, old_to_new.max(), new_to_old.max(), bound)
            # the same closed curve, not a piece of it: the areas agree to the perimeter × that error
            area_old, area_new = shapely.Polygon(np.column_stack([ox, oy])).area, shapely.Polygon(
                np.column_stack([nx, ny])).area
            perimeter = shapely.LinearRing(np.column_stack([nx, ny])).length
            assert abs(area_old - area_new) <= perimeter * bound


def test_a_roller_that_all_but_stops_is_traced_finer() -> None:
    """A 36-stop turret of 5 mm rollers: near the line of centres a roller's path all but stops and its
    envelope sweeps round the roller within one step of 720 a turn. The trace says so (TooCoarse);
    the plates are traced finer, and their contour is the one traced at 2880 a turn, within δ."""
    cam = make_parallel_cam(36, 400.0, 350.0, 5.0, 90.0, "MS", plates=3)
    with pytest.raises(TooCoarse):
        trace_plate(cam, 2, 720)
    coarse = sample_parallel(cam, 16)
    fine = sample_parallel(cam, 2880)
    delta = CHORD_SHARE * 5.0
    for a, b in zip(coarse.plates, fine.plates):
        ring = shapely.LinearRing(np.column_stack([b.x_mm, b.y_mm]))
        # each exact point of one lies within the other's chord tolerance of it
        assert shapely.distance(shapely.points(a.x_mm, a.y_mm), ring).max() <= delta


@pytest.mark.parametrize("curve", ["MS", "MT", "cycloid", "constant-velocity"])
def test_the_turret_and_the_centres_are_the_models(curve: str) -> None:
    """ParallelCam.turret and envelope.centres write out the indexer's motion and the oscillating
    follower's pitch point for speed: they agree with camcore.cams.turret.turret_motion (the indexer's
    motion table) and with the follower model's pitch point (camcore.profile.followers), over several
    turns, at the index's ends and in the dwell."""
    from camcore.cams.parallel.envelope import centres, envelope
    from camcore.cams.turret import turret_motion

    cam = make_parallel_cam(6, 100.0, 60.0, 8.0, 120.0, curve, plates=3)
    theta = np.concatenate([np.linspace(-13.0, 40.0, 20_001), [0.0, 2 * math.pi, math.radians(120.0)]])
    for mine, theirs in zip(cam.turret(theta), turret_motion(cam.indexer, theta), strict=True):
        # both are h·S(θ/θh) and its slopes; they round differently (degrees there, radians here)
        assert np.abs(mine - theirs).max() <= 1e-13
    alpha0 = 0.3
    px, py, p1x, p1y, p2x, p2y = centres(cam, alpha0, theta)
    e = envelope(cam, alpha0, 1.0, theta)  # the follower model's numbers (test_parallel_envelope.py)
    assert np.abs(px - e.px).max() <= 1e-12 and np.abs(py - e.py).max() <= 1e-12
    speed = np.hypot(p1x, p1y)
    assert np.abs(p1x / speed - e.tx).max() <= 1e-12 and np.abs(p1y / speed - e.ty).max() <= 1e-12
    # the pitch curve's curvature from P′, P″ against the follower's κp (on side +1 the envelope's κ is −κp)
    kappa_pitch = -(p1x * p2y - p1y * p2x) / speed**3
    assert np.abs(kappa_pitch + e.kappa).max() <= 1e-12 * max(1.0, float(np.abs(e.kappa).max()))
    # the second derivative against a central difference of the first (h = 1e-6 rad: error ~1e-9·|P⁗|)
    # inside the index, away from the law's break points
    t = np.linspace(0.1, 1.9, 101)
    h = 1e-6
    ahead, behind = centres(cam, alpha0, t + h), centres(cam, alpha0, t - h)
    _, _, _, _, q2x, q2y = centres(cam, alpha0, t)
    assert np.abs((ahead[2] - behind[2]) / (2 * h) - q2x).max() <= 1e-5 * np.abs(q2x).max()
    assert np.abs((ahead[3] - behind[3]) / (2 * h) - q2y).max() <= 1e-5 * np.abs(q2y).max()


@pytest.mark.parametrize("curve", ["MS", "cycloid", "constant-velocity"])
def test_a_few_turret_angles_are_the_arrays_numbers_to_the_bit(curve: str) -> None:
    """ParallelCam.turret takes up to 8 angles in Python floats: every number equals the one its
    array formulas (written out here) give, bit for bit, at random angles over several turns, at
    whole turns, on the index's end and just either side, and a non-finite angle is the arrays'."""
    cam = make_parallel_cam(6, 100.0, 60.0, 8.0, 120.0, curve, plates=3)
    law, t_start, s_start, d_t, scales, theta_h, h = cam._law

    def by_arrays(theta: np.ndarray) -> list[np.ndarray]:
        turns = np.floor(theta * (0.5 / math.pi))
        within = theta - turns * (2 * math.pi)
        s, v, a = law.derivatives((t_start + d_t * np.minimum(within / theta_h, 1.0)).reshape(-1), 2)
        index = (within <= theta_h).reshape(-1)
        return [(np.where(index, scales[0] * (s - s_start), h).reshape(theta.shape) + turns * h),
                np.where(index, scales[1] * v, 0.0).reshape(theta.shape),
                np.where(index, scales[2] * a, 0.0).reshape(theta.shape)]

    rng = np.random.default_rng(38)
    edges = [0.0, -0.0, 2 * math.pi, -2 * math.pi, theta_h, np.nextafter(theta_h, 0.0), np.nextafter(theta_h, 9.0),
             4 * math.pi + theta_h, 1e-300]
    cases = [np.array(edges[:8]), np.array(edges[8:]), np.array([[0.5, 1.0], [2.0, -3.0]]), np.array(1.25),
             np.array([np.nan, 1.0]), np.array([np.inf])]
    cases += [rng.uniform(-20.0, 30.0, n) for n in (1, 2, 5, 8) for _ in range(50)]
    for theta in cases:
        with np.errstate(invalid="ignore"):  # the non-finite cases: inf − inf in the arrays' within
            got, want = cam.turret(theta), by_arrays(theta)
        for g, w in zip(got, want, strict=True):
            assert g.shape == theta.shape
            np.testing.assert_array_equal(np.ascontiguousarray(g).view(np.int64),
                                          np.ascontiguousarray(w).view(np.int64))  # bits: -0.0 ≠ 0.0


def test_a_foot_search_gives_up_only_where_the_point_is_off_the_envelope(monkeypatch: pytest.MonkeyPatch) -> None:
    # points at known gaps g off an envelope, along its normal at cam angle u (their foot): within 2ε
    # (2e-5 mm at C = 100 mm) the foot is found, beyond it NaN, as the search run all its steps says; the
    # lanes far off stop it early (fewer evaluations of the envelopes)
    from camcore.cams.parallel import crossings

    cam = CASES[0].cam()
    rng = np.random.default_rng(11)
    eps2 = 2 * COVER_SHARE * cam.center_distance_mm
    alpha0 = cam.start_angles(0)[0]
    step = 2 * math.pi / 1444
    calls = [0]
    real = crossings.track

    def counted(*args: object) -> object:
        calls[0] += 1
        return real(*args)  # type: ignore[arg-type]

    monkeypatch.setattr(crossings, "track", counted)
    for gap in (1e-7, 1e-6, 1.9e-5, 2.1e-5, 1e-4, 1e-2, 0.3):
        for side in (-1.0, 1.0):
            u = rng.uniform(0.0, 2 * math.pi, 3)
            e = real(cam, alpha0, side, u)
            x, y = e.x - gap * e.ty, e.y + gap * e.tx  # along N = J·T, the envelope's normal
            for k in range(3):
                start = u[k:k + 1] + rng.uniform(-0.5, 0.5) * step
                calls[0] = 0
                found = crossings.feet(cam, np.array([alpha0]), np.array([side]), float(x[k]), float(y[k]), start, step)
                early = calls[0]
                # the reference: every step the search may take, no lane given up
                monkeypatch.setattr(crossings, "FAR_STEP_SHARE", 0.0)
                calls[0] = 0
                full = crossings.feet(cam, np.array([alpha0]), np.array([side]), float(x[k]), float(y[k]), start, step)
                monkeypatch.setattr(crossings, "FAR_STEP_SHARE", 1e-3)
                assert np.array_equal(found, full, equal_nan=True), (gap, side)
                assert np.isnan(found[0]) == (gap > eps2), (gap, found)
                if gap <= eps2:
                    assert abs(found[0] - u[k]) < 1e-9, (gap, found[0] - u[k])
                if gap >= 1e-4:
                    assert early < calls[0], (gap, early, calls[0])
