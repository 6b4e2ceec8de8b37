"""The surfaces of a barrel cam's solid as bicubic B-splines within a tolerance of the exact
ones (numpy only; :mod:`camcore.export.barrel_solid` sews them in the kernel, and its module
notes say what the groove and the solid are).

Between consecutive break points of the lift (a *stretch*) five surfaces: each wall over
(θ, r), r from the groove's bottom radius r_b to the outer radius r_o (:func:`flank_on_cylinder`,
the roller's exact envelope); the floor over (θ, t) on the cylinder r_b, the cam-frame angle and
z linear in t from the lower wall's edge (t = 0) to the upper's (t = 1); and the two bands of
the outer cylinder r_o over (θ, t), from each wall's outer edge (t = 0) straight along the axis
to the blank's end (t = 1). Each is the Hermite interpolant of the exact points, their θ and
r (or t) derivatives and the twist, all from central differences of the exact surface
(one-sided in θ at a break), at nodes in θ shared by the five surfaces of a stretch and nodes
across each: a B-spline with double inner knots (C¹). The edges two surfaces share are made
from the same data (the floor's and the bands' edges are the walls' own values and θ
derivatives), so they share their poles. The nodes are halved until every surface, evaluated
at the middle of each patch and of each patch's edges (where a cubic Hermite's error peaks),
lies within 0.8 × the tolerance of the exact surface there (the distance between points of the
same parameters: an upper bound of the distance between the surfaces).

References
----------
.. [1] L. Piegl, W. Tiller, *The NURBS Book*, 2nd ed. (1997), 2.2-2.5 (knot multiplicity and
   continuity) and the bicubic Hermite (Coons) patch in Bezier form.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..cams.barrel.geometry import BarrelCam, check_grid, flank_on_cylinder
from ..curves.base import FloatArray
from ..deadline import checkpoint
from ..errors import GeometryError, InvalidParameterError, LimitExceededError
from ..profile.checks import lift_corners
from ..profile.lift import TWO_PI

#: the surfaces are fitted to this share of the tolerance (the check sees the patches' middles)
AIM = 0.8
#: steps of the central differences: θ [rad], and across [mm or -] relative to the span's size;
#: their error ~step²·|F'''|/6 ≈ 1e-10·|F'''|, their rounding ~1e-16·|F|/step ≈ 1e-11·|F|/1e-5
STEP_THETA = 1e-5
STEP_ACROSS = 1e-4
#: the first node spacings: 15° along the groove, three nodes across each surface
FIRST_STEP_RAD = math.radians(15.0)
FIRST_ACROSS = 3
#: halvings of a node spacing before the fit is refused (15° → 0.12°)
REFINEMENTS = 7
#: the surfaces of a stretch, in the order of its cross-section (walls, floor, bands)
NAMES = ("upper", "lower", "floor", "lower_band", "upper_band")

Surface = Callable[[FloatArray, FloatArray], FloatArray]
#: a surface's poles (2·nθ × 2·n_across × 3) and its knots in θ and across
Patch = tuple[FloatArray, FloatArray, FloatArray]


@dataclass(frozen=True)
class BarrelSurfaces:
    """The solid's surfaces, stretch by stretch, and what was measured of them.

    ``stretches``: per stretch, each surface of :data:`NAMES` as (poles, θ knots, knots across);
    ``deviation_mm``: the largest distance measured from the exact surfaces; the radii and the
    blank's ends ``z0_mm``, ``z1_mm``; ``z_min_mm``, ``z_max_mm``: the groove's extent along the axis.
    """

    stretches: tuple[dict[str, Patch], ...]
    deviation_mm: float
    outer_radius_mm: float
    bottom_radius_mm: float
    z_min_mm: float
    z_max_mm: float
    z0_mm: float
    z1_mm: float

    @property
    def poles_count(self) -> int:
        """Poles of all surfaces [-]."""
        return sum(p.shape[0] * p.shape[1] for s in self.stretches for p, _, _ in s.values())


def _hermite(values: Surface, theta: FloatArray, across: FloatArray, step_across: float
             ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Values, ∂θ, ∂across and the twist of a surface at the node grid (central differences,
    one-sided in θ at the stretch's ends: they lie on breaks of the lift)."""
    h, k = STEP_THETA, step_across
    t, a = np.meshgrid(theta, across, indexing="ij")
    steps = [(i, j) for i in range(5) for j in (-1, 0, 1)]
    # every value the differences need, at θ + (i − 2)·h and across + j·k, in one evaluation
    every = values(np.stack([t + (i - 2) * h for i, _ in steps]), np.stack([a + j * k for _, j in steps]))
    grid = {step: every[n] for n, step in enumerate(steps)}
    value = {i: grid[(i, 0)] for i in range(5)}
    across_rate = {i: (grid[(i, 1)] - grid[(i, -1)]) / (2 * k) for i in range(5)}
    out = []
    for f in (value, across_rate):  # their θ derivatives: the θ rate, and the twist
        d = (f[3] - f[1]) / (2 * h)
        d[0] = (-3 * f[2][0] + 4 * f[3][0] - f[4][0]) / (2 * h)
        d[-1] = (3 * f[2][-1] - 4 * f[1][-1] + f[0][-1]) / (2 * h)
        out.append(d)
    return value[2], out[0], across_rate[2], out[1]


def _pole_map(nodes: FloatArray) -> tuple[np.ndarray, FloatArray, FloatArray]:
    """For a C¹ cubic B-spline through Hermite data at ``nodes``: each pole's node and the
    multiple of the derivative added there (±h/3), and the knots (4 at the ends, 2 inside)."""
    h = np.diff(nodes)
    index = [0, 0]
    scale = [0.0, h[0] / 3]
    for i in range(1, len(nodes) - 1):
        index += [i, i]
        scale += [-h[i - 1] / 3, h[i] / 3]
    index += [len(nodes) - 1, len(nodes) - 1]
    scale += [-h[-1] / 3, 0.0]
    knots = np.concatenate([[nodes[0]] * 4, np.repeat(nodes[1:-1], 2), [nodes[-1]] * 4])
    return np.array(index), np.array(scale), knots


def hermite_patch(p: FloatArray, pu: FloatArray, pv: FloatArray, puv: FloatArray, u: FloatArray, v: FloatArray
                  ) -> Patch:
    """The poles and knots of the bicubic Hermite surface through values, first derivatives and
    twists at a grid of nodes.

    Parameters
    ----------
    p, pu, pv, puv : ndarray
        The points and, per unit of u and v, their derivatives and twists, shape (n, m, 3) [mm].
    u, v : ndarray
        The nodes, increasing, shapes (n,) and (m,) [rad, mm or -].

    Returns
    -------
    (ndarray, ndarray, ndarray)
        The poles (2n × 2m × 3) [mm] and the knots in u and v (double inside: C¹).

    References
    ----------
    Piegl and Tiller (1997): a patch's Bezier poles P + cu·Pu + cv·Pv + cu·cv·Puv, cu and cv
    0 or ±h/3; a double inner knot of a cubic joins two Bezier pieces with C¹.
    """
    iu, cu, ku = _pole_map(u)
    iv, cv, kv = _pole_map(v)
    sel = np.ix_(iu, iv)
    cu3, cv3 = cu[:, None, None], cv[None, :, None]
    return p[sel] + cu3 * pu[sel] + cv3 * pv[sel] + cu3 * cv3 * puv[sel], ku, kv


def _middles(p: FloatArray, pu: FloatArray, pv: FloatArray, puv: FloatArray, u: FloatArray, v: FloatArray
             ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The Hermite surface on the grid of its nodes and their midpoints (shape (2n−1, 2m−1)),
    and that grid's u and v."""

    def along(f: FloatArray, fd: FloatArray, h: FloatArray, axis: int) -> FloatArray:
        # the cubic Hermite at s = 1/2: (f0 + f1)/2 + h·(f0' − f1')/8, interleaved with the nodes
        n = len(h)
        f0, f1 = np.take(f, range(n), axis), np.take(f, range(1, n + 1), axis)
        d0, d1 = np.take(fd, range(n), axis), np.take(fd, range(1, n + 1), axis)
        shape = [1, 1, 1]
        shape[axis] = n
        mid = 0.5 * (f0 + f1) + h.reshape(shape) * (d0 - d1) / 8
        order = np.argsort(np.concatenate([np.arange(n + 1) * 2, np.arange(n) * 2 + 1]))
        return np.take(np.concatenate([f, mid], axis=axis), order, axis)

    pm, pvm = along(p, pu, np.diff(u), 0), along(pv, puv, np.diff(u), 0)
    um = np.sort(np.concatenate([u, 0.5 * (u[:-1] + u[1:])]))
    vm = np.sort(np.concatenate([v, 0.5 * (v[:-1] + v[1:])]))
    return along(pm, pvm, np.diff(v), 1), um, vm


def _functions(cam: BarrelCam, r_b: float, r_o: float, z0: float, z1: float) -> dict[str, Surface]:
    """The five surfaces as functions of (θ, r) or (θ, t): points (…, 3) [mm]."""

    def wall(name: str) -> Surface:
        def f(theta: FloatArray, r: FloatArray) -> FloatArray:
            return np.stack(flank_on_cylinder(cam, theta, r)[name], axis=-1)
        return f

    def floor(theta: FloatArray, t: FloatArray) -> FloatArray:
        both = flank_on_cylinder(cam, theta, np.full_like(theta, r_b))
        (lx, ly, lz), (ux, uy, uz) = both["lower"], both["upper"]
        a0 = np.arctan2(ly, lx)
        phi = a0 + t * (np.mod(np.arctan2(uy, ux) - a0 + math.pi, TWO_PI) - math.pi)
        return np.stack([r_b * np.cos(phi), r_b * np.sin(phi), lz + t * (uz - lz)], axis=-1)

    def band(name: str, end: float) -> Surface:
        def f(theta: FloatArray, t: FloatArray) -> FloatArray:
            x, y, z = flank_on_cylinder(cam, theta, np.full_like(theta, r_o))[name]
            return np.stack([x, y, (1.0 - t) * z + t * end], axis=-1)  # z = end exactly at t = 1
        return f

    return {"upper": wall("upper"), "lower": wall("lower"), "floor": floor, "lower_band": band("lower", z0),
            "upper_band": band("upper", z1)}


def barrel_surfaces(cam: BarrelCam, tolerance_mm: float, end_margin_mm: float, max_poles: int = 400_000
                    ) -> BarrelSurfaces:
    """The surfaces of a barrel cam's solid within a tolerance of the exact ones (module notes).

    Parameters
    ----------
    cam : BarrelCam
        The cam.
    tolerance_mm : float
        The largest distance of each surface from the exact one at its patches' middles [mm].
    end_margin_mm : float
        The blank's length beyond the groove at each end [mm].
    max_poles : int
        The most poles of all surfaces [-] (more: LimitExceededError at the solid's tolerance).

    Returns
    -------
    BarrelSurfaces
        Stretch by stretch, each surface's poles and knots; the deviation measured.

    Raises
    ------
    GeometryError
        A lift whose velocity jumps; walls that turn back between r_b and r_o (undercut).
    InvalidParameterError
        A tolerance or margin that is not positive.
    LimitExceededError
        More than ``max_poles`` poles.

    References
    ----------
    Piegl and Tiller (1997); the module notes.
    """
    if not (math.isfinite(tolerance_mm) and tolerance_mm > 0):
        raise InvalidParameterError("tolerance_mm must be a positive number.", field=("solid", "tolerance_mm"))
    if not (math.isfinite(end_margin_mm) and end_margin_mm > 0):
        raise InvalidParameterError("end_margin_mm must be greater than 0.", field=("solid", "end_margin_mm"))
    kinks = lift_corners(cam.lift)
    if kinks:
        raise GeometryError(f"the lift's velocity jumps at cam angle {kinks[0]:.6g}°: the groove's walls have a corner "
                            "there; the solid is made for a lift with a continuous velocity.", field=("solid",))
    r_o = cam.pitch_radius_mm + 0.5 * cam.roller_length_mm
    r_b = r_o - cam.groove_depth_mm
    z_min, z_max = _check_walls(cam, r_b, r_o)
    z0, z1 = z_min - end_margin_mm, z_max + end_margin_mm
    functions = _functions(cam, r_b, r_o, z0, z1)
    across = {"upper": (r_b, r_o), "lower": (r_b, r_o), "floor": (0.0, 1.0), "lower_band": (0.0, 1.0),
              "upper_band": (0.0, 1.0)}
    counts = dict.fromkeys(NAMES, FIRST_ACROSS)
    bounds = sorted({0.0, TWO_PI, *[float(b) for b in cam.lift.breaks_rad if 0.0 < b < TWO_PI]})
    aim = AIM * tolerance_mm
    while True:  # again whenever a stretch needed more nodes across: all stretches share them at their ends
        before = dict(counts)
        stretches: list[dict[str, Patch]] = []
        worst = 0.0
        for a, b in itertools.pairwise(bounds):
            data, deviation = _fit_stretch(functions, across, counts, a, b, aim, tolerance_mm)
            worst = max(worst, deviation)
            stretches.append(_stretch(data))
            poles = sum(p.shape[0] * p.shape[1] for s in stretches for p, _, _ in s.values())
            if poles > max_poles:
                raise LimitExceededError("B-spline poles of the solid", poles, max_poles,
                                         field=("solid", "tolerance_mm"))
        if counts == before:
            break
    for name, (poles, _, _) in stretches[-1].items():  # θ = 2π is 0: the last edge the first's, bit for bit
        poles[-1] = stretches[0][name][0][0]
    return BarrelSurfaces(tuple(stretches), worst, r_o, r_b, z_min, z_max, z0, z1)


def _fit_stretch(functions: dict[str, Surface], across: dict[str, tuple[float, float]], counts: dict[str, int],
                 a: float, b: float, aim: float, tolerance_mm: float
                 ) -> tuple[dict[str, tuple[FloatArray, ...]], float]:
    """Hermite data of the five surfaces over θ = a … b, the nodes halved until all are within
    ``aim`` (across first: at the θ nodes the error is the spacing across alone)."""
    n = max(2, math.ceil((b - a) / FIRST_STEP_RAD))
    for _ in range(REFINEMENTS + 1):
        checkpoint()
        theta = np.linspace(a, b, n + 1)
        data: dict[str, tuple[FloatArray, ...]] = {}
        deviation = 0.0
        for name in NAMES:
            f, (lo, hi) = functions[name], across[name]
            while True:
                v = np.linspace(lo, hi, counts[name])
                hermite = _hermite(f, theta, v, STEP_ACROSS * max(1.0, abs(lo), abs(hi)))
                points, um, vm = _middles(*hermite, theta, v)
                tt, vv = np.meshgrid(um, vm, indexing="ij")
                error = np.linalg.norm(points - f(tt, vv), axis=-1)
                if float(error[::2].max()) <= aim or counts[name] >= 2**REFINEMENTS:
                    break
                counts[name] = 2 * counts[name] - 1
            data[name] = (*hermite, theta, v)
            deviation = max(deviation, float(error.max()))
        if deviation <= aim:
            return data, deviation
        n *= 2
    raise GeometryError(f"the solid could not be fitted within {tolerance_mm!r} mm between cam angles "
                        f"{math.degrees(a):.6g}° and {math.degrees(b):.6g}°.", field=("solid", "tolerance_mm"))


def _stretch(data: dict[str, tuple[FloatArray, ...]]) -> dict[str, Patch]:
    """The five surfaces' poles and knots, the floor's and the bands' edges the walls' own data."""
    p = {name: [np.array(x) for x in d[:4]] for name, d in data.items()}
    # (surface, its column across, the wall, the wall's row across): the floor from the lower wall's
    # bottom edge (t = 0) to the upper's (t = 1); each band from its wall's outer edge (t = 0)
    for face, column, wall, row in (("floor", 0, "lower", 0), ("floor", -1, "upper", 0),
                                    ("lower_band", 0, "lower", -1), ("upper_band", 0, "upper", -1)):
        for k in (0, 1):  # the value and its θ derivative: all the edge's poles are made of
            p[face][k][:, column] = p[wall][k][:, row]
    return {name: hermite_patch(p[name][0], p[name][1], p[name][2], p[name][3], data[name][4], data[name][5])
            for name in data}


def _check_walls(cam: BarrelCam, r_b: float, r_o: float) -> tuple[float, float]:
    """Refuse walls that turn back (the envelope loops) anywhere from r_b to r_o: each wall's
    cam-frame angle must advance with θ at every radius (on the lift's check grid, 7200 angles
    and the breaks); and the groove's lowest and highest z [mm]."""
    grid = check_grid(cam.lift)
    grid = grid[np.concatenate([[True], np.diff(grid) > 1e-9])]  # the grid's left limits at the breaks: 1e-10 apart
    z_min, z_max = math.inf, -math.inf
    for r in np.linspace(r_b, r_o, 5):
        for name in ("upper", "lower"):
            x, y, z = flank_on_cylinder(cam, grid, np.full_like(grid, r))[name]
            z_min, z_max = min(z_min, float(z.min())), max(z_max, float(z.max()))
            back = np.nonzero(np.diff(np.unwrap(np.arctan2(y, x))) <= 0.0)[0]
            if back.size:
                raise GeometryError(
                    f"the {name} wall turns back at cam angle {math.degrees(grid[back[0]]):.6g}° at radius {r:.6g} mm: "
                    "the roller is larger than the groove's radius of curvature there (undercut), so the groove has "
                    "no wall to cut. Enlarge the pitch radius or use a smaller roller.", field=("roller_radius_mm",))
    return z_min, z_max
