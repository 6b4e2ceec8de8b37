"""The plates of a parallel indexing cam: contours, contacts, pressure angles, checks.

Each plate's contour is traced exactly (:mod:`.trace`: the pieces of its rollers' envelopes, the
crossings solved) and written as points within ``CHORD_SHARE``·Rr of it (:mod:`.polyline`). A
roller touches its plate at a sampled cam angle where one of its two envelope points is free (no
roller at any cam angle comes nearer to it than Rr − ε, :mod:`.trace`) and lies on the contour
(within the polyline's δ of it). The force of the plate on the roller acts along the contact
normal (from the plate into the roller): it drives the turret forward where the normal has a
component along the roller's velocity, and holds it back otherwise. The plates hold the turret
(conjugacy) at a cam angle where some contact drives and some contact holds.

References
----------
.. [1] INDEXMAN technical guide, section 5: the index law the turret follows.
.. [2] Shinzato and Kunigami (1988): the oscillating roller follower's pitch curve and pressure
   angle (:mod:`camcore.profile.followers`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..._checks import count
from ...errors import GeometryError
from ...results import doc
from .geometry import FloatArray, ParallelCam
from .polyline import CHORD_SHARE, ContourPoints, contour_points, distance_to_polyline
from .trace import PlateContour, PlateSamples, TooCoarse, trace_plate

#: a roller counts as at its plate (for the undercut check) within this share of its radius
NEAR_PLATE = 0.05
#: the envelopes are traced at no fewer cam angles per turn than this (a whole multiple of the
#: answer's): at 0.5° a roller moves ≲ 1.5 mm a step, a few hundredths of its radius of
#: curvature, where each crossing's Newton start is good; coarser, a stretch of a few steps (a
#: notch) may be stepped over
TRACE_SAMPLES = 720
#: where that is too coarse to follow a roller whose path all but stops (its envelope sweeps round
#: it within a step: a 5 mm roller on a 36-stop turret, traced at 720), the trace is done again
#: twice as fine, at most this many times
REFINEMENTS = 2
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
    """One plate: its contour in the cam's frame (counter-clockwise round the axis), contacts and checks."""

    plate: int = field(metadata=doc("0 … plates − 1"))
    roller_start_angle_deg: FloatArray = field(metadata=doc("arm angle α₀ of each roller of its layer at θ = 0"))
    x_mm: FloatArray = field(metadata=doc(
        "contour, cam frame, counter-clockwise: exact points, within 1e-4·Rr of the exact contour between them"))
    y_mm: FloatArray = field(metadata=doc("contour, cam frame"))
    roller: NDArray[np.intp] = field(metadata=doc("the roller that touches the contour there"))
    contact_cam_angle_deg: FloatArray = field(metadata=doc("the cam angle at which it touches there"))
    pressure_angle_deg: FloatArray = field(metadata=doc("pressure angle of that contact, within ±90°"))
    radius_of_curvature_mm: FloatArray = field(metadata=doc(
        "of the contour there: positive convex, negative concave"))
    contacts: Contacts = field(metadata=doc(
        "every contact over the turn's sampled cam angles (side −1 envelope points first, by roller, by angle)"))
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
    contours: list[PlateContour] = field(default_factory=list, repr=False, metadata=doc(
        "each plate's exact contour (its pieces), for files and fits; not part of an answer"))


def _contacts(cam: ParallelCam, s: PlateSamples, px: FloatArray, py: FloatArray, finer: int
              ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Which sampled envelope points touch the plate (free and on the contour) and which are at it
    (within NEAR_PLATE·Rr of the contour), shape (2, chains, L); only every ``finer``-th point, the
    answer's cam angles, is asked."""
    rr = cam.roller_radius_mm
    chord = CHORD_SHARE * rr
    radius = np.hypot(px, py)
    ex, ey = s.env.x, s.env.y
    r = np.hypot(ex, ey)
    near_ring = (r >= radius.min() - NEAR_PLATE * rr) & (r <= radius.max() + NEAR_PLATE * rr)
    near_ring[:, :, np.arange(s.length) % finer != 0] = False
    flat = np.flatnonzero(near_ring.reshape(-1))
    gap_flat = np.full(ex.size, np.inf)
    gap_flat[flat] = distance_to_polyline(ex.reshape(-1)[flat], ey.reshape(-1)[flat], px, py, NEAR_PLATE * rr)
    gap = gap_flat.reshape(ex.shape)
    # a point of the exact contour is within δ of the polyline (and rounding of 100 mm coordinates)
    on = gap <= chord * (1 + 1e-6) + 1e-12 * cam.center_distance_mm
    touching = np.zeros(ex.shape, dtype=bool)
    for side in range(2):
        for chain in range(s.alpha0.size):
            j = np.flatnonzero(on[side, chain])
            if j.size:
                touching[side, chain, j] = s.is_free(side, chain, j)
    return touching, gap <= NEAR_PLATE * rr


def _check_round_the_axis(cam: ParallelCam, plate: int, x: FloatArray, y: FloatArray) -> None:
    """The contour must go once round the cam axis and stay inside the turret's axis."""
    c = cam.center_distance_mm
    turns = float(np.sum(np.diff(np.unwrap(np.arctan2(np.append(y, y[0]), np.append(x, x[0])))))) / (2 * math.pi)
    if round(turns) != 1 or float(np.hypot(x, y).max()) > c * (1 - 1e-6):
        raise GeometryError(
            f"Plate {plate} reaches the turret's axis (center_distance_mm {c!r}): its rollers leave the cam room past "
            "the turret's shaft; fewer stops or more rollers per plate bring them round to the cam.")


def _trace(cam: ParallelCam, plate: int, samples: int, finer: int
           ) -> tuple[PlateContour, PlateSamples, int, ContourPoints]:
    """The plate traced at samples × finer cam angles, or twice or four times that where a roller's
    path all but stops and its envelope sweeps round the roller within a step; its points checked
    to go once round the axis inside the turret's axis."""
    for more in range(REFINEMENTS + 1):
        try:
            contour, s = trace_plate(cam, plate, samples * finer * 2**more)
            break
        except TooCoarse:
            if more == REFINEMENTS:
                raise
    pts = contour_points(contour, s.step)
    _check_round_the_axis(cam, plate, pts.x, pts.y)
    return contour, s, finer * 2**more, pts


def plate_contour(cam: ParallelCam, plate: int, samples: int) -> tuple[PlateContour, ContourPoints]:
    """One plate's exact contour and its points, without the contacts (for its files).

    Parameters
    ----------
    cam : ParallelCam
        The cam.
    plate : int
        0 … plates − 1 [-].
    samples : int
        Cam angles per turn, as :func:`sample_parallel` takes them (traced at least 720 a turn) [-].

    Returns
    -------
    (PlateContour, ContourPoints)
        The pieces and the points (counter-clockwise, within 1e-4·Rr of the contour).

    Raises
    ------
    GeometryError
        As :func:`sample_parallel`.

    References
    ----------
    :mod:`camcore.cams.parallel.trace` (the method).
    """
    n = count("samples", samples)
    contour, _s, _finer, pts = _trace(cam, plate, n, trace_factor(n))
    return contour, pts


def _plate(cam: ParallelCam, plate: int, samples: int, finer: int) -> tuple[Plate, PlateContour]:
    contour, s, finer, pts = _trace(cam, plate, samples, finer)
    touching, at_plate = _contacts(cam, s, pts.x, pts.y, finer)
    side, chain, j = np.nonzero(touching)
    roller = s.roller(chain, j)
    i = (j % (samples * finer)) // finer
    # the answer's order: side −1 first, then by roller, then by cam angle
    order = np.lexsort((i, roller, side))
    contacts = Contacts(np.degrees(i[order] * (2 * math.pi / samples)), roller[order].astype(np.intp),
                        s.env.pressure_deg[side, chain, j][order], s.env.drives[side, chain, j][order])
    radius = np.hypot(pts.x, pts.y)
    convex = pts.rho[pts.rho > 0]
    kappa = s.env.kappa
    undercut = bool(np.any(at_plate & (kappa > 0) & (kappa * cam.roller_radius_mm > 1)))
    checks = PlateChecks(
        min_convex_radius_of_curvature_mm=float(convex.min()) if convex.size else None,
        undercut=undercut, min_radius_mm=float(radius.min()), max_radius_mm=float(radius.max()))
    return Plate(plate, np.degrees(cam.start_angles(plate)), pts.x, pts.y, pts.roller, np.degrees(pts.cam_angle),
                 pts.pressure_deg, pts.rho, contacts, checks), contour


def trace_factor(samples: int) -> int:
    """How many times finer than the answer's cam angles the envelopes are traced.

    Parameters
    ----------
    samples : int
        The answer's cam angles per turn [-].

    Returns
    -------
    int
        The factor, the least whole number making samples × factor ≥ TRACE_SAMPLES [-].

    References
    ----------
    The measurement beside :data:`TRACE_SAMPLES`.
    """
    return max(1, math.ceil(TRACE_SAMPLES / samples))


def sample_parallel(cam: ParallelCam, samples: int = 361) -> ParallelResult:
    """The plates of a parallel indexing cam: exact contours, contacts and checks.

    Parameters
    ----------
    cam : ParallelCam
        The cam (:func:`camcore.cams.parallel.make_parallel_cam`).
    samples : int
        Cam angles evenly over the turn (0 ≤ θ < 360°) at which the rollers' envelopes are taken
        and the contacts found; the contours' points are at those angles, at the crossings, and
        between them where the chord tolerance needs more [-].

    Returns
    -------
    ParallelResult
        Each plate's contour (counter-clockwise, exact points within 1e-4·Rr of it between them)
        [mm], its contacts and checks; the turret's angle and whether it is held both ways at
        each sampled cam angle; the exact contours.

    Raises
    ------
    GeometryError
        A plate wider than the centre distance (it would cross the turret's axis), rollers that
        sweep over the cam axis, or a sampling too coarse to tell three envelopes apart.

    References
    ----------
    INDEXMAN technical guide, section 5 (the index law); Shinzato and Kunigami (1988) (the
    oscillating roller follower); Farouki and Neff (1990) (offset curves).
    """
    n = count("samples", samples)
    theta = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    finer = trace_factor(n)
    made = [_plate(cam, p, n, finer) for p in range(cam.plates)]
    plates = [m[0] for m in made]
    best = {True: np.full(n, np.inf), False: np.full(n, np.inf)}  # by sense: drives, holds
    step = 360.0 / n
    for plate in plates:
        i = np.rint(plate.contacts.cam_angle_deg / step).astype(np.intp) % n
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
                          checks, [m[1] for m in made])
