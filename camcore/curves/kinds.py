"""The registry of curve kinds: how each kind of curve spec is built.

A curve is given by its kind (``named``, ``makino``, ``universal``, ``polynomial``,
``bezier``, ``points``) and that kind's parameters, plus a direction (``rise`` or
``return``, Makino's INIT = 2). The service's specs carry exactly these names; it builds
every curve through :func:`build_curve` and checks the size limits each kind declares.
A new kind is one module with its law plus one entry here.

References
----------
.. [1] Makino (1977), subroutine CURVE (INIT = 2: the symmetrical return stroke).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ..errors import InvalidParameterError
from .bezier import BezierCurve
from .catalog import named_curve
from .curve import Curve
from .makino import makino_curve
from .points import PointsCurve
from .polynomial import NAMED_POLYNOMIALS, check_choice, named_polynomial, polynomial_from_boundary
from .reverse import ReturnCurve
from .universal import universal_curve

DIRECTIONS = ("rise", "return")


@dataclass(frozen=True)
class Law:
    """A curve spec as plain data: its kind (a key of :data:`CURVE_KINDS`), that kind's
    parameters and its direction, as :func:`build_curve` takes them.

    In a motion program some parameters may be left out to be matched or solved
    (:mod:`camcore.motion.laws`): a polynomial's ``start``/``end``, a universal curve's
    ``v0``/``v7``, Makino curve 2's ``t4``.
    """

    kind: str
    parameters: Mapping[str, Any] = field(default_factory=dict)
    direction: str = "rise"


@dataclass(frozen=True)
class SizeLimit:
    """A size a kind's spec may not exceed: its name in messages, the setting that holds
    the limit, the builder's keyword that takes it, the parameter it is read from, and how
    to read the size off the parameters."""

    what: str
    setting: str
    argument: str
    parameter: str
    size: Callable[[Mapping[str, Any]], int]


@dataclass(frozen=True)
class LawCost:
    """What one curve of a kind costs, in seconds on the reference machine (camcore.work):
    ``build_s`` to build it with its characteristic values and its inverse's start tables,
    ``sample_s`` per time at which S, V, A, J are evaluated (or S inverted), and
    ``characteristics_s`` to build it with its characteristic values only (None: ``build_s``;
    a closed-form law's inverse tables are most of its ``build_s``)."""

    build_s: float
    sample_s: float
    characteristics_s: float | None = None

    @property
    def values_s(self) -> float:
        """Building the curve and finding its characteristic values, no inverse tables [s]."""
        return self.build_s if self.characteristics_s is None else self.characteristics_s


@dataclass(frozen=True)
class Parameter:
    """One parameter of a kind as a request states it: what a service makes its field from
    when the kind has no spec of its own (service.curves.specs).

    ``type`` is ``float``, ``int`` or ``list`` (of floats); the bounds are inclusive
    (``minimum``, ``maximum``) or not (``above``, ``below``); without a ``default`` the
    parameter is required."""

    name: str
    type: type
    description: str
    default: Any = None
    required: bool = True
    minimum: float | None = None
    maximum: float | None = None
    above: float | None = None
    below: float | None = None


@dataclass(frozen=True)
class CurveKind:
    """One kind of curve spec: its builder, the parameters it takes, its size limit and
    its cost (a function of the parameters, known before anything is built).

    ``fields`` declares the parameters' types and bounds and ``example`` one valid set of
    them, for a kind that a service serves without a spec written for it: a new law is its
    module and this entry."""

    name: str
    description: str
    build: Callable[..., Curve]
    parameters: tuple[str, ...]
    cost: Callable[[Mapping[str, Any]], LawCost]
    limit: SizeLimit | None = None
    fields: tuple[Parameter, ...] = ()
    example: Mapping[str, Any] = field(default_factory=dict)


# Measured one at a time, best of 3 (camcore.work's reference machine), times 1.5 for a
# busy machine: closed-form laws build with their inverse tables in ≤ 18 ms and evaluate
# 200 000 times in ≤ 5 ms; a Bezier curve of degree d builds in 16-94 ms (d = 3-30) and
# costs 0.24-1.8 µs per time (a Newton solve for its parameter; 0.2 + 0.002·d² µs fits
# within 12 %); a points curve of n points builds in 11 ms + 7.5 µs·n.
# Built with their characteristic values only (no inverse tables), the slowest measured, best
# of 3 on a machine running a test suite beside: a Makino curve 1.6 ms (curve 4 from a target Vm,
# 34), a universal curve 1.64 ms (300 random break points, with and without end velocities), a
# polynomial from its end conditions 2.3 ms; times 1.5.
#: a law in closed form (named, Makino, universal; a dwell costs no more)
CLOSED_FORM_COST = LawCost(build_s=0.03, sample_s=5e-8, characteristics_s=1.5 * 1.65e-3)
#: a polynomial law (its coefficients solved from the end conditions)
POLYNOMIAL_COST = LawCost(build_s=0.03, sample_s=5e-8, characteristics_s=1.5 * 2.4e-3)


def _bezier_cost(p: Mapping[str, Any]) -> LawCost:
    degree = max(len(p["control_points"]) - 1, 1)
    return LawCost(build_s=1.5 * (0.005 + 0.0035 * degree), sample_s=1.5e-6 * (0.2 + 0.002 * degree ** 2))


def _points_cost(p: Mapping[str, Any]) -> LawCost:
    return LawCost(build_s=1.5 * (0.011 + 7.5e-6 * len(p["t"])), sample_s=5e-8)


def _polynomial(name: str | None = None, start: Mapping[str, float | None] | None = None,
                end: Mapping[str, float | None] | None = None) -> Curve:
    check_choice(name, start, end)
    if name is not None:
        return named_polynomial(name)
    assert start is not None and end is not None  # check_choice
    return polynomial_from_boundary(start, end)


CURVE_KINDS: dict[str, CurveKind] = {
    kind.name: kind
    for kind in (
        CurveKind("named", "a catalog curve by id, alias or Makino number", named_curve, ("name",),
                  lambda p: CLOSED_FORM_COST),
        CurveKind("makino", "Makino's curve by classification number, with its own parameters",
                  makino_curve, ("number", "z", "t4", "t1", "t3", "vm", "t1_over_t3", "v_ratio"), lambda p: CLOSED_FORM_COST),
        CurveKind("universal", "Makino's universal cam curve: break points and end conditions",
                  universal_curve, ("t", "m", "v0", "v7", "s0", "s7"), lambda p: CLOSED_FORM_COST),
        CurveKind("polynomial", "a polynomial law by name, or the least-degree one meeting end conditions",
                  _polynomial, ("name", "start", "end"), lambda p: POLYNOMIAL_COST),
        CurveKind("bezier", "lift over drive angle as a Bezier curve in the (θ, h) plane", BezierCurve,
                  ("control_points",), _bezier_cost,
                  SizeLimit("Bezier degree", "max_bezier_degree", "max_degree", "control_points", lambda p: len(p["control_points"]) - 1)),
        CurveKind("points", "a measured table (t, s), interpolated by a smooth spline", PointsCurve, ("t", "s", "v"),
                  _points_cost,
                  SizeLimit("number of points", "max_curve_points", "max_points", "t", lambda p: len(p["t"]))),
    )
}

#: the names a polynomial spec may give (the keys of the named polynomials)
POLYNOMIAL_NAMES = tuple(NAMED_POLYNOMIALS)


def build_curve(kind: str, parameters: Mapping[str, Any], direction: str = "rise",
                limits: Mapping[str, int] | None = None) -> Curve:
    """The curve of one spec.

    Parameters
    ----------
    kind : str
        A key of :data:`CURVE_KINDS`.
    parameters : mapping
        The kind's parameters (missing or None: the kind's default).
    direction : {"rise", "return"}
        ``return`` plays the rise backwards in time (Makino's INIT = 2).
    limits : mapping, optional
        Size limits by setting name (``max_bezier_degree``, ``max_curve_points``): handed
        to the builder, which raises :class:`LimitExceededError` above them.

    Returns
    -------
    Curve

    References
    ----------
    Makino (1977), subroutine CURVE (INIT = 2).
    """
    spec = CURVE_KINDS.get(kind)
    if spec is None:
        raise InvalidParameterError(f"curve type must be one of {', '.join(CURVE_KINDS)}, not {kind!r}.")
    if direction not in DIRECTIONS:
        raise InvalidParameterError(f"direction must be 'rise' or 'return', not {direction!r}.")
    args = {name: parameters[name] for name in spec.parameters if parameters.get(name) is not None}
    if spec.limit is not None and limits is not None and spec.limit.setting in limits:
        args[spec.limit.argument] = limits[spec.limit.setting]
    rise = spec.build(**args)
    return ReturnCurve(rise) if direction == "return" else rise
