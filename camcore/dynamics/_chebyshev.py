"""Chebyshev–Lobatto interpolation on [-1, 1]: nodes, the integral of the interpolant, Clenshaw.

A smooth function sampled at the N Chebyshev–Lobatto points s_i = −cos(πi/(N−1)) (ascending,
both ends included) is represented by the polynomial of degree N − 1 through the samples.
:data:`CUMULATIVE` maps the samples to that polynomial's integral from −1 to each node, and
:data:`INTEGRAL_COEFFICIENTS` to the Chebyshev coefficients of the integral (to evaluate it
anywhere with :func:`clenshaw`). For a function analytic near [-1, 1] the interpolant converges
geometrically (Trefethen, ch. 8), so with enough nodes both are exact to rounding.

References
----------
.. [1] L. N. Trefethen, *Approximation Theory and Approximation Practice* (SIAM, 2013),
   ch. 2-3 (Chebyshev points and series), ch. 8 (convergence for analytic functions),
   ch. 19 (Clenshaw–Curtis quadrature, integrating the interpolant).
.. [2] C. W. Clenshaw, "A note on the summation of Chebyshev series", Math. Tables Aids
   Comput. 9 (1955) 118-120.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import chebyshev as C
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


def lobatto_nodes(n: int) -> FloatArray:
    """The n Chebyshev–Lobatto points on [-1, 1], ascending, ends exact."""
    nodes = -np.cos(np.pi * np.arange(n) / (n - 1))
    nodes[0], nodes[-1] = -1.0, 1.0
    if n % 2:
        nodes[n // 2] = 0.0
    return nodes


def _matrices(n: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(values → coefficients, values → integral's coefficients, values → integral at the nodes)."""
    nodes = lobatto_nodes(n)
    vandermonde = C.chebvander(nodes, n - 1)  # [i, k] = T_k(s_i)
    to_coefficients = np.linalg.inv(vandermonde)
    # the integral from −1 of each T_k, as coefficients of degree n
    integrate = np.zeros((n + 1, n))
    for k in range(n):
        unit = np.zeros(n)
        unit[k] = 1.0
        integrate[:, k] = C.chebint(unit, lbnd=-1.0)
    integral_coefficients: FloatArray = integrate @ to_coefficients
    cumulative: FloatArray = C.chebvander(nodes, n) @ integral_coefficients
    return np.asarray(to_coefficients, dtype=np.float64), integral_coefficients, cumulative


#: nodes per interval of the response (see camcore.dynamics.response for why 32)
NODES = 32
LOBATTO = lobatto_nodes(NODES)
_, INTEGRAL_COEFFICIENTS, CUMULATIVE = _matrices(NODES)
#: the Clenshaw–Curtis weights: the last row of CUMULATIVE (the integral over [-1, 1])
WEIGHTS = CUMULATIVE[-1].copy()

#: nodes of the test that a piece of acceleration is resolved (degree 16)
RESOLVE_NODES = 17
RESOLVE_LOBATTO = lobatto_nodes(RESOLVE_NODES)
RESOLVE_COEFFICIENTS = _matrices(RESOLVE_NODES)[0]


def clenshaw(coefficients: ComplexArray, s: FloatArray) -> ComplexArray:
    """Σ_k c[..., k]·T_k(s) for each row of coefficients at its own s (Clenshaw's recurrence).

    ``coefficients`` has shape (m, K) and ``s`` shape (m,); the answer has shape (m,).
    """
    b1 = np.zeros(s.shape, dtype=coefficients.dtype)
    b2 = np.zeros(s.shape, dtype=coefficients.dtype)
    two_s = 2.0 * s
    for k in range(coefficients.shape[1] - 1, 0, -1):
        b1, b2 = coefficients[:, k] + two_s * b1 - b2, b1
    result: ComplexArray = coefficients[:, 0] + s * b1 - b2
    return result


def clenshaw_rows(table: ComplexArray, rows: NDArray[np.intp], s: FloatArray) -> ComplexArray:
    """Σ_k table[rows, k]·T_k(s): the series of row ``rows[i]`` of ``table`` at ``s[i]``, one
    column gathered at a time (no (points × terms) copy of the table)."""
    b1 = np.zeros(s.shape, dtype=table.dtype)
    b2 = np.zeros(s.shape, dtype=table.dtype)
    two_s = 2.0 * s
    for k in range(table.shape[1] - 1, 0, -1):
        b1, b2 = table[rows, k] + two_s * b1 - b2, b1
    result: ComplexArray = table[rows, 0] + s * b1 - b2
    return result
