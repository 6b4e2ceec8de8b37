"""Base-circle sizing: the smallest base radius that meets a pressure-angle limit and a
radius-of-curvature limit.

References
----------
.. [1] Shinzato and Kunigami (1988): the pressure angle of a translating follower,
   tan φ = (s' − σe)/(s0 + s), falls as the base radius grows.
.. [2] Bezier valve-cam notes: a flat tappet's cam radius Rb + s + s'' must stay positive.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from .._maxima import periodic_grid_maxima
from .._solvers import NoFeasiblePointError, smallest_feasible
from ..curves.base import FloatArray
from ..errors import GeometryError, InvalidParameterError
from .cam import CamSpec, validate
from .checks import LiftGrid, check_maxima, corners, lift_grid, profile_checks
from .followers import FlatTranslating, KnifeEdgeTranslating

Constraint = Literal["pressure_angle", "radius_of_curvature", "geometry"]


@dataclass(frozen=True)
class BaseCircleResult:
    """The smallest base radius meeting the limits and which one decided it.

    ``active_constraint``: ``"pressure_angle"``, ``"radius_of_curvature"`` or
    ``"geometry"`` (no limit binds; the smallest radius the follower geometry allows).
    """

    base_radius_mm: float
    active_constraint: Constraint
    max_pressure_angle_deg: float
    min_radius_of_curvature_mm: float
    radius_for_pressure_angle_mm: float | None
    radius_for_curvature_mm: float | None


def _solve_radius(spec: CamSpec, margin: Callable[[CamSpec], float], what: str) -> float:
    """Smallest Rb with margin(spec(Rb)) ≥ 0 (margin assumed to grow with Rb), to 1e-10
    relative (:func:`smallest_feasible`); where the geometry cannot be assembled the margin
    is unknown and the step bisects."""
    lo = spec.model.min_base_radius_mm()

    def at(rb: float) -> float:
        s = replace(spec, base_radius_mm=rb)
        try:
            validate(s)
        except GeometryError:
            return -math.inf
        return float(margin(s))

    try:
        return smallest_feasible(at, lo, max(lo * 1.5, max(1.0, spec.base_radius_mm)))
    except NoFeasiblePointError as exc:
        raise GeometryError(f"No base radius up to {exc.largest_tried!r} mm meets the {what} limit.") from None


def _flat_translating_radius(spec: CamSpec, grid: LiftGrid, req: float) -> float | None:
    """Closed form of a flat translating face: ρ = Rb + s + s'' ≥ req where s + s'' is least."""
    (_, m), = periodic_grid_maxima(lambda t: -np.sum(spec.lift.derivatives(t, 2)[::2], axis=0)[None, :],
                                   grid.theta, -(grid.lift[0] + grid.lift[2])[None, :])
    # ρ = Rb + s + s'' > req strictly at the minimum would need Rb > req − min; take equality
    r_c = req + m
    return r_c if r_c > 0 else None


def _translating_pressure_radius(spec: CamSpec, grid: LiftGrid, limit_deg: float) -> float | None:
    """Closed form of a translating knife-edge or roller: tan φ = (s' − σe)/(s0 + s), so |φ| ≤ α at
    every θ exactly when s0 ≥ |s' − σe|/tan α − s there; s0 is the largest of that over the turn (the
    checks' grid and local grids) and Rb = √(s0² + e²) − Rr. None where that is not above the
    geometry's floor (the floor itself is no cam: the root solve then finds the smallest one)."""
    e, sigma = spec.follower.offset_mm, spec.sigma
    slope = math.tan(math.radians(limit_deg))

    def needed(h: FloatArray, h1: FloatArray) -> FloatArray:
        p = h1 - sigma * e
        return np.vstack([p / slope - h, -p / slope - h])

    found = periodic_grid_maxima(lambda t: needed(*spec.lift.derivatives(t, 1)[:2]), grid.theta,
                                 needed(grid.lift[0], grid.lift[1]))
    s0 = max(0.0, *(m for _, m in found))
    rb = math.sqrt(s0 * s0 + e * e) - spec.model.roller_radius_mm
    return rb if rb > spec.model.min_base_radius_mm() else None


def _curvature_margin(spec: CamSpec, grid: LiftGrid, req: float) -> float:
    """Smallest radius of curvature of the cam surface less the limit [mm]; an undercut cam
    fails however large its nominal radius (a negative margin)."""
    found = check_maxima(spec, grid, ("kappa",))
    kmax = found["kappa"][1]
    rr = spec.model.roller_radius_mm
    rho_pitch = 1.0 / kmax if kmax > 0 else math.inf
    if rr > 0 and kmax > 0 and rr >= rho_pitch:
        return -1.0 - abs(rho_pitch - rr)
    return rho_pitch - rr - req


def size_base_circle(
    spec: CamSpec,
    max_pressure_angle_deg: float | None = None,
    min_radius_of_curvature_mm: float | None = None,
) -> BaseCircleResult:
    """Smallest base radius with max |pressure angle| ≤ the limit and min radius of curvature
    ≥ the limit (either may be None). Flat-faced followers always need a convex cam
    (ρ > 0): a missing curvature limit means 0.

    Each limit is solved on its own by the Illinois method to 1e-10 relative on the exact
    extreme it limits (grid + local grids, :func:`check_maxima`; the lift on the grid does not
    change with the radius and is evaluated once); the answer is the larger radius. Two are
    closed forms: a translating knife-edge's or roller's pressure angle, tan φ = (s' − σe)/(s0 + s),
    is within α everywhere exactly when s0 ≥ max_θ(|s' − σe|/tan α − s), Rb = √(s0² + e²) − Rr (the
    largest found as the checks find theirs); and the flat-faced translating face's curvature,
    Rb = ρreq − min(s + s'').

    Parameters
    ----------
    spec : CamSpec
        The cam; its base radius is only the starting guess.
    max_pressure_angle_deg : float, optional
        Limit of the largest |pressure angle| over the turn, 0 < limit < 90 [deg]; ignored
        for flat-faced followers (their pressure angle is 0).
    min_radius_of_curvature_mm : float, optional
        Limit of the smallest radius of curvature of the cam surface, ≥ 0 [mm].

    Returns
    -------
    BaseCircleResult
        The radius, the limit that decided it, the checks at that radius and the radius
        each limit alone would need.

    Raises
    ------
    InvalidParameterError
        No limit, or a limit out of range.
    GeometryError
        The lift has a corner (a curvature limit cannot be met), or no radius up to the
        largest tried meets a limit.

    References
    ----------
    Shinzato and Kunigami (1988), eq. (6), and the offset form tan φ = (s' − σe)/(s0 + s);
    Bezier valve-cam notes, eq. (11) (flat tappet: ρ = Rb + s + s'' > 0); Dowell and Jarratt
    (1971), the Illinois method.
    """
    model = spec.model
    if max_pressure_angle_deg is not None and not (0 < max_pressure_angle_deg < 90):
        raise InvalidParameterError("max_pressure_angle_deg must lie between 0 and 90 degrees.")
    if min_radius_of_curvature_mm is not None and not (math.isfinite(min_radius_of_curvature_mm)
                                                       and min_radius_of_curvature_mm >= 0):
        raise InvalidParameterError("min_radius_of_curvature_mm must be a finite number ≥ 0.")
    if model.flat_faced and min_radius_of_curvature_mm is None:
        min_radius_of_curvature_mm = 0.0
    if max_pressure_angle_deg is None and min_radius_of_curvature_mm is None:
        raise InvalidParameterError("Give a pressure-angle limit, a curvature limit, or both.")
    r_p: float | None = None
    r_c: float | None = None
    grid = lift_grid(spec)
    if max_pressure_angle_deg is not None and isinstance(model, KnifeEdgeTranslating):
        r_p = _translating_pressure_radius(spec, grid, max_pressure_angle_deg)
    if r_p is None and max_pressure_angle_deg is not None and not model.flat_faced:
        lim = max_pressure_angle_deg
        r_p = _solve_radius(spec, lambda s: lim - math.degrees(check_maxima(s, grid, ("pressure",))["pressure"][1]),
                            "pressure-angle")
    if min_radius_of_curvature_mm is not None:
        req = min_radius_of_curvature_mm
        if corners(spec, grid):
            raise GeometryError("The lift's velocity jumps, so the cam has a corner (radius 0) at any base radius.")
        if isinstance(model, FlatTranslating):
            r_c = _flat_translating_radius(spec, grid, req)
        else:
            r_c = _solve_radius(spec, lambda s: _curvature_margin(s, grid, req), "radius-of-curvature")
    active: Constraint = "geometry"
    rb = max(model.min_base_radius_mm(), 1e-9)
    limits: tuple[tuple[float | None, Constraint], ...] = ((r_p, "pressure_angle"), (r_c, "radius_of_curvature"))
    candidates = [(r, n) for r, n in limits if r is not None]
    if candidates:
        rb, active = max(candidates)
    final = replace(spec, base_radius_mm=rb)
    validate(final)
    ch = profile_checks(final, grid)
    return BaseCircleResult(rb, active, ch.max_pressure_angle_deg, ch.min_radius_of_curvature_mm, r_p, r_c)

