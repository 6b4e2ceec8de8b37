"""A plate's contour, or the path of a cutter round it, as lines and arcs within a tolerance.

The plate cam's fit (:mod:`camcore.toolpath.fit`: greedy biarcs, each measured both ways against
the exact curve by :mod:`camcore.toolpath.measure`) is run on each piece of the plate's exact contour (:mod:`.trace`), offset by the
tool radius Rt towards the piece's roller: a point of the piece is the roller's centre P plus
s·Rr·N (:mod:`.envelope`), so the cutter's centre is P + s·(Rr − Rt)·N, the envelope of circles
of radius Rr − Rt about the same centres, exact in closed form as the piece is. Every corner of
the plate is convex (the plate is what lies outside every roller): the cutter rolls round it on
an arc of radius Rt about the corner, from the one piece's normal to the next one's (none for
Rt = 0, the contour itself). Where two envelopes run together the hand-over turns by a few
1e-4 rad at most; it gets its small arc the same way. A cutter fits every concave stretch of the
contour when Rt is at most its smallest concave radius (a roller's own circle at the least: Rr).

The path runs clockwise round the plate, as climb milling round an outside with a clockwise
spindle (M3), and starts where the contour's first piece does.

References
----------
.. [1] Farouki and Neff (1990): the offset of an offset curve; its speed |1 + w·κ|·|P′|.
.. [2] Meek and Walton (1992): G1 arc splines within a tolerance (:mod:`camcore.toolpath.fit`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...curves.base import FloatArray
from ...errors import GeometryError, InvalidParameterError, LimitExceededError
from ...toolpath import CutterPath, Element, OffsetCurve
from ...toolpath.compute import GRID_STEPS
from ...toolpath.fit import Budget, fit_stretch
from ...toolpath.geometry import corner_arc
from .envelope import centres, envelope
from .trace import PlateContour

#: a hand-over or corner turning by less than this gets no arc: the cutter's two offsets then part
#: by Rt × the turn, below 1e-9 mm for a 10 mm tool
LEAST_TURN_RAD = 1e-10
#: the elements are chained end to start as they are made; a gap over this share of C is a bug
GAP_SHARE = 1e-12


class PieceCurve(OffsetCurve):
    """One piece of a plate's contour offset by ``offset_mm`` towards its roller (Rr: the contour
    itself; Rr − Rt: a cutter's centre), in θ = side·τ, which grows along the walk.

    :mod:`camcore.toolpath.fit` and :mod:`camcore.toolpath.measure` read a curve through :meth:`sample` (``points`` and ``travel``
    come from it); this gives it the piece, exact from the roller's pitch curve.
    """

    def __init__(self, contour: PlateContour, piece: int, offset_mm: float):
        self.contour, self.piece = contour, piece
        self.offset_mm = float(offset_mm)
        self.side = contour.pieces[piece].side

    def sample(self, theta: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """x, y of the offset point, the unit tangent as θ grows and the stretch (d/dθ = stretch·tangent)."""
        p = self.contour.pieces[self.piece]
        px, py, p1x, p1y, p2x, p2y = centres(self.contour.cam, p.alpha0_rad, self.side * np.asarray(theta, dtype=float))
        speed = np.hypot(p1x, p1y)
        tx, ty = p1x / speed, p1y / speed
        # the pitch curve's curvature towards the piece's side (the follower's κp, signed by the side)
        kappa = p.side * (p1x * p2y - p1y * p2x) / speed**3
        w = self.offset_mm
        x, y = px - p.side * w * ty, py + p.side * w * tx  # P + s·w·J·T
        # dE/dτ = |P′|·(1 − w·κ)·T; d/dθ = side·d/dτ
        return x, y, self.side * tx, self.side * ty, speed * (1.0 - w * kappa)

    def normal(self, theta: float) -> FloatArray:
        """The contour's unit normal at θ, from the plate towards the roller [-]."""
        p = self.contour.pieces[self.piece]
        e = envelope(self.contour.cam, p.alpha0_rad, float(p.side), np.array([self.side * theta]))
        return np.array([p.side * e.ty[0], -p.side * e.tx[0]])


def concave_radius(contour: PlateContour, rho: FloatArray, cam_angle_deg: FloatArray) -> tuple[float, float | None]:
    """The smallest concave radius of curvature of a plate's contour, and where.

    Parameters
    ----------
    contour : PlateContour
        The contour (its points' radii are given).
    rho : ndarray
        The contour's radius of curvature at its points, positive convex [mm].
    cam_angle_deg : ndarray
        The cam angle of the contact at each point [deg].

    Returns
    -------
    (float, float or None)
        The radius [mm] (infinite: nowhere concave) and the cam angle there [deg].

    References
    ----------
    Farouki and Neff (1990): a tool of radius Rt follows a concave radius ρ only if Rt ≤ ρ.
    """
    concave = np.flatnonzero(rho < 0)
    if concave.size == 0:
        return math.inf, None
    k = concave[np.argmin(-rho[concave])]
    return float(-rho[k]), float(cam_angle_deg[k])


def fit_plate(contour: PlateContour, tool_radius_mm: float, tolerance_mm: float, min_concave_radius_mm: float,
              min_concave_radius_at_deg: float | None, max_elements: int = 100_000) -> CutterPath:
    """A plate's contour (``tool_radius_mm`` 0) or a cutter's centre path round it, as lines and arcs.

    Parameters
    ----------
    contour : PlateContour
        The plate's exact contour.
    tool_radius_mm : float
        Rt, 0 for the contour itself [mm].
    tolerance_mm : float
        The largest deviation of the lines and arcs from the exact path, measured both ways [mm].
    min_concave_radius_mm : float
        The contour's smallest concave radius (:func:`concave_radius`) [mm].
    min_concave_radius_at_deg : float or None
        Where it is [deg].
    max_elements : int
        The most lines and arcs [-].

    Returns
    -------
    CutterPath
        Clockwise round the plate (module notes), the deviation measured.

    Raises
    ------
    GeometryError
        A tool larger than the contour's smallest concave radius.
    InvalidParameterError
        A tool radius below 0 or a tolerance that is not positive.
    LimitExceededError
        More than ``max_elements`` lines and arcs.

    References
    ----------
    Meek and Walton (1992), arc splines within a tolerance; Farouki and Neff (1990), offsets.
    """
    rt = float(tool_radius_mm)
    if not (math.isfinite(rt) and rt >= 0):
        raise InvalidParameterError("tool_radius_mm must be 0 or more.", field=("tool_radius_mm",))
    if not (math.isfinite(tolerance_mm) and tolerance_mm > 0):
        raise InvalidParameterError("tolerance_mm must be a positive number.", field=("tolerance_mm",))
    if rt > min_concave_radius_mm:
        where = "" if min_concave_radius_at_deg is None else f" (its roller's contact at cam angle " \
                                                             f"{min_concave_radius_at_deg:.4g}°)"
        raise GeometryError(
            f"the tool (radius {rt!r} mm) is larger than the concave radius of curvature it must follow on the plate, "
            f"{min_concave_radius_mm:.6g} mm{where}: it would cut into the contour there. Use a smaller tool.",
            field=("tool_radius_mm",))
    cam = contour.cam
    offset = cam.roller_radius_mm - rt
    budget = Budget(max_elements)
    step = 2 * math.pi / GRID_STEPS
    curves = [PieceCurve(contour, k, offset) for k in range(len(contour.pieces))]
    ranges = [(p.side * p.tau_start_rad, p.side * p.tau_end_rad) for p in contour.pieces]
    ends = [_ends(curve, *span) for curve, span in zip(curves, ranges)]
    elements: list[Element] = []
    deviation = 0.0
    for k, curve in enumerate(curves):
        theta0, theta1 = ranges[k]
        # each piece starts where the path has come to (the piece before's exact end, or the cutter's
        # arc round the corner after it): where two envelopes hand over their ends part by up to 2ε,
        # and the fit then measures that against the exact piece
        here = ends[k - 1][1][0]
        arc = _corner(curves[k - 1], curve, rt, budget)
        if arc:
            arc = [replace(arc[0], start=(float(here[0]), float(here[1])))]
            here = np.array(arc[0].end)
        elements += arc
        if theta1 - theta0 <= 0:
            continue
        start = (here, ends[k][0][1])
        spans, measured = fit_stretch(curve, theta0, theta1, start, ends[k][1], tolerance_mm, step, budget)
        deviation = max(deviation, measured)
        elements += [e for s in spans for e in s.elements]
    if not elements:
        raise GeometryError("the plate's contour has no length to fit.")
    closed = _closed(elements, GAP_SHARE * cam.center_distance_mm)
    # counter-clockwise as traced: run it the other way, clockwise round the plate
    path = [e.reversed() for e in reversed(closed)]
    return CutterPath("surface", "outside", -offset, tuple(path), True, deviation, min_concave_radius_mm,
                      min_concave_radius_at_deg, False, rt)


def _ends(curve: PieceCurve, theta0: float, theta1: float) -> tuple[tuple[FloatArray, FloatArray],
                                                                     tuple[FloatArray, FloatArray]]:
    """The points and unit travel tangents at both ends of a piece."""
    x, y, tx, ty, _ = curve.travel(np.array([theta0, theta1]))
    return (np.array([x[0], y[0]]), np.array([tx[0], ty[0]])), (np.array([x[1], y[1]]), np.array([tx[1], ty[1]]))


def _corner(before: PieceCurve, after: PieceCurve, rt: float, budget: Budget) -> list[Element]:
    """The cutter's arc about the plate's corner between two pieces (none for Rt = 0 or no turn)."""
    if rt == 0:
        return []
    a, b = before.contour.pieces[before.piece], after.contour.pieces[after.piece]
    end_a, start_b = a.side * a.tau_end_rad, b.side * b.tau_start_rad
    n0, n1 = before.normal(end_a), after.normal(start_b)
    turn = math.atan2(float(n0[0] * n1[1] - n0[1] * n1[0]), float(n0 @ n1))
    if abs(turn) <= LEAST_TURN_RAD:
        return []
    if turn < 0:  # the plate's corners are convex: a concave one is a bug of the trace
        raise GeometryError(f"the plate's contour turns concave by {turn!r} rad at a corner; it cannot be cut.")
    # the corner point itself: the contour (offset Rr) at the end of the piece before
    corner = PieceCurve(before.contour, before.piece, before.contour.cam.roller_radius_mm)
    cx, cy = corner.points(np.array([end_a]))
    arc = corner_arc(np.array([cx[0], cy[0]]), rt, n0, n1, a.tau_end_rad)
    if arc is None:
        return []
    budget.add(1)
    return [arc]


def _closed(elements: list[Element], max_gap_mm: float) -> list[Element]:
    """The chain with each element starting exactly where the one before ends (they are made so: a
    gap is rounding, or a bug)."""
    out = [elements[0]]
    for e in elements[1:]:
        gap = math.dist(out[-1].end, e.start)
        if gap > max_gap_mm:
            raise GeometryError(f"the plate's path has a gap of {gap!r} mm between two pieces (at most "
                                f"{max_gap_mm!r} expected).")
        out.append(replace(e, start=out[-1].end))
    gap = math.dist(out[-1].end, out[0].start)
    if gap > max_gap_mm:
        raise GeometryError(f"the plate's path does not close: a gap of {gap!r} mm.")
    out[0] = replace(out[0], start=out[-1].end)
    return out


def relocated_limit(error: LimitExceededError, field: tuple[str | int, ...]) -> LimitExceededError:
    """The same limit, named at another request field.

    Parameters
    ----------
    error : LimitExceededError
        The limit the fit ran into (named at ``tolerance_mm``).
    field : tuple
        Where the caller's request has the tolerance.

    Returns
    -------
    LimitExceededError
        The same numbers at ``field``.

    References
    ----------
    camcore.errors (a field is a path into the arguments of the call that raised).
    """
    return LimitExceededError(error.what, error.requested, error.limit, field=field)
