"""Designing a plate cam: the smallest cam that meets the limits, then the softest spring.

Map: :mod:`.problem` (what a design asks and its rules), :mod:`.spring` (the softest spring and its
preload over a speed range), :mod:`.evaluate` (the limits of many candidates at once on a sampled
lift), :mod:`.search` (the bounded search: coarse grid, shrinking local grids), :mod:`.exact` (the
exact solves at the design found), :mod:`.design` (all of it, :func:`design_profile`),
:mod:`.results` (what it answers).
"""

from .design import design_profile
from .problem import VARIABLES, DesignLimits, DesignProblem, FollowerLoad, check_problem
from .results import DesignConstraint, DesignSearch, DesignValues, ProfileDesign

__all__ = [
    "VARIABLES", "DesignConstraint", "DesignLimits", "DesignProblem", "DesignSearch", "DesignValues",
    "FollowerLoad", "ProfileDesign", "check_problem", "design_profile",
]
