"""Triangle meshes as binary STL, written directly (no kernel): for surfaces camcore samples itself.

The file is the 1989 specification's binary layout: an 80-byte header, the facet count as a
little-endian uint32, then 50 bytes per facet (normal and three vertices as float32, a zero
attribute word). Facet normals are the unit normals of the vertices' order (counter-clockwise
seen from outside); a degenerate facet gets the zero normal, which readers recompute.

References
----------
.. [1] 3D Systems, "StereoLithography Interface Specification" (1989): the binary STL.
"""

from __future__ import annotations

import numpy as np

from ..curves.base import FloatArray
from ..errors import LimitExceededError

FACET = np.dtype([("normal", "<f4", 3), ("vertices", "<f4", (3, 3)), ("attribute", "<u2")])


def mesh_stl(triangles: FloatArray, header: str = "camcore mesh", max_triangles: int | None = None,
             field: tuple[str | int, ...] = ()) -> bytes:
    """A triangle mesh as a binary STL.

    Parameters
    ----------
    triangles : ndarray
        Facets, shape (m, 3, 3): vertices counter-clockwise seen from outside [mm].
    header : str
        Up to 80 ASCII characters for the header (not starting with "solid", which marks an
        ASCII STL) [-].
    max_triangles : int, optional
        Refuse a mesh of more facets [-].
    field : tuple
        The request field a refusal names [-].

    Returns
    -------
    bytes
        The binary STL (84 + 50·m bytes).

    Raises
    ------
    LimitExceededError
        More than ``max_triangles`` facets.

    References
    ----------
    3D Systems (1989), binary STL.
    """
    tri = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
    if max_triangles is not None and tri.shape[0] > max_triangles:
        raise LimitExceededError("STL facets", tri.shape[0], max_triangles, field=field)
    text = header.encode("ascii")[:80]
    if text.lower().startswith(b"solid"):
        raise ValueError("a binary STL header must not start with 'solid'.")
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    facets = np.zeros(tri.shape[0], dtype=FACET)
    facets["normal"] = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    facets["vertices"] = tri
    return text.ljust(80, b" ") + np.uint32(tri.shape[0]).tobytes() + facets.tobytes()
