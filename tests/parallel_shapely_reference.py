"""The parallel cam's plates as camcore drew them before issue 36: by polygon boolean operations.

Kept as an independent route for tests/camcore/cams/test_parallel.py: the contour of each plate
is what Shapely leaves of a disc of radius C once every roller's swept band (its path over the
turn as a polyline, widened by its radius) is taken away, each ring vertex then put on the exact
circle of the nearest roller. Its error is its own: the chords of the polyline between exact
vertices cut into a roller by (spacing)²/(8·Rr), and a vertex near where two rollers' pieces meet
may be put on the wrong one's circle. Nothing here uses camcore.cams.parallel's tracing.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely

from camcore.cams.parallel.geometry import ParallelCam
from camcore.curves.base import FloatArray
from camcore.errors import GeometryError

#: path points per sampled cam angle: at 181 samples a path moving 150 mm/rad steps 0.65 mm, and
#: the contour's chords between exact points cut into a roller by (step)²/(8·Rr), 4.4e-3 mm for
#: Rr = 12 mm (tests/camcore/cams/test_parallel.py measures it)
PATH_POINTS_PER_SAMPLE = 8
#: golden-section steps putting a vertex on its roller: a bracket of 4 path steps (≤ 1°)
#: shrinks by 0.618^50 to 1e-12 rad
GOLDEN_STEPS = 50


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


def shapely_contour(cam: ParallelCam, plate: int, samples: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The plate's contour, each vertex put on the roller that touches it: x, y [mm], roller [-], θ [rad].

    The rollers' paths over the turn as polylines of 8 points per sampled cam angle, each widened by
    Rr (Shapely's buffer), their union taken from a disc of radius C, the part holding the axis
    kept; each vertex of its ring moved onto the circle of the roller whose centre is nearest (the
    cam angle by golden section on the exact index law)."""
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
