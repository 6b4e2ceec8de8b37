"""The exact base radius of one candidate design, and its limits' exact values.

Every extreme here is the one the checks report: the pressure angle and the radius of curvature as
:func:`camcore.profile.checks.profile_checks` finds them (the best of a 7200-point grid with every break
point, refined by local grids), the contact force and the Hertz pressure as
:func:`camcore.profile.dynamics.follower_dynamics` finds them (the same grid, golden section between
neighbours). Each limit's own smallest base radius is solved by :func:`camcore._solvers.smallest_feasible`
to 1e-10 relative on its margin, which grows with the base radius; the design's is the largest of them
and the lower bound, as :func:`camcore.profile.base_circle.size_base_circle` takes the larger of its two.

For a translating follower without a separate return limit the pressure angle and the curvature are
:func:`size_base_circle` itself, started where it would be started at the lower bound, so a design whose
only free variable is the base radius answers the very number ``sizeBaseCircle`` does.

References
----------
.. [1] Shinzato and Kunigami (1988), eq. (6); Bezier valve-cam notes, eq. (11) (the flat tappet's
   ρ = Rb + s + s'').
.. [2] Dowell and Jarratt (1971), the Illinois method.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from ..._maxima import periodic_grid_maxima
from ..._solvers import NoFeasiblePointError, smallest_feasible
from ...curves.base import FloatArray
from ...errors import GeometryError
from ..base_circle import size_base_circle
from ..cam import CamSpec, kinematics, validate
from ..checks import check_maxima, lift_grid
from .problem import DesignLimits, placed
from .roots import assembly_range
from .spring import SpringModel


@dataclass(frozen=True)
class Candidate:
    """One design's free values: the follower's place (:func:`placed`) and roller radius [mm], spring rate
    [N/mm or N·m/rad] and preload [N or N·m] (None without a load)."""

    place_mm: float
    roller_radius_mm: float
    rate: float | None = None
    preload: float | None = None


class ExactCam:
    """The exact solves over one lift for any candidate: each limit's smallest base radius and, at a
    base radius, each limit's value."""

    def __init__(self, spec: CamSpec, limits: DesignLimits, spring: SpringModel | None, rb_lo: float, rb_hi: float):
        self.spec, self.limits, self.spring = spec, limits, spring
        self.rb_lo, self.rb_hi = rb_lo, rb_hi
        self.grid = lift_grid(spec)
        self.translating = spec.follower.motion == "translating"
        #: exact runs over the turn (checks or dynamics extremes) of the solves here, and calls of size_base_circle
        self.runs = 0
        self.sizings = 0
        self._geometric: dict[tuple[float, float], dict[str, float]] = {}
        self._stress: dict[tuple[float, ...], float] = {}

    def cam(self, c: Candidate, rb: float) -> CamSpec:
        """The cam of a candidate at base radius ``rb`` (not validated)."""
        return replace(self.spec, base_radius_mm=rb, follower=placed(self.spec.follower, c.place_mm, c.roller_radius_mm))

    def curvature_needed(self, c: Candidate) -> float | None:
        """The smallest radius of curvature of the surface the candidate must keep [mm] (None: no limit)."""
        lim = self.limits
        if lim.min_radius_of_curvature_mm is None and lim.min_radius_of_curvature_roller_multiple is None:
            return None if self.spec.follower.type == "knife-edge" else 0.0
        multiple = lim.min_radius_of_curvature_roller_multiple or 0.0
        return max(lim.min_radius_of_curvature_mm or 0.0, multiple * c.roller_radius_mm)

    def curvature_name(self, c: Candidate) -> str:
        """The curvature limit's request name: the one that asks more of this candidate (the millimetres
        on a tie, and when no limit is given: a roller's undercut, a flat face's convexity)."""
        lim = self.limits
        if lim.min_radius_of_curvature_roller_multiple is None:
            return "min_radius_of_curvature_mm"
        multiple = lim.min_radius_of_curvature_roller_multiple * c.roller_radius_mm
        mm = lim.min_radius_of_curvature_mm
        return "min_radius_of_curvature_mm" if mm is not None and mm >= multiple else \
            "min_radius_of_curvature_roller_multiple"

    # ------------------------------------------------------------------ margins at a base radius
    def signed_pressure(self, spec: CamSpec) -> tuple[float, float]:
        """The largest φ and the largest −φ over the turn [deg] (exact, as the checks refine)."""
        self.runs += 1
        def both(theta: FloatArray) -> FloatArray:
            phi = kinematics(spec, theta).pressure
            return np.vstack([phi, -phi])

        values = self.grid.kinematics(spec).pressure
        found = periodic_grid_maxima(both, self.grid.theta, np.vstack([values, -values]))
        return math.degrees(found[0][1]), math.degrees(found[1][1])

    def _pressure_margins(self) -> dict[str, Callable[[CamSpec], float]]:
        lim = self.limits
        out: dict[str, Callable[[CamSpec], float]] = {}
        if self.spec.model.flat_faced:
            return out
        rise, ret = lim.max_pressure_angle_deg, lim.max_return_pressure_angle_deg
        if lim.split_pressure:
            if rise is not None:
                out["max_pressure_angle_deg"] = lambda s: float(rise) - self.signed_pressure(s)[0]
            if ret is not None:
                out["max_return_pressure_angle_deg"] = lambda s: float(ret) - self.signed_pressure(s)[1]
        elif rise is not None or ret is not None:
            limit = float(rise if rise is not None else ret)  # type: ignore[arg-type]
            name = "max_pressure_angle_deg" if rise is not None else "max_return_pressure_angle_deg"
            out[name] = lambda s: limit - max(self.signed_pressure(s))
        return out

    def _curvature_margin(self, req: float) -> Callable[[CamSpec], float]:
        """The smallest radius of curvature of the surface's convex parts less ``req`` [mm]; an undercut
        roller fails however large the radius (base_circle's margin, flat faces by their own ρ)."""
        def margin(s: CamSpec) -> float:
            self.runs += 1
            if s.model.flat_faced:
                return -check_maxima(s, self.grid, ("neg_rho",))["neg_rho"][1] - req
            kmax = check_maxima(s, self.grid, ("kappa",))["kappa"][1]
            rr = s.model.roller_radius_mm
            rho_pitch = 1.0 / kmax if kmax > 0 else math.inf
            if rr > 0 and kmax > 0 and rr >= rho_pitch:
                return -1.0 - abs(rho_pitch - rr)
            return rho_pitch - rr - req

        return margin

    # ------------------------------------------------------------------ each limit's own radius
    def _solve(self, spec: CamSpec, margin: Callable[[CamSpec], float], lo: float, hi: float,
               unimodal: bool = False) -> float:
        """Smallest Rb in [lo, hi] with margin ≥ 0 (lo itself when it meets it; +inf when none does).

        ``unimodal``: the margin may fall again towards ``hi`` (the Hertz pressure on a concave flank);
        where ``hi`` fails, a point that meets it on the way to its maximum brackets the root."""
        def at(rb: float) -> float:
            s = replace(spec, base_radius_mm=rb)
            try:
                validate(s)
            except GeometryError:
                return -math.inf
            return float(margin(s))

        if at(lo) >= 0:
            return lo
        if not hi > lo:
            return math.inf
        if at(hi) < 0:
            found = _feasible_point(at, lo, hi) if unimodal else None
            if found is None:
                return math.inf
            hi = found
        try:
            return smallest_feasible(at, lo, hi)
        except NoFeasiblePointError:
            return math.inf

    def bracket(self, c: Candidate) -> tuple[float, float]:
        """Where the candidate's base radius may lie: (the geometric floor, the upper bound or the largest
        radius its arm can be assembled at) [mm]."""
        model = self.cam(c, self.rb_hi).model
        if self.translating:
            return model.min_base_radius_mm(), self.rb_hi
        return assembly_range(model, self.spec.lift.derivatives(np.linspace(0.0, 2 * math.pi, 721), 0)[0],
                               1e-3 * self.rb_lo, self.rb_hi)

    def geometric_radii(self, c: Candidate) -> dict[str, float]:
        """Each geometric limit's own smallest base radius (pressure angle, curvature) [mm]; +inf where
        the bounds hold none (kept for each place and roller radius: the spring does not change them)."""
        key = (c.place_mm, c.roller_radius_mm)
        if key not in self._geometric:
            self._geometric[key] = self._geometric_radii(c)
        return dict(self._geometric[key])

    def _geometric_radii(self, c: Candidate) -> dict[str, float]:
        spec = self.cam(c, self.rb_lo)
        req = self.curvature_needed(c)
        pressure = self._pressure_margins()
        out: dict[str, float] = {}
        if self.translating and not self.limits.split_pressure:
            # size_base_circle itself: the same margins, started at the lower bound
            limit = self.limits.max_pressure_angle_deg or self.limits.max_return_pressure_angle_deg
            if limit is not None or req is not None or spec.model.flat_faced:
                self.sizings += 1
                result = size_base_circle(spec, None if spec.model.flat_faced else limit, req)
                if result.radius_for_pressure_angle_mm is not None:
                    out[next(iter(pressure))] = result.radius_for_pressure_angle_mm
                if result.radius_for_curvature_mm is not None:
                    out[self.curvature_name(c)] = result.radius_for_curvature_mm
            return out
        lo, hi = self.bracket(c)
        margins = dict(pressure)
        if req is not None:
            margins[self.curvature_name(c)] = self._curvature_margin(req)
        for name, margin in margins.items():
            # an arm's pressure angle rises again as the arm nears folding: unimodal, not monotone
            out[name] = self._solve(spec, margin, lo, hi, unimodal=not self.translating)
        return out

    def stress_radius(self, c: Candidate, start: float) -> float:
        """The Hertz limit's own smallest base radius above ``start`` [mm]: −inf when it is met at ``start``
        already (its root lies below and decides nothing), +inf when no radius within the bounds meets it."""
        assert self.spring is not None and c.rate is not None and c.preload is not None
        allowed = self.limits.allowed_stress_mpa
        assert allowed is not None
        key = (c.place_mm, c.roller_radius_mm, c.rate, c.preload, start)
        if key not in self._stress:
            self._stress[key] = self._stress_radius(c, start, allowed)
        return self._stress[key]

    def _stress_radius(self, c: Candidate, start: float, allowed: float) -> float:
        assert self.spring is not None and c.rate is not None and c.preload is not None
        hi = self.rb_hi if self.translating else self.bracket(c)[1]
        margin = self.spring.stress_margin(c.rate, c.preload, allowed)
        spec = self.cam(c, start)
        if margin(spec) >= 0:
            return -math.inf  # met at the start: its own root lies below, and decides nothing
        return self._solve(spec, margin, start, hi, unimodal=True)

    def radii(self, c: Candidate) -> dict[str, float]:
        """Every limit's own smallest base radius [mm]: the geometric ones, then the stress from the
        largest of those (the stress's root below them would not decide anything)."""
        out = self.geometric_radii(c)
        if self.limits.allowed_stress_mpa is not None and self.spring is not None:
            start = max([self.rb_lo, *[r for r in out.values() if math.isfinite(r)]])
            out["allowed_stress_mpa"] = self.stress_radius(c, start)
        return out

    # ------------------------------------------------------------------ values at a design
    def values(self, c: Candidate, rb: float) -> dict[str, tuple[float, float]]:
        """Each limit's (value, limit) at the candidate's cam of base radius ``rb``: the pressure angles
        [deg], the smallest radius of curvature [mm] (the roller-multiple limit as ρ/Rr [-]), the
        Hertz pressure [N/mm²] and the smallest contact force [N]."""
        spec = self.cam(c, rb)
        validate(spec)
        lim, out = self.limits, {}
        rise, ret = self.signed_pressure(spec) if not spec.model.flat_faced else (0.0, 0.0)
        for name in self._pressure_margins():
            given: float | None = getattr(lim, name)
            limit = given if given is not None else (lim.max_pressure_angle_deg or lim.max_return_pressure_angle_deg)
            assert limit is not None
            value = {"max_pressure_angle_deg": rise, "max_return_pressure_angle_deg": ret}[name]
            out[name] = (max(rise, ret) if not lim.split_pressure else value, float(limit))
        req = self.curvature_needed(c)
        if req is not None:
            rho = req + self._curvature_margin(req)(spec)
            if lim.min_radius_of_curvature_mm is not None or lim.min_radius_of_curvature_roller_multiple is None:
                out["min_radius_of_curvature_mm"] = (rho, lim.min_radius_of_curvature_mm or 0.0)
            if lim.min_radius_of_curvature_roller_multiple is not None:
                out["min_radius_of_curvature_roller_multiple"] = (rho / c.roller_radius_mm,
                                                                   lim.min_radius_of_curvature_roller_multiple)
        if self.spring is not None and c.rate is not None and c.preload is not None:
            contact, stress = self.spring.extremes(c.rate, c.preload, spec)
            out["safety_margin_n"] = (contact, self.spring.margin_n)
            if lim.allowed_stress_mpa is not None and stress is not None:
                out["allowed_stress_mpa"] = (stress, lim.allowed_stress_mpa)
        return out



def _feasible_point(margin: Callable[[float], float], a: float, b: float) -> float | None:
    """A point of (a, b) where a unimodal margin is ≥ 0: golden section towards its maximum (to 1e-6 of the
    bracket: a window of feasible radii narrower than that is taken for none), stopping at the first such
    point; None when its maximum is < 0."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    x1, x2 = b - g * (b - a), a + g * (b - a)
    f1, f2 = margin(x1), margin(x2)
    width = 1e-6 * (b - a)
    while True:
        if max(f1, f2) >= 0:
            return x1 if f1 >= 0 else x2
        if b - a < width:
            return None
        if f1 < f2:  # the maximum lies in [x1, b]
            a, x1, f1 = x1, x2, f2
            x2 = a + g * (b - a)
            f2 = margin(x2)
        else:
            b, x2, f2 = x2, x1, f1
            x1 = b - g * (b - a)
            f1 = margin(x1)
