"""The search's evaluator: for many candidate designs at once, each limit's margin at any base radius
and the smallest base radius that meets every limit, from the lift sampled on a grid.

A candidate ("lane") is a place (an offset e, or an arm's pivot distance d), a roller radius Rr, and a
spring (rate and preload); the base
radius Rb is solved for. Every limit's margin grows with Rb (the pressure angle falls, the radius of
curvature grows, the Hertz stress falls with the curvature and the normal force), so the smallest
Rb meeting all of them is the root of the smallest margin, bracketed between the geometric floor
and the upper bound and refined for all lanes together by the Illinois method
(:func:`camcore._solvers.illinois_roots`).

Extremes here are the largest sampled value on a grid of :data:`SEARCH_GRID` angles plus every break
point of the lift and its left neighbour (no refinement): they rank candidates, and the design the
search settles on is solved again exactly (:mod:`.exact`), so the grid's error (a relative
½·h²·|f''|/f, about 1e-6 for h = 0.25°) moves only where the search looks, not the answer.

For a translating knife-edge or roller follower the pitch curve depends on s0 = √((Rb + Rr)² − e²)
and e only, and its quantities are closed forms of the lift (r = s0 + s, p = s' − σe):

    tan φ = p / r,    κp = (r² − r·s'' + p·(p + s')) / (r² + p²)^{3/2},

evaluated for every lane at once; the pressure limit even gives Rb in closed form (φ ≤ α at every
angle ⇔ s0 ≥ max_θ((s' − σe)/tan α − s)). Other followers are evaluated lane by lane with their
own kinematics (:meth:`camcore.profile.followers.FollowerModel.kinematics`).

References
----------
.. [1] Shinzato and Kunigami (1988), eq. (6): tan φ = (s' − σe)/(s0 + s).
.. [2] Dowell and Jarratt (1971), the Illinois method.
.. [3] Johnson (1985), §4.2: the Hertz pressure of a line contact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..._maxima import golden_max
from ...curves.base import FloatArray
from ...deadline import checkpoint
from ...errors import GeometryError
from ..cam import CamSpec
from ..checks import lift_check_grid
from ..dynamics import effective_modulus_mpa
from .problem import DesignLimits, placed
from .roots import IndexArray, assembly_range, feasible_points, illinois
from .spring import SpringModel

BoolArray = NDArray[np.bool_]
#: evenly spaced angles of the search's grid over one turn (0.25°), before the lift's break points
SEARCH_GRID = 1440
#: lanes evaluated together (measured on 1446 angles: 8 lanes at a time 21-32 µs a lane, 32 at a time 55-75 µs,
#: 343 at once 51-72 µs: the (lanes × angles) arrays of a few lanes stay in the cache)
CHUNK = 8
#: the smallest base radius the search considers, as a share of the lower bound (a positive radius)
FLOOR_SHARE = 1e-3


@dataclass(frozen=True)
class Lanes:
    """Candidate designs, one per lane: the follower's place (a translating one's offset e, an oscillating
    one's pivot distance d) [mm], roller radius Rr [mm], spring rate k [N/mm or N·m/rad] and preload [N or
    N·m] (the spring NaN without a load)."""

    place: FloatArray
    roller: FloatArray
    rate: FloatArray
    preload: FloatArray

    def take(self, which: IndexArray) -> Lanes:
        """The lanes of these indices."""
        return Lanes(self.place[which], self.roller[which], self.rate[which], self.preload[which])

    @property
    def size(self) -> int:
        """How many lanes."""
        return int(self.place.size)


class SearchCam:
    """A cam's limits evaluated for many candidates at once on the search grid.

    ``spec``: the cam with its fixed follower values and lift; ``limits``; ``spring``: the follower's
    spring model (None: no load); ``rb_lo``: the base radius's lower bound [mm].
    """

    def __init__(self, spec: CamSpec, limits: DesignLimits, spring: SpringModel | None, rb_lo: float):
        self.spec, self.limits, self.spring = spec, limits, spring
        self.model = spec.model
        self.sigma = spec.sigma
        self.theta = lift_check_grid(spec.lift, SEARCH_GRID)
        self.lift = spec.lift.derivatives(self.theta, 2)
        self.floor = FLOOR_SHARE * rb_lo
        self.closed_form = spec.follower.motion == "translating" and not self.model.flat_faced
        self.oscillating_point = spec.follower.motion == "oscillating" and not self.model.flat_faced
        if self.oscillating_point:
            self.arm_mm = float(spec.follower.arm_length_mm or 0.0)
            swing = np.radians(self.lift[0])
            self.swing_range = (float(swing.min()), float(swing.max()))
        self.state = None if spring is None else spring.loaded.state(self.theta)
        roller = None if spring is None else spring.load.roller
        self.stress_scale = None
        if limits.allowed_stress_mpa is not None and roller is not None:
            e_star = effective_modulus_mpa(roller.youngs_modulus_mpa, roller.poisson_ratio, roller.cam_modulus_mpa,
                                           roller.cam_poisson)
            # p0² = F_n·E*/(π·b·R): this is E*/(π·b·p_allowed²)
            self.stress_scale = e_star / (math.pi * roller.width_mm * limits.allowed_stress_mpa**2)
        self.margin_evaluations = 0
        #: the curvature limit's request name (the millimetres when both are given: its value is then
        #: the larger requirement)
        self.curvature_name = ("min_radius_of_curvature_mm" if limits.min_radius_of_curvature_mm is not None
                               or limits.min_radius_of_curvature_roller_multiple is None
                               else "min_radius_of_curvature_roller_multiple")
        #: whether the stress limit counts (off: the geometry alone)
        self.with_stress = True
        #: the preload's lower bound, for lanes whose preload follows their rate [N or N·m]
        self.preload_floor = 0.0

    # ------------------------------------------------------------------ the limits
    def curvature_needed(self, roller: FloatArray) -> FloatArray | None:
        """The smallest radius of curvature of the cam surface each lane must keep [mm] (None: no limit:
        a knife-edge without one; a roller must not undercut, a flat face must be convex; both limits given:
        the larger)."""
        lim = self.limits
        if lim.min_radius_of_curvature_mm is None and lim.min_radius_of_curvature_roller_multiple is None:
            return None if self.spec.follower.type == "knife-edge" else np.zeros_like(roller)
        multiple = lim.min_radius_of_curvature_roller_multiple or 0.0
        return np.maximum(lim.min_radius_of_curvature_mm or 0.0, multiple * roller)

    def _kinematics(self, lanes: Lanes, rb: FloatArray, pressure: bool
                    ) -> tuple[FloatArray | None, FloatArray, FloatArray | None, BoolArray]:
        """φ (when ``pressure``), κp (point followers) or the surface's ρ (flat faces), cos φ (with a stress
        limit) and whether each lane's cam can be assembled, on the search grid: rows are lanes [rad,
        1/mm or mm, -]."""
        h, h1, h2 = (x[None, :] for x in self.lift)
        stress = self.stress_scale is not None and self.with_stress
        if self.closed_form:
            e, rr = lanes.place[:, None], lanes.roller[:, None]
            square = (rb[:, None] + rr) ** 2 - e * e
            valid = (square[:, 0] > 0) & (rb > 0)
            s0 = np.sqrt(np.where(valid[:, None], square, 1.0))
            r, p = s0 + h, h1 - self.sigma * e
            den = r * r + p * p
            kappa = (r * r - r * h2 + p * (p + h1)) / den**1.5
            return (np.arctan2(p, r) if pressure else None), kappa, (r / np.sqrt(den) if stress else None), valid
        if self.oscillating_point:
            return self._arm_kinematics(lanes, rb)
        n = self.theta.size
        phi, curv, cos_phi = np.zeros((rb.size, n)), np.zeros((rb.size, n)), np.ones((rb.size, n))
        valid = np.ones(rb.size, dtype=bool)
        for i in range(rb.size):
            follower = placed(self.spec.follower, float(lanes.place[i]), float(lanes.roller[i]))
            model = type(self.model)(follower)
            try:
                if not rb[i] > 0:
                    raise GeometryError("no base circle")
                model.check(float(rb[i]))
                model.check_swing(float(rb[i]), self.lift[0])
            except GeometryError:
                valid[i] = False
                continue
            kin = model.kinematics(float(rb[i]), self.sigma, self.theta, self.lift)
            phi[i] = kin.pressure
            curv[i] = kin.rho_cam if self.model.flat_faced else kin.kappa_pitch
            cos_phi[i] = np.cos(kin.pressure)
        return phi, curv, cos_phi, valid

    def _arm_kinematics(self, lanes: Lanes, rb: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, BoolArray]:
        """An oscillating knife-edge or roller for every lane at once: the point B(α) = (d − L cos α, L sin α) at
        α = α0 + ψ, cos α0 = (d² + L² − (Rb + Rr)²)/(2dL), and the point followers' formulas of
        :mod:`camcore.profile.followers` (u1 = c' − σJc, u2 = c'' − 2σJc' − c, κp = −σ(u1 × u2)/|u1|³,
        φ = atan2(u1·v̂, −σ u1·Jv̂))."""
        arm, sg = self.arm_mm, self.sigma
        d, r = lanes.place, rb + lanes.roller
        alpha0 = np.arccos(np.clip((d * d + arm * arm - r * r) / (2 * d * arm), -1.0, 1.0))
        valid = ((np.abs(d - arm) < r) & (r < d + arm) & (alpha0 + self.swing_range[0] > 0)
                 & (alpha0 + self.swing_range[1] < math.pi))
        a = alpha0[:, None] + np.radians(self.lift[0])[None, :]
        a1, a2 = np.radians(self.lift[1])[None, :], np.radians(self.lift[2])[None, :]
        sa, ca = np.sin(a), np.cos(a)
        cx, cy = d[:, None] - arm * ca, arm * sa
        c1x, c1y = arm * sa * a1, arm * ca * a1
        c2x, c2y = arm * (ca * a1 * a1 + sa * a2), arm * (-sa * a1 * a1 + ca * a2)
        u1x, u1y = c1x + sg * cy, c1y - sg * cx
        u2x, u2y = c2x + 2 * sg * c1y - cx, c2y - 2 * sg * c1x - cy
        speed = np.hypot(u1x, u1y)
        kappa = -sg * (u1x * u2y - u1y * u2x) / speed**3
        along, across = u1x * sa + u1y * ca, -sg * (-u1x * ca + u1y * sa)  # u1·v̂ and −σ u1·Jv̂, v̂ = (sin α, cos α)
        return np.arctan2(along, across), kappa, across / speed, valid

    def _stress_squared(self, lanes: Lanes, kappa: FloatArray, cos_phi: FloatArray) -> FloatArray:
        """(p0/p_allowed)² at every angle of every lane: F_n·E*/(π·b·R)/p_allowed², with
        F_n = max_ω(Q)/(r·cos φ) and R = Rr·(1 − Rr·κp); +inf where R ≤ 0 (undercut) [-]."""
        assert self.spring is not None and self.state is not None and self.stress_scale is not None
        force = self.spring.peak_force(self.state, lanes.rate, lanes.preload)
        normal = np.maximum(force, 0.0) / (self.state.arm[None, :] * cos_phi)
        rr = lanes.roller[:, None]
        radius = rr * (1.0 - rr * kappa)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(radius > 0, self.stress_scale * normal / radius, np.inf)

    def extremes(self, lanes: Lanes, rb: FloatArray, pressure: bool = True) -> tuple[dict[str, FloatArray], BoolArray]:
        """The sampled extremes each limit bounds, at these base radii, and whether each lane's cam can be
        assembled: ``rise`` max φ and ``return`` max −φ [deg], ``kappa`` max κp [1/mm] (point followers)
        or ``rho`` min ρ [mm] (flat faces), ``stress`` max (p0/p_allowed)² [-]."""
        checkpoint()
        if rb.size > CHUNK:
            parts = [self.extremes(lanes.take(np.arange(i, min(i + CHUNK, rb.size))), rb[i:i + CHUNK], pressure)
                     for i in range(0, rb.size, CHUNK)]
            return ({k: np.concatenate([p[0][k] for p in parts]) for k in parts[0][0]},
                    np.concatenate([p[1] for p in parts]))
        self.margin_evaluations += rb.size
        phi, curv, cos_phi, valid = self._kinematics(lanes, rb, pressure)
        out = {}
        if phi is not None:
            deg = np.degrees(phi)
            out = {"rise": deg.max(axis=1), "return": (-deg).max(axis=1)}
        if self.model.flat_faced:
            out["rho"] = curv.min(axis=1)
        else:
            out["kappa"] = curv.max(axis=1)
        if self.stress_scale is not None and self.with_stress:
            assert cos_phi is not None
            out["stress"] = self._stress_squared(lanes, curv, cos_phi).max(axis=1)
        return out, valid

    def _pressure_limits(self) -> dict[str, tuple[float, tuple[str, ...]]]:
        """Each pressure limit's name → (limit [deg], the extremes it bounds)."""
        lim = self.limits
        if self.model.flat_faced:
            return {}
        rise, ret = lim.max_pressure_angle_deg, lim.max_return_pressure_angle_deg
        if lim.split_pressure:
            out: dict[str, tuple[float, tuple[str, ...]]] = {}
            if rise is not None:
                out["max_pressure_angle_deg"] = (rise, ("rise",))
            if ret is not None:
                out["max_return_pressure_angle_deg"] = (ret, ("return",))
            return out
        if rise is None and ret is None:
            return {}
        name = "max_pressure_angle_deg" if rise is not None else "max_return_pressure_angle_deg"
        return {name: (float(rise if rise is not None else ret), ("rise", "return"))}  # type: ignore[arg-type]

    def margins(self, lanes: Lanes, rb: FloatArray, pressure: bool = True) -> dict[str, FloatArray]:
        """Each limit's margin at these base radii, ≥ 0 where it is met, −inf where the cam cannot be
        assembled (dimensionless: shares of the limit).

        ``pressure=False`` leaves the pressure limits out (the closed form has met them already)."""
        ext, valid = self.extremes(lanes, rb, pressure)
        out = {}
        if pressure:
            for name, (limit, sides) in self._pressure_limits().items():
                out[name] = 1.0 - np.max(np.vstack([ext[side] for side in sides]), axis=0) / limit
        needed = self.curvature_needed(lanes.roller)
        if needed is not None:
            name = self.curvature_name
            if self.model.flat_faced:
                out[name] = (ext["rho"] - needed) / np.maximum(needed, 1.0)
            else:
                out[name] = 1.0 - ext["kappa"] * (lanes.roller + needed)
        if "stress" in ext:
            out["allowed_stress_mpa"] = 1.0 - ext["stress"]
        return {name: np.where(valid, m, -np.inf) for name, m in out.items()}

    def values(self, lanes: Lanes, rb: FloatArray) -> dict[str, tuple[FloatArray, FloatArray]]:
        """Each limit's (value, limit) at these base radii, in its own unit: the largest pressure angle
        [deg], the smallest radius of curvature of the surface [mm] (a ratio ρ/Rr [-] for the
        roller-multiple limit), the largest Hertz pressure [N/mm²]; NaN where the cam cannot be assembled."""
        ext, valid = self.extremes(lanes, rb)
        lim, out = self.limits, {}
        for name, (limit, sides) in self._pressure_limits().items():
            out[name] = (np.max(np.vstack([ext[side] for side in sides]), axis=0), np.full(rb.size, limit))
        needed = self.curvature_needed(lanes.roller)
        if needed is not None:
            with np.errstate(divide="ignore"):
                rho = ext["rho"] if self.model.flat_faced else 1.0 / ext["kappa"] - lanes.roller
            if self.curvature_name == "min_radius_of_curvature_roller_multiple":
                out[self.curvature_name] = (rho / lanes.roller, needed / lanes.roller)
            else:
                out[self.curvature_name] = (rho, needed)
        if "stress" in ext:
            allowed = float(lim.allowed_stress_mpa or 0.0)
            out["allowed_stress_mpa"] = (allowed * np.sqrt(ext["stress"]), np.full(rb.size, allowed))
        return {name: (np.where(valid, v, np.nan), limit) for name, (v, limit) in out.items()}

    def best_margin(self, lanes: Lanes, rb_hi: float, names: tuple[str, ...] | None = None, refine: bool = False
                    ) -> tuple[FloatArray, FloatArray]:
        """The largest over the base radius of the smallest of these limits' margins (all: None), for each
        lane, and the base radius where [-, mm].

        Where every margin grows with the radius (a translating follower's geometry) it is the upper end's;
        else the margin is unimodal over the lane's range (an arm's pressure angle rises again as it nears
        folding; the stress on a concave flank rises with the radius): the best of :data:`BEST_RADII`
        radii spread over it, and with ``refine`` that refined by golden section."""
        lo, hi = self.bracket(lanes, rb_hi)
        ok = np.isfinite(lo) & np.isfinite(hi)
        lo, hi = np.where(ok, lo, rb_hi), np.where(ok, hi, rb_hi)

        def smallest(which: IndexArray, rb: FloatArray) -> FloatArray:
            m = self.margins(lanes.take(which), np.asarray(rb, dtype=np.float64))
            return np.where(ok[which], np.min(np.vstack([m[n] for n in (names or tuple(m))]), axis=0), -np.inf)

        every = np.arange(lanes.size)
        monotone = self.closed_form and not (self.stress_scale is not None and (names is None or
                                                                                "allowed_stress_mpa" in names))
        if monotone:
            return smallest(every, hi), hi
        share = np.linspace(0.0, 1.0, BEST_RADII)
        radii = lo[:, None] + (hi - lo)[:, None] * share[None, :]
        values = smallest(np.repeat(every, BEST_RADII), radii.ravel()).reshape(lanes.size, BEST_RADII)
        j = np.argmax(values, axis=1)
        best, at = values[every, j], radii[every, j]
        if refine:
            step = (hi - lo) / (BEST_RADII - 1)
            x, v = golden_max(lambda r: smallest(every, r), np.maximum(lo, at - step), np.minimum(hi, at + step),
                              width=1e-9 * float(np.max(hi)))
            better = v > best
            best, at = np.where(better, v, best), np.where(better, x, at)
        return best, at

    def bracket(self, lanes: Lanes, rb_hi: float) -> tuple[FloatArray, FloatArray]:
        """Each lane's range of base radii worth solving in: from the geometric floor (or the pressure's
        closed form) to ``rb_hi``, or to the largest radius its arm can be assembled and swung at [mm]."""
        lo = np.full(lanes.size, self.floor)
        hi = np.full(lanes.size, float(rb_hi))
        if self.closed_form:
            lo = np.maximum(lo, np.abs(lanes.place) - lanes.roller + 1e-9 * max(1.0, rb_hi))
            return np.maximum(lo, self.pressure_radius(lanes)), hi
        if self.oscillating_point:
            # |d − L| < Rb + Rr < d + L, and α0 + ψmax < π: Rb + Rr < √(d² + L² + 2dL·cos ψmax)
            d, arm = lanes.place, self.arm_mm
            reach = np.minimum(d + arm, np.sqrt(np.maximum(d * d + arm * arm + 2 * d * arm
                                                           * math.cos(self.swing_range[1]), 0.0)))
            margin = 1e-9 * np.maximum(1.0, reach)
            lo = np.maximum(lo, np.abs(d - arm) - lanes.roller + margin)
            hi = np.minimum(hi, reach - lanes.roller - margin)
            return np.where(lo <= hi, lo, np.inf), np.where(lo <= hi, hi, np.inf)
        for i in range(lanes.size):
            follower = placed(self.spec.follower, float(lanes.place[i]), float(lanes.roller[i]))
            lo[i], hi[i] = assembly_range(type(self.model)(follower), self.lift[0], lo[i], rb_hi)
        return lo, hi

    # ------------------------------------------------------------------ the smallest base radius
    def pressure_radius(self, lanes: Lanes) -> FloatArray:
        """The closed form of a translating point follower: the smallest Rb with every sampled pressure
        angle within its limit, s0 = max_θ((s' − σe)/tan α_rise − s, (σe − s')/tan α_return − s) [mm];
        0 without a pressure limit."""
        lim = self.limits
        rise = lim.max_pressure_angle_deg
        ret = lim.max_return_pressure_angle_deg if lim.max_return_pressure_angle_deg is not None else rise
        rise = rise if rise is not None else ret
        if rise is None or ret is None:
            return np.zeros(lanes.size)
        h, h1 = self.lift[0][None, :], self.lift[1][None, :]
        p = h1 - self.sigma * lanes.place[:, None]
        s0 = np.maximum(p / math.tan(math.radians(rise)) - h, -p / math.tan(math.radians(ret)) - h).max(axis=1)
        return np.sqrt(np.maximum(s0, 0.0) ** 2 + lanes.place**2) - lanes.roller

    def needed_radius(self, lanes: Lanes, rb_hi: float) -> FloatArray:
        """The smallest base radius meeting every limit, for each lane, +inf where none up to ``rb_hi`` does
        [mm]: the geometric limits' root (:meth:`_geometric_radius`), then the stress's above it.

        The geometric margins grow with the base radius. The Hertz pressure's need not: on a concave flank
        it rises with the base radius (the flank flattens, the contact conforms less), so the largest over
        the turn first falls and then rises, and its margin is unimodal. Above the geometric root it is
        therefore met at once, or it falls there (then nowhere above), or it rises: a root below the upper
        end when that meets it, else below the margin's maximum (golden section) if that does.
        """
        if self.stress_scale is None or not self.with_stress:
            return self._geometric_radius(lanes, rb_hi)
        self.with_stress = False
        try:
            out = self._geometric_radius(lanes, rb_hi)
        finally:
            self.with_stress = True
        _lo, upper = self.bracket(lanes, rb_hi)

        def stress(which: IndexArray, rb: FloatArray) -> FloatArray:
            return self.margins(lanes.take(which), rb, pressure=False)["allowed_stress_mpa"]

        lanes_in = np.flatnonzero(np.isfinite(out))
        if lanes_in.size == 0:
            return out
        at_g = stress(lanes_in, out[lanes_in])
        need = lanes_in[at_g < 0]
        if need.size == 0:
            return out
        g, f_g, top = out[need].copy(), at_g[at_g < 0], upper[need].astype(np.float64)
        out[need] = np.inf
        rising = stress(need, g + RISE_STEP * (top - g)) > f_g
        need, g, f_g, top = need[rising], g[rising], f_g[rising], top[rising]
        if need.size == 0:
            return out
        at_top = stress(need, top)
        unmet = np.flatnonzero(at_top < 0)
        if unmet.size:
            top[unmet], at_top[unmet] = feasible_points(lambda which, x: stress(need[unmet[which]], x), g[unmet],
                                                        top[unmet])
        ok = at_top >= 0
        need, g, f_g, top, at_top = need[ok], g[ok], f_g[ok], top[ok], at_top[ok]
        if need.size:
            out[need] = illinois(lambda which, rb: stress(need[which], rb), g, top, f_g, at_top)
        return out

    def _geometric_radius(self, lanes: Lanes, rb_hi: float) -> FloatArray:
        """The root of the smallest margin (every limit but the stress: they all grow with the base
        radius), from the geometric floor or the pressure's closed form up to ``rb_hi`` [mm].

        Below the lower bound the root is still solved (not clipped): how far below it says how much
        room a candidate leaves, which ranks candidates that all meet the limits at the lower bound.
        """
        lo, upper = self.bracket(lanes, rb_hi)
        out = np.full(lanes.size, np.inf)
        pressure = not self.closed_form

        def smallest(which: IndexArray, rb: FloatArray) -> FloatArray:
            m = self.margins(lanes.take(which), rb, pressure)
            return np.min(np.vstack(list(m.values())), axis=0) if m else np.zeros(rb.size)

        open_ = np.flatnonzero(np.isfinite(lo) & (lo <= upper))  # an arm that cannot be assembled: both +inf
        if open_.size == 0:
            return out
        at_lo = smallest(open_, lo[open_])
        met = at_lo >= 0
        out[open_[met]] = lo[open_[met]]
        rest = open_[~met]
        if rest.size == 0:
            return out
        hi = upper[rest].astype(np.float64)
        at_hi = smallest(rest, hi)
        unmet = np.flatnonzero(at_hi < 0)
        if unmet.size and self.oscillating_point:
            # an arm's pressure angle rises again as the arm nears folding (α0 → π): the margin is unimodal,
            # so where the upper end fails a point that meets it on the way to its maximum brackets the root
            hi[unmet], at_hi[unmet] = feasible_points(lambda which, x: smallest(rest[unmet[which]], x),
                                                      lo[rest[unmet]].astype(np.float64), hi[unmet].copy())
        bracketed = at_hi >= 0
        rest, hi, at_hi = rest[bracketed], hi[bracketed], at_hi[bracketed]
        if rest.size == 0:
            return out
        a, f_a = lo[rest].astype(np.float64), at_lo[~met][bracketed]
        out[rest] = illinois(lambda which, rb: smallest(rest[which], rb), a, hi, f_a, at_hi)
        return out


#: the step above the geometric root, as a share of the way to the upper end, that tells whether the
#: stress margin still rises there
RISE_STEP = 1e-4
#: base radii over a lane's range at which a 422's best value is looked for (then refined by golden section)
BEST_RADII = 9
