"""A barrel cam's groove on a four-axis mill: the cutter's path as straight moves in (A, X).

Machine
-------
The cam lies with its axis on the rotary axis A, along the machine's X; the tool stands radial
to the cam, its axis along Z through the cam axis (Y = 0), and Z is the distance of the tool's
tip from the cam axis. X = 0 is the plane z = 0 of the cam's frame (the follower's zero lift),
and A is the cam angle θ in degrees: the tool's angular place on the cam, so that it runs over
the cam as the follower does in service. At A = 0 the cam's angle 0 (its +x axis) is under the
tool. In ISO 841's terms A+ is the tool's right-hand turn about +X relative to the part, which
a rotary table makes by turning the part clockwise seen from +X looking at the origin: the way
the cam turns in service, its z axis along +X.

Path
----
A cutter of the roller's radius is the roller: its axis runs where the roller's does, on the
groove's centre line, A = θ, X = s(θ) (u = R·θ, y = s: :mod:`camcore.cams.barrel`). A smaller
cutter (Rt < Rr) cuts each wall in a pass of its own, its axis offset by d = ±(Rr − Rt) along
the unit normal N = (−s', R)/w, w = √(R² + s'²), of the developed groove at the pitch radius R:
u = R·θ + d·N_u, y = s + d·N_y, so A = θ − d·s'/(R·w) and X = s + d·R/w, exact from the lift's
derivatives. On the cylinder of radius ρ the axis then crosses at P = (ρ·A, X), and

    dP/dθ = k·(ρ, s'),  k = 1 − d·R·s''/w³,

so the path turns back (and the cutter cuts into the wall) where k ≤ 0: refused. Travel is
climb milling with a clockwise spindle (M3), the wall on the tool's right: the lower wall
(−y) with A rising, the upper wall with A falling; a cutter of the roller's size cuts the
slot with A rising. The two passes meet in the middle when Rt ≥ Rr/2 (else a rib would stand
between them: refused).

The offset is exact at the pitch radius in the developed plane; the walls it cuts are not the
roller's at every radius, because the normal of the roller's wall turns along its length
(its developed slope is s'/r at radius r) while the cutter stays radial. :func:`wall_gaps`
measures it in 3-D against the exact flanks (:func:`camcore.cams.barrel.flank_points`); the
toolpath reports the largest gap across the roller's length.

Fit
---
Each block is a straight move in (A, X): the control moves both at constant rates, so the
tool's axis crosses each cylinder r about the cam axis on a helix, a straight line in that
cylinder's developed plane (r·A, X). A block's error along the circumference grows with r, so
the path is fitted, and measured, in the developed plane of the cam's outer radius R + ℓ/2
(the largest radius the cutter's side cuts the wall), and measured again at the pitch radius.
The nodes lie on the exact path; the greedy search takes the longest chords whose grid points
stay within 0.8 of the tolerance, and each chord is then measured against the exact path both
ways (:func:`camcore.toolpath.measure.measure`: the curve's largest distance from the chord and
the chord's from the curve, refined between samples by golden section) and split again where
it misses. Arcs are not used: a G2/G3 arc cannot take a rotary axis on most controls.

References
----------
.. [1] ISO 841:2001, Industrial automation systems — Numerical control of machines — Coordinate
   system and motion nomenclature (A about X, right-hand rule; a moving part's primed axes).
.. [2] R. T. Farouki, C. A. Neff, "Analytic properties of plane offset curves", CAGD 7 (1990)
   83-99: the offset turns back where 1 − d·κ ≤ 0.
.. [3] Meek and Walton (1992): fitting within a tolerance measured against the curve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._maxima import golden_max, periodic_grid_max
from ...curves.base import FloatArray
from ...errors import GeometryError, InvalidParameterError
from ...profile.checks import lift_corners
from ...profile.lift import TWO_PI
from ...toolpath.fit import Budget
from .chords import DevelopedPath, chord_deviation, chords, fit_path
from .geometry import BarrelCam, check_grid, flank_points

#: cam angles and positions along the roller where the walls a smaller cutter leaves are measured
WALL_ANGLES = 361
WALL_POSITIONS = 5


@dataclass(frozen=True)
class RotaryPass:
    """One pass of the cutter: its nodes in the order it runs them, and its measured deviation.

    ``wall``: ``groove`` (a cutter of the roller's size on the centre line: both walls),
    ``lower`` or ``upper``; ``offset_mm``: d along the developed normal (+: towards +y);
    ``cam_angle_deg``, ``a_deg``, ``x_mm``: the nodes (A is the tool's angle, θ's offset by d);
    the deviations at the outer and the pitch radius; ``length_mm``: the moves' length in the
    developed plane of the pitch radius (the feed's length).
    """

    wall: str
    offset_mm: float
    cam_angle_deg: FloatArray
    a_deg: FloatArray
    x_mm: FloatArray
    max_deviation_mm: float
    max_deviation_pitch_mm: float
    length_mm: float


@dataclass(frozen=True)
class BarrelToolpath:
    """The passes of a barrel cam's groove on a four-axis mill (module notes)."""

    tool_radius_mm: float
    roller_radius_mm: float
    tolerance_mm: float
    pitch_radius_mm: float
    outer_radius_mm: float
    groove_bottom_radius_mm: float
    passes: tuple[RotaryPass, ...]
    wall_gap_max_mm: float
    wall_gap_min_mm: float
    wall_gap_at_deg: float | None
    wall_gap_at_position_mm: float | None

    @property
    def max_deviation_mm(self) -> float:
        """The largest deviation of any pass, at the outer radius [mm]."""
        return max(p.max_deviation_mm for p in self.passes)

    @property
    def max_deviation_pitch_mm(self) -> float:
        """The largest deviation of any pass, at the pitch radius [mm]."""
        return max(p.max_deviation_pitch_mm for p in self.passes)

    @property
    def segments_count(self) -> int:
        """Straight moves of all passes [-]."""
        return sum(len(p.a_deg) - 1 for p in self.passes)

    @property
    def wall_error_mm(self) -> float:
        """The largest |gap| between the walls the passes cut and the exact flanks [mm]."""
        return max(abs(self.wall_gap_max_mm), abs(self.wall_gap_min_mm))


def check_cutter(follower: str, roller: str, roller_radius_mm: float, tool_radius_mm: float) -> None:
    """Raise when a groove cannot be cut by this cutter as the module cuts it (the lift apart).

    Parameters
    ----------
    follower : {"translating", "oscillating"}
        The follower's motion.
    roller : {"cylindrical", "conical"}
        The roller's shape.
    roller_radius_mm : float
        Rr [mm].
    tool_radius_mm : float
        Rt, the cutter's radius [mm].

    Raises
    ------
    InvalidParameterError, GeometryError
        A follower other than translating, a conical roller, a cutter larger than the roller or
        smaller than half of it, with the field.

    References
    ----------
    The module notes (a radial cutter is the roller only when the roller's axis is radial).
    """
    if not (math.isfinite(tool_radius_mm) and tool_radius_mm > 0):
        raise InvalidParameterError("tool_radius_mm must be a positive number.", field=("tool_radius_mm",))
    if follower != "translating":
        raise GeometryError(
            "the four-axis toolpath is made for a translating follower: an oscillating roller's axis lies "
            "L(1 − cos ψ) off the cam axis, so a radial cutter cannot stand where the roller stands.",
            field=("follower",))
    if roller != "cylindrical":
        raise GeometryError("the four-axis toolpath is made for a cylindrical roller: an end mill cannot cut a "
                            "conical roller's walls.", field=("roller",))
    if tool_radius_mm > roller_radius_mm:
        raise InvalidParameterError(
            f"the cutter (radius {tool_radius_mm!r} mm) is wider than the groove (roller radius {roller_radius_mm!r} "
            "mm): give tool_radius_mm ≤ the roller's radius.", field=("tool_radius_mm",))
    if tool_radius_mm < 0.5 * roller_radius_mm:
        raise InvalidParameterError(
            f"the cutter (radius {tool_radius_mm!r} mm) is smaller than half the roller's radius ({roller_radius_mm!r} "
            "mm): its two passes, one on each wall, would leave a rib of material between them.",
            field=("tool_radius_mm",))


def check_toolpath(cam: BarrelCam, tool_radius_mm: float, tolerance_mm: float) -> None:
    """Raise when a barrel cam's groove cannot be cut with this cutter as the module cuts it.

    Parameters
    ----------
    cam : BarrelCam
        The cam.
    tool_radius_mm : float
        Rt, the cutter's radius [mm].
    tolerance_mm : float
        The fitting tolerance [mm].

    Raises
    ------
    InvalidParameterError, GeometryError
        :func:`check_cutter`; a tolerance that is not positive; a smaller cutter where the lift's
        velocity jumps (each wall has a corner there its offset cannot follow).

    References
    ----------
    The module notes.
    """
    if not (math.isfinite(tolerance_mm) and tolerance_mm > 0):
        raise InvalidParameterError("tolerance_mm must be a positive number.", field=("tolerance_mm",))
    check_cutter(cam.follower, cam.roller, cam.roller_radius_mm, tool_radius_mm)
    kinks = lift_corners(cam.lift)
    if tool_radius_mm < cam.roller_radius_mm and kinks:
        raise GeometryError(
            f"the lift's velocity jumps at cam angle {kinks[0]:.6g}°: a cutter smaller than the roller cannot follow "
            "the corner of each wall there; use a cutter of the roller's radius, or a lift with a continuous velocity.",
            field=("tool_radius_mm",))


def compute_barrel_toolpath(cam: BarrelCam, tool_radius_mm: float, tolerance_mm: float,
                            max_elements: int = 100_000) -> BarrelToolpath:
    """The passes of a barrel cam's groove on a four-axis mill, fitted within a tolerance.

    Parameters
    ----------
    cam : BarrelCam
        A translating follower with a cylindrical roller.
    tool_radius_mm : float
        Rt, from half the roller's radius to the roller's radius [mm].
    tolerance_mm : float
        The largest deviation of the machine's straight moves from the exact path, measured in the
        developed plane of the cam's outer radius [mm].
    max_elements : int
        The most straight moves of all passes [-] (more: LimitExceededError at tolerance_mm).

    Returns
    -------
    BarrelToolpath
        One pass (Rt = Rr) or two, the deviations measured and, for a smaller cutter, the gaps of
        the walls it cuts against the exact flanks.

    Raises
    ------
    InvalidParameterError, GeometryError
        :func:`check_toolpath`; a wall whose offset turns back (k ≤ 0).
    LimitExceededError
        More than ``max_elements`` moves.

    References
    ----------
    The module notes; Farouki and Neff (1990); Meek and Walton (1992).
    """
    check_toolpath(cam, tool_radius_mm, tolerance_mm)
    rr, r = cam.roller_radius_mm, cam.pitch_radius_mm
    outer = r + 0.5 * cam.roller_length_mm
    budget = Budget(max_elements)
    d = rr - tool_radius_mm
    plan = [("groove", 0.0, False)] if d == 0.0 else [("lower", -d, False), ("upper", d, True)]
    passes = []
    for wall, offset, backwards in plan:
        if offset != 0.0:
            _check_stretch(cam, offset)
        passes.append(_pass(cam, wall, offset, outer, tolerance_mm, budget, backwards))
    gap_max = gap_min = 0.0
    at_deg: float | None = None
    at_x: float | None = None
    if d > 0.0:
        angles = np.linspace(0.0, 360.0, WALL_ANGLES)
        x_in, x_out = cam.roller_ends_mm
        positions = np.linspace(x_in, x_out, WALL_POSITIONS)
        gaps = wall_gaps(cam, tool_radius_mm, angles, positions)
        both = np.stack([gaps["lower"], gaps["upper"]])
        gap_max, gap_min = float(both.max()), float(both.min())
        worst = np.unravel_index(int(np.argmax(np.abs(both))), both.shape)
        at_deg, at_x = float(angles[worst[1]]), float(positions[worst[2]])
    return BarrelToolpath(float(tool_radius_mm), rr, float(tolerance_mm), r, outer, outer - cam.groove_depth_mm,
                          tuple(passes), gap_max, gap_min, at_deg, at_x)


def _check_stretch(cam: BarrelCam, offset: float) -> None:
    """Refuse an offset path that turns back: k = 1 − d·R·s''/w³ ≤ 0 somewhere."""
    grid = check_grid(cam.lift)
    path = DevelopedPath(cam, offset, cam.pitch_radius_mm)
    at, worst = periodic_grid_max(lambda t: -path.machine(t)[3], grid, np.asarray(cam.lift.breaks_rad))
    if worst >= 0.0:
        side = "upper" if offset > 0 else "lower"
        raise GeometryError(
            f"the {side} wall's developed radius of curvature at cam angle {math.degrees(at):.6g}° is smaller than the "
            f"cutter's offset from the groove's centre line ({abs(offset)!r} mm): its path would turn back. Use a "
            "larger cutter.", field=("tool_radius_mm",))


def _pass(cam: BarrelCam, wall: str, offset: float, outer: float, tol: float, budget: Budget,
          backwards: bool) -> RotaryPass:
    """One pass fitted at the outer radius over the whole turn, stretch by stretch between the lift's breaks."""
    curve = DevelopedPath(cam, offset, outer)
    bounds = sorted({0.0, TWO_PI, *[float(b) for b in cam.lift.breaks_rad if 0.0 < b < TWO_PI]})
    spans, deviation = fit_path(curve, bounds, tol, budget)
    nodes = np.array([spans[0].theta0] + [s.theta1 for s in spans])
    pitch = DevelopedPath(cam, offset, cam.pitch_radius_mm)
    deviation_pitch = float(chord_deviation(pitch, chords(pitch, nodes)).max())
    a_rad, x, _, _ = curve.machine(nodes)
    length = float(np.hypot(np.diff(a_rad) * cam.pitch_radius_mm, np.diff(x)).sum())
    if backwards:
        nodes, a_rad, x = nodes[::-1], a_rad[::-1], x[::-1]
    return RotaryPass(wall, float(offset), np.degrees(nodes), np.degrees(a_rad), np.asarray(x, dtype=np.float64),
                      deviation, deviation_pitch, length)


def wall_gaps(cam: BarrelCam, tool_radius_mm: float, cam_angle_deg: FloatArray, positions_mm: FloatArray
              ) -> dict[str, FloatArray]:
    """How far the walls a cutter's passes cut stand off the exact flanks, in 3-D.

    Each exact flank point P (:func:`flank_points`, the roller's contact at cam angle θ and
    position x along its axis) is compared with the cutter on the exact path of its wall's pass
    (offset d = ±(Rr − Rt); 0 for a cutter of the roller's radius): the gap is the least distance
    of P from the cutter's radial axis over the path, less Rt. Positive: material left standing
    on the wall (the groove too narrow there); negative: the cutter went past the wall.

    Parameters
    ----------
    cam : BarrelCam
        A translating follower's cam with a cylindrical roller.
    tool_radius_mm : float
        Rt [mm].
    cam_angle_deg : array_like
        Cam angles θ of the flank points, shape (n,) [deg].
    positions_mm : array_like
        Positions along the roller's axis, shape (m,) [mm].

    Returns
    -------
    dict
        ``"lower"`` and ``"upper"``: the gaps, shape (n, m) [mm].

    References
    ----------
    The module notes; the distance of a point (ρ, φ, z) from the radial line at angle A and
    height X: √((ρ·sin(φ − A))² + (z − X)²) where cos(φ − A) > 0; Kiefer (1953), golden section.
    """
    theta = np.radians(np.asarray(cam_angle_deg, dtype=np.float64)).reshape(-1)
    flanks = flank_points(cam, np.degrees(theta), positions_mm)
    d = cam.roller_radius_mm - tool_radius_mm
    # the nearest cutter position lies within a roller's width (and the offset) of θ along the path
    window = 2.0 * (cam.roller_radius_mm + d) / cam.roller_ends_mm[0]
    out = {}
    for wall, sign in (("lower", -1.0), ("upper", 1.0)):
        px, py, pz = (np.asarray(c).reshape(-1) for c in flanks[wall])
        centre = np.repeat(theta, flanks[wall][0].shape[1])
        path = DevelopedPath(cam, sign * d, cam.pitch_radius_mm)
        nearest = _nearest_axis(path, np.hypot(px, py), np.arctan2(py, px), pz, centre, window)
        out[wall] = (nearest - tool_radius_mm).reshape(flanks[wall][0].shape)
    return out


def _nearest_axis(path: DevelopedPath, rho: FloatArray, phi: FloatArray, z: FloatArray, centre: FloatArray,
                  window: float) -> FloatArray:
    """The least distance of points (ρ, φ, z) from the cutter's radial axis over the path's cam
    angles within ``window`` of ``centre`` (33 samples, the best refined by golden section) [mm]."""
    lanes = np.arange(centre.size)

    def closeness(t: FloatArray, lane: np.ndarray) -> FloatArray:
        a, x, _, _ = path.machine(t)
        turn = np.mod(phi[lane] - a + math.pi, TWO_PI) - math.pi
        dist2 = (rho[lane] * np.sin(turn)) ** 2 + (z[lane] - x) ** 2
        return np.where(np.cos(turn) > 0.0, -dist2, -np.inf)  # the axis is a half-line out from the cam axis

    steps = 33
    grid = centre[:, None] + np.linspace(-window, window, steps)[None, :]
    values = closeness(grid.reshape(-1), np.repeat(lanes, steps)).reshape(centre.size, steps)
    best = np.argmax(values, axis=1)
    lo = grid[lanes, np.maximum(best - 1, 0)]
    hi = grid[lanes, np.minimum(best + 1, steps - 1)]
    _, refined = golden_max(lambda t: closeness(t, lanes), lo, hi, width=1e-9)
    return np.asarray(np.sqrt(-np.maximum(values[lanes, best], refined)))
