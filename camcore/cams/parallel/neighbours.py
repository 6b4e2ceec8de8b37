"""Near points through a grid of square cells: the roller centres near a set of query points.

The reference points (roller centres) are sorted by cell once. A block of query points that lie
close together (a stretch of one envelope) then takes every reference point in the cells its
bounding box, widened by the reach, overlaps: a few slices of the sorted points, one per column
of cells, and a dense table of distances block × those points, without gathering pair by pair.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...curves.base import FloatArray

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

    def within_box(self, lo_x: float, lo_y: float, hi_x: float, hi_y: float) -> IntArray:
        """The reference points in the cells a box overlaps (a superset of those inside it), in no
        particular order.

        Parameters
        ----------
        lo_x, lo_y, hi_x, hi_y : float
            The box [mm].

        Returns
        -------
        ndarray
            Indices of reference points [-].

        References
        ----------
        J. L. Bentley, J. H. Friedman, "Data structures for range searching", ACM Computing
        Surveys 11 (1979) 397-409 (cells: fixed-radius near neighbours).
        """
        i0 = max(0, math.floor((lo_x - self.x0) / self.cell))
        i1 = min(self.nx - 1, math.floor((hi_x - self.x0) / self.cell))
        j0 = max(0, math.floor((lo_y - self.y0) / self.cell))
        j1 = min(self.ny - 1, math.floor((hi_y - self.y0) / self.cell))
        if i0 > i1 or j0 > j1:
            return np.zeros(0, dtype=np.intp)
        # one column of cells is one run of keys, so one slice of the sorted points
        parts = [self.order[self.start[i * self.ny + j0]:self.start[i * self.ny + j1 + 1]] for i in range(i0, i1 + 1)]
        return np.concatenate(parts)

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
