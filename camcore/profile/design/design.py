"""The smallest plate cam that works: the base radius as small as the limits allow, then the softest
spring, then the smallest preload, over the variables the user frees within their bounds.

How the optimum is found (each step exact where it can be, bounded where it cannot):

1. **The spring** (with a load). The force along the motion, M·q''·ω² + C·q'·ω + K·q + Q0 + Q_ext,
   does not depend on the cam's geometry (a flat-faced oscillating follower's lever arm does: its
   spring is solved at the final cam), so the margin fixes the spring alone: for each rate K the
   smallest preload is Q0_min(K) in closed form (:mod:`.spring`), non-increasing in K because the
   lift is ≥ 0, so the softest rate whose preload fits under its upper bound is a monotone root; the
   preload is then the larger of its lower bound and Q0_min.
2. **The base radius.** For fixed offset, roller radius and spring every limit's margin grows with the
   base radius, so the smallest feasible radius is the largest of each limit's own root (as
   :func:`camcore.profile.base_circle.size_base_circle` does), and the lower bound.
3. **The rest** (offset or an arm's pivot distance, roller radius): a bounded search (:mod:`.search`) over
   them, on the lift sampled every 0.25° (:mod:`.evaluate`), located to 1e-5 of each variable's range; the
   design it settles on is solved again exactly (:mod:`.exact`).

Where the spring and the Hertz limit trade (a preload lower bound below what the softest spring needs:
a stiffer spring with less preload presses less at low lift, where a rise's acceleration peaks), the
spring rate between the softest and the stiffest that still lowers the preload joins the search as a
variable; at the design found, the softest rate whose stress still fits is then solved for.

References
----------
.. [1] Norton, *Cam Design and Manufacturing Handbook*: sizing a cam for pressure angle, radius of
   curvature, contact stress and follower jump.
.. [2] Dowell and Jarratt (1971), the Illinois method; Hooke and Jeeves (1961), pattern search.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from ..._maxima import golden_max
from ..._solvers import smallest_feasible
from ...curves.base import FloatArray
from ...errors import GeometryError, InvalidParameterError
from ..cam import CamSpec
from ..checks import corners
from .evaluate import Lanes, SearchCam
from .exact import Candidate, ExactCam
from .problem import PLACE, DesignProblem, check_problem, placed
from .results import DesignConstraint, DesignSearch, DesignValues, ProfileDesign
from .roots import assembly_range
from .search import LOCATION_TOLERANCE, SearchOutcome, grid_minimum, nested_minimum
from .spring import SpringModel

#: a limit within this share of its size (at least 1 unit) counts as active besides the one that set a variable
ACTIVE_SHARE = 1e-4
#: limits whose value must stay at or below the limit (the others at or above)
UPPER_LIMITS = ("max_pressure_angle_deg", "max_return_pressure_angle_deg", "allowed_stress_mpa")
METHOD = ("the spring by its monotone root (the softest rate whose smallest preload fits); the base radius as the "
          "largest of each limit's own root (Illinois, 1e-10); the offset (an arm's pivot distance) and the roller "
          "radius by nested searches, "
          "each a coarse grid that brackets its best point and golden section to 1e-5 of its range, on the lift "
          "sampled every 0.25°; where the spring rate trades against the stress, the rate that presses least by "
          "golden section (the stress is convex in it) and the softest that fits by its root; the design found "
          "solved again exactly")


class _Problem:
    """A design problem's values, unpacked once."""

    def __init__(self, problem: DesignProblem):
        self.p = problem
        spec, follower = problem.cam, problem.cam.follower
        self.spec, self.limits = spec, problem.limits
        self.rate_name, self.preload_name = problem.spring_names()
        rb = problem.bounds("base_radius_mm", spec.base_radius_mm)
        assert rb is not None
        self.rb_lo, self.rb_hi = rb
        #: the variable that places the follower (an offset, or an arm's pivot distance) and its bounds
        self.place_name = PLACE[follower.motion]
        given = follower.offset_mm if follower.motion == "translating" else follower.pivot_distance_mm
        self.place = problem.bounds(self.place_name, given) or (0.0, 0.0)
        self.roller = problem.bounds("roller_radius_mm", follower.roller_radius_mm) or (0.0, 0.0)
        self.rate = problem.bounds(self.rate_name, problem.spring_rate)
        self.preload = problem.bounds(self.preload_name, 0.0 if problem.preload is None else problem.preload)
        self.margin_n = problem.limits.safety_margin_n or 0.0
        self.geometry_spring = follower.motion == "oscillating" and spec.model.flat_faced

    def free(self, name: str) -> bool:
        """The variable is free with room between its bounds."""
        return name in self.p.free and self.p.free[name][0] < self.p.free[name][1]

    def spring_cam(self, rb: float | None = None, place_mm: float | None = None) -> CamSpec:
        """A cam that can be assembled, for the spring's model (its figures do not depend on the
        geometry, except a flat-faced oscillating follower's lever arm: then the cam at ``rb``, placed at
        ``place_mm``)."""
        follower = placed(self.spec.follower, self.place[0] if place_mm is None else place_mm, self.roller[0])
        if rb is not None:
            return replace(self.spec, follower=follower, base_radius_mm=rb)
        if follower.motion == "translating":
            return replace(self.spec, follower=follower,
                           base_radius_mm=self.rb_hi + max(abs(self.place[0]), abs(self.place[1])) + 1.0)
        lift = self.spec.lift.derivatives(np.linspace(0.0, 2 * math.pi, 721), 0)[0]
        lo, hi = self.place
        for place in dict.fromkeys((lo, hi, 0.5 * (lo + hi))):  # a free pivot: any place the arm assembles at
            follower = placed(self.spec.follower, place, self.roller[0])
            model = replace(self.spec, follower=follower).model
            _lo, top = assembly_range(model, lift, 1e-3 * self.rb_lo, max(self.rb_hi, 1e3 * self.rb_hi))
            if math.isfinite(top):
                return replace(self.spec, follower=follower, base_radius_mm=top)
        raise GeometryError("The arm cannot be assembled on any base circle with this lift.")


def _refuse_corners(spec: CamSpec, problem: DesignProblem) -> None:
    lim = problem.limits
    curvature = (lim.min_radius_of_curvature_mm is not None or lim.min_radius_of_curvature_roller_multiple is not None
                 or spec.follower.type != "knife-edge")
    jumps = corners(spec)
    if jumps and (curvature or problem.load is not None):
        where = ", ".join(f"{a:.6g}°" for a in jumps[:5])
        raise GeometryError(
            f"The lift's velocity jumps at {where}: the cam has a corner there (radius of curvature 0) and the "
            "follower an impact, at any base radius. Use motion laws whose velocity is continuous at every join.")


def _spring(pb: _Problem, spring: SpringModel) -> tuple[float, bool, float]:
    """The softest rate that keeps the margin, whether the rate trades against the stress, and the
    stiffest rate worth searching then (422 at safety_margin_n when no spring within the bounds holds)."""
    assert pb.rate is not None and pb.preload is not None
    softest = spring.softest(pb.rate[0], pb.rate[1], pb.preload[1])
    if softest is None:
        contact, _stress = spring.extremes(pb.rate[1], pb.preload[1])
        raise InvalidParameterError(
            f"safety_margin_n: the largest contact force the follower keeps within the bounds is {contact:.4g} N "
            f"(the stiffest spring, {pb.rate[1]:g}, with the largest preload, {pb.preload[1]:g}), below the margin of "
            f"{pb.margin_n:g} N at the worst speed of the range.", field=("limits", "safety_margin_n"))
    coupled = (pb.limits.allowed_stress_mpa is not None and pb.free(pb.rate_name) and pb.free(pb.preload_name)
               and spring.min_preload(softest) > pb.preload[0])
    stiffest = softest
    if coupled:
        stiffest = spring.softest(softest, pb.rate[1], pb.preload[0]) or pb.rate[1]
    return softest, coupled and stiffest > softest, stiffest


def design_profile(problem: DesignProblem) -> ProfileDesign:
    """The smallest plate cam that meets the limits, then the softest spring, then the smallest preload.

    Parameters
    ----------
    problem : DesignProblem
        The cam's lift and follower (fixed values), the free variables with their bounds [mm, N/mm or
        N·m/rad, N or N·m], the limits and the follower's load.

    Returns
    -------
    ProfileDesign
        The designed values, every limit and free bound at the design (value, limit, margin, active),
        and how the search went.

    Raises
    ------
    InvalidParameterError
        A rule of the problem broken (:func:`.problem.check_problem`), or no design within the bounds
        meets the limits: the error names the limit that cannot be met (``limits.<name>``) and the best
        value reachable within the bounds.
    GeometryError
        A lift whose velocity jumps, where a curvature limit or the dynamics need its second derivative.

    References
    ----------
    Norton, *Cam Design and Manufacturing Handbook* (sizing for pressure angle, curvature, stress and
    jump); Dowell and Jarratt (1971), the Illinois method; Hooke and Jeeves (1961), pattern search.
    """
    check_problem(problem)
    pb = _Problem(problem)
    _refuse_corners(pb.spec, problem)
    spring: SpringModel | None = None
    softest, coupled, stiffest = math.nan, False, math.nan
    load = problem.load
    if load is not None and not pb.geometry_spring:
        spring = SpringModel(pb.spring_cam(), load, pb.margin_n)
        softest, coupled, stiffest = _spring(pb, spring)
    geometry = [n for n in (pb.place_name, "roller_radius_mm") if pb.free(n) and not (
        n == "offset_mm" and pb.spec.model.flat_faced)]
    search = SearchCam(pb.spec, pb.limits, spring, pb.rb_lo)
    search.preload_floor = pb.preload[0] if pb.preload is not None else 0.0
    exact = ExactCam(pb.spec, pb.limits, spring, pb.rb_lo, pb.rb_hi)

    def lanes_of(points: FloatArray, names: list[str], rate: float, preload: float | None) -> Lanes:
        """Candidates at these points, every one with this spring rate and preload."""
        m = points.shape[0]
        column = {n: points[:, i] for i, n in enumerate(names)}
        preload = math.nan if preload is None else preload
        return Lanes(column.get(pb.place_name, np.full(m, pb.place[0])),
                     column.get("roller_radius_mm", np.full(m, pb.roller[0])), np.full(m, rate), np.full(m, preload))

    def run(rate: float) -> tuple[SearchOutcome, Candidate | None]:
        """The geometry searched with this spring rate (its preload the smallest that holds)."""
        preload = None if spring is None else _preload(pb, spring, rate)
        outcome = minimum(lambda x: search.needed_radius(lanes_of(x, geometry, rate, preload), pb.rb_hi),
                          np.asarray(box[0], dtype=np.float64), np.asarray(box[1], dtype=np.float64))
        if outcome.point is None:
            return outcome, None
        point = dict(zip(geometry, (float(x) for x in outcome.point), strict=True))
        return outcome, Candidate(point.get(pb.place_name, pb.place[0]), point.get("roller_radius_mm", pb.roller[0]),
                                  None if spring is None else rate, preload)

    box = ([pb.place[0] if n == pb.place_name else pb.roller[0] for n in geometry],
           [pb.place[1] if n == pb.place_name else pb.roller[1] for n in geometry])
    names, rate = list(geometry), softest
    traded = coupled  # the rate is chosen against the stress: the softest that fits is solved for at the end
    if coupled and spring is not None:
        names.append(pb.rate_name)
        # the geometry alone first: when, at that optimum, some rate keeps the stress within its limit (the
        # rate that presses least there, by golden section: the stress is convex in the rate), this lower
        # bound of the base radius is the optimum
        search.with_stress = False
        outcome, cand = run(softest)
        search.with_stress = True
        if cand is not None:
            geometric = max([pb.rb_lo, *exact.geometric_radii(cand).values()])
            rate = _least_stress_rate(search, cand, min(geometric, pb.rb_hi), softest, stiffest)
            cand = replace(cand, rate=rate, preload=_preload(pb, spring, rate))
            if not (geometric <= pb.rb_hi and exact.stress_radius(cand, geometric) == -math.inf):
                # the stress decides even then: the geometry again at that rate, then the rate that
                # presses least at the geometry found
                evaluated = outcome.evaluations
                outcome, cand = run(rate)
                outcome = replace(outcome, evaluations=outcome.evaluations + evaluated)
                if cand is not None:
                    at = min(max([pb.rb_lo, *exact.radii(cand).values()]), pb.rb_hi)
                    rate = _least_stress_rate(search, cand, at, softest, stiffest)
                    cand = replace(cand, rate=rate, preload=_preload(pb, spring, rate))
    else:
        outcome, cand = run(softest)
    preload = None if spring is None else _preload(pb, spring, rate)
    rates = (softest, stiffest) if traded else None
    if cand is None:
        raise _infeasible(pb, search, exact, geometry, *box, lambda x: lanes_of(x, geometry, rate, preload), rates)
    radii = exact.radii(cand)
    rb = max([pb.rb_lo, *radii.values()])
    if not rb <= pb.rb_hi:
        raise _infeasible(pb, search, exact, geometry, *box, lambda x: lanes_of(x, geometry, rate, preload), rates)
    rate_set_by_stress = False
    if traded and spring is not None:
        cand, rate_set_by_stress = _softest_at(pb, spring, exact, cand, rb, softest)
        radii = exact.radii(cand)
        rb = max([pb.rb_lo, *radii.values()])
    if load is not None and pb.geometry_spring:
        spring = SpringModel(pb.spring_cam(rb, cand.place_mm), load, pb.margin_n)
        exact.spring = spring
        softest, _coupled, _stiffest = _spring(pb, spring)
        cand = replace(cand, rate=softest, preload=_preload(pb, spring, softest))
    return _answer(pb, exact, spring, cand, rb, radii, softest, rate_set_by_stress, outcome, names, search)


def minimum(objective: Callable[[FloatArray], FloatArray], lo: FloatArray, hi: FloatArray) -> SearchOutcome:
    """The search of :mod:`.search` for this many variables: nested one at a time up to two (the offset and
    the roller radius), a grid and local grids beyond.

    Parameters
    ----------
    objective : callable
        ``points (m, d) -> values (m,)``, +inf where infeasible [mm].
    lo, hi : ndarray
        The box [mm, N/mm or N·m/rad].

    Returns
    -------
    SearchOutcome
        The best point and its value [mm].

    References
    ----------
    Kiefer (1953), golden-section search; Hooke and Jeeves (1961), pattern search.
    """
    return nested_minimum(objective, lo, hi) if lo.size <= 2 else grid_minimum(objective, lo, hi)


def _least_stress_rate(search: SearchCam, cand: Candidate, rb: float, softest: float, stiffest: float) -> float:
    """The spring rate in [softest, stiffest] with the least largest Hertz pressure at this cam (on the
    search's grid, by golden section: at each angle the normal force is affine in the rate plus the
    convex smallest preload, so their largest is convex in the rate) [N/mm or N·m/rad]."""
    return _least_stress_at(search, cand, rb, softest, stiffest)[0]


def _least_stress_at(search: SearchCam, cand: Candidate, rb: float, softest: float, stiffest: float
                     ) -> tuple[float, float]:
    """:func:`_least_stress_rate` and its (p0/p_allowed)² on the search's grid [N/mm or N·m/rad, -]."""
    assert search.spring is not None
    spring = search.spring

    def stress(rate: FloatArray) -> FloatArray:
        preload = np.maximum(search.preload_floor, (-spring.reserve(search.state, rate)).max(axis=1))
        lanes = Lanes(np.full(rate.size, cand.place_mm), np.full(rate.size, cand.roller_radius_mm), rate, preload)
        return search.extremes(lanes, np.full(rate.size, rb))[0]["stress"]

    return _least_stress(stress, softest, stiffest)


def _least_stress(stress: Callable[[FloatArray], FloatArray], softest: float, stiffest: float) -> tuple[float, float]:
    """The rate of [softest, stiffest] where ``stress`` (convex) is least, and its value: 17 rates, then golden
    section between the best one's neighbours [N/mm or N·m/rad, -]."""
    rates = np.linspace(softest, stiffest, 17)
    on_grid = stress(rates)
    j = int(np.argmin(on_grid))
    a, b = float(rates[max(j - 1, 0)]), float(rates[min(j + 1, 16)])
    x, v = golden_max(lambda r: -stress(np.asarray(r, dtype=np.float64)), a, b,
                      width=LOCATION_TOLERANCE * (stiffest - softest))
    return (float(x[0]), -float(v[0])) if -float(v[0]) <= float(on_grid[j]) else (float(rates[j]), float(on_grid[j]))


def _preload(pb: _Problem, spring: SpringModel, rate: float) -> float:
    """The smallest preload within its bounds that keeps the margin at this rate [N or N·m]."""
    assert pb.preload is not None
    if not pb.free(pb.preload_name):
        return pb.preload[0]
    return max(pb.preload[0], spring.min_preload(rate))


def _softest_at(pb: _Problem, spring: SpringModel, exact: ExactCam, cand: Candidate, rb: float,
                softest: float) -> tuple[Candidate, bool]:
    """Among the rates the search could have taken, the softest whose stress still fits at this cam
    (its margin grows with the rate there, the preload falling faster than the spring force rises where
    the stress peaks)."""
    allowed = pb.limits.allowed_stress_mpa
    assert allowed is not None and cand.rate is not None
    spec = exact.cam(cand, rb)

    def margin(rate: float) -> float:
        return spring.stress_margin(rate, _preload(pb, spring, rate), allowed)(spec)

    if cand.rate <= softest or margin(softest) >= 0:
        return replace(cand, rate=softest, preload=_preload(pb, spring, softest)), False
    rate = smallest_feasible(margin, softest, cand.rate)
    return replace(cand, rate=rate, preload=_preload(pb, spring, rate)), True


def _answer(pb: _Problem, exact: ExactCam, spring: SpringModel | None, cand: Candidate, rb: float,
            radii: dict[str, float], softest: float, rate_set_by_stress: bool, outcome: SearchOutcome,
            names: list[str], search: SearchCam) -> ProfileDesign:
    values = exact.values(cand, rb)
    sets: dict[str, list[str]] = {}
    deciding = [n for n, r in radii.items() if r == rb]
    for n in deciding:
        sets.setdefault(n, []).append("base_radius_mm")
    at_bound: dict[str, str] = {}
    if not deciding and pb.free("base_radius_mm"):
        at_bound["base_radius_mm"] = "base_radius_mm"
    if spring is not None and cand.rate is not None and pb.rate is not None and pb.preload is not None:
        if pb.free(pb.rate_name):
            if rate_set_by_stress:
                sets.setdefault("allowed_stress_mpa", []).append(pb.rate_name)
            elif cand.rate > pb.rate[0]:
                sets.setdefault("safety_margin_n", []).append(pb.rate_name)
            else:
                at_bound[pb.rate_name] = pb.rate_name
        if pb.free(pb.preload_name):
            if cand.preload is not None and cand.preload > pb.preload[0]:
                sets.setdefault("safety_margin_n", []).append(pb.preload_name)
            else:
                at_bound[pb.preload_name] = pb.preload_name
    constraints = []
    for name, (value, limit) in values.items():
        margin = limit - value if name in UPPER_LIMITS else value - limit
        chosen = tuple(sets.get(name, ()))
        active = bool(chosen) or abs(margin) <= ACTIVE_SHARE * max(abs(limit), 1.0)
        constraints.append(DesignConstraint(name, float(value), float(limit), float(margin), active, chosen))
    design = DesignValues(
        base_radius_mm=rb,
        offset_mm=cand.place_mm if pb.spec.follower.motion == "translating" else None,
        pivot_distance_mm=cand.place_mm if pb.spec.follower.motion == "oscillating" else None,
        roller_radius_mm=cand.roller_radius_mm if pb.spec.follower.type == "roller" else None,
        **({} if spring is None else {pb.rate_name: cand.rate, pb.preload_name: cand.preload}))
    own: dict[str, float | None] = {"base_radius_mm": rb, pb.place_name: cand.place_mm,
                                    "roller_radius_mm": cand.roller_radius_mm, pb.rate_name: cand.rate,
                                    pb.preload_name: cand.preload}
    for name, (lo, hi) in pb.p.free.items():
        at = own.get(name)
        if at is None:
            continue
        bound = lo if abs(at - lo) <= abs(hi - at) else hi
        room = abs(at - bound)
        active = name in at_bound or room <= LOCATION_TOLERANCE * (hi - lo)
        constraints.append(DesignConstraint(f"free.{name}", float(at), float(bound), float(room), active,
                                            (name,) if active else ()))
    report = DesignSearch(METHOD, tuple(names), outcome.coarse_points, outcome.rounds, outcome.evaluations,
                          search.margin_evaluations, exact.runs + (0 if spring is None else spring.exact_runs),
                          exact.sizings, LOCATION_TOLERANCE)
    return ProfileDesign(design, tuple(constraints), report, exact.cam(cand, rb))


def _infeasible(pb: _Problem, search: SearchCam, exact: ExactCam, names: list[str], lo: list[float],
                hi: list[float], lanes_of: Callable[[FloatArray], Lanes],
                rates: tuple[float, float] | None) -> InvalidParameterError:
    """The 422 of a problem no design within the bounds meets: the first limit that cannot be met even
    alone, with the best value reachable (at the upper bound of the base radius, the other variables
    searched for it as the design is), or else the limit furthest from being met where they come closest."""
    box_lo, box_hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)

    def worst(names: tuple[str, ...] | None) -> Callable[[FloatArray], FloatArray]:
        """−(the best margin over the base radius) of these limits (all: None), to minimise."""
        def objective(points: FloatArray) -> FloatArray:
            return np.nan_to_num(-search.best_margin(lanes_of(points), pb.rb_hi, names)[0], nan=np.inf,
                                 neginf=np.inf)
        return objective

    names_of = list(search.margins(lanes_of(np.asarray([box_lo])), np.array([pb.rb_hi])).keys())
    alone, outcome = None, None
    for name in names_of:  # the coarse grid screens; a limit it finds unmet everywhere is refined to be sure
        if grid_minimum(worst((name,)), box_lo, box_hi, refine=False).value > 0:
            outcome = minimum(worst((name,)), box_lo, box_hi)
            if outcome.point is None or outcome.value > 0:
                alone = name
                break
    if alone is not None and outcome is not None:
        name, how = alone, "alone"
    else:
        outcome = minimum(worst(None), box_lo, box_hi)
        how = "together"
        name = names_of[0]
    point = box_lo if outcome.point is None else outcome.point
    lanes = lanes_of(np.asarray([point]))
    _best, best_at = search.best_margin(lanes, pb.rb_hi, (name,) if how == "alone" else None, refine=True)
    cand = Candidate(float(lanes.place[0]), float(lanes.roller[0]),
                     None if exact.spring is None else float(lanes.rate[0]),
                     None if exact.spring is None else float(lanes.preload[0]))
    at = float(best_at[0]) if math.isfinite(float(best_at[0])) else pb.rb_hi
    if rates is not None and exact.spring is not None:
        if name == "allowed_stress_mpa":  # the base radius and the rate that press least, together
            lo_rb, hi_rb = (float(x[0]) for x in search.bracket(lanes, pb.rb_hi))
            if math.isfinite(lo_rb):
                best = golden_max(lambda r: -np.array([_least_stress_at(search, cand, float(v), *rates)[1] for v in r]),
                                  lo_rb, hi_rb, width=1e-6 * hi_rb)[0]
                at = float(best[0])
        rate = _least_stress_rate(search, cand, at, *rates)
        cand = replace(cand, rate=rate, preload=_preload(pb, exact.spring, rate))
    try:
        values = exact.values(cand, at)
    except GeometryError:
        values = {}
    if how == "together" and values:
        margin_of = {n: (lim - v if n in UPPER_LIMITS else v - lim) / max(abs(lim), 1.0)
                     for n, (v, lim) in values.items() if n != "safety_margin_n"}
        name = min(margin_of, key=lambda n: margin_of[n])
    value, limit = values.get(name, (math.nan, math.nan))
    unit = {"max_pressure_angle_deg": "°", "max_return_pressure_angle_deg": "°", "min_radius_of_curvature_mm": " mm",
            "allowed_stress_mpa": " MPa"}.get(name, "")
    word = "smallest" if name in UPPER_LIMITS else "largest"
    place = "offset" if pb.place_name == "offset_mm" else "pivot distance"
    where = (f"base radius {at:.6g} mm" + (f", {place} {cand.place_mm:.6g} mm" if pb.place_name in names else "")
             + (f", roller radius {cand.roller_radius_mm:.6g} mm" if "roller_radius_mm" in names else "")
             + (f", spring rate {cand.rate:.6g}" if rates is not None and cand.rate is not None else ""))
    if how == "alone":
        message = (f"{name}: the {word} reachable within the bounds is {value:.4g}{unit} (limit {limit:g}{unit}), "
                   f"at {where}.")
    else:
        message = (f"{name}: the limits cannot all be met within the bounds; where they come closest ({where}), "
                   f"{name} is {value:.4g}{unit} against the limit {limit:g}{unit}.")
    return InvalidParameterError(message, field=("limits", name))
