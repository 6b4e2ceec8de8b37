"""The plates of a parallel indexing cam: contours, contacts, pressure angles, checks
(the method: :mod:`camcore.cams.parallel.geometry`)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import NDArray

from ..._checks import count
from ...errors import GeometryError
from ...results import doc
from .geometry import FloatArray, ParallelCam

#: path points per sampled cam angle: at 181 samples a path moving 150 mm/rad steps 0.65 mm, and
#: the contour's chords between exact points cut into a roller by (step)²/(8·Rr), 4.4e-3 mm for
#: Rr = 12 mm (tests/camcore/cams/test_parallel.py measures it)
PATH_POINTS_PER_SAMPLE = 8
#: a roller touches its plate where an envelope point is this close to the contour, as a share
#: of the roller radius: above the chords' cut between exact vertices
CONTACT_TOLERANCE = 1e-3
#: a roller counts as at its plate (for the undercut check) within this share of its radius
NEAR_PLATE = 0.05
#: golden-section steps putting a vertex on its roller: a bracket of 4 path steps (≤ 1°)
#: shrinks by 0.618^50 to 1e-12 rad
GOLDEN_STEPS = 50
#: contacts listed in the checks of a cam that does not hold its turret, at most
LISTED_ANGLES = 10


@dataclass(frozen=True)
class Contacts:
    """Where a plate's rollers are in contact over a turn: one row per roller in contact at a cam angle."""

    cam_angle_deg: FloatArray = field(metadata=doc("the cam angle [deg]"))
    roller: NDArray[np.intp] = field(metadata=doc("the roller in contact (index in its layer)"))
    pressure_angle_deg: FloatArray = field(metadata=doc(
        "between the contact normal and the roller centre's velocity, signed, within ±90° [deg]"))
    drives: NDArray[np.bool_] = field(metadata=doc("true: the plate pushes the turret forward; false: it holds it back"))


@dataclass(frozen=True)
class PlateChecks:
    """What limits one plate."""

    min_convex_radius_of_curvature_mm: float | None = field(metadata=doc(
        "smallest radius of curvature where the contour is convex; null: nowhere convex"))
    undercut: bool = field(metadata=doc(
        "a roller's path bends (convex) tighter than its radius while the roller is at the plate "
        "(within 5 % of its radius): the contour cannot follow it"))
    min_radius_mm: float = field(metadata=doc("the contour's smallest distance from the cam axis"))
    max_radius_mm: float = field(metadata=doc("the contour's largest distance from the cam axis"))


@dataclass(frozen=True)
class Plate:
    """One plate: its contour in the cam's frame (sorted by polar angle), contacts and checks."""

    plate: int = field(metadata=doc("0 … plates − 1"))
    roller_start_angle_deg: FloatArray = field(metadata=doc("arm angle α₀ of each roller of its layer at θ = 0"))
    x_mm: FloatArray = field(metadata=doc("contour, cam frame"))
    y_mm: FloatArray = field(metadata=doc("contour, cam frame"))
    roller: NDArray[np.intp] = field(metadata=doc("the roller that touches the contour there"))
    contact_cam_angle_deg: FloatArray = field(metadata=doc("the cam angle at which it touches there"))
    pressure_angle_deg: FloatArray = field(metadata=doc("pressure angle of that contact, within ±90°"))
    radius_of_curvature_mm: FloatArray = field(metadata=doc(
        "of the contour there: positive convex, negative concave"))
    contacts: Contacts = field(metadata=doc("every contact over the turn's sampled cam angles"))
    checks: PlateChecks = field(metadata=doc("what limits the plate"))


@dataclass(frozen=True)
class ParallelChecks:
    """What limits the cam as a whole."""

    conjugate: bool = field(metadata=doc(
        "at every sampled cam angle some contact drives the turret and some contact holds it"))
    unheld_cam_angles_deg: list[float] = field(metadata=doc(
        "the first sampled cam angles (at most 10) where no contact drives or none holds"))
    max_pressure_angle_deg: float = field(metadata=doc(
        "over the index, the largest of drive_pressure_angle_deg and hold_pressure_angle_deg (where there is a contact)"))
    max_pressure_angle_at_deg: float = field(metadata=doc("the cam angle of it"))
    undercut: bool = field(metadata=doc("any plate undercut"))
    turret_axis_clearance_mm: float = field(metadata=doc(
        "centre distance less the plates' largest radius: room for the turret's shaft"))


@dataclass(frozen=True)
class ParallelResult:
    """The plates, the turret's motion over the turn and the checks."""

    cam_angle_deg: FloatArray = field(metadata=doc("the turn's sampled cam angles, 0 ≤ θ < 360"))
    turret_angle_deg: FloatArray = field(metadata=doc("φ: the turret's turn at each"))
    held_forward: NDArray[np.bool_] = field(metadata=doc("some contact drives the turret forward"))
    held_back: NDArray[np.bool_] = field(metadata=doc("some contact holds the turret back"))
    drive_pressure_angle_deg: FloatArray = field(metadata=doc(
        "the smallest |pressure angle| of the contacts that drive (the best placed to carry the load); NaN: none"))
    hold_pressure_angle_deg: FloatArray = field(metadata=doc(
        "the smallest |pressure angle| of the contacts that hold; NaN: none"))
    plates: list[Plate] = field(metadata=doc("one per plate"))
    checks: ParallelChecks = field(metadata=doc("the cam's checks"))


@dataclass(frozen=True)
class _RollerStates:
    """The follower model's contact of every roller of a plate at cam angles (rollers × angles)."""

    x: FloatArray
    y: FloatArray
    pressure_deg: FloatArray
    drives: NDArray[np.bool_]
    kappa: FloatArray
    rho: FloatArray


def _states(cam: ParallelCam, plate: int, theta: FloatArray) -> _RollerStates:
    """Both sides of every roller of the plate at cam angles, shape (2, rollers, angles): side 0 is the
    follower model's contact point (the pitch curve's cam side while the roller goes round the cam
    the way the cam's surface leaves it), side 1 the opposite point of the roller, the cam side
    where the roller overtakes the cam's surface (near the line of centres): there the normal, the
    sense and the curvature turn over."""
    phi, d1, d2 = cam.turret(theta)
    lift = [np.degrees(phi), np.degrees(d1), np.degrees(d2)]
    rows = []
    c, s = np.cos(theta), np.sin(theta)
    rr = cam.roller_radius_mm
    for alpha0 in cam.start_angles(plate):
        k = cam.follower(float(alpha0)).kinematics(0.0, 1.0, theta, lift)
        (x, y), (bx, by) = k.contact, k.pitch
        # atan2(t·v̂, n·v̂): |p| < 90° where the normal (plate into roller) has a forward component
        p = k.pressure
        drives = np.abs(p) < math.pi / 2
        folded = np.degrees(np.where(drives, p, p - np.sign(p) * math.pi))
        with np.errstate(divide="ignore"):
            rho_other = -1.0 / k.kappa_pitch - rr
        rows.append(((c * x + s * y, c * (2 * bx - x) + s * (2 * by - y)),
                     (-s * x + c * y, -s * (2 * bx - x) + c * (2 * by - y)),
                     (folded, folded), (drives, ~drives), (k.kappa_pitch, -k.kappa_pitch), (k.rho_cam, rho_other)))
    return _RollerStates(*(np.stack([np.array([row[q][side] for row in rows]) for side in (0, 1)])
                           for q in range(6)))


def _golden(f: Callable[[FloatArray], FloatArray], lo: FloatArray, hi: FloatArray) -> FloatArray:
    """Minimisers of f (vectorised: one per bracket [lo, hi]) by golden-section search."""
    r = (math.sqrt(5) - 1) / 2
    a, b = lo.copy(), hi.copy()
    x1, x2 = b - r * (b - a), a + r * (b - a)
    f1, f2 = f(x1), f(x2)
    for _ in range(GOLDEN_STEPS):
        left = f1 <= f2  # the minimum is in [a, x2]: x2 ← x1, a new x1; else [x1, b]: x1 ← x2, a new x2
        b = np.where(left, x2, b)
        a = np.where(left, a, x1)
        new = np.where(left, b - r * (b - a), a + r * (b - a))
        f_new = f(new)
        x1, x2 = np.where(left, new, x2), np.where(left, x1, new)
        f1, f2 = np.where(left, f_new, f2), np.where(left, f1, f_new)
    return 0.5 * (a + b)


def _contour(cam: ParallelCam, plate: int, samples: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The plate's contour, each vertex put on the roller that touches it: x, y [mm], roller [-], θ [rad]."""
    path_theta = np.linspace(0.0, 2 * math.pi, PATH_POINTS_PER_SAMPLE * samples + 1)
    alpha0 = cam.start_angles(plate)
    px, py = cam.centres(alpha0[:, None], path_theta[None, :])
    rr, c = cam.roller_radius_mm, cam.center_distance_mm
    paths = [shapely.LineString(np.column_stack([px[k], py[k]])) for k in range(alpha0.size)]
    swept = shapely.unary_union([path.buffer(rr, quad_segs=16) for path in paths])
    free = shapely.Point(0.0, 0.0).buffer(c, quad_segs=256).difference(swept)
    holding = [g for g in getattr(free, "geoms", [free]) if g.contains(shapely.Point(0.0, 0.0))]
    if not holding:
        raise GeometryError(f"The rollers of plate {plate} sweep over the cam axis: nothing is left of the plate.")
    ring = np.asarray(holding[0].exterior.coords)[:-1]
    if np.hypot(ring[:, 0], ring[:, 1]).max() > c * (1 - 1e-6):
        raise GeometryError(
            f"Plate {plate} reaches the turret's axis (center_distance_mm {c!r}): its rollers leave the cam room "
            "past the turret's shaft; fewer stops or more rollers per plate bring them round to the cam.")
    # the nearest path point of every roller, in blocks of vertices (a few MB of distances each)
    roller = np.empty(len(ring), dtype=np.intp)
    guess = np.empty(len(ring))
    block = max(1, 2**20 // px.size)
    for lo in range(0, len(ring), block):
        d2 = (px[None] - ring[lo:lo + block, 0, None, None]) ** 2 + (py[None] - ring[lo:lo + block, 1, None, None]) ** 2
        flat = np.argmin(d2.reshape(d2.shape[0], -1), axis=1)
        roller[lo:lo + block], at = np.divmod(flat, px.shape[1])
        guess[lo:lo + block] = path_theta[at]
    theta = np.empty(len(ring))
    step = path_theta[1]
    for k in np.unique(roller):
        sel = roller == k
        vx, vy = ring[sel, 0], ring[sel, 1]

        def gap(t: FloatArray, a0: float = float(alpha0[k]), vx: FloatArray = vx, vy: FloatArray = vy) -> FloatArray:
            bx, by = cam.centres(a0, t)
            return (bx - vx) ** 2 + (by - vy) ** 2

        theta[sel] = _golden(gap, guess[sel] - 2 * step, guess[sel] + 2 * step)
    bx, by = cam.centres(alpha0[roller], theta)
    dx, dy = ring[:, 0] - bx, ring[:, 1] - by
    scale = rr / np.hypot(dx, dy)
    # a cam angle past either end of the turn is another roller's within it: each turn moves every
    # roller on by the m/stops rollers of one index
    turns = np.floor(theta / (2 * math.pi)).astype(np.intp)
    roller = np.mod(roller + turns * (cam.rollers_per_plate // cam.stops), cam.rollers_per_plate)
    return bx + dx * scale, by + dy * scale, roller, theta - turns * 2 * math.pi


def _plate(cam: ParallelCam, plate: int, samples: int, theta: FloatArray) -> Plate:
    x, y, roller, when = _contour(cam, plate, samples)
    rr = cam.roller_radius_mm
    # pressure angle and curvature of each vertex: the side of its roller that lies there
    at = _states(cam, plate, when)
    cols = np.arange(when.size)
    near = [np.hypot(at.x[side, roller, cols] - x, at.y[side, roller, cols] - y) for side in (0, 1)]
    side = (near[1] < near[0]).astype(np.intp)
    pressure = at.pressure_deg[side, roller, cols]
    rho = at.rho[side, roller, cols]
    # contacts over the turn: envelope points on the contour
    states = _states(cam, plate, theta)
    ring = shapely.LinearRing(np.column_stack([x, y]))
    # only points within the contour's largest radius can lie on it
    gap = np.full(states.x.shape, np.inf)
    near_ring = np.hypot(states.x, states.y) <= np.hypot(x, y).max() + NEAR_PLATE * rr
    gap[near_ring] = shapely.distance(shapely.points(states.x[near_ring], states.y[near_ring]), ring)
    touching = gap <= CONTACT_TOLERANCE * rr
    at_plate = gap <= NEAR_PLATE * rr
    _, roller_idx, theta_idx = np.nonzero(touching)
    contacts = Contacts(np.degrees(theta[theta_idx]), roller_idx, states.pressure_deg[touching],
                        states.drives[touching])
    radius = np.hypot(x, y)
    convex = rho[rho > 0]
    undercut = bool(np.any(at_plate & (states.kappa > 0) & (states.kappa * rr > 1)))
    checks = PlateChecks(
        min_convex_radius_of_curvature_mm=float(convex.min()) if convex.size else None,
        undercut=undercut, min_radius_mm=float(radius.min()), max_radius_mm=float(radius.max()))
    return Plate(plate, np.degrees(cam.start_angles(plate)), x, y, roller.astype(np.intp), np.degrees(when), pressure, rho,
                 contacts, checks)


def sample_parallel(cam: ParallelCam, samples: int = 361) -> ParallelResult:
    """The plates of a parallel indexing cam: contours, contacts and checks.

    Parameters
    ----------
    cam : ParallelCam
        The cam (:func:`camcore.cams.parallel.make_parallel_cam`).
    samples : int
        Rays from the cam axis per contour, and cam angles over the turn (evenly, 0 ≤ θ < 360°)
        at which contacts are found [-].

    Returns
    -------
    ParallelResult
        Each plate's contour (the rays' crossings and the contact points on it, by polar
        angle) [mm], its contacts and checks; the turret's angle and whether it is held both
        ways at each sampled cam angle.

    Raises
    ------
    GeometryError
        A plate wider than the centre distance (it would cross the turret's axis).

    References
    ----------
    INDEXMAN technical guide, section 5 (the index law); Shinzato and Kunigami (1988) (the
    oscillating roller follower).
    """
    n = count("samples", samples)
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    plates = [_plate(cam, p, n, theta) for p in range(cam.plates)]
    best = {True: np.full(n, np.inf), False: np.full(n, np.inf)}  # by sense: drives, holds
    step = 360.0 / n
    for plate in plates:
        i = np.rint(plate.contacts.cam_angle_deg / step).astype(np.intp)
        for sense in (True, False):
            mine = plate.contacts.drives == sense
            np.minimum.at(best[sense], i[mine], np.abs(plate.contacts.pressure_angle_deg[mine]))
    forward, back = np.isfinite(best[True]), np.isfinite(best[False])
    unheld = np.flatnonzero(~(forward & back))
    drive, hold = (np.where(np.isfinite(best[s]), best[s], np.nan) for s in (True, False))
    index = theta <= math.radians(cam.indexer.indexing_angle_deg)
    worst_of = np.where(index, np.fmax(drive, hold), np.nan)
    worst = int(np.nanargmax(worst_of)) if np.isfinite(worst_of).any() else 0
    clearance = cam.center_distance_mm - max(p.checks.max_radius_mm for p in plates)
    checks = ParallelChecks(
        conjugate=not unheld.size, unheld_cam_angles_deg=[float(step * i) for i in unheld[:LISTED_ANGLES]],
        max_pressure_angle_deg=float(np.nan_to_num(worst_of[worst])),
        max_pressure_angle_at_deg=float(np.degrees(theta[worst])),
        undercut=any(p.checks.undercut for p in plates), turret_axis_clearance_mm=float(clearance))
    return ParallelResult(np.degrees(theta), np.degrees(cam.turret(theta)[0]), forward, back, drive, hold, plates,
                          checks)
