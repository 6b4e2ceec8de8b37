"""Binary STL read by numpy (the layout of the 1989 specification), and a mesh's directed edges: the
tests of every STL camcore writes (the plate cam's solid, the roller-gear rib) read it this way."""

from __future__ import annotations

from collections import Counter

import numpy as np

FACET = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])


def read_stl(data: bytes) -> np.ndarray:
    """The facets of a binary STL, shape (n, 3, 3) [mm]; the count in the header must match."""
    count = int(np.frombuffer(data, "<u4", 1, 80)[0])
    assert len(data) == 84 + 50 * count
    return np.frombuffer(data, dtype=FACET, count=count, offset=84)["v"].astype(np.float64)


def directed_edges(facets: np.ndarray, decimals: int | None = 4) -> Counter[tuple[tuple[float, ...], ...]]:
    """How often each directed edge (vertex → next vertex of a facet) occurs; vertices named by their
    coordinates rounded to ``decimals`` (None: as written). A closed, consistently oriented mesh has
    each directed edge once and its reverse once."""
    keys = facets if decimals is None else np.round(facets, decimals)
    edges: Counter[tuple[tuple[float, ...], ...]] = Counter()
    for a, b in ((0, 1), (1, 2), (2, 0)):
        for p, q in zip(map(tuple, keys[:, a].tolist()), map(tuple, keys[:, b].tolist()), strict=True):
            edges[(p, q)] += 1
    return edges
