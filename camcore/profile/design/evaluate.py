"""The search's evaluator: for many candidate designs at once, each limit's margin at any base radius
and the smallest base radius that meets every limit, from the lift sampled on a grid.

A candidate ("lane") is an offset e, a roller radius Rr, and a spring (rate and preload); the base
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
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from ...curves.base import FloatArray
from ...deadline import checkpoint
from ...errors import GeometryError
from ..cam import CamSpec
from ..checks import lift_check_grid
from ..dynamics import effective_modulus_mpa
from .problem import DesignLimits
from .spring import SpringModel

BoolArray = NDArray[np.bool_]
IndexArray = NDArray[np.intp]
#: evenly spaced angles of the search's grid over one turn (0.25°), before the lift's break points
SEARCH_GRID = 1440
#: lanes evaluated together (measured on 1446 angles: 8 lanes at a time 21-32 µs a lane, 32 at a time 55-75 µs,
#: 343 at once 51-72 µs: the (lanes × angles) arrays of a few lanes stay in the cache)
CHUNK = 8
#: the smallest base radius the search considers, as a share of the lower bound (a positive radius)
FLOOR_SHARE = 1e-3


@dataclass(frozen=True)
class Lanes:
    """Candidate designs, one per lane: offset e [mm], roller radius Rr [mm], spring rate k [N/mm or
    N·m/rad] and preload [N or N·m] (the spring NaN without a load)."""

    offset: FloatArray
    roller: FloatArray
    rate: FloatArray
    preload: FloatArray

    def take(self, which: IndexArray) -> Lanes:
        """The lanes of these indices."""
        return Lanes(self.offset[which], self.roller[which], self.rate[which], self.preload[which])

    @property
    def size(self) -> int:
        """How many lanes."""
        return int(self.offset.size)


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
        self.state = None if spring is None else spring.loaded.state(self.theta)
        roller = None if spring is None else spring.load.roller
        self.stress_scale = None
        if limits.allowed_stress_mpa is not None and roller is not None:
            e_star = effective_modulus_mpa(roller.youngs_modulus_mpa, roller.poisson_ratio, roller.cam_modulus_mpa,
                                           roller.cam_poisson)
            # p0² = F_n·E*/(π·b·R): this is E*/(π·b·p_allowed²)
            self.stress_scale = e_star / (math.pi * roller.width_mm * limits.allowed_stress_mpa**2)
        self.margin_evaluations = 0
        #: whether the stress limit counts (off: the geometry alone)
        self.with_stress = True
        #: the preload's lower bound, for lanes whose preload follows their rate [N or N·m]
        self.preload_floor = 0.0

    # ------------------------------------------------------------------ the limits
    def curvature_needed(self, roller: FloatArray) -> FloatArray | None:
        """The smallest radius of curvature of the cam surface each lane must keep [mm] (None: no limit:
        a knife-edge without one; a roller must not undercut, a flat face must be convex)."""
        lim = self.limits
        if lim.min_radius_of_curvature_roller_multiple is not None:
            return lim.min_radius_of_curvature_roller_multiple * roller
        if lim.min_radius_of_curvature_mm is not None:
            return np.full_like(roller, lim.min_radius_of_curvature_mm)
        if self.spec.follower.type == "knife-edge":
            return None
        return np.zeros_like(roller)

    def _kinematics(self, lanes: Lanes, rb: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, BoolArray]:
        """φ, κp (point followers) or the surface's ρ (flat faces), cos φ and whether each lane's cam can be
        assembled, on the search grid: rows are lanes [rad, 1/mm or mm, -]."""
        h, h1, h2 = (x[None, :] for x in self.lift)
        if self.closed_form:
            e, rr = lanes.offset[:, None], lanes.roller[:, None]
            square = (rb[:, None] + rr) ** 2 - e * e
            valid = (square[:, 0] > 0) & (rb > 0)
            s0 = np.sqrt(np.where(valid[:, None], square, 1.0))
            r, p = s0 + h, h1 - self.sigma * e
            den = r * r + p * p
            kappa = (r * r - r * h2 + p * (p + h1)) / den**1.5
            return np.arctan2(p, r), kappa, r / np.sqrt(den), valid
        n = self.theta.size
        phi, curv, cos_phi = np.zeros((rb.size, n)), np.zeros((rb.size, n)), np.ones((rb.size, n))
        valid = np.ones(rb.size, dtype=bool)
        for i in range(rb.size):
            follower = replace(self.spec.follower, offset_mm=float(lanes.offset[i]),
                               roller_radius_mm=float(lanes.roller[i]))
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

    def extremes(self, lanes: Lanes, rb: FloatArray) -> tuple[dict[str, FloatArray], BoolArray]:
        """The sampled extremes each limit bounds, at these base radii, and whether each lane's cam can be
        assembled: ``rise`` max φ and ``return`` max −φ [deg], ``kappa`` max κp [1/mm] (point followers)
        or ``rho`` min ρ [mm] (flat faces), ``stress`` max (p0/p_allowed)² [-]."""
        checkpoint()
        if rb.size > CHUNK:
            parts = [self.extremes(lanes.take(np.arange(i, min(i + CHUNK, rb.size))), rb[i:i + CHUNK])
                     for i in range(0, rb.size, CHUNK)]
            return ({k: np.concatenate([p[0][k] for p in parts]) for k in parts[0][0]},
                    np.concatenate([p[1] for p in parts]))
        self.margin_evaluations += rb.size
        phi, curv, cos_phi, valid = self._kinematics(lanes, rb)
        deg = np.degrees(phi)
        out = {"rise": deg.max(axis=1), "return": (-deg).max(axis=1)}
        if self.model.flat_faced:
            out["rho"] = curv.min(axis=1)
        else:
            out["kappa"] = curv.max(axis=1)
        if self.stress_scale is not None and self.with_stress:
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
        ext, valid = self.extremes(lanes, rb)
        out = {}
        if pressure:
            for name, (limit, sides) in self._pressure_limits().items():
                out[name] = 1.0 - np.max(np.vstack([ext[side] for side in sides]), axis=0) / limit
        needed = self.curvature_needed(lanes.roller)
        if needed is not None:
            name = ("min_radius_of_curvature_roller_multiple"
                    if self.limits.min_radius_of_curvature_roller_multiple is not None else "min_radius_of_curvature_mm")
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
            if lim.min_radius_of_curvature_roller_multiple is not None:
                out["min_radius_of_curvature_roller_multiple"] = (
                    rho / lanes.roller, np.full(rb.size, lim.min_radius_of_curvature_roller_multiple))
            else:
                out["min_radius_of_curvature_mm"] = (rho, needed)
        if "stress" in ext:
            allowed = float(lim.allowed_stress_mpa or 0.0)
            out["allowed_stress_mpa"] = (allowed * np.sqrt(ext["stress"]), np.full(rb.size, allowed))
        return {name: (np.where(valid, v, np.nan), limit) for name, (v, limit) in out.items()}

    def bracket(self, lanes: Lanes, rb_hi: float) -> tuple[FloatArray, FloatArray]:
        """Each lane's range of base radii worth solving in: from the geometric floor (or the pressure's
        closed form) to ``rb_hi``, or to the largest radius its arm can be assembled and swung at [mm]."""
        lo = np.full(lanes.size, self.floor)
        hi = np.full(lanes.size, float(rb_hi))
        if self.closed_form:
            lo = np.maximum(lo, np.abs(lanes.offset) - lanes.roller + 1e-9 * max(1.0, rb_hi))
            return np.maximum(lo, self.pressure_radius(lanes)), hi
        for i in range(lanes.size):
            follower = replace(self.spec.follower, offset_mm=float(lanes.offset[i]),
                               roller_radius_mm=float(lanes.roller[i]))
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
        p = h1 - self.sigma * lanes.offset[:, None]
        s0 = np.maximum(p / math.tan(math.radians(rise)) - h, -p / math.tan(math.radians(ret)) - h).max(axis=1)
        return np.sqrt(np.maximum(s0, 0.0) ** 2 + lanes.offset**2) - lanes.roller

    def needed_radius(self, lanes: Lanes, rb_hi: float) -> FloatArray:
        """The smallest base radius meeting every limit, for each lane: the root of the smallest margin,
        from the geometric floor (or the pressure's closed form) up to ``rb_hi``; +inf where even ``rb_hi``
        does not meet them [mm].

        Below the lower bound the root is still solved (not clipped): how far below it says how much
        room a candidate leaves, which ranks candidates that all meet the limits at the lower bound.
        """
        lo, upper = self.bracket(lanes, rb_hi)
        out = np.full(lanes.size, np.inf)
        pressure = not self.closed_form

        def smallest(which: IndexArray, rb: FloatArray) -> FloatArray:
            m = self.margins(lanes.take(which), rb, pressure)
            return np.min(np.vstack(list(m.values())), axis=0) if m else np.zeros(rb.size)

        open_ = np.flatnonzero(lo <= upper)
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
        bracketed = at_hi >= 0
        rest, hi, at_hi = rest[bracketed], hi[bracketed], at_hi[bracketed]
        if rest.size == 0:
            return out
        a, f_a = lo[rest].astype(np.float64), at_lo[~met][bracketed]
        out[rest] = _illinois(lambda which, rb: smallest(rest[which], rb), a, hi, f_a, at_hi)
        return out


#: the search's base radius is solved to this relative width (it ranks candidates; the answer is solved
#: again to 1e-10 by the exact solves)
ROOT_REL_TOL = 1e-9


def _illinois(margin: object, a: FloatArray, b: FloatArray, f_a: FloatArray, f_b: FloatArray) -> FloatArray:
    """The smallest x in (a, b] with margin ≥ 0 for every lane, margins growing with x (f_a < 0 ≤ f_b):
    Illinois regula falsi on all open lanes together, to :data:`ROOT_REL_TOL`; the feasible ends."""
    side = np.zeros(a.size, dtype=np.int8)  # +1: b moved last time, −1: a moved last time
    active = np.arange(a.size)
    for _ in range(200):
        checkpoint()
        active = active[(b[active] - a[active] > ROOT_REL_TOL * np.maximum(1.0, b[active])) & (f_b[active] != 0)]
        if active.size == 0:
            break
        lo, hi, flo, fhi = a[active], b[active], f_a[active], f_b[active]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            chord = hi - fhi * (hi - lo) / (fhi - flo)
        mid = np.where(np.isfinite(chord) & (chord > lo) & (chord < hi), chord, 0.5 * (lo + hi))
        f_mid = margin(active, mid)  # type: ignore[operator]
        ok = f_mid >= 0
        stale = side[active]
        b[active] = np.where(ok, mid, hi)
        f_b[active] = np.where(ok, f_mid, np.where(stale == -1, 0.5 * fhi, fhi))
        a[active] = np.where(ok, lo, mid)
        f_a[active] = np.where(ok, np.where(stale == 1, 0.5 * flo, flo), f_mid)
        side[active] = np.where(ok, 1, -1)
    return b


def assembly_range(model: object, lift: FloatArray, floor: float, rb_hi: float) -> tuple[float, float]:
    """The base radii within [floor, rb_hi] at which a follower can be assembled and swung through the lift.

    Parameters
    ----------
    model : FollowerModel
        The follower (its ``check`` and ``check_swing``).
    lift : ndarray
        The lift sampled over the turn [mm or deg].
    floor : float
        The smallest base radius worth considering [mm].
    rb_hi : float
        The largest [mm].

    Returns
    -------
    (float, float)
        The range (lo, hi) [mm]: an oscillating arm reaches the base circle only between |d − L| − Rr and
        d + L − Rr and must not swing through the line of centres, so hi may lie below ``rb_hi`` (found by
        bisection to 1e-12 relative); (inf, inf) where no radius works.

    References
    ----------
    Shinzato and Kunigami (1988), fig. 1 (the follower's geometry); camcore.profile.followers (the checks).
    """
    def ok(rb: float) -> bool:
        try:
            model.check(rb)  # type: ignore[attr-defined]
            model.check_swing(rb, lift)  # type: ignore[attr-defined]
        except GeometryError:
            return False
        return True

    lo = max(floor, float(model.min_base_radius_mm()) * (1.0 + 1e-12) + 1e-12)  # type: ignore[attr-defined]
    if lo > rb_hi or not ok(lo):
        return math.inf, math.inf
    if ok(rb_hi):
        return lo, rb_hi
    good, bad = lo, rb_hi
    while bad - good > 1e-12 * bad:
        mid = 0.5 * (good + bad)
        good, bad = (mid, bad) if ok(mid) else (good, mid)
    return lo, good
