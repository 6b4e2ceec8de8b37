"""An estimate: seconds on the reference machine, as terms each with the request field that
drives it (camcore.work says how the figures were measured)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ..curves.kinds import CURVE_KINDS, LawCost

Field = tuple[str | int, ...]


@dataclass(frozen=True)
class WorkTerm:
    """One part of an estimate: the request field that drives it, what it is, its cost [s]."""

    field: Field
    what: str
    seconds: float


@dataclass(frozen=True)
class WorkEstimate:
    """The estimated seconds of a computation, as a sum of terms."""

    terms: tuple[WorkTerm, ...] = ()

    @property
    def seconds(self) -> float:
        """The estimate [s]."""
        return sum(term.seconds for term in self.terms)

    def __add__(self, other: WorkEstimate) -> WorkEstimate:
        return WorkEstimate(self.terms + other.terms)

    def largest(self) -> WorkTerm:
        """The term that costs most (what to reduce first)."""
        return max(self.terms, key=lambda term: term.seconds)


def law_cost(kind: str, parameters: Mapping[str, Any]) -> LawCost:
    """The cost of one curve of a kind with these parameters, before it is built.

    Parameters
    ----------
    kind : str
        A key of :data:`camcore.curves.kinds.CURVE_KINDS`.
    parameters : mapping
        The kind's parameters (sizes are read from them: control points, points).

    Returns
    -------
    LawCost
        Seconds to build it (with characteristic values and inverse start tables) and
        per evaluated time [s].

    References
    ----------
    camcore.curves.kinds, the measurements beside each kind's cost.
    """
    return CURVE_KINDS[kind].cost(parameters)


def curve_work(law: LawCost, field: Field, values_only: bool = False) -> WorkEstimate:
    """Building one curve.

    Parameters
    ----------
    law : LawCost
        The curve's cost (:func:`law_cost`).
    field : tuple
        The request field of the curve spec.
    values_only : bool
        Only the curve and its characteristic values, not its inverse's tables
        (:attr:`LawCost.values_s`) [-].

    Returns
    -------
    WorkEstimate
        One term [s].

    References
    ----------
    camcore.curves.kinds (LawCost).
    """
    if values_only:
        return WorkEstimate((WorkTerm(field, "building the curve and its characteristic values", law.values_s),))
    return WorkEstimate((WorkTerm(field, "building the curve", law.build_s),))


def per_item_work(count: int, seconds_each: float, field: Field, what: str) -> WorkEstimate:
    """``count`` items of equal cost, e.g. the rows of a table.

    Parameters
    ----------
    count : int
        Number of items [-].
    seconds_each : float
        Cost of one item [s].
    field : tuple
        The request field that sets the count.
    what : str
        What the items are, for the caller's message.

    Returns
    -------
    WorkEstimate
        One term [s].

    References
    ----------
    camcore.work, module notes.
    """
    return WorkEstimate((WorkTerm(field, what, count * seconds_each),))

