"""A plate's exact contour as points: every point on the contour, none farther apart than the chord
tolerance allows; and distances from a polyline.

The points of a piece are its ends and the rollers' envelope at the sampled cam angles between
them, every one exact (:mod:`.envelope`). A chord between two points of a curve of radius ρ
stands off it by (length)²/(8ρ), so each step is cut into equal steps of the cam angle until its
chord is at most √(8·ρ·δ) long, ρ the smaller radius at its ends: no chord then stands off the
contour by more than δ = ``CHORD_SHARE``·Rr (to first order: the radius varies little over a
step). A chord of a convex stretch lies inside the plate and one of a concave stretch outside,
so no roller that keeps off the exact contour comes into the polyline by more than δ either.

References
----------
.. [1] The sagitta of a circular arc: s = c²/(8ρ) for a chord c, to first order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import NDArray

from ...curves.base import FloatArray
from .envelope import EnvelopePoints, envelope
from .geometry import ParallelCam
from .neighbours import CellGrid
from .trace import PlateContour

#: δ, the largest distance of the polyline from the exact contour, as a share of Rr: 1.2 µm at
#: Rr = 12 mm, below a machine's resolution; the points are then ~0.34 mm apart on a roller's arc
CHORD_SHARE = 1e-4
#: a step is cut into at most this many: the contour's radius of curvature near a cusp of an
#: undercut envelope tends to 0, which no finite cut follows
MOST_CUTS = 256
#: the cuts aim at this share of δ, so a chord whose largest offset is not at its middle (the
#: radius varies along it) still keeps within δ
AIM = 0.8
#: passes that cut again a chord whose middle stands off the contour by more than AIM·δ (the cuts of a
#: step are even in cam angle, not in length); one is enough where the speed is steady
REFINE_PASSES = 3


@dataclass(frozen=True)
class ContourPoints:
    """Points of a plate's contour, in order (counter-clockwise), the first not repeated.

    ``piece``: the piece each lies on; ``tau``: its roller's cam angle there (any real) [rad];
    ``roller``: the roller of the layer at the cam angle ``cam_angle`` (0 ≤ θ < 2π) [rad];
    ``pressure_deg``, ``drives``, ``rho`` as :class:`camcore.cams.parallel.envelope.EnvelopePoints`.
    """

    x: FloatArray
    y: FloatArray
    piece: NDArray[np.intp]
    tau: FloatArray
    roller: NDArray[np.intp]
    cam_angle: FloatArray
    pressure_deg: FloatArray
    drives: NDArray[np.bool_]
    rho: FloatArray


def _piece_angles(contour: PlateContour, step: float) -> list[FloatArray]:
    """Each piece's cam angles: its start, the sampled angles inside, its end."""
    out = []
    for p in contour.pieces:
        a, b = p.tau_start_rad, p.tau_end_rad
        lo, hi = min(a, b), max(a, b)
        inside = np.arange(math.floor(lo / step) + 1, math.ceil(hi / step)) * step
        inside = inside[(inside > lo) & (inside < hi)]
        out.append(np.concatenate([[a], inside if b > a else inside[::-1], [b]]))
    return out


def _envelope_reusing(cam: ParallelCam, alpha: FloatArray, side: FloatArray, tau: FloatArray, known: EnvelopePoints,
                      known_tau: FloatArray, source: NDArray[np.intp]) -> EnvelopePoints:
    """:func:`envelope` at (α₀, side, τ), each point whose τ is the same float as ``known_tau[source]``
    taken from ``known`` there (its α₀ and side are the same: it is the same point) and only the others
    computed."""
    old = known_tau[source]
    fresh = np.flatnonzero((tau != old) | (np.signbit(tau) != np.signbit(old)))
    new = envelope(cam, alpha[fresh], side[fresh], tau[fresh])
    columns = {}
    for name in (f.name for f in fields(EnvelopePoints)):
        column = getattr(known, name)[source]
        column[fresh] = getattr(new, name)
        columns[name] = column
    return EnvelopePoints(**columns)


def contour_points(contour: PlateContour, step: float) -> ContourPoints:
    """A plate's contour as points (module notes): exact, within δ of the contour between them.

    Parameters
    ----------
    contour : PlateContour
        The plate's pieces.
    step : float
        The sampled cam angles' step, 2π/samples [rad].

    Returns
    -------
    ContourPoints
        The points, each piece's end left out (it is the next piece's start), with what touches
        the contour there.

    References
    ----------
    The sagitta of an arc, c²/(8ρ) (module notes).
    """
    cam = contour.cam
    rr = cam.roller_radius_mm
    chord = AIM * CHORD_SHARE * rr
    angles = _piece_angles(contour, step)
    which = np.repeat(np.arange(len(angles)), [a.size for a in angles])
    alpha = np.array([p.alpha0_rad for p in contour.pieces])[which]
    side = np.array([float(p.side) for p in contour.pieces])[which]
    tau = np.concatenate(angles)
    e = envelope(cam, alpha, side, tau)
    # the cuts of each step (a step ends a piece where the next piece starts)
    same = which[1:] == which[:-1]
    length = np.hypot(np.diff(e.x), np.diff(e.y))
    radius = np.fmin(np.abs(e.rho[1:]), np.abs(e.rho[:-1]))
    radius = np.where(np.isfinite(radius) & (radius > 0), radius, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        cuts = np.ceil(length / np.sqrt(8 * radius * chord))
    cuts = np.where(np.isfinite(cuts), np.clip(cuts, 1, MOST_CUTS), MOST_CUTS).astype(np.intp)
    cuts = np.where(same, cuts, 0)  # no step from a piece's end to the next piece's start
    starts = np.flatnonzero(same)
    k = cuts[starts]
    owner = np.repeat(starts, k)
    frac = (np.arange(int(k.sum())) - np.repeat(np.cumsum(k) - k, k)) / np.repeat(k, k)
    tau_all = tau[owner] + frac * (tau[owner + 1] - tau[owner])
    piece = which[owner]
    p = _envelope_reusing(cam, alpha[owner], side[owner], tau_all, e, tau, owner)
    # where the envelope's speed varies within a step (a roller all but stopping) the even cuts
    # are uneven in length: each chord whose middle stands off by more than δ is cut again (only the
    # chords cut in the pass before are measured again: the others' middles are within δ)
    todo = np.arange(tau_all.size)
    for _ in range(REFINE_PASSES):
        nxt_tau = np.append(tau_all[1:], np.nan)
        inner = np.append(piece[1:] == piece[:-1], False)
        # a piece's last chord runs to its end, the next piece's start (the same point)
        ends = np.flatnonzero(~inner)
        nxt_tau[ends] = [contour.pieces[k].tau_end_rad for k in piece[ends]]
        mid = envelope(cam, alpha[owner[todo]], side[owner[todo]], 0.5 * (tau_all[todo] + nxt_tau[todo]))
        nx = np.append(p.x[1:], p.x[0])
        ny = np.append(p.y[1:], p.y[0])
        end_pts = envelope(cam, alpha[owner][ends], side[owner][ends], nxt_tau[ends])
        nx[ends], ny[ends] = end_pts.x, end_pts.y
        x0, y0 = p.x[todo], p.y[todo]
        cx, cy = nx[todo] - x0, ny[todo] - y0
        norm = np.hypot(cx, cy)
        with np.errstate(divide="ignore", invalid="ignore"):
            off = np.abs((mid.x - x0) * cy - (mid.y - y0) * cx) / norm
        off = np.where(norm > 0, off, np.hypot(mid.x - x0, mid.y - y0))
        more = np.ones(tau_all.size, dtype=np.intp)
        more[todo] = np.where(off > chord, np.minimum(np.ceil(np.sqrt(off / chord) * 1.5), MOST_CUTS), 1)
        if (more == 1).all():
            break
        frac = (np.arange(int(more.sum())) - np.repeat(np.cumsum(more) - more, more)) / np.repeat(more, more)
        base = np.repeat(np.arange(tau_all.size), more)
        last_tau = tau_all
        tau_all = tau_all[base] + frac * (nxt_tau[base] - tau_all[base])
        owner, piece = owner[base], piece[base]
        p = _envelope_reusing(cam, alpha[owner], side[owner], tau_all, p, last_tau, base)
        todo = np.flatnonzero(more[base] > 1)
    g = cam.rollers_per_plate // cam.stops
    first = np.array([pc.roller for pc in contour.pieces])[piece]
    turns = np.floor(tau_all / (2 * math.pi))
    roller = np.mod(first + turns.astype(np.intp) * g, cam.rollers_per_plate).astype(np.intp)
    return ContourPoints(p.x, p.y, piece.astype(np.intp), tau_all, roller, tau_all - turns * 2 * math.pi,
                         p.pressure_deg, p.drives, p.rho)


def distance_to_polyline(qx: FloatArray, qy: FloatArray, vx: FloatArray, vy: FloatArray, reach: float) -> FloatArray:
    """Distance of each point from a closed polyline where it is within ``reach``; +∞ farther.

    Parameters
    ----------
    qx, qy : ndarray
        The points [mm].
    vx, vy : ndarray
        The polyline's vertices, closed from the last back to the first [mm].
    reach : float
        The largest distance wanted [mm].

    Returns
    -------
    ndarray
        The distances [mm]: exact to each segment, +∞ beyond ``reach``.

    References
    ----------
    Bentley and Friedman (1979), cells (:mod:`.neighbours`); the distance to a segment by the
    clamped projection on it.
    """
    ex, ey = np.roll(vx, -1) - vx, np.roll(vy, -1) - vy
    seg2 = ex * ex + ey * ey
    # a point within reach of a segment is within reach + its length of its first vertex
    grid = CellGrid(vx, vy, reach + float(np.sqrt(seg2.max(initial=0.0))))
    qi, vi = grid.pairs(qx, qy)
    dx, dy = qx[qi] - vx[vi], qy[qi] - vy[vi]
    with np.errstate(invalid="ignore", divide="ignore"):
        u = np.clip(np.where(seg2[vi] > 0, (dx * ex[vi] + dy * ey[vi]) / seg2[vi], 0.0), 0.0, 1.0)
    d = np.hypot(dx - u * ex[vi], dy - u * ey[vi])
    out = np.full(qx.shape, np.inf)
    np.minimum.at(out, qi, d)
    return np.where(out <= reach, out, np.inf)
