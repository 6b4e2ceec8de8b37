"""Distances from points to a closed polyline through many points, for the tests that check a curve
against a dense sampling of it (scipy's k-d tree finds the candidates, numpy the exact distances)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree


def distance_to_ring(points: np.ndarray, ring: np.ndarray, nearest: int = 16) -> np.ndarray:
    """Each point's distance from the closed polyline ``ring`` (n × 2, closed from its last point back
    to its first): to the segments on either side of its ``nearest`` nearest vertices. The polyline is
    dense next to the distances asked, so its nearest point is on one of them; at a corner the
    nearest vertex may lie on the other side of it, the nearest segment among the next ones."""
    _, near = cKDTree(ring).query(points, k=nearest)
    n = len(ring)
    best = np.full(len(points), np.inf)
    for k in np.atleast_2d(near.T):
        for a, b in ((k - 1) % n, k), (k, (k + 1) % n):
            p0, p1 = ring[a], ring[b]
            seg = p1 - p0
            u = np.clip(np.einsum("ij,ij->i", points - p0, seg) / np.einsum("ij,ij->i", seg, seg), 0.0, 1.0)
            best = np.minimum(best, np.hypot(*(points - p0 - u[:, None] * seg).T))
    return best
