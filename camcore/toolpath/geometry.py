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
        cx, cy = self.centre
        a0 = math.atan2(self.start[1] - cy, self.start[0] - cx)
        a1 = math.atan2(self.end[1] - cy, self.end[0] - cx)
        return (a1 - a0) % (2 * math.pi) if self.ccw else -((a0 - a1) % (2 * math.pi))

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
        to_ends = np.minimum(np.hypot(x - sx, y - sy), np.hypot(x - ex, y - ey))
        if self.centre is None:
            dx, dy = ex - sx, ey - sy
            length2 = dx * dx + dy * dy
            if length2 == 0.0:
                return to_ends
            u = np.clip(((x - sx) * dx + (y - sy) * dy) / length2, 0.0, 1.0)
            return np.hypot(x - (sx + u * dx), y - (sy + u * dy))
        cx, cy = self.centre
        a0 = math.atan2(sy - cy, sx - cx)
        sweep = self.sweep_rad
        # angle of each point from the start, measured in the arc's sense, in [0, 2π)
        rel = np.mod((np.arctan2(y - cy, x - cx) - a0) * math.copysign(1.0, sweep), 2 * math.pi)
        on_arc = rel <= abs(sweep)
        radial = np.abs(np.hypot(x - cx, y - cy) - self.radius_mm)
        return np.where(on_arc, radial, to_ends)

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
    rows = []
    for e in pair:
        (sx, sy), (ex, ey), (cx, cy) = e.start, e.end, e.centre  # type: ignore[misc]  # arcs, by the test above
        sweep = e.sweep_rad
        rows.append((sx, sy, ex, ey, cx, cy, math.atan2(sy - cy, sx - cx), math.copysign(1.0, sweep), abs(sweep),
                     e.radius_mm))
    sx, sy, ex, ey, cx, cy, a0, sense, width, radius = np.array(rows).T[:, :, None]
    to_ends = np.minimum(np.hypot(x - sx, y - sy), np.hypot(x - ex, y - ey))
    rel = np.mod((np.arctan2(y - cy, x - cx) - a0) * sense, 2 * math.pi)
    radial = np.abs(np.hypot(x - cx, y - cy) - radius)
    both = np.where(rel <= width, radial, to_ends)
    return np.minimum(both[0], both[1])


def arc_through(start: FloatArray, tangent: FloatArray, end: FloatArray, theta0: float = 0.0,
                theta1: float = 0.0) -> Element:
    """The arc from ``start`` leaving along the unit ``tangent`` to ``end`` (a line when
    ``end`` lies on the tangent).

    Parameters
    ----------
    start, end : ndarray
        The ends (x, y) [mm].
    tangent : ndarray
        Unit tangent at ``start`` [-].
    theta0, theta1 : float
        Cam angles of the curve the element stands for [rad].

    Returns
    -------
    Element
        The line or the arc.

    References
    ----------
    Bolton (1975): an arc is fixed by one end, its tangent there and the other end; its
    signed curvature is 2 (t × c)/|c|² for the chord c.
    """
    chord = end - start
    c2 = float(chord @ chord)
    cross = float(tangent[0] * chord[1] - tangent[1] * chord[0])
    s, e = (float(start[0]), float(start[1])), (float(end[0]), float(end[1]))
    if c2 == 0.0 or abs(cross) <= STRAIGHT * c2:
        return Element(s, e, None, True, theta0, theta1)
    curvature = 2.0 * cross / c2
    # centre on the left of the tangent for a left turn (ccw), on the right for a right turn
    cx = float(start[0]) - tangent[1] / curvature
    cy = float(start[1]) + tangent[0] / curvature
    return Element(s, e, (float(cx), float(cy)), curvature > 0, theta0, theta1)


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
    q0 = p0 + d * t0
    q1 = p1 - d * t1
    joint = 0.5 * (q0 + q1)
    leg = q1 - q0
    norm = math.hypot(float(leg[0]), float(leg[1]))
    if norm == 0.0:
        return None
    tm = leg / norm
    mid = 0.5 * (theta0 + theta1)
    first = arc_through(p0, t0, joint, theta0, mid)
    # the second arc is the reversed arc from p1 leaving backwards along −t1: exact at p1
    second = arc_through(p1, -t1, joint, theta1, mid).reversed()
    if not _joins_along(second, joint, tm):
        return None
    return first, second


def _joins_along(element: Element, joint: FloatArray, tangent: FloatArray) -> bool:
    """Whether ``element`` leaves ``joint`` along ``tangent`` (a sanity check of the construction)."""
    if element.centre is None:
        dx, dy = element.end[0] - element.start[0], element.end[1] - element.start[1]
    else:
        rx, ry = element.start[0] - element.centre[0], element.start[1] - element.centre[1]
        dx, dy = (-ry, rx) if element.ccw else (ry, -rx)
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

    def distance_slope(self, lane: np.ndarray, x: FloatArray, y: FloatArray, vx: FloatArray, vy: FloatArray
                       ) -> tuple[FloatArray, FloatArray]:
        """Distance of point i from element ``lane[i]`` [mm], and its rate as the point moves at
        (vx, vy): the velocity along the unit vector from the element's nearest point [mm per unit of
        the velocity's parameter] (0 on the element)."""
        sx, sy, ex, ey = self.sx[lane], self.sy[lane], self.ex[lane], self.ey[lane]
        dx, dy = ex - sx, ey - sy
        length2 = dx * dx + dy * dy
        with np.errstate(invalid="ignore", divide="ignore"):
            u = np.clip(np.where(length2 > 0, ((x - sx) * dx + (y - sy) * dy) / length2, 0.0), 0.0, 1.0)
        # from the nearest point: the line's foot, the arc's centre (radially), or the nearer end
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

    def velocity(self, lane: np.ndarray, u: FloatArray) -> tuple[FloatArray, FloatArray]:
        """d/du of :meth:`point` [mm]."""
        a = self.a0[lane] + u * self.sweep[lane]
        rs = self.r[lane] * self.sweep[lane]
        arc = self.arc[lane]
        return (np.where(arc, -rs * np.sin(a), self.ex[lane] - self.sx[lane]),
                np.where(arc, rs * np.cos(a), self.ey[lane] - self.sy[lane]))

    def point(self, lane: np.ndarray, u: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The point a fraction ``u`` (0 … 1) along element ``lane[i]`` [mm]."""
        sx, sy, ex, ey = self.sx[lane], self.sy[lane], self.ex[lane], self.ey[lane]
        a = self.a0[lane] + u * self.sweep[lane]
        r, cx, cy = self.r[lane], self.cx[lane], self.cy[lane]
        arc = self.arc[lane]
        return (np.where(arc, cx + r * np.cos(a), sx + u * (ex - sx)),
                np.where(arc, cy + r * np.sin(a), sy + u * (ey - sy)))
