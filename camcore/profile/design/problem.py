"""What a plate-cam design asks: the cam's lift and follower, the variables the search may move
(each within its bounds), the limits the design must meet and what holds the follower on the cam.

The names are the request's (``free.offset_mm``, ``limits.max_pressure_angle_deg``, ``mass_kg``),
so every error of :func:`check_problem` carries the field it is about.

References
----------
.. [1] Norton, *Cam Design and Manufacturing Handbook*: the cam designer's variables (base radius,
   offset, roller radius, spring rate and preload) and limits (pressure angle, radius of curvature,
   contact stress, follower jump).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Literal

from ...errors import InvalidParameterError
from ..cam import CamSpec
from ..dynamics.load import RollerMaterials
from ..followers import Follower

Variable = Literal["base_radius_mm", "offset_mm", "pivot_distance_mm", "roller_radius_mm", "spring_rate_n_mm",
                   "preload_n", "spring_rate_nm_rad", "preload_nm"]
#: every variable the search may move, by the follower's motion (its spring in its own units)
VARIABLES: dict[str, tuple[str, ...]] = {
    "translating": ("base_radius_mm", "offset_mm", "roller_radius_mm", "spring_rate_n_mm", "preload_n"),
    "oscillating": ("base_radius_mm", "pivot_distance_mm", "roller_radius_mm", "spring_rate_nm_rad", "preload_nm"),
}
#: the variable that places the follower beside the cam, by its motion (:func:`placed`)
PLACE = {"translating": "offset_mm", "oscillating": "pivot_distance_mm"}
#: the spring's and the load's fields of each motion: (spring rate, preload, mass, damping, external)
SPRING_FIELDS = {"translating": ("spring_rate_n_mm", "preload_n", "mass_kg", "damping_n_s_mm", "external_force_n"),
                 "oscillating": ("spring_rate_nm_rad", "preload_nm", "inertia_kgm2", "damping_nm_s_rad",
                                 "external_torque_nm")}
#: variables a request may name that this search does not move, and why
NOT_SEARCHED = {
    "arm_length_mm": "the arm length is not a design variable of this search (the machine's linkage sets it): give "
                     "arm_length_mm in follower, and free pivot_distance_mm to place the arm",
}


def placed(follower: Follower, place_mm: float, roller_radius_mm: float) -> Follower:
    """The follower placed and with this roller: ``place_mm`` is a translating follower's offset e, an
    oscillating one's pivot distance d from the cam's centre.

    Parameters
    ----------
    follower : Follower
        The follower's other values.
    place_mm : float
        e or d [mm].
    roller_radius_mm : float
        Rr [mm].

    Returns
    -------
    Follower
        A copy with these values (not validated).

    References
    ----------
    Norton, *Cam Design and Manufacturing Handbook* (the offset and the pivot as design variables).
    """
    if follower.motion == "translating":
        return replace(follower, offset_mm=place_mm, roller_radius_mm=roller_radius_mm)
    return replace(follower, pivot_distance_mm=place_mm, roller_radius_mm=roller_radius_mm)


@dataclass(frozen=True)
class DesignLimits:
    """The limits a design must meet (None: not asked).

    ``max_pressure_angle_deg`` limits the pressure angle while the cam pushes the follower out
    (φ > 0), and on the return too unless ``max_return_pressure_angle_deg`` is given (φ < 0: the
    spring drives the follower back, so a larger angle is usual there). The smallest radius of
    curvature of the cam surface's convex parts is at least ``min_radius_of_curvature_mm`` and
    ``min_radius_of_curvature_roller_multiple`` × the roller radius (the larger, when both are given). ``allowed_stress_mpa``
    [N/mm²] bounds the roller's Hertz pressure, ``safety_margin_n`` the contact force the
    follower keeps, both at the worst speed of the range.
    """

    max_pressure_angle_deg: float | None = None
    max_return_pressure_angle_deg: float | None = None
    min_radius_of_curvature_mm: float | None = None
    min_radius_of_curvature_roller_multiple: float | None = None
    allowed_stress_mpa: float | None = None
    safety_margin_n: float | None = None

    @property
    def split_pressure(self) -> bool:
        """The return stroke has a limit of its own (else one limit of |φ|)."""
        return (self.max_return_pressure_angle_deg is not None
                and self.max_return_pressure_angle_deg != self.max_pressure_angle_deg)


@dataclass(frozen=True)
class FollowerLoad:
    """What moves with the follower besides the spring, in the follower's own units, and the speeds.

    ``mass``: the moving mass [kg] (translating) or the arm's inertia about its pivot [kg·m²]
    (oscillating); ``damping``: [N·s/mm] or [N·m·s/rad]; ``external``: a constant force [N] or
    torque [N·m], positive pressing the follower onto the cam; ``speed_rpm``: the camshaft's
    speed range (lo, hi) [rpm], equal ends for one speed; ``roller``: the roller's width and
    materials, for the Hertz stress.
    """

    mass: float
    speed_rpm: tuple[float, float]
    damping: float = 0.0
    external: float = 0.0
    roller: RollerMaterials | None = None


@dataclass(frozen=True)
class DesignProblem:
    """A plate cam to design.

    ``cam``: the follower with its fixed values and the lift (its ``base_radius_mm`` is the fixed
    base radius when that is not free, otherwise only a starting value); ``free``: variable name →
    (lo, hi) bounds; ``limits``; ``load`` (None: no spring, a design by geometry alone);
    ``spring_rate`` and ``preload``: their fixed values when not free, in the follower's units.
    """

    cam: CamSpec
    free: Mapping[str, tuple[float, float]]
    limits: DesignLimits = field(default_factory=DesignLimits)
    load: FollowerLoad | None = None
    spring_rate: float | None = None
    preload: float | None = None

    @property
    def motion(self) -> str:
        """translating or oscillating."""
        return self.cam.follower.motion

    def spring_names(self) -> tuple[str, str]:
        """The request's names of the spring rate and the preload for this follower."""
        rate, preload = SPRING_FIELDS[self.motion][:2]
        return rate, preload

    def bounds(self, name: str, fixed: float | None) -> tuple[float, float] | None:
        """(lo, hi) of a variable: its bounds when free, (v, v) at its fixed value, None without one."""
        if name in self.free:
            return self.free[name]
        return None if fixed is None else (fixed, fixed)


def _bad(message: str, *where: str | int) -> InvalidParameterError:
    return InvalidParameterError(message, field=tuple(where))


def _check_bounds(problem: DesignProblem) -> None:
    follower = problem.cam.follower
    own = VARIABLES[follower.motion]
    for name, (lo, hi) in problem.free.items():
        if name in NOT_SEARCHED:
            raise _bad(f"free.{name}: {NOT_SEARCHED[name]}.", "free", name)
        if name not in own:
            other = next((m for m, names in VARIABLES.items() if name in names), None)
            why = (f"an {follower.motion} follower's variables are {', '.join(own)}" if other is None or other !=
                   follower.motion else "")
            raise _bad(f"free.{name} is not a variable of a {follower.motion} {follower.type} follower ({why}).",
                       "free", name)
        if name == "roller_radius_mm" and follower.type != "roller":
            raise _bad(f"free.roller_radius_mm: a {follower.type} follower has no roller.", "free", name)
        if name == "offset_mm" and follower.type == "flat-faced":
            raise _bad("free.offset_mm: the offset of a flat-faced translating follower does not change its cam (the "
                       "face is perpendicular to the motion), so it cannot be designed; give offset_mm in follower.",
                       "free", name)
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise _bad(f"free.{name}: the bounds must be finite numbers, not [{lo!r}, {hi!r}].", "free", name)
        if lo > hi:
            raise _bad(f"free.{name}: the lower bound {lo!r} is above the upper bound {hi!r}.", "free", name)
        if name in ("base_radius_mm", "pivot_distance_mm", "roller_radius_mm", "spring_rate_n_mm",
                    "spring_rate_nm_rad") and not lo > 0:
            raise _bad(f"free.{name}: the lower bound must be greater than 0, not {lo!r}.", "free", name)


def _check_limits(problem: DesignProblem) -> None:
    limits, follower = problem.limits, problem.cam.follower
    for name in ("max_pressure_angle_deg", "max_return_pressure_angle_deg"):
        value = getattr(limits, name)
        if value is not None and not (0 < value < 90):
            raise _bad(f"limits.{name} must lie between 0 and 90 degrees, not {value!r}.", "limits", name)
    for name in ("min_radius_of_curvature_mm", "min_radius_of_curvature_roller_multiple", "safety_margin_n"):
        value = getattr(limits, name)
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise _bad(f"limits.{name} must be a finite number ≥ 0, not {value!r}.", "limits", name)
    if limits.min_radius_of_curvature_roller_multiple is not None and follower.type != "roller":
        raise _bad(f"limits.min_radius_of_curvature_roller_multiple needs a roller follower, not a {follower.type}.",
                   "limits", "min_radius_of_curvature_roller_multiple")
    if limits.allowed_stress_mpa is not None:
        if not (math.isfinite(limits.allowed_stress_mpa) and limits.allowed_stress_mpa > 0):
            raise _bad(f"limits.allowed_stress_mpa must be greater than 0, not {limits.allowed_stress_mpa!r}.",
                       "limits", "allowed_stress_mpa")
        if follower.type != "roller":
            raise _bad(f"limits.allowed_stress_mpa: the contact stress is a roller's, not a {follower.type} "
                       "follower's.", "limits", "allowed_stress_mpa")


def _check_load(problem: DesignProblem) -> None:
    rate, preload, mass, _damping, _external = SPRING_FIELDS[problem.motion]
    load, limits = problem.load, problem.limits
    if load is None:
        wanted = [name for name, given in ((rate, rate in problem.free or problem.spring_rate is not None),
                                           (preload, preload in problem.free or problem.preload is not None),
                                           ("limits.allowed_stress_mpa", limits.allowed_stress_mpa is not None),
                                           ("limits.safety_margin_n", limits.safety_margin_n is not None)) if given]
        if wanted:
            raise _bad(f"{wanted[0]} needs the follower's {mass} (and speed_rpm): a spring holds a moving mass "
                       "on the cam.", mass)
        return
    if not (math.isfinite(load.mass) and load.mass > 0):
        raise _bad(f"{mass} must be greater than 0, not {load.mass!r}.", mass)
    lo, hi = load.speed_rpm
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi):
        raise _bad(f"speed_rpm must be one speed > 0 or a range [lo, hi] with 0 < lo ≤ hi, not [{lo!r}, {hi!r}].",
                   "speed_rpm")
    if rate not in problem.free and problem.spring_rate is None:
        raise _bad(f"give {rate} or free it (free.{rate}): the follower's {mass} needs a spring.", rate)
    if problem.spring_rate is not None and rate not in problem.free and not problem.spring_rate > 0:
        raise _bad(f"{rate} must be greater than 0, not {problem.spring_rate!r}.", rate)
    if load.roller is None and limits.allowed_stress_mpa is not None:
        raise _bad("limits.allowed_stress_mpa needs roller {width_mm, materials}: the contact stress of a line "
                   "contact depends on its width.", "roller")
    if load.roller is not None and problem.cam.follower.type != "roller":
        raise _bad(f"roller (width and materials, for the contact stress) needs a roller follower, not a "
                   f"{problem.cam.follower.type}.", "roller")


def check_problem(problem: DesignProblem) -> None:
    """The rules of a design problem, each error naming its request field.

    Parameters
    ----------
    problem : DesignProblem
        The cam, the free variables with their bounds, the limits and the load.

    Raises
    ------
    InvalidParameterError
        A variable the follower does not have or that this search does not move, bounds with
        lo > hi (or not finite, or not positive where the variable must be), a limit out of range,
        a spring without the mass it holds (or a mass without a spring), a stress limit without the
        roller's width, and an objective that cannot move (neither the base radius nor the spring
        free with room between its bounds).

    References
    ----------
    Norton, *Cam Design and Manufacturing Handbook* (the designer's variables and limits).
    """
    _check_bounds(problem)
    _check_limits(problem)
    _check_load(problem)
    rate, preload = problem.spring_names()
    movable = [name for name in ("base_radius_mm", rate, preload)
               if name in problem.free and problem.free[name][0] < problem.free[name][1]]
    if not movable or (movable != ["base_radius_mm"] and "base_radius_mm" not in movable and problem.load is None):
        raise _bad("nothing to minimise: the objective is the smallest base radius, then the softest spring, then "
                   f"the smallest preload; free base_radius_mm (or, with the follower's load, {rate} or {preload}) "
                   "with its lower bound below its upper bound.", "free")
    if "base_radius_mm" not in problem.free:
        rb = problem.cam.base_radius_mm
        if not (math.isfinite(rb) and rb > 0):
            raise _bad(f"base_radius_mm must be greater than 0 when it is not free, not {rb!r}.", "base_radius_mm")
