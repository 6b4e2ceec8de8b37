"""Polynomials matched to their neighbours, alone or in chains (splines).

A matched polynomial meets, at an omitted end, its neighbour's position, velocity and
acceleration (quintic; with ``match: jerk`` also the jerk: septic). Its neighbour is fixed
(a dwell, a catalog law, …) or itself a matched polynomial. Consecutive matched
polynomials form a *chain*; at a join inside a chain nothing is given, and the rule is that
the chain is as smooth there as the two degrees allow: with m_L and m_R the orders the two
polynomials match (2 for quintics, 3 for septics), derivatives 1 … m_L + m_R are continuous
(a chain of quintics is a C4 quintic spline, of septics a C6 septic spline). The unknowns
are the derivatives 1 … max(m_L, m_R) at the join, shared by both sides, which gives as many
equations as unknowns; a chain that is the whole program closes over the period (a periodic
spline).

Each polynomial is the confluent Hermite interpolant of its end conditions
(:func:`camcore.curves.polynomial.boundary_matrix`, the same matrix
:func:`~camcore.curves.polynomial.polynomial_from_boundary` solves), in its local time
T = (x − x_a)/β: p⁽ᵏ⁾(T) = βᵏ·dᵏs/dxᵏ. The unknowns at a join are scaled by a length
L = min(β_L, β_R) (w = Lᵏ·dᵏs/dxᵏ) and so are the equations, so that spans of very
different lengths do not make the system ill-conditioned by units alone.

References
----------
.. [1] R. L. Norton, Cam Design and Manufacturing Handbook, ch. 3 (polynomials from boundary
   conditions).
.. [2] C. de Boor, A Practical Guide to Splines (2001): splines through given values, their
   continuity at the knots as a linear system.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..curves.curve import Curve
from ..curves.polynomial import boundary_matrix, polynomial_from_boundary
from ..errors import InvalidParameterError
from .laws import ORDER_KEYS

#: the chain's linear system, rows and columns scaled to unit maxima, is refused (422) as
#: singular above this condition number (~1/(100·eps)). Below it the solve is backward
#: stable: the equations' residuals — the jumps at the joins — stay at rounding level even
#: where the condition number is large (1e10 measured for spans 3.6° next to 178°, septics),
#: and the join report shows them.
MAX_CONDITION = 1e14


@dataclass(frozen=True)
class Member:
    """One polynomial of a chain, in real units.

    ``span_deg`` β [deg], ``s_a`` its start position and ``stroke`` h [mm or deg]; ``order``
    the derivatives it matches at a free end (2 or 3); ``start``/``end``: its known end
    conditions by order (1 v, 2 a, 3 j) [mm or deg per deg^k], or None for an end joined
    to another member of the chain (orders 1 … ``order`` unknown).
    """

    span_deg: float
    s_a: float
    stroke: float
    order: int
    start: Mapping[int, float] | None
    end: Mapping[int, float] | None

    def orders(self, side: int) -> list[int]:
        """The derivative orders given at the start (0) or the end (1)."""
        known = self.start if side == 0 else self.end
        return list(range(1, self.order + 1)) if known is None else sorted(known)


def _derivative_rows(n: int, where: float, highest: int) -> NDArray[np.float64]:
    """Rows d = 0 … highest: dᵈ/dTᵈ of T⁰ … Tⁿ⁻¹ at T = where."""
    rows = np.zeros((highest + 1, n))
    for d in range(highest + 1):
        for k in range(d, n):
            rows[d, k] = math.perm(k, d) * (where ** (k - d) if k > d else 1.0)
    return rows


def solve_chain(members: Sequence[Member], periodic: bool) -> list[tuple[dict[int, float], dict[int, float]]]:
    """The end conditions of every polynomial of a chain, its inner joins solved.

    At an inner join the two polynomials share their unknowns: the derivatives 1 … M of s
    at the join, M the larger of their matched orders (so v and a, and j between septics,
    are one number on both sides). The equations: a polynomial that matches fewer orders
    has its derivatives up to M equal to the shared ones, and derivatives M + 1 … m_L + m_R
    are continuous.

    Parameters
    ----------
    members : sequence of Member
        The chain's polynomials in order; member p's end is free exactly when member p + 1's
        start is (and, for a periodic chain, the last member's end and the first's start).
    periodic : bool
        The chain is the whole program: its last member joins its first.

    Returns
    -------
    list of (dict, dict)
        Each member's start and end conditions by order [mm or deg per deg^k].

    Raises
    ------
    InvalidParameterError
        The chain's conditions are dependent or nearly so (condition number over
        :data:`MAX_CONDITION`), or not finite.

    References
    ----------
    Norton, Cam Design and Manufacturing Handbook, ch. 3; de Boor (2001), splines through given values.
    """
    r = len(members)
    joins = [(p, p + 1) for p in range(r - 1) if members[p].end is None]
    if periodic:
        joins.append((r - 1, 0))
    # unknowns: w_k = Lᵏ·dᵏs/dxᵏ at each join, k = 1 … M (shared by both sides)
    column: dict[tuple[int, int], int] = {}  # (join, order) → column
    at_join: dict[tuple[int, int], int] = {}  # (member, side) → join
    lengths = []
    for q, (left, right) in enumerate(joins):
        lengths.append(min(members[left].span_deg, members[right].span_deg))
        at_join[(left, 1)], at_join[(right, 0)] = q, q
        for order in range(1, max(members[left].order, members[right].order) + 1):
            column[(q, order)] = len(column)
    n_unknown = len(column)
    highest = 2 * max(m.order for m in members)
    # each member's p⁽ᵈ⁾ at both ends as weights on its conditions: known part + unknown columns
    weights = []
    for p, m in enumerate(members):
        conds = [(0, 0.0)] + [(k, 0.0) for k in m.orders(0)] + [(0, 1.0)] + [(k, 1.0) for k in m.orders(1)]
        inverse = np.linalg.inv(boundary_matrix(conds))
        ends = [_derivative_rows(len(conds), 0.0, highest) @ inverse, _derivative_rows(len(conds), 1.0, highest) @ inverse]
        known = np.zeros(len(conds))
        columns = np.zeros((len(conds), n_unknown))
        for c, (order, where) in enumerate(conds):
            side = int(where)
            if order == 0:
                known[c] = m.s_a + (m.stroke if side else 0.0)
                continue
            given = m.start if side == 0 else m.end
            if given is not None:
                known[c] = m.span_deg**order * given[order]  # p⁽ᵏ⁾ = βᵏ·dᵏs/dxᵏ
            else:
                q = at_join[(p, side)]
                columns[c, column[(q, order)]] = (m.span_deg / lengths[q]) ** order  # βᵏ·w/Lᵏ
        weights.append([(rows @ known, rows @ columns) for rows in ends])
    matrix = np.zeros((n_unknown, n_unknown))
    rhs = np.zeros(n_unknown)
    row = 0
    for q, (left, right) in enumerate(joins):
        length, m_left, m_right = lengths[q], members[left].order, members[right].order
        sides = ((left, 1, m_left), (right, 0, m_right))
        for d in range(min(m_left, m_right) + 1, m_left + m_right + 1):
            # Lᵈ·dᵈs/dxᵈ of each side that does not take w_d as its own condition
            terms = [(length / members[p].span_deg) ** d * np.array(weights[p][side][1][d]) for p, side, m in sides
                     if d > m]
            fixed = [(length / members[p].span_deg) ** d * weights[p][side][0][d] for p, side, m in sides if d > m]
            if len(terms) == 2:  # both sides have it: continuous (L·left − L·right = 0)
                matrix[row] = terms[0] - terms[1]
                rhs[row] = fixed[1] - fixed[0]
            else:  # one side has it: it equals the shared w_d
                matrix[row] = terms[0]
                matrix[row, column[(q, d)]] -= 1.0
                rhs[row] = -fixed[0]
            row += 1
    solution: NDArray[np.float64] = np.zeros(0)
    if n_unknown:
        with np.errstate(all="ignore"):
            rows = np.max(np.abs(matrix), axis=1, keepdims=True)
            scaled = matrix / np.where(rows > 0, rows, 1.0)
            cols = np.max(np.abs(scaled), axis=0, keepdims=True)
            scaled = scaled / np.where(cols > 0, cols, 1.0)
            condition = np.linalg.cond(scaled)
        if not (np.isfinite(condition) and condition <= MAX_CONDITION and np.all(np.isfinite(rhs))):
            raise InvalidParameterError(
                "the conditions at the joins between these matched polynomials are (nearly) dependent, so no one "
                "spline meets them; give explicit end conditions to one of them or change the spans.")
        solution = np.asarray(np.linalg.solve(matrix, rhs), dtype=np.float64)
    out = []
    for p, m in enumerate(members):
        sides_out: list[dict[int, float]] = []
        for side, given in ((0, m.start), (1, m.end)):
            if given is not None:
                sides_out.append(dict(given))
                continue
            q = at_join[(p, side)]
            sides_out.append({order: float(solution[column[(q, order)]]) / lengths[q] ** order
                              for order in m.orders(side)})
        out.append((sides_out[0], sides_out[1]))
    return out


def matched_polynomial(member: Member, start: Mapping[int, float], end: Mapping[int, float]) -> tuple[Curve, float]:
    """The polynomial law of a member with its end conditions known.

    Parameters
    ----------
    member : Member
        Its span, start position and stroke.
    start, end : mapping
        Its conditions by order at both ends [mm or deg per deg^k].

    Returns
    -------
    (Curve, float)
        The law on T ∈ [0, 1] from :func:`polynomial_from_boundary`, normalised to run 0 → 1
        when the stroke is not 0 (gain = stroke), else in units of the largest condition
        βᵏ·|dᵏs/dxᵏ| (an out-and-back move) [-]; and its gain [mm or deg].

    Raises
    ------
    InvalidParameterError
        Conditions that do not determine a polynomial, or that are not finite.

    References
    ----------
    Norton, Cam Design and Manufacturing Handbook, ch. 3 (polynomials from boundary conditions).
    """
    beta = member.span_deg
    t_derivs = [{k: beta**k * v for k, v in cond.items()} for cond in (start, end)]
    gain = member.stroke
    if gain == 0:
        gain = max((abs(v) for cond in t_derivs for v in cond.values()), default=0.0) or 1.0
    if not (math.isfinite(gain) and all(math.isfinite(v) for cond in t_derivs for v in cond.values())):
        raise InvalidParameterError("the matched polynomial's end conditions are not finite numbers.")
    ends = []
    for s, cond in ((0.0, t_derivs[0]), (member.stroke / gain, t_derivs[1])):
        values: dict[str, float | None] = {"s": s}
        values.update({ORDER_KEYS[k]: v / gain for k, v in cond.items()})
        ends.append(values)
    return polynomial_from_boundary(ends[0], ends[1]), gain
