"""Designing a plate cam (camcore.profile.design): the search's evaluations and the exact solves at the
design it finds, counted before the work from what the request frees and limits.

References
----------
.. [1] M. Nygard, *Release It!*, 2nd ed. (2018), ch. 5: bounded work, fail fast.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from ..curves.kinds import LawCost
from ..profile.design import search
from .estimate import Field, WorkEstimate, WorkTerm
from .profiles import DYNAMICS_PER_CHECKS, base_circle_work, checks_work

#: points of the nested search's coarse grids (outer, inner), read from the search itself, which also stops
#: at LOCATION_TOLERANCE of each range and counts its golden steps (golden_steps)
NESTED_OUTER, NESTED_INNER = search.NESTED_OUTER_POINTS, search.NESTED_INNER_POINTS
LOCATION_TOLERANCE = search.LOCATION_TOLERANCE
golden_steps = search.golden_steps
#: evaluations of a candidate's limits at one base radius per candidate the search solves, measured over
#: the cases of tests/camcore/profile/test_design.py: 1.0 where the pressure's closed form decides (nothing
#: else can bind), 1.0-3.0 with curvature limits (the bracket's ends and the Illinois steps where one
#: binds), 1.0-5.6 more with a stress limit (up to 10.6 for a limit within 0.1% of the least stress the
#: bounds allow: the margin then falls again below the upper bound for most candidates, and a golden
#: section looks for the window that meets it), 16 for an oscillating arm (the pressure angle in the root)
MARGINS_GEOMETRY = 4
MARGINS_STRESS = 8
#: where the spring rate trades against the stress, the search's second run is at a rate chosen for the
#: stress, where the margin falls again below the upper bound for most candidates: measured 10.6
MARGINS_STRESS_TRADED = 12
MARGINS_ARM = 18
MARGINS_FLAT = 20
#: one evaluation of one candidate's limits on the search's 1446 angles, its share of the search's own
#: steps included: measured 39-42 µs for a translating follower (the closed forms), 108 µs for an
#: oscillating arm (its closed forms), about 0.5 ms for a flat face (its own kinematics, one candidate);
#: ×1.5
MARGIN_CLOSED_FORM_S = 1.5 * 4.5e-5
MARGIN_ARM_S = 1.5 * 1.1e-4
#: an arm whose pivot is searched too: many of its candidates lie by the edge where no base radius meets
#: the pressure limit, and their roots are sought a lane or two at a time (the golden section for the window
#: that meets it, then Illinois), so each evaluation carries its call's own cost: measured 17.3-20.1
#: evaluations a candidate and 250 µs each (the pivot example, pivots over 10-400 mm, limits of 20° and 30°,
#: a knife-edge); kept at 24 and ×1.5 of 260 µs
MARGINS_ARM_PLACED = 24
MARGIN_ARM_PLACED_S = 1.5 * 2.6e-4
MARGIN_FLAT_S = 1.5 * 5e-4
#: exact runs over the turn in the final solves, measured: a limit's own radius 15-20 runs of the checks
#: (size_base_circle's CHECKS_PER_LIMIT); the spring's root up to 40 runs of its preload, each about a
#: third of a run of the checks (1 ms against 3 ms); the stress's radius about 20 runs of the dynamics'
#: extremes, 32 in all where the rate trades against the stress and the geometry's optimum keeps (the
#: softest rate that fits, by Illinois), 139 where it does not (the stress within 0.1% of the least the
#: bounds allow: the geometry searched again, a golden section for the window of radii that meets it); the values at the design 3 runs of
#: the checks and one of the dynamics
OWN_SOLVE_RUNS = 20
SPRING_RUNS = 40
SPRING_RUN_SHARE = 0.35
STRESS_RUNS = 25
STRESS_RUNS_TRADED = 140
VALUE_CHECKS = 3


def search_candidates(variables: int, trades: bool) -> int:
    """Candidates the search solves a base radius for, before it runs.

    Parameters
    ----------
    variables : int
        Geometric variables searched (offset, roller radius), 0-2 [-].
    trades : bool
        The spring rate may trade against the stress: the geometry searched twice at most (alone, then at
        the rate that presses least), and a golden section over the rate.

    Returns
    -------
    int
        Candidates [-]: nested golden sections (coarse grid, two inner points and the steps of each level).

    References
    ----------
    Kiefer (1953), golden-section search.
    """
    per_level = [NESTED_OUTER + 2 + golden_steps(NESTED_OUTER), NESTED_INNER + 2 + golden_steps(NESTED_INNER)]
    nested = math.prod(per_level[:variables]) if variables else 1
    return 2 * nested + RATE_SEARCH if trades else nested


#: candidates of the golden section over the spring rate (17 points, then golden steps to 1e-5)
RATE_SEARCH = 17 + 2 + 30


def design_work(laws: Sequence[LawCost | None], *, searched: int, kind: str, roots: bool, pressure_limits: int,
                own_solves: bool, curvature: bool, stress: bool, load: bool, trades: bool, segments_field: Field,
                free_field: Field) -> WorkEstimate:
    """A plate-cam design: the search and the exact solves at its design (the curves and the designed cam's
    profile counted apart).

    Parameters
    ----------
    laws : sequence of LawCost or None
        Each segment's law (None: a dwell or the default cycloid).
    searched : int
        Variables the search moves (offset, roller radius) [-].
    kind : str
        ``closed_form`` (a translating knife-edge or roller), ``arm`` (an oscillating one), ``placed_arm`` (an
        oscillating one whose pivot is searched) or ``flat``.
    roots : bool
        A limit besides the pressure angle can decide the base radius (curvature).
    pressure_limits : int
        Pressure-angle limits solved (0-2) [-].
    own_solves : bool
        The limits' radii are solved here, not by size_base_circle (an oscillating follower, a separate
        return limit).
    curvature, stress, load, trades : bool
        A curvature limit (or a roller's undercut, a flat face's convexity); a stress limit; a spring; the
        spring rate trading against the stress.
    segments_field, free_field : tuple
        The request fields of the lift and of the free variables.

    Returns
    -------
    WorkEstimate
        The search, the exact solves and the spring [s].

    References
    ----------
    camcore.profile.design; the measurements beside :data:`MARGINS_GEOMETRY` and :data:`MARGIN_CLOSED_FORM_S`.
    """
    candidates = search_candidates(searched, trades)
    per, margin_s = {"closed_form": (MARGINS_GEOMETRY if roots else 1, MARGIN_CLOSED_FORM_S),
                     "arm": (MARGINS_ARM, MARGIN_ARM_S), "placed_arm": (MARGINS_ARM_PLACED, MARGIN_ARM_PLACED_S),
                     "flat": (MARGINS_FLAT, MARGIN_FLAT_S)}[kind]
    per += (MARGINS_STRESS_TRADED if trades else MARGINS_STRESS) if stress else 0
    limits = pressure_limits + int(curvature) + int(stress)
    # the 422's best values, when none is feasible: a coarse grid per limit and one search more, one
    # evaluation of the limits per candidate
    infeasible = limits * (NESTED_OUTER * NESTED_INNER ** max(searched - 1, 0) if searched else 1) + candidates
    check = checks_work(laws, segments_field).seconds
    solves = 2 if trades else 1
    geometric = (solves * OWN_SOLVE_RUNS * (pressure_limits + int(curvature)) * check if own_solves
                 else solves * base_circle_work(laws, pressure_limits + int(curvature), segments_field).seconds)
    spring = SPRING_RUNS * SPRING_RUN_SHARE * check * (2 if trades else 1) if load else 0.0
    dynamics = DYNAMICS_PER_CHECKS * check
    exact = geometric + spring + VALUE_CHECKS * check + (dynamics if load else 0.0)
    exact += (STRESS_RUNS_TRADED if trades else STRESS_RUNS) * dynamics if stress else 0.0
    return WorkEstimate((
        WorkTerm(free_field, f"the search's {candidates} candidates", (candidates * per + infeasible) * margin_s),
        WorkTerm(segments_field, "the exact solves at the design found and the spring", exact)))
