"""Lines and circular arcs in the plane: the elements of a toolpath, biarcs, distances.

An :class:`Element` is a straight line or a circular arc from ``start`` to ``end``; an arc
also has its ``centre`` and its sense (``ccw``: counter-clockwise seen from +z, as G3; else
clockwise, as G2). A biarc joins two points with given unit tangents by two arcs that meet
with a common tangent; of the one-parameter family this module takes the one whose two
tangent legs are equal (Bolton 1975), which is symmetric in its ends and defined whenever
the tangents do not both point against the chord.

References
----------
.. [1] K. M. Bolton, "Biarc curves", Computer-Aided Design 7 (1975) 89-92.
.. [2] D. S. Meek, D. J. Walton, "Approximation of discrete data by G1 arc splines",
   Computer-Aided Design 24 (1992) 301-306.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..curves.base import FloatArray

#: an arc whose sagitta over its chord would be below this fraction of the chord is written
#: as a line: its curvature is rounding noise (a chord of 10 mm bulging by 1e-12 mm)
STRAIGHT = 1e-13


@dataclass(frozen=True)
class Element:
    """One element of a path: a line, or an arc about ``centre`` (``ccw`` its sense).

    ``theta0_rad`` and ``theta1_rad`` are the cam angles of the exact curve the element
    stands for (equal for an arc that rounds a corner of the cam).
    """

    start: tuple[float, float]
    end: tuple[float, float]
    centre: tuple[float, float] | None = None
    ccw: bool = True
    theta0_rad: float = 0.0
    theta1_rad: float = 0.0

    @property
    def is_arc(self) -> bool:
        """Whether the element is an arc (else a line)."""
        return self.centre is not None

    @property
    def radius_mm(self) -> float:
        """The arc's radius (infinite for a line) [mm]."""
        if self.centre is None:
            return math.inf
        return math.hypot(self.start[0] - self.centre[0], self.start[1] - self.centre[1])

    @property
    def sweep_rad(self) -> float:
        """Signed angle the arc turns through, positive counter-clockwise (0 for a line) [rad]."""
        if self.centre is None:
            return 0.0
        return _sweep(self.start, self.end, self.centre, self.ccw)

    @property
    def length_mm(self) -> float:
        """Length along the element [mm]."""
        if self.centre is None:
            return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])
        return self.radius_mm * abs(self.sweep_rad)

    def reversed(self) -> Element:
        """The same element run the other way."""
        return Element(self.end, self.start, self.centre, not self.ccw, self.theta1_rad, self.theta0_rad)

    def points(self, count: int) -> FloatArray:
        """``count`` points evenly along the element, both ends included, shape (count, 2) [mm]."""
        u = np.linspace(0.0, 1.0, count)
        if self.centre is None:
            sx, sy = self.start
            ex, ey = self.end
            return np.column_stack([sx + u * (ex - sx), sy + u * (ey - sy)])
        cx, cy = self.centre
        r = self.radius_mm
        a = math.atan2(self.start[1] - cy, self.start[0] - cx) + u * self.sweep_rad
        pts = np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])
        pts[-1] = self.end  # the exact end, not its rounding through the angle
        return pts

    def distance(self, x: FloatArray, y: FloatArray) -> FloatArray:
        """Distance of the points (x, y) from the element (not its full line or circle) [mm]."""
        sx, sy = self.start
        ex, ey = self.end
        if self.centre is None:
            dx, dy = ex - sx, ey - sy
            length2 = dx * dx + dy * dy
            if length2 == 0.0:
                return np.minimum(np.hypot(x - sx, y - sy), np.hypot(x - ex, y - ey))
            u = np.clip(((x - sx) * dx + (y - sy) * dy) / length2, 0.0, 1.0)
            return np.hypot(x - (sx + u * dx), y - (sy + u * dy))
        return _arcs_distance((self.start, self.end), (_arc_row(self.start, self.end, self.centre, self.ccw),),
                              x, y)[0]

    def extreme_points(self) -> list[tuple[float, float]]:
        """The ends and, for an arc, its points farthest along ±x and ±y (its bounding box) [mm]."""
        pts = [self.start, self.end]
        if self.centre is None:
            return pts
        cx, cy = self.centre
        r = self.radius_mm
        a0 = math.atan2(self.start[1] - cy, self.start[0] - cx)
        sweep = self.sweep_rad
        for k, (px, py) in enumerate(((cx + r, cy), (cx, cy + r), (cx - r, cy), (cx, cy - r))):
            rel = ((k * math.pi / 2 - a0) * math.copysign(1.0, sweep)) % (2 * math.pi)
            if rel <= abs(sweep):
                pts.append((px, py))
        return pts


def pair_distance(pair: tuple[Element, Element], x: FloatArray, y: FloatArray) -> FloatArray:
    """Distance of the points (x, y) from the nearer of two elements (a biarc) [mm].

    Parameters
    ----------
    pair : (Element, Element)
        The elements.
    x, y : ndarray
        The points, one dimension [mm].

    Returns
    -------
    ndarray
        The distance, ``np.minimum(pair[0].distance(x, y), pair[1].distance(x, y))`` to the bit:
        two arcs are measured in one pass of :meth:`Element.distance`'s operations over a row each
        (the greedy fit asks this of a few dozen points, dozens of times per path, where each pass
        costs mostly its fixed part) [mm].

    References
    ----------
    Bolton (1975), biarcs; the distance from a circular arc: radial where the point's angle is
    within the sweep, else to the nearer end.
    """
    first, second = pair
    if first.centre is None or second.centre is None:
        return np.minimum(first.distance(x, y), second.distance(x, y))
    # a biarc's joint ends the first arc and starts the second: its distances are taken once
    ends = ((first.start, first.end, second.end) if first.end == second.start else
            (first.start, first.end, second.start, second.end))
    both = _arcs_distance(ends, (_arc_row(first.start, first.end, first.centre, first.ccw),
                                 _arc_row(second.start, second.end, second.centre, second.ccw)), x, y)
    return np.minimum(both[0], both[1])


def _arcs_distance(ends: tuple[tuple[float, float], ...], rows: tuple[tuple[float, ...], ...],
                   x: FloatArray, y: FloatArray) -> FloatArray:
    """Distance of the points (x, y) from each of some arcs, a row per arc (:func:`_arc_row`): radial where
    the point's angle about the centre is within the sweep, else to the nearer end. ``ends``: one more
    than the arcs when each starts where the one before ends (a joint's distance taken once), else two
    per arc."""
    corner = np.array(ends).T[:, :, None]
    cx, cy, a0, sense, width, radius = np.array(rows).T[:, :, None]
    to_end = np.hypot(x - corner[0], y - corner[1])
    chained = len(ends) == len(rows) + 1
    to_ends = np.minimum(to_end[:-1], to_end[1:]) if chained else np.minimum(to_end[0::2], to_end[1::2])
    dx, dy = x - cx, y - cy
    # angle of each point from the start, measured in the arc's sense, in [0, 2π)
    rel = np.mod((np.arctan2(dy, dx) - a0) * sense, 2 * math.pi)
    radial = np.abs(np.hypot(dx, dy) - radius)
    return np.where(rel <= width, radial, to_ends)


def _arc_row(start: tuple[float, float], end: tuple[float, float], centre: tuple[float, float], ccw: bool
             ) -> tuple[float, float, float, float, float, float]:
    """An arc's centre, the angle of its start about the centre, the sign and size of its sweep (turning
    counter-clockwise when ``ccw``) and its radius: the one definition :class:`Element`'s properties and
    the distances read."""
    (sx, sy), (cx, cy) = start, centre
    sweep = _sweep(start, end, centre, ccw)
    return cx, cy, math.atan2(sy - cy, sx - cx), math.copysign(1.0, sweep), abs(sweep), math.hypot(sx - cx, sy - cy)


def _sweep(start: tuple[float, float], end: tuple[float, float], centre: tuple[float, float], ccw: bool) -> float:
    """The signed angle an arc turns through from ``start`` to ``end`` about ``centre``, positive
    counter-clockwise, in the arc's sense (``ccw``) [rad]."""
    (sx, sy), (ex, ey), (cx, cy) = start, end, centre
    a0 = math.atan2(sy - cy, sx - cx)
    a1 = math.atan2(ey - cy, ex - cx)
    return (a1 - a0) % (2 * math.pi) if ccw else -((a0 - a1) % (2 * math.pi))


def _centre(start: tuple[float, float], tangent: tuple[float, float], end: tuple[float, float], chord2: float
            ) -> tuple[tuple[float, float] | None, bool]:
    """The centre (None: a line) and sense of the arc from ``start`` leaving along the unit ``tangent`` to
    ``end``, from its chord's squared length ``chord2`` (numpy's dot product of the chord: a fused
    multiply-add that Python's floats have not). Bolton (1975): an arc is fixed by one end, its
    tangent there and the other end; its signed curvature is 2 (t × c)/|c|² for the chord c."""
    cross = tangent[0] * (end[1] - start[1]) - tangent[1] * (end[0] - start[0])
    if chord2 == 0.0 or abs(cross) <= STRAIGHT * chord2:
        return None, True
    curvature = 2.0 * cross / chord2
    # centre on the left of the tangent for a left turn (ccw), on the right for a right turn
    return (start[0] - tangent[1] / curvature, start[1] + tangent[0] / curvature), curvature > 0


class Biarc(NamedTuple):
    """An equal-leg biarc as numbers (:func:`biarc_of`): its ends and joint [mm], each arc's centre
    (None: a line) [mm] and sense as run from ``start`` to ``end`` (ccw, as G3)."""

    start: tuple[float, float]
    joint: tuple[float, float]
    end: tuple[float, float]
    centres: tuple[tuple[float, float] | None, tuple[float, float] | None]
    ccw: tuple[bool, bool]

    def elements(self, theta0: float = 0.0, theta1: float = 0.0) -> tuple[Element, Element]:
        """The two elements, standing for cam angles θ0 … θ1 (the joint gets their mean) [rad]."""
        mid = 0.5 * (theta0 + theta1)
        return (Element(self.start, self.joint, self.centres[0], self.ccw[0], theta0, mid),
                Element(self.joint, self.end, self.centres[1], self.ccw[1], mid, theta1))

    def distance(self, x: FloatArray, y: FloatArray) -> FloatArray:
        """:func:`pair_distance` of :meth:`elements` to the bit, without making them [mm]."""
        (c0, c1), (ccw0, ccw1) = self.centres, self.ccw
        if c0 is None or c1 is None:
            return pair_distance(self.elements(), x, y)
        both = _arcs_distance((self.start, self.joint, self.end), (_arc_row(self.start, self.joint, c0, ccw0),
                                                                   _arc_row(self.joint, self.end, c1, ccw1)), x, y)
        return np.minimum(both[0], both[1])


def biarc(p0: FloatArray, t0: FloatArray, p1: FloatArray, t1: FloatArray, theta0: float = 0.0,
          theta1: float = 0.0) -> tuple[Element, Element] | None:
    """The equal-leg biarc from ``p0`` (unit tangent ``t0``) to ``p1`` (unit tangent ``t1``).

    Parameters
    ----------
    p0, p1 : ndarray
        The ends (x, y) [mm].
    t0, t1 : ndarray
        Unit tangents at the ends, in the direction of travel [-].
    theta0, theta1 : float
        Cam angles of the curve the biarc stands for; the joint gets their mean [rad].

    Returns
    -------
    (Element, Element) or None
        The two elements, or None where no equal-leg biarc exists (both tangents against
        the chord).

    References
    ----------
    Bolton (1975): legs of equal length d, |p1 − d t1 − (p0 + d t0)| = 2d, the joint
    halfway between the two leg ends; Meek and Walton (1992), G1 arc splines.
    """
    found = biarc_of(p0, t0, p1, t1)
    return None if found is None else found.elements(theta0, theta1)


def biarc_of(p0: FloatArray, t0: FloatArray, p1: FloatArray, t1: FloatArray) -> Biarc | None:
    """:func:`biarc` as numbers, without its elements (the greedy fit tries several per element it keeps).

    Parameters
    ----------
    p0, p1 : ndarray
        The ends (x, y) [mm].
    t0, t1 : ndarray
        Unit tangents at the ends, in the direction of travel [-].

    Returns
    -------
    Biarc or None
        The biarc, or None where no equal-leg biarc exists.

    References
    ----------
    Bolton (1975), biarcs; Meek and Walton (1992), G1 arc splines.
    """
    v = p1 - p0
    t = t0 + t1
    vt = float(v @ t)
    vv = float(v @ v)
    if vv == 0.0:
        return None
    four_minus_tt = 4.0 - float(t @ t)  # = 2(1 − t0·t1) ≥ 0
    # the positive root of (4 − t·t)d² + 2(v·t)d − v·v = 0, written without cancellation
    root = math.sqrt(vt * vt + max(four_minus_tt, 0.0) * vv)
    if vt > 0.0:
        d = vv / (vt + root)
    elif four_minus_tt > 1e-14:
        d = (root - vt) / four_minus_tt
    else:
        return None
    if not (math.isfinite(d) and d > 0.0):
        return None
    # from here Python floats: numpy's elementwise operations on two-vectors round as theirs do, at a
    # fraction of the cost (the greedy fit builds a biarc per trial); the dot products stay numpy's
    (x0, y0), (u0, w0), (x1, y1), (u1, w1) = p0.tolist(), t0.tolist(), p1.tolist(), t1.tolist()
    q0x, q0y, q1x, q1y = x0 + d * u0, y0 + d * w0, x1 - d * u1, y1 - d * w1
    joint = (0.5 * (q0x + q1x), 0.5 * (q0y + q1y))
    norm = math.hypot(q1x - q0x, q1y - q0y)
    if norm == 0.0:
        return None
    chord0 = np.array((joint[0] - x0, joint[1] - y0))
    chord1 = np.array((joint[0] - x1, joint[1] - y1))
    centre0, ccw0 = _centre((x0, y0), (u0, w0), joint, float(chord0 @ chord0))
    # the second arc is the arc from p1 leaving backwards along −t1 (exact at p1), run forwards
    centre1, ccw1 = _centre((x1, y1), (-u1, -w1), joint, float(chord1 @ chord1))
    if not _leaves_along(joint, (x1, y1), centre1, not ccw1, ((q1x - q0x) / norm, (q1y - q0y) / norm)):
        return None
    return Biarc((x0, y0), joint, (x1, y1), (centre0, centre1), (ccw0, not ccw1))


def _leaves_along(start: tuple[float, float], end: tuple[float, float], centre: tuple[float, float] | None, ccw: bool,
                  tangent: tuple[float, float]) -> bool:
    """Whether the element from ``start`` to ``end`` (about ``centre`` in sense ``ccw``; a line without
    one) leaves its start along ``tangent`` (a sanity check of the construction)."""
    if centre is None:
        dx, dy = end[0] - start[0], end[1] - start[1]
    else:
        rx, ry = start[0] - centre[0], start[1] - centre[1]
        dx, dy = (-ry, rx) if ccw else (ry, -rx)
    return bool(dx * tangent[0] + dy * tangent[1] > 0.0)


def corner_arc(centre: FloatArray, radius_mm: float, normal0: FloatArray, normal1: FloatArray,
               theta_rad: float) -> Element | None:
    """The arc about a corner point from ``centre + r·normal0`` to ``centre + r·normal1``,
    turning the short way (the offset of a corner: the tool rolls about it).

    Parameters
    ----------
    centre : ndarray
        The corner point (x, y) [mm].
    radius_mm : float
        Signed offset: the arc lies at |r| from the corner, on the side of the normals
        when r > 0, on the other side when r < 0 [mm].
    normal0, normal1 : ndarray
        Unit normals before and after the corner [-].
    theta_rad : float
        Cam angle of the corner [rad].

    Returns
    -------
    Element or None
        The arc, or None when the offset or the turn is zero.

    References
    ----------
    The offset of a curve with a corner: the corner's normal cone swept at the offset
    distance (Meek and Walton 1992 join G1 arc splines the same way).
    """
    turn = math.atan2(float(normal0[0] * normal1[1] - normal0[1] * normal1[0]), float(normal0 @ normal1))
    if radius_mm == 0.0 or turn == 0.0:
        return None
    start = centre + radius_mm * normal0
    end = centre + radius_mm * normal1
    # centre + r·N turns with N whatever the sign of r (a rotation commutes with the scaling)
    ccw = turn > 0
    return Element((float(start[0]), float(start[1])), (float(end[0]), float(end[1])),
                   (float(centre[0]), float(centre[1])), ccw, theta_rad, theta_rad)


def path_area(elements: list[Element]) -> float:
    """Signed area a closed path of lines and arcs encloses, positive when it runs counter-clockwise.

    Parameters
    ----------
    elements : list of Element
        A closed chain (each element ends where the next starts).

    Returns
    -------
    float
        The area (Green's theorem: the chords' shoelace sum plus each arc's circular segment) [mm²].

    References
    ----------
    Green's theorem, A = ½∮(x dy − y dx); a circular segment of radius r and sweep φ has
    area r²(φ − sin φ)/2.
    """
    area = 0.0
    for e in elements:
        area += 0.5 * (e.start[0] * e.end[1] - e.end[0] * e.start[1])
        if e.centre is not None:
            phi = e.sweep_rad
            area += 0.5 * e.radius_mm ** 2 * (phi - math.sin(phi))
    return area


class ElementArrays:
    """Elements as arrays, for distances from many points to many elements at once.

    Parameters
    ----------
    elements : list of Element
        The elements; lane k of a query asks about ``elements[k]``.
    """

    #: the rows of :attr:`table`, the ones a query reads together next to each other (a query gathers a
    #: slice of rows in one operation: per operation, not per number, is what a gather costs here)
    ROWS = ("a0", "sweep", "r", "cx", "cy", "sense", "width", "sx", "sy", "ex", "ey")

    def __init__(self, elements: list[Element]):
        # one pass over the elements, a row per quantity (a list per quantity cost ten passes)
        given = np.array([(*e.start, *e.end, *(e.centre or (0.0, 0.0)), e.radius_mm if e.centre is not None else 0.0,
                           e.sweep_rad, e.centre is not None) for e in elements], dtype=np.float64).reshape(-1, 9).T
        sx, sy, ex, ey, cx, cy, r, sweep, arc = given
        a0 = np.arctan2(sy - cy, sx - cx)
        self.table = np.array([a0, sweep, r, cx, cy, np.where(sweep < 0, -1.0, 1.0), np.abs(sweep), sx, sy, ex, ey])
        self.arc = arc > 0.0
        # a fit of arcs only (or lines only) skips the other kind's formulas: a lane takes its own kind's
        self.kinds = "arcs" if bool(self.arc.all()) else "lines" if not bool(self.arc.any()) else "both"

    def distance_slope(self, lane: np.ndarray, x: FloatArray, y: FloatArray, vx: FloatArray, vy: FloatArray
                       ) -> tuple[FloatArray, FloatArray]:
        """Distance of point i from element ``lane[i]`` [mm], and its rate as the point moves at
        (vx, vy): the velocity along the unit vector from the element's nearest point [mm per unit of
        the velocity's parameter] (0 on the element). ``lane`` may have rows (one element per row for
        the same points), the answers then too."""
        a0, _, r, cx, cy, sense, width, sx, sy, ex, ey = self.table[:, lane]
        xs, ys, xe, ye = x - sx, y - sy, x - ex, y - ey  # each read by several quantities below
        to_start, to_end = np.hypot(xs, ys), np.hypot(xe, ye)
        to_ends = np.minimum(to_start, to_end)
        with np.errstate(invalid="ignore", divide="ignore"):
            # from the nearest point: the arc's centre (radially) or the nearer end; the line's foot
            start_nearer = to_start <= to_end
            end = (np.where(start_nearer, xs, xe) * vx + np.where(start_nearer, ys, ye) * vy) / to_ends
            if self.kinds != "lines":
                rx, ry = x - cx, y - cy
                on_arc = np.mod((np.arctan2(ry, rx) - a0) * sense, 2 * math.pi) <= width
                radius = np.hypot(rx, ry)
                off = radius - r
                arc = np.where(on_arc, np.abs(off), to_ends)
                arc_slope = np.where(on_arc, np.sign(off) * (rx * vx + ry * vy) / radius, end)
            if self.kinds != "arcs":
                dx, dy = ex - sx, ey - sy
                length2 = dx * dx + dy * dy
                u = np.clip(np.where(length2 > 0, (xs * dx + ys * dy) / length2, 0.0), 0.0, 1.0)
                fx, fy = x - (sx + u * dx), y - (sy + u * dy)
                line = np.hypot(fx, fy)
                line_slope = (fx * vx + fy * vy) / line
        if self.kinds == "arcs":
            distance, slope = arc, arc_slope
        elif self.kinds == "lines":
            distance, slope = line, line_slope
        else:
            is_arc = self.arc[lane]
            distance, slope = np.where(is_arc, arc, line), np.where(is_arc, arc_slope, line_slope)
        return distance, np.where(distance > 0, slope, 0.0)

    def along(self, lane: np.ndarray, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """The point a fraction ``u`` (0 … 1) along element ``lane[i]`` [mm] and its velocity d/du [mm]
        (one angle and its cosine and sine for both)."""
        if self.kinds != "lines":
            a0, sweep, r, cx, cy = self.table[:5, lane]
            a = a0 + u * sweep
            cos, sin = np.cos(a), np.sin(a)
            rs = r * sweep
            arc = cx + r * cos, cy + r * sin, -rs * sin, rs * cos
        if self.kinds == "arcs":
            return arc
        sx, sy, ex, ey = self.table[7:, lane]
        dx, dy = ex - sx, ey - sy
        line = sx + u * dx, sy + u * dy, dx, dy
        if self.kinds == "lines":
            return line
        is_arc = self.arc[lane]
        x, y, vx, vy = (np.where(is_arc, of_arc, of_line) for of_arc, of_line in zip(arc, line))
        return x, y, vx, vy
