"""Several plates' contours in one drawing: a parallel indexing cam's plates as DXF.

Each plate is a closed LWPOLYLINE through its contour's points on a layer of its own
(``PLATE_0``, ``PLATE_1``, …), all in the cam's frame about the cam axis (the plates stand on
one another along it; a CAD user shows one layer at a time). The header's extents
(``$EXTMIN/$EXTMAX``) and limits and the opening view are the drawing's real bounding box, as
for a single contour (:mod:`.contour`: LibreOffice scales a drawing to the header's extents).

:data:`PLATE_FORMATS` is the registry of these downloads (:mod:`camcore.export`).

References
----------
.. [1] Autodesk, DXF Reference (AutoCAD 2010): LWPOLYLINE (closed flag 70 = 1), LAYER,
   $INSUNITS, $MEASUREMENT, $EXTMIN/$EXTMAX, $LIMMIN/$LIMMAX, VPORT.
"""

from __future__ import annotations

import io
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidParameterError
from .contour import _open, _xy, _zoom_to_drawing
from .registry import FileFormat

#: a plate's layer: PLATE_0, PLATE_1, …
LAYER = "PLATE_{}"


@dataclass(frozen=True)
class PlateDrawing:
    """Plates to draw: each one's contour as points in the cam's frame [mm], in order round it.

    Attributes
    ----------
    x_mm, y_mm : tuple of numpy.ndarray
        One array per plate: its closed contour (a repeated closing point is dropped).
    """

    x_mm: tuple[np.ndarray, ...]
    y_mm: tuple[np.ndarray, ...]

    @property
    def points(self) -> int:
        """The contours' points together [-]."""
        return sum(int(np.size(x)) for x in self.x_mm)


def plates_dxf(drawing: PlateDrawing) -> bytes:
    """The plates as a DXF R2010 drawing in millimetres, one layer and one closed LWPOLYLINE each.

    Parameters
    ----------
    drawing : PlateDrawing
        Each plate's contour [mm].

    Returns
    -------
    bytes
        The DXF file (UTF-8 text), units millimetres ($INSUNITS = 4, $MEASUREMENT = 1), the
        extents the contours' bounding box.

    Raises
    ------
    InvalidParameterError
        No plate, or a contour with mismatched coordinates, fewer than 2 points or non-finite ones.

    References
    ----------
    Autodesk, DXF Reference (AutoCAD 2010): LWPOLYLINE, LAYER, the header's extents; ezdxf
    documentation: ``ezdxf.new``, ``Modelspace.add_lwpolyline``, ``Layout.reset_extents``.
    """
    import ezdxf
    from ezdxf import units

    if not drawing.x_mm or len(drawing.x_mm) != len(drawing.y_mm):
        raise InvalidParameterError("a drawing of plates needs one contour (x and y) per plate.")
    doc = ezdxf.new("R2010")
    doc.units = units.MM
    doc.header["$MEASUREMENT"] = 1  # metric
    msp = doc.modelspace()
    all_x, all_y = [], []
    for p, (x, y) in enumerate(zip(drawing.x_mm, drawing.y_mm)):
        px, py = _open(*_xy(x, y))
        layer = LAYER.format(p)
        doc.layers.add(layer, color=1 + p % 7)
        msp.add_lwpolyline(list(zip(px.tolist(), py.tolist())), format="xy", close=True, dxfattribs={"layer": layer})
        all_x.append(px)
        all_y.append(py)
    _zoom_to_drawing(doc, np.concatenate(all_x), np.concatenate(all_y), None)
    stream = io.StringIO()
    doc.write(stream)
    return stream.getvalue().encode("utf-8")


# Measured (camcore.work's reference machine, the largest of 3 runs): 3 plates of 1 000 to 20 000
# points each, 33 ms at 3 000 points, 90 ms at 6 000, 235 ms at 18 000, 1.18 s at 60 000 (ezdxf's
# LWPOLYLINE, ~10 µs a point to add and as much to write, a little more than linear); ×2
def _dxf_cost(points: int) -> float:
    return 2 * (0.01 + 1.5e-5 * points + 1e-10 * points**2)


#: the downloads of several plates' contours, by name; ``cost(points)``
PLATE_FORMATS: dict[str, FileFormat[PlateDrawing]] = {f.name: f for f in (
    FileFormat("dxf", "application/dxf", "parallel_cam.dxf",
               "AutoCAD 2010 DXF in mm: each plate's contour a closed polyline of exact points (within 1e-4 of the "
               "roller radius of the exact contour), on its own layer PLATE_0, PLATE_1, …", plates_dxf, _dxf_cost),
)}


__all__ = ["LAYER", "PLATE_FORMATS", "PlateDrawing", "plates_dxf"]
