"""The largest deviation |X| during the motion: the samples at the nodes, refined at turning points.

X is known at every node of every subcell (≥ 60 per natural period). Between two nodes δ
apart, a maximum of |X| rises above the nearer node by at most X''·(δ/2)²/2 = X''·δ²/8; the
intervals where X' changes sign and whose larger |X| comes within twice that bound of the
largest sample hold every maximum that could beat it. On each (the :data:`MAX_CANDIDATES`
highest per τ), X' = 0 is solved by Newton's iteration on the closed form of X
(_response.state_at), kept inside the interval, bisecting when a step would leave it, to
the spacing of floating-point numbers. At the root the value is exact to the rounding of X,
since an error ε in the position changes |X| by X''·ε²/2 only.

References
----------
.. [1] W. H. Press et al., *Numerical Recipes*, 3rd ed. (2007), §9.4: Newton–Raphson
   safeguarded by bisection (rtsafe).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from . import _chebyshev as cheb
from ._forcing import Forcing
from ._response import MAX_CANDIDATES, NEWTON_STEPS, Solution, series, state_at

FloatArray = NDArray[np.float64]
IndexArray = NDArray[np.intp]
_EPS = float(np.finfo(float).eps)


def peak_deviation(solution: Solution, forcing: Forcing) -> FloatArray:
    """max |X| over u ∈ [0, 1] for each τ value of the solution [-]."""
    x, xd = solution.deviation()
    batch = x.shape[0]
    size = np.abs(x)
    sampled = size.reshape(batch, -1).max(axis=1)
    d, sub = solution.damping, solution.sub
    xdd = (-sub.accel[None] - 2.0 * d.zeta_omega[:, None, None] * xd - d.omega[:, None, None] ** 2 * x)
    spacing = float(sub.half.max() * np.diff(cheb.LOBATTO).max())
    bound = np.abs(xdd).reshape(batch, -1).max(axis=1) * spacing**2 / 4.0  # twice X''·δ²/8
    turns = xd[..., :-1] * xd[..., 1:] < 0  # a zero at a node is a sample already
    top = np.maximum(size[..., :-1], size[..., 1:])
    near = top >= (sampled - bound)[:, None, None]
    score = np.where(turns & near, top, -np.inf).reshape(batch, -1)
    keep = min(MAX_CANDIDATES, score.shape[1])
    pick = np.argpartition(-score, keep - 1, axis=1)[:, :keep]
    rows = np.repeat(np.arange(batch), keep)
    flat = pick.ravel()
    real = np.isfinite(score[rows, flat])
    rows, flat = rows[real], flat[real]
    if rows.size == 0:
        return sampled
    cell, node = np.divmod(flat, cheb.NODES - 1)
    refined = _turning_values(solution, forcing, rows, cell, node, xd[rows, cell, node])
    out = sampled.copy()
    np.maximum.at(out, rows, refined)
    return out


def _turning_values(solution: Solution, forcing: Forcing, rows: IndexArray, cell: IndexArray, node: IndexArray,
                    slope_lo: FloatArray) -> FloatArray:
    """|X| where X' = 0 between nodes ``node`` and ``node + 1`` (X' changes sign there)."""
    coefficients = series(solution, rows, cell)
    half = solution.sub.half[cell]
    lo = cheb.LOBATTO[node].copy()
    hi = cheb.LOBATTO[node + 1].copy()
    s = (lo + hi) / 2.0
    x, xd, xdd = state_at(solution, forcing, rows, cell, coefficients, s)
    active = np.ones(s.shape, dtype=bool)
    rising = slope_lo > 0
    for _ in range(NEWTON_STEPS):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        below = (xd[idx] > 0) == rising[idx]  # the root lies above s
        lo[idx] = np.where(below, s[idx], lo[idx])
        hi[idx] = np.where(below, hi[idx], s[idx])
        with np.errstate(divide="ignore", invalid="ignore"):
            step = -xd[idx] / (xdd[idx] * half[idx])
        new = s[idx] + step
        outside = ~(np.isfinite(new) & (new > lo[idx]) & (new < hi[idx]))
        new = np.where(outside, (lo[idx] + hi[idx]) / 2.0, new)
        settled = (xd[idx] == 0) | (np.abs(new - s[idx]) <= 2 * _EPS) | (hi[idx] - lo[idx] <= 4 * _EPS)
        move = idx[~settled]
        active[idx[settled]] = False
        if move.size:
            s[move] = new[~settled]
            x[move], xd[move], xdd[move] = state_at(solution, forcing, rows[move], cell[move], coefficients[move],
                                                    s[move])
    result: FloatArray = np.abs(x)
    return result
