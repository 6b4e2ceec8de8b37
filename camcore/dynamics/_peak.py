"""The largest deviation |X| during the motion: the samples at the nodes, refined at turning points.

X is known at every node of every subcell (≥ 30 per natural period). Between two nodes δ
apart, a maximum of |X| rises above the nearer node by at most X''·(δ/2)²/2 = X''·δ²/8; the
intervals where X' changes sign and whose larger |X| comes within twice that bound of the
largest sample hold every maximum that could beat it. On each (the :data:`MAX_CANDIDATES`
highest per τ), X' = 0 is solved by Newton's iteration on the closed form of X
(_response.state_at), kept inside the interval (a false-position step where Newton's would
leave it), until a step or the interval is below 1e-12 of the subcell. The value is then exact
to the rounding of X, since an error ε in the position changes |X| by X''·ε²/2 only.

References
----------
.. [1] W. H. Press et al., *Numerical Recipes*, 3rd ed. (2007), §9.2 (false position), §9.4
   (Newton–Raphson kept inside a bracket, rtsafe).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from . import _chebyshev as cheb
from ._forcing import Forcing
from ._response import MAX_CANDIDATES, NEWTON_STEPS, Solution, series, state_at

FloatArray = NDArray[np.float64]
IndexArray = NDArray[np.intp]


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
    refined = _turning_values(solution, forcing, rows, cell, node, (xd[rows, cell, node], xd[rows, cell, node + 1]))
    out = sampled.copy()
    np.maximum.at(out, rows, refined)
    return out


def _turning_values(solution: Solution, forcing: Forcing, rows: IndexArray, cell: IndexArray, node: IndexArray,
                    slope: tuple[FloatArray, FloatArray]) -> FloatArray:
    """|X| where X' = 0 between nodes ``node`` and ``node + 1`` (X' changes sign there: ``slope``
    holds X' at both)."""
    coefficients = series(solution, rows, cell)
    half = solution.sub.half[cell]
    lo, hi = cheb.LOBATTO[node].copy(), cheb.LOBATTO[node + 1].copy()
    f_lo, f_hi = slope[0].copy(), slope[1].copy()
    s = lo - f_lo * (hi - lo) / (f_hi - f_lo)  # false position to start
    x, xd, xdd = state_at(solution, forcing, rows, cell, coefficients, s)
    active = np.ones(s.shape, dtype=bool)
    for _ in range(NEWTON_STEPS):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        below = (xd[idx] > 0) == (f_lo[idx] > 0)  # the root lies above s
        lo[idx], f_lo[idx] = np.where(below, s[idx], lo[idx]), np.where(below, xd[idx], f_lo[idx])
        hi[idx], f_hi[idx] = np.where(below, hi[idx], s[idx]), np.where(below, f_hi[idx], xd[idx])
        with np.errstate(divide="ignore", invalid="ignore"):
            new = s[idx] - xd[idx] / (xdd[idx] * half[idx])
        outside = ~(np.isfinite(new) & (new > lo[idx]) & (new < hi[idx]))
        # Newton leaves the bracket (the root next to a node, or X'' small): false position
        secant = lo[idx] - f_lo[idx] * (hi[idx] - lo[idx]) / (f_hi[idx] - f_lo[idx])
        new = np.where(outside, secant, new)
        # an error δ in s changes |X| by X''·(h·δ)²/2: 1e-12 is far below rounding
        settled = (xd[idx] == 0) | (np.abs(new - s[idx]) <= 1e-12) | (hi[idx] - lo[idx] <= 1e-12)
        move = idx[~settled]
        active[idx[settled]] = False
        if move.size:
            s[move] = np.clip(new[~settled], lo[move], hi[move])
            x[move], xd[move], xdd[move] = state_at(solution, forcing, rows[move], cell[move], coefficients[move],
                                                    s[move])
    result: FloatArray = np.abs(x)
    return result
