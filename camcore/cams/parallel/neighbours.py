"""Near points: reference points near query points, through a grid of square cells or along chains.

:class:`CellGrid` sorts the reference points (a polyline's vertices) by cell once; each query then
takes the points of the 3 × 3 cells round its own, pair by pair.

:class:`Chains` is for points that follow one another along closed paths (the roller centres at
the sampled cam angles, one chain per roller's path): it wants only where each chain passes
nearest a query. The points are cut into groups of neighbours along the chains, each held in a
ball (its middle point, out to its farthest); a block of queries that lie close together (a
stretch of one envelope) looks only into the groups whose ball comes within reach of one of them,
each with one point either side, and keeps the points no farther than their neighbours.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...curves.base import FloatArray
from ...deadline import checkpoint

IntArray = NDArray[np.intp]


class CellGrid:
    """Reference points sorted by square cells of side ``cell_mm``.

    Parameters
    ----------
    x, y : ndarray
        The reference points [mm].
    cell_mm : float
        The cell's side [mm].
    """

    def __init__(self, x: FloatArray, y: FloatArray, cell_mm: float):
        self.cell = float(cell_mm)
        self.x, self.y = np.asarray(x, dtype=np.float64).reshape(-1), np.asarray(y, dtype=np.float64).reshape(-1)
        self.x0 = float(self.x.min(initial=0.0))
        self.y0 = float(self.y.min(initial=0.0))
        self.nx = math.floor((float(self.x.max(initial=0.0)) - self.x0) / self.cell) + 1
        self.ny = math.floor((float(self.y.max(initial=0.0)) - self.y0) / self.cell) + 1
        key = (np.floor((self.x - self.x0) / self.cell).astype(np.intp) * self.ny
               + np.floor((self.y - self.y0) / self.cell).astype(np.intp))
        self.order = np.argsort(key, kind="stable").astype(np.intp)
        self.start = np.searchsorted(key[self.order], np.arange(self.nx * self.ny + 1)).astype(np.intp)

    def pairs(self, qx: FloatArray, qy: FloatArray) -> tuple[IntArray, IntArray]:
        """Every (query, reference) pair in neighbouring cells: all pairs closer than a cell, and some farther.

        Parameters
        ----------
        qx, qy : ndarray
            Query points [mm].

        Returns
        -------
        (ndarray, ndarray)
            The query's index and the reference point's index of each pair [-].

        References
        ----------
        Bentley and Friedman (1979), cells.
        """
        qx, qy = np.asarray(qx, dtype=np.float64).reshape(-1), np.asarray(qy, dtype=np.float64).reshape(-1)
        ix = np.floor((qx - self.x0) / self.cell)
        iy = np.floor((qy - self.y0) / self.cell)
        # a query more than a cell outside the grid has no reference point within a cell
        which = np.flatnonzero((ix >= -1) & (ix <= self.nx) & (iy >= -1) & (iy <= self.ny))
        ix, iy = ix[which].astype(np.intp), iy[which].astype(np.intp)
        owners, refs = [], []
        for di in (-1, 0, 1):
            col = ix + di
            ok = (col >= 0) & (col < self.nx)
            j0 = np.clip(iy - 1, 0, self.ny - 1)
            j1 = np.clip(iy + 1, 0, self.ny - 1)
            ok &= (iy + 1 >= 0) & (iy - 1 < self.ny)
            # the three cells of a column are one run of keys, so one slice of the sorted points
            lo = np.where(ok, self.start[np.clip(col, 0, self.nx - 1) * self.ny + j0], 0)
            hi = np.where(ok, self.start[np.clip(col, 0, self.nx - 1) * self.ny + j1 + 1], 0)
            counts = hi - lo
            total = int(counts.sum())
            ends = np.cumsum(counts)
            offset = np.arange(total) - np.repeat(ends - counts, counts)
            owners.append(np.repeat(which, counts))
            refs.append(self.order[np.repeat(lo, counts) + offset])
        return np.concatenate(owners).astype(np.intp), np.concatenate(refs).astype(np.intp)


def block_order(x: FloatArray, y: FloatArray, cell_mm: float) -> IntArray:
    """An order of points that keeps neighbours together (by cell, columns then rows), for blocks.

    Parameters
    ----------
    x, y : ndarray
        The points [mm].
    cell_mm : float
        The cell's side [mm].

    Returns
    -------
    ndarray
        A permutation of the points' indices [-].

    References
    ----------
    Bentley and Friedman (1979), cells.
    """
    ix = np.floor((x - x.min(initial=0.0)) / cell_mm).astype(np.intp)
    iy = np.floor((y - y.min(initial=0.0)) / cell_mm).astype(np.intp)
    # a snake through the columns: the next block starts where the last one ended
    iy = np.where(ix % 2 == 1, -iy, iy)
    return np.lexsort((iy, ix)).astype(np.intp)


#: points per group of a chain: a group's ball (round its middle point, out to its farthest) rules it
#: out for a query at one distance. Smaller groups rule out more but cost more balls to test: on the
#: README's plates 16 traced fastest (8 and 32 ~10 % slower, 4 took the passes 1.6 times as long)
GROUP = 16
#: queries per dense table of distances (block × the groups near the block): the walk asks at most
#: 256 points at a time, so one table a chunk
QUERY_BLOCK = 256


class Chains:
    """Runs of reference points (chains), in groups of GROUP neighbours along each, for the points
    of the chains that pass nearest a query.

    Parameters
    ----------
    x, y : ndarray
        The chains' points, chain after chain [mm].
    length : int
        Points per chain [-].
    reach : float
        The largest distance wanted from a query [mm].
    """

    def __init__(self, x: FloatArray, y: FloatArray, length: int, reach: float):
        self.x, self.y, self.length, self.reach = x, y, length, reach
        chains = x.size // length
        first = np.arange(0, length, GROUP)
        last = np.minimum(first + GROUP, length) - 1
        middle = (first + last) // 2
        cx, cy = x.reshape(chains, length), y.reshape(chains, length)
        members = np.minimum(first[:, None] + np.arange(GROUP), last[:, None])
        gx, gy = cx[:, middle], cy[:, middle]
        radius = np.hypot(cx[:, members] - gx[:, :, None], cy[:, members] - gy[:, :, None]).max(axis=2).reshape(-1)
        # the bound, widened by far more than the rounding of the distances it compares
        self.span = reach + radius + 1e-9 * (reach + radius)
        self.gx, self.gy = gx.reshape(-1), gy.reshape(-1)
        self.chain_start = np.repeat(np.arange(chains) * length, first.size)
        self.group_first = self.chain_start + np.tile(first, chains)

    def minima(self, qx: FloatArray, qy: FloatArray) -> tuple[IntArray, IntArray, FloatArray]:
        """Every point of the chains within reach of a query and no farther from it than its neighbours
        along its chain (a chain's ends have one neighbour each): where each chain passes nearest each
        query. A point m is returned for query q when d²(q, m) < reach² and d²(q, m) ≤ d²(q, m ± 1).

        Parameters
        ----------
        qx, qy : ndarray
            The queries [mm].

        Returns
        -------
        (ndarray, ndarray, ndarray)
            The query's index, the point's index and their squared distance [mm²], ordered by query
            block, then by the point's index for each query.

        References
        ----------
        Bentley and Friedman (1979), cells; the triangle inequality rules out a group of points whose
        ball stands off a query by more than the reach.
        """
        gx, gy, x, y, length, span = self.gx, self.gy, self.x, self.y, self.length, self.span
        window = np.arange(-1, GROUP + 1)
        reach2 = self.reach * self.reach
        order = block_order(qx, qy, self.reach) if qx.size > QUERY_BLOCK else np.arange(qx.size)
        found: list[tuple[IntArray, IntArray, FloatArray]] = []
        for b in range(0, qx.size, QUERY_BLOCK):
            checkpoint()
            idx = order[b:b + QUERY_BLOCK]
            bx, by = qx[idx], qy[idx]
            near = np.flatnonzero((gx + span >= bx.min()) & (gx - span <= bx.max())
                                  & (gy + span >= by.min()) & (gy - span <= by.max()))
            if near.size == 0:
                continue
            r, k = np.nonzero(np.hypot(gx[near] - bx[:, None], gy[near] - by[:, None]) < span[near])
            g = near[k]
            # each group with one point either side, a chain's ends standing beyond everything
            m = self.group_first[g][:, None] + window
            start = self.chain_start[g][:, None]
            inside = (m >= start) & (m < start + length)
            m = np.where(inside, m, self.group_first[g][:, None])
            d2 = (x[m] - bx[r][:, None]) ** 2 + (y[m] - by[r][:, None]) ** 2
            d2[~inside] = np.inf
            here = d2[:, 1:-1]
            keep = inside[:, 1:-1] & (here < reach2) & (here <= d2[:, :-2]) & (here <= d2[:, 2:])
            rows, cols = np.nonzero(keep)
            found.append((idx[r[rows]], m[rows, cols + 1], here[rows, cols]))
        if not found:
            empty = np.zeros(0, dtype=np.intp)
            return empty, empty, np.zeros(0)
        return (np.concatenate([f[0] for f in found]), np.concatenate([f[1] for f in found]),
                np.concatenate([f[2] for f in found]))
