"""Polynomial motion laws: S(T) = Σ c_k T^k on [0, 1].

Named laws: constant velocity (S = T), 3-4-5 (S = 10T³ − 15T⁴ + 6T⁵) and 4-5-6-7
(S = 35T⁴ − 84T⁵ + 70T⁶ − 20T⁷), and the law of least degree meeting any boundary
conditions on S, V, A, J at T = 0 and T = 1 (confluent Hermite interpolation).

References
----------
H. Makino, 自動機械機構学 (1976) — polynomial cam curves; R. L. Norton, Cam Design and
Manufacturing Handbook, ch. 3 (the 3-4-5 and 4-5-6-7 polynomials).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from fractions import Fraction

import numpy as np
from numpy.polynomial import Polynomial
from numpy.typing import NDArray

from ..errors import InvalidParameterError
from .base import FloatArray
from .curve import Curve

NAMED_POLYNOMIALS: dict[str, tuple[float, ...]] = {
    "3-4-5": (0.0, 0.0, 0.0, 10.0, -15.0, 6.0),
    "4-5-6-7": (0.0, 0.0, 0.0, 0.0, 35.0, -84.0, 70.0, -20.0),
    "constant-velocity": (0.0, 1.0),
}

_ORDER_KEYS = ("s", "v", "a", "j")


class PolynomialCurve(Curve):
    """S(T) = Σ c_k T^k on [0, 1], one smooth piece.

    Parameters
    ----------
    coefficients : sequence of float
        c_0, c_1, … in increasing powers of T.
    """

    def __init__(self, coefficients: Sequence[float] | FloatArray):
        coef = np.asarray(coefficients, dtype=np.float64)
        if coef.size == 0 or not np.all(np.isfinite(coef)):
            raise InvalidParameterError("polynomial coefficients must be finite numbers.")
        self.coefficients = coef
        self._polys = [Polynomial(coef)]
        for _ in range(4):
            self._polys.append(self._polys[-1].deriv())
        self.piece_starts = np.array([0.0])
        self.t_end = 1.0

    def eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        return [np.asarray(self._polys[k](t), dtype=np.float64) for k in range(order + 1)]


def named_polynomial(name: str) -> PolynomialCurve:
    """A named polynomial law.

    Parameters
    ----------
    name : str
        A key of :data:`NAMED_POLYNOMIALS`: ``constant-velocity`` (S = T), ``3-4-5``
        (S = 10T³ − 15T⁴ + 6T⁵) or ``4-5-6-7`` (S = 35T⁴ − 84T⁵ + 70T⁶ − 20T⁷).

    Returns
    -------
    PolynomialCurve
        S(T) on [0, 1], rising from 0 to 1.

    Raises
    ------
    KeyError
        For any other name (the service offers only these names).

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, ch. 3 (the 3-4-5 and 4-5-6-7
    polynomials); H. Makino, 自動機械機構学 (1976), polynomial cam curves.
    """
    return PolynomialCurve(NAMED_POLYNOMIALS[name])


def _singular(matrix: NDArray[np.float64]) -> bool:
    """Whether the square matrix of whole numbers is singular, decided exactly (fractions, not floats:
    rounding could hide a zero pivot and give a polynomial of huge coefficients instead)."""
    rows = [[Fraction(int(x)) for x in row] for row in matrix]
    n = len(rows)
    for col in range(n):
        pivot = next((r for r in range(col, n) if rows[r][col] != 0), None)
        if pivot is None:
            return True
        rows[col], rows[pivot] = rows[pivot], rows[col]
        for r in range(col + 1, n):
            factor = rows[r][col] / rows[col][col]
            rows[r] = [x - factor * y for x, y in zip(rows[r], rows[col], strict=True)]
    return False


def boundary_matrix(conditions: Sequence[tuple[int, float]]) -> NDArray[np.float64]:
    """The confluent Vandermonde matrix of boundary conditions on a polynomial.

    Parameters
    ----------
    conditions : sequence of (int, float)
        (order, T) of each condition: the order-th derivative [-] at T = 0 or 1 [-].

    Returns
    -------
    ndarray
        Row i holds d^order/dT^order of T^k at T for k = 0 … n − 1 [-]; the polynomial of
        degree n − 1 with coefficients c meets the conditions' values b when M·c = b.

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, ch. 3 (polynomial laws from boundary
    conditions).
    """
    n = len(conditions)
    matrix = np.zeros((n, n))
    for i, (order, where) in enumerate(conditions):
        for k in range(order, n):
            # d^order/dT^order of T^k at T = where
            matrix[i, k] = math.perm(k, order) * (where ** (k - order) if k > order else 1.0)
    return matrix


def polynomial_from_boundary(start: Mapping[str, float | None], end: Mapping[str, float | None]) -> PolynomialCurve:
    """The polynomial of least degree meeting the given end conditions.

    Parameters
    ----------
    start, end : mapping
        Values of ``s`` (required), ``v``, ``a``, ``j`` at T = 0 and T = 1, dimensionless
        [-]; a missing or None entry is free. The degree is the number of conditions minus one.

    Returns
    -------
    PolynomialCurve
        S(T) = Σ c_k T^k on [0, 1], the coefficients from the confluent Vandermonde system.

    Raises
    ------
    InvalidParameterError
        S missing at an end, a non-finite condition, or conditions that do not determine one
        polynomial (its equations not independent, e.g. J the only condition beyond S).

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, ch. 3 (polynomial laws from boundary
    conditions; 3-4-5 is s, v, a given at both ends); H. Makino, 自動機械機構学 (1976).
    """
    rows: list[NDArray[np.float64]] = []
    rhs: list[float] = []
    for where, cond in ((0.0, start), (1.0, end)):
        if cond.get("s") is None:
            raise InvalidParameterError("a polynomial law needs S at both ends.")
        for order, key in enumerate(_ORDER_KEYS):
            value = cond.get(key)
            if value is None:
                continue
            if not math.isfinite(float(value)):
                raise InvalidParameterError(f"boundary {key} at T = {where:g} must be finite.")
            rows.append(np.array([order, where]))
            rhs.append(float(value))
    n = len(rhs)
    matrix = boundary_matrix([(int(order), float(where)) for order, where in rows])
    if _singular(matrix):
        raise InvalidParameterError(
            f"these boundary conditions do not determine a polynomial of degree {n - 1}: its {n} equations are not "
            "independent (e.g. j the only condition beyond s); give lower-order conditions (v, a) too.")
    coef = np.linalg.solve(matrix, np.array(rhs))
    return PolynomialCurve(coef)


def check_choice(name: str | None, start: object, end: object) -> None:
    """A polynomial law is given by name, or by both end conditions, not both.

    Parameters
    ----------
    name : str or None
        A key of :data:`NAMED_POLYNOMIALS`.
    start, end : object
        End conditions at T = 0 and T = 1, or None.

    References
    ----------
    Norton, Cam Design and Manufacturing Handbook, ch. 3 (polynomial laws from boundary
    conditions).
    """
    if name is None and (start is None or end is None):
        raise InvalidParameterError("give a polynomial name, or both start and end boundary conditions")
    if name is not None and (start is not None or end is not None):
        raise InvalidParameterError("give a polynomial name or boundary conditions, not both")
