"""The toolpath of a plate cam: the cutter-centre path of each wall, as lines and arcs.

A side names the walls and the tool's place (:mod:`.offset` for the offsets):

* ``outside``: the cam surface, the tool outside it (a plate cam; a groove's inner wall);
* ``inside``: a roller's track, its outer wall (the surface offset by the roller's diameter,
  B + Rr·N) with the tool inside it; for a knife-edge or flat face the surface itself with
  the tool inside it (a pocket, a female template);
* ``groove``: both walls of a roller's track (``outside`` and ``inside``), one path each.

Each path runs the way climb milling with a clockwise spindle (M3) runs: clockwise round an
outside, counter-clockwise inside a wall; it starts at cam angle 0.

Refused (:class:`GeometryError`, 422): a wall that is itself undercut (looped), a sharp corner
of a wall the offset cannot follow, and, unless ``allow_gouge``, a tool larger than the
smallest concave radius it must follow (its centre path would turn back on itself: the tool
cuts into the wall), named with the cam angle.

References
----------
.. [1] Farouki and Neff (1990): the offset of a curve turns back where 1 + dκ ≤ 0.
.. [2] Meek and Walton (1992): G1 arc splines within a tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from .._maxima import periodic_grid_maxima
from .._solvers import scan_roots
from ..curves.base import FloatArray
from ..errors import GeometryError, InvalidParameterError
from ..profile.cam import CamSpec
from ..profile.checks import check_grid, corners
from ..profile.lift import TWO_PI
from .fit import Budget, fit_stretch
from .geometry import Element, corner_arc, path_area
from .offset import LEFT_LIMIT_RAD, OffsetCurve, base_stretch, corner_turn, one_sided

Side = Literal["outside", "inside", "groove"]
SIDES: tuple[str, ...] = ("outside", "inside", "groove")
#: greedy grid: cam angles per turn; the biarc ends are picked from it (finer where a
#: biarc spans less than a few steps: :func:`fit_stretch` refits tighter)
GRID_STEPS = 2048


@dataclass(frozen=True)
class CutterPath:
    """The closed cutter-centre path of one wall.

    ``wall``: ``surface`` (the cam surface) or ``outer-wall`` (a roller track's outer wall);
    ``side``: the tool outside or inside that wall; ``offset_mm``: the path's offset from the
    base curve (pitch curve, or the surface of a flat face) along the outward normal;
    ``elements``: lines and arcs in the order the tool runs them; ``clockwise``: its sense;
    ``max_deviation_mm``: measured against the exact offset curve, both ways;
    ``min_concave_radius_mm``: the smallest radius of curvature the tool must fit into on
    this wall (infinite when it has none) and ``min_concave_radius_at_deg`` where;
    ``gouges``: the tool is larger than that radius (made only with ``allow_gouge``);
    ``lead_in_mm``: the free room beside the start, for a lead-in along the normal (the tool
    radius; in a roller's track the way to its centre line, Rr − Rt).
    """

    wall: str
    side: str
    offset_mm: float
    elements: tuple[Element, ...]
    clockwise: bool
    max_deviation_mm: float
    min_concave_radius_mm: float
    min_concave_radius_at_deg: float | None
    gouges: bool
    lead_in_mm: float

    @property
    def length_mm(self) -> float:
        """Length of the path [mm]."""
        return sum(e.length_mm for e in self.elements)


@dataclass(frozen=True)
class Toolpath:
    """The paths of the walls asked for, with the largest deviation and the element count."""

    tool_radius_mm: float
    tolerance_mm: float
    side: str
    paths: tuple[CutterPath, ...]

    @property
    def max_deviation_mm(self) -> float:
        """The largest measured deviation of any path [mm]."""
        return max(p.max_deviation_mm for p in self.paths)

    @property
    def segments_count(self) -> int:
        """Lines and arcs in all paths [-]."""
        return sum(len(p.elements) for p in self.paths)


def walls(spec: CamSpec, side: str) -> list[tuple[str, float, float]]:
    """The walls a side cuts: (name, offset w of the wall from the base curve, tool side ε).

    Parameters
    ----------
    spec : CamSpec
        The cam.
    side : str
        ``outside``, ``inside`` or ``groove``.

    Returns
    -------
    list of (str, float, float)
        Name, w [mm] and ε (+1: the tool outside the wall, −1: inside) [-] of each wall.

    Raises
    ------
    InvalidParameterError
        An unknown side, or a groove asked of a follower without a roller.

    References
    ----------
    Module notes; the roller's track: the pitch curve ± Rr (Shinzato and Kunigami 1988, fig. 1).
    """
    rr = spec.model.roller_radius_mm
    if side not in SIDES:
        raise InvalidParameterError(f"side must be one of {', '.join(SIDES)}, not {side!r}.", field=("side",))
    surface = ("surface", -rr, 1.0)
    if side == "outside":
        return [surface]
    if rr == 0.0:
        if side == "groove":
            raise InvalidParameterError("a groove is the track of a roller: give a roller follower "
                                        "(roller_radius_mm > 0), or side 'outside' or 'inside'.", field=("side",))
        return [("surface", 0.0, -1.0)]
    outer = ("outer-wall", rr, -1.0)
    return [outer] if side == "inside" else [surface, outer]


def compute_toolpath(spec: CamSpec, tool_radius_mm: float, tolerance_mm: float, side: str = "outside",
                     allow_gouge: bool = False, max_elements: int = 100_000) -> Toolpath:
    """The cutter-centre path of a plate cam's wall(s), fitted with lines and arcs.

    Parameters
    ----------
    spec : CamSpec
        The cam.
    tool_radius_mm : float
        Radius of the cutter, > 0 [mm].
    tolerance_mm : float
        Largest deviation of the fitted path from the exact cutter-centre curve, > 0 [mm].
    side : str
        ``outside``, ``inside`` or ``groove`` (module notes).
    allow_gouge : bool
        Follow the exact offset even where the tool is larger than a concave radius of the
        wall (the path then loops: the tool cuts into the wall), instead of refusing.
    max_elements : int
        Largest number of elements of the paths together [-]; more: LimitExceededError.

    Returns
    -------
    Toolpath
        One :class:`CutterPath` per wall.

    Raises
    ------
    GeometryError
        An undercut wall, a sharp corner a wall cannot follow, or (without ``allow_gouge``)
        a tool larger than a concave radius it must follow, with the cam angle.
    InvalidParameterError
        A tool radius or tolerance that is not positive, or a tool wider than the track.
    LimitExceededError
        The tolerance needs more than ``max_elements`` elements.

    References
    ----------
    Farouki and Neff (1990), offset curves; Meek and Walton (1992), arc splines within a tolerance.
    """
    if not (math.isfinite(tool_radius_mm) and tool_radius_mm > 0):
        raise InvalidParameterError("tool_radius_mm must be a positive number.", field=("tool_radius_mm",))
    if not (math.isfinite(tolerance_mm) and tolerance_mm > 0):
        raise InvalidParameterError("tolerance_mm must be a positive number.", field=("tolerance_mm",))
    chosen = walls(spec, side)
    rr = spec.model.roller_radius_mm
    if rr > 0 and side in ("inside", "groove") and tool_radius_mm > rr:
        raise InvalidParameterError(
            f"the tool (radius {tool_radius_mm!r} mm) is wider than the roller's track (roller radius {rr!r} mm): it "
            "would cut into the opposite wall; give tool_radius_mm ≤ roller_radius_mm.", field=("tool_radius_mm",))
    budget = Budget(max_elements)
    paths = tuple(_path(spec, name, w, eps, tool_radius_mm, tolerance_mm, allow_gouge, budget, side == "groove")
                  for name, w, eps in chosen)
    return Toolpath(float(tool_radius_mm), float(tolerance_mm), side, paths)


def fit_surface(spec: CamSpec, tolerance_mm: float, max_elements: int = 100_000) -> CutterPath:
    """The cam surface itself (a tool of radius 0) as lines and arcs within ``tolerance_mm``.

    Parameters
    ----------
    spec : CamSpec
        The cam.
    tolerance_mm : float
        Largest deviation from the exact surface, measured both ways, > 0 [mm].
    max_elements : int
        Largest number of elements [-].

    Returns
    -------
    CutterPath
        The surface, clockwise, starting at cam angle 0.

    Raises
    ------
    GeometryError
        An undercut surface or a sharp corner it cannot follow.
    LimitExceededError
        More than ``max_elements`` elements.

    References
    ----------
    Meek and Walton (1992), G1 arc splines within a tolerance.
    """
    if not (math.isfinite(tolerance_mm) and tolerance_mm > 0):
        raise InvalidParameterError("tolerance_mm must be a positive number.", field=("tolerance_mm",))
    (name, w, eps), = walls(spec, "outside")
    return _path(spec, name, w, eps, 0.0, tolerance_mm, False, Budget(max_elements))


def _path(spec: CamSpec, wall: str, w: float, eps: float, rt: float, tol: float, allow_gouge: bool,
          budget: Budget, groove: bool = False) -> CutterPath:
    corner_rad = [math.radians(c) for c in corners(spec)]
    turns = {c: corner_turn(spec, c) for c in corner_rad}
    on_grid = BaseOnGrid.of(spec)  # the wall's checks, its concave radius and the path's cusps all scan it
    undercut, concave = _wall_extremes(spec, w, eps, on_grid)
    _check_wall(spec, wall, w, corner_rad, turns, undercut)
    radius, at_rad = _concave_radius(concave, w, eps, corner_rad, turns)
    gouges = rt > radius
    where = "" if at_rad is None else f" at cam angle {math.degrees(at_rad):.4g}°"
    if gouges and not allow_gouge:
        raise GeometryError(
            f"the tool (radius {rt!r} mm) is larger than the concave radius of curvature it must follow on the "
            f"{wall.replace('-', ' ')}, {radius:.6g} mm{where}: its path would turn back and cut into the wall. "
            "Use a smaller tool, or set allow_gouge.", field=("tool_radius_mm",))
    d = w + eps * rt
    curve = OffsetCurve(spec, d)
    bounds = sorted({0.0, TWO_PI, *[c for c in corner_rad if c > 0.0], *_cusps(spec, d, on_grid)})
    # the joins' one-sided limits sit LEFT_LIMIT_RAD before their break: that far apart, times
    # the path's speed there (about its radius), so the gap they leave grows with the cam's size
    joins = [one_sided(b, -1.0) for b in bounds[1:] if b in turns or b == TWO_PI]
    # every stretch's ends and the joins' speed from one evaluation of the curve (mostly its fixed cost)
    ends = [(_end_angles(bounds[k], +1.0, bounds[k] in turns),
             _end_angles(bounds[k + 1], -1.0, bounds[k + 1] in turns or bounds[k + 1] == TWO_PI))
            for k in range(len(bounds) - 1)]
    x, y, tx, ty, travel_speed = curve.travel(np.array([t for pair in ends for end in pair for t in end] + joins))
    elements: list[Element] = []
    deviation = 0.0
    for k in range(len(bounds) - 1):
        a, b = bounds[k], bounds[k + 1]
        if a in turns and a > 0.0:
            elements += _corner(curve, a, budget)
        # the ends' point and tangent: entries 4k, 4k + 1 (start) and 4k + 2, 4k + 3 (end) of the evaluation
        start = (np.array([x[4 * k], y[4 * k]]), np.array([tx[4 * k + 1], ty[4 * k + 1]]))
        end = (np.array([x[4 * k + 2], y[4 * k + 2]]), np.array([tx[4 * k + 3], ty[4 * k + 3]]))
        spans, measured = fit_stretch(curve, a, b, start, end, tol, TWO_PI / GRID_STEPS, budget)
        deviation = max(deviation, measured)
        elements += [e for s in spans for e in s.elements]
    if 0.0 in turns:
        elements += _corner(curve, TWO_PI, budget)
    speed = float(travel_speed[4 * len(ends):].max()) if joins else 0.0
    elements = _closed(elements, 1e-6 + 4.0 * LEFT_LIMIT_RAD * speed)
    clockwise = path_area(elements) < 0
    if clockwise != (eps > 0):  # climb milling: clockwise round an outside, counter-clockwise inside
        elements = [e.reversed() for e in reversed(elements)]
        clockwise = not clockwise
    # the lead-in's free room: a tool radius beside a plate cam or a pocket's wall; in a
    # roller's track (a groove, or its outer wall) the way to the track's centre line
    lead = abs(w) - rt if (groove or eps < 0) and w != 0.0 else rt
    return CutterPath(wall, "outside" if eps > 0 else "inside", d, tuple(elements), clockwise, deviation,
                      radius, None if at_rad is None else math.degrees(at_rad), bool(gouges), lead)


def _closed(elements: list[Element], max_gap_mm: float) -> list[Element]:
    """The chain with each element starting exactly where the one before ends (the one-sided
    limits at corners and at 2π leave gaps of LEFT_LIMIT_RAD·|dP/dθ|: ~1e-9 mm on a 100 mm
    cam, 1e-6 mm at a base radius of 1e5 mm, 1e-5 mm at 1e6; ``max_gap_mm`` bounds them, a
    larger gap is a bug)."""
    out = [elements[0]]
    for e in elements[1:] + [elements[0]]:
        gap = math.dist(out[-1].end, e.start)
        assert gap < max_gap_mm, f"the path has a gap of {gap} mm (at most {max_gap_mm} expected)"
        # e from the last one's end: dataclasses.replace(e, start=…), made directly (replace costs µs)
        joined = Element(out[-1].end, e.end, e.centre, e.ccw, e.theta0_rad, e.theta1_rad)
        if e is elements[0]:
            out[0] = joined
        else:
            out.append(joined)
    return out


def _end_angles(theta: float, side: float, limit: bool) -> tuple[float, float]:
    """The cam angles of an end's point and of its unit travel tangent: a one-sided limit at a corner or
    at 2π (``limit``, :func:`.offset.one_sided`, both at it); at a cusp the point itself and the tangent
    from just inside (1e-7 rad)."""
    if limit or theta == 0.0:
        at = one_sided(theta, side)
        return at, at
    return theta, theta + side * 1e-7


def _corner(curve: OffsetCurve, theta: float, budget: Budget) -> list[Element]:
    """The arc the cutter centre runs about a corner of the base curve (the exact offset there)."""
    centre = curve.base_point(theta % TWO_PI)
    _, _, n0 = curve.left(theta)
    _, _, n1 = curve.right(theta % TWO_PI)
    arc = corner_arc(centre, curve.offset_mm, n0, n1, theta)
    if arc is None:
        return []
    budget.add(1)
    return [arc]


@dataclass(frozen=True)
class BaseOnGrid:
    """A cam's base curve on its check grid (:func:`camcore.profile.checks.check_grid`): what the
    scans of one wall share, the coefficients a and b of :func:`.offset.base_curve` (the scans read
    no point)."""

    grid: FloatArray
    a: FloatArray
    b: FloatArray

    @classmethod
    def of(cls, spec: CamSpec) -> BaseOnGrid:
        """The base curve of ``spec`` on its check grid."""
        grid = check_grid(spec)
        return cls(grid, *base_stretch(spec, grid))


def _wall_extremes(spec: CamSpec, w: float, eps: float, on_grid: BaseOnGrid
                   ) -> tuple[tuple[float, float], tuple[float, float]]:
    """The wall's worst shrink (−(a + w·b), scaled: ≥ 0 where it loops) and its largest curvature
    concave towards the tool on side ε, each with its cam angle [rad]: one scan of the check grid
    refines both, one evaluation of the base curve per round for the two."""
    scale = float(np.abs(on_grid.a).max())

    def both(a: FloatArray, b: FloatArray) -> FloatArray:
        stretch = a + w * b
        with np.errstate(divide="ignore", invalid="ignore"):  # a looping wall's stretch passes 0: refused below
            return np.stack([-stretch / scale, -eps * b / stretch])

    undercut, concave = periodic_grid_maxima(lambda t: both(*base_stretch(spec, t)), on_grid.grid,
                                             both(on_grid.a, on_grid.b))
    return undercut, concave


def _check_wall(spec: CamSpec, wall: str, w: float, corner_rad: list[float], turns: dict[float, float],
                undercut: tuple[float, float]) -> None:
    """Refuse a wall that loops (undercut, :func:`_wall_extremes`) or has a corner its offset cannot follow."""
    name = wall.replace("-", " ")
    if corner_rad and spec.model.flat_faced:
        raise GeometryError(f"the lift's velocity jumps at cam angle {math.degrees(corner_rad[0]):.6g}°: a flat face "
                            "cannot follow that corner, so the cam has no surface to cut there.", field=("profile",))
    for c in corner_rad:
        if turns[c] * w < 0:
            raise GeometryError(
                f"the {name} has a sharp corner at cam angle {math.degrees(c):.6g}° (the lift's velocity jumps there); "
                "a toolpath is made for walls whose corners are rounded by the roller: give the motion a continuous "
                "velocity.", field=("profile",))
    worst_t, worst = undercut
    if worst >= 0.0:
        raise GeometryError(
            f"the {name} is undercut at cam angle {math.degrees(worst_t):.6g}°: its curvature is tighter than the "
            "roller (or the face cannot stay convex), so it loops and no tool can cut it. Enlarge the base circle.",
            field=("profile",))


def concave_radius(spec: CamSpec, w: float, eps: float, corner_rad: list[float],
                   turns: dict[float, float], on_grid: BaseOnGrid | None = None) -> tuple[float, float | None]:
    """The smallest concave radius of curvature a tool on side ε of the wall w must follow.

    Parameters
    ----------
    spec : CamSpec
        The cam.
    w : float
        The wall's offset from the base curve along the outward normal [mm].
    eps : float
        +1 for the tool outside the wall, −1 inside [-].
    corner_rad : list of float
        The base curve's corners [rad].
    turns : dict
        The normal's turn at each corner, positive where convex [rad].
    on_grid : BaseOnGrid, optional
        The base curve on the check grid, when the caller has it.

    Returns
    -------
    (float, float or None)
        The radius [mm] (infinite where the wall is nowhere concave towards the tool) and the
        cam angle where it is [rad].

    References
    ----------
    Farouki and Neff (1990): an offset at distance d of a curve of curvature κ has curvature
    κ/(1 + dκ); a tool of radius Rt fits a concave radius ρ only if Rt ≤ ρ.
    """
    on_grid = BaseOnGrid.of(spec) if on_grid is None else on_grid
    return _concave_radius(_wall_extremes(spec, w, eps, on_grid)[1], w, eps, corner_rad, turns)


def _concave_radius(concave: tuple[float, float], w: float, eps: float, corner_rad: list[float],
                    turns: dict[float, float]) -> tuple[float, float | None]:
    """:func:`concave_radius` from the wall's largest concave curvature and its cam angle (:func:`_wall_extremes`)."""
    at, k = concave
    radius, where = (1.0 / k, at) if k > 0 else (math.inf, None)
    for c in corner_rad:
        # a corner concave towards the tool: the wall there is the roller's arc, radius |w|
        if -eps * turns[c] > 0 and abs(w) < radius:
            radius, where = abs(w), c
    return radius, where


def _cusps(spec: CamSpec, d: float, on_grid: BaseOnGrid) -> list[float]:
    """Cam angles where the offset turns back (its stretch a + d·b changes sign), at breaks too."""
    def stretch(a: FloatArray, b: FloatArray) -> FloatArray:
        return a + d * b

    roots, _values = scan_roots(lambda t: stretch(*base_stretch(spec, t)), on_grid.grid, stretch(on_grid.a, on_grid.b))
    return [r for r in roots if 0.0 < r < TWO_PI]
