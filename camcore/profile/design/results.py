"""What a plate-cam design answers: the design, every limit at it, and how the search went.

References
----------
.. [1] Norton, *Cam Design and Manufacturing Handbook*: the designer's variables and limits.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ...results import doc
from ..cam import CamSpec


@dataclass(frozen=True)
class DesignValues:
    """The designed values (free ones found, the others as given)."""

    base_radius_mm: float = field(metadata=doc("the base circle's radius Rb [mm]"))
    offset_mm: float | None = field(metadata=doc("translating follower: the offset e of its line of motion [mm]"))
    pivot_distance_mm: float | None = field(metadata=doc(
        "oscillating follower: the distance d from the cam's centre to the arm's pivot [mm]"))
    roller_radius_mm: float | None = field(metadata=doc("roller follower: the roller's radius Rr [mm]"))
    spring_rate_n_mm: float | None = field(default=None, metadata=doc(
        "translating follower with a load: the spring rate k [N/mm]"))
    preload_n: float | None = field(default=None, metadata=doc(
        "translating follower with a load: the spring's force F0 at zero lift [N]"))
    spring_rate_nm_rad: float | None = field(default=None, metadata=doc(
        "oscillating follower with a load: the spring rate about the pivot [N·m/rad]"))
    preload_nm: float | None = field(default=None, metadata=doc(
        "oscillating follower with a load: the spring's torque T0 at zero swing [N·m]"))


@dataclass(frozen=True)
class DesignConstraint:
    """One limit (or one bound of a free variable) at the design."""

    name: str = field(metadata=doc(
        "the limit's request field (max_pressure_angle_deg, max_return_pressure_angle_deg, "
        "min_radius_of_curvature_mm or min_radius_of_curvature_roller_multiple, allowed_stress_mpa, safety_margin_n), "
        "or free.<variable> for the bound a free variable is nearest"))
    value: float = field(metadata=doc(
        "what the design reaches: the largest pressure angle (on the rise, or the return) [deg], the smallest "
        "radius of curvature of the cam surface's convex parts [mm] (with the roller-multiple limit: that over the "
        "roller radius), the largest Hertz pressure [MPa], the smallest contact force [N], each exact over the "
        "turn and at the worst speed of the range; for a bound, the variable's value"))
    limit: float = field(metadata=doc("the limit, in the same unit; for a bound, the nearer bound"))
    margin: float = field(metadata=doc(
        "how far the design is inside the limit, in the same unit (≥ 0: met): limit − value for an upper limit, "
        "value − limit for a lower one; for a bound, the distance to it"))
    active: bool = field(metadata=doc(
        "the limit holds the design where it is: it sets a variable (sets), or it is met within 1e-4 of its "
        "limit (a second limit balanced against the first by the search)"))
    sets: tuple[str, ...] = field(default=(), metadata=doc(
        "the design variables this limit decided (base_radius_mm: its own smallest base radius is the design's; "
        "the spring rate or the preload: their solve stopped on it)"))


@dataclass(frozen=True)
class DesignSearch:
    """How the design was found, and what it cost."""

    method: str = field(metadata=doc("the method, in a sentence"))
    variables: tuple[str, ...] = field(metadata=doc(
        "the variables the bounded search moved (the base radius and, unless it trades against the stress, the "
        "spring are solved, not searched)"))
    coarse_points: int = field(metadata=doc("candidates of the coarse grid over the whole box"))
    rounds: int = field(metadata=doc("rounds of local grids"))
    evaluations: int = field(metadata=doc(
        "candidates whose smallest base radius the search solved (on a grid of 1440 angles and the break points)"))
    margin_evaluations: int = field(metadata=doc(
        "evaluations of a candidate's limits at one base radius inside those solves"))
    exact_evaluations: int = field(metadata=doc(
        "runs of the exact checks or dynamics over the turn in the final solves (besides base_circle_sizings)"))
    base_circle_sizings: int = field(metadata=doc("calls of sizeBaseCircle's solver in the final solves"))
    location_tolerance: float = field(metadata=doc(
        "the search stops when it has located the best candidate within this share of each variable's range"))


@dataclass(frozen=True)
class ProfileDesign:
    """The smallest cam that works: the design, its limits and how it was found."""

    design: DesignValues = field(metadata=doc("the designed values"))
    constraints: tuple[DesignConstraint, ...] = field(metadata=doc("every limit and every free bound at the design"))
    search: DesignSearch = field(metadata=doc("how it was found"))
    cam: CamSpec = field(metadata={"internal": True})
