"""The contour downloads: CSV, plain "X Y Z" text, DXF.

All functions take the contour as x, y arrays in millimetres (the cam's own frame,
e.g. ``ProfileResult.x_mm, y_mm``). A repeated closing point (last = first within 1e-9 of the contour size, as from
``sample_profile`` over 0–360° with both ends) is dropped where a closed entity is
written, so a DXF polyline has one vertex per distinct point.

:data:`FORMATS` is the registry of contour downloads (:mod:`camcore.export` for all of them):
each entry names a format and gives its writer, media type, file name and a one-line
description. Everything that offers a download (the service's ``?format=`` values, answer
headers, the OpenAPI document) is read from it, so a new format is one entry here.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InvalidParameterError
from .registry import FileFormat

if TYPE_CHECKING:
    from ezdxf.document import Drawing


def _xy(x: ArrayLike, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    px = np.asarray(x, dtype=np.float64).reshape(-1)
    py = np.asarray(y, dtype=np.float64).reshape(-1)
    if px.shape != py.shape or px.size < 2:
        raise InvalidParameterError("x and y must have the same length, at least 2 points.")
    if not (np.all(np.isfinite(px)) and np.all(np.isfinite(py))):
        raise InvalidParameterError("The contour has non-finite coordinates.")
    return px, py


def _open(px: np.ndarray, py: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop a repeated closing point."""
    size = max(float(np.abs(px).max()), float(np.abs(py).max()), 1.0)
    if px.size > 2 and np.hypot(px[0] - px[-1], py[0] - py[-1]) <= 1e-9 * size:
        return px[:-1], py[:-1]
    return px, py


def contour_csv(
    x: ArrayLike, y: ArrayLike, cam_angle_deg: ArrayLike | None = None, with_z: bool = False
) -> str:
    """CSV text with a header: ``cam_angle_deg,x_mm,y_mm`` (``,z_mm`` = 0 with ``with_z``).

    Full float precision (``repr``), ``.`` as decimal mark, ``\\n`` line ends.

    Parameters
    ----------
    x, y : array_like
        Contour points in the cam's frame, same length, at least 2, finite [mm].
    cam_angle_deg : array_like, optional
        Cam angle of each point [deg]; written as the first column when given.
    with_z : bool
        Add a ``z_mm`` column of zeros (for CAD imports that want three coordinates).

    Returns
    -------
    str
        The CSV text, one row per point (a repeated closing point is kept).

    Raises
    ------
    InvalidParameterError
        Mismatched lengths, fewer than 2 points, non-finite coordinates, or a
        ``cam_angle_deg`` of another length.

    References
    ----------
    RFC 4180, "Common Format and MIME Type for Comma-Separated Values (CSV) Files" (header
    row, comma separators); Python documentation, ``repr`` of a float (the shortest string
    that reads back to the same float).
    """
    px, py = _xy(x, y)
    cols: list[tuple[str, Sequence[float]]] = []
    if cam_angle_deg is not None:
        a = np.asarray(cam_angle_deg, dtype=np.float64).reshape(-1)
        if a.shape != px.shape:
            raise InvalidParameterError("cam_angle_deg must have one value per contour point.")
        cols.append(("cam_angle_deg", a.tolist()))
    cols += [("x_mm", px.tolist()), ("y_mm", py.tolist())]
    if with_z:
        cols.append(("z_mm", [0.0] * px.size))
    lines = [",".join(name for name, _ in cols)]
    for row in zip(*(c for _, c in cols)):
        lines.append(",".join(repr(float(v)) for v in row))
    return "\n".join(lines) + "\n"


def contour_xyz(x: ArrayLike, y: ArrayLike, close: bool = True) -> str:
    """Plain "X Y Z" lines (space separated, z = 0, no header) for CAD "curve through
    points" import. With ``close`` the first point is repeated at the end (once).

    Parameters
    ----------
    x, y : array_like
        Contour points in the cam's frame, same length, at least 2, finite [mm]; a repeated
        closing point is dropped first.
    close : bool
        Repeat the first point at the end, so the imported curve closes.

    Returns
    -------
    str
        One ``x y 0.0`` line per point, full float precision (``repr``).

    Raises
    ------
    InvalidParameterError
        Mismatched lengths, fewer than 2 points or non-finite coordinates.

    References
    ----------
    Python documentation, ``repr`` of a float (shortest round-tripping string); the plain
    "X Y Z" text read by CAD "curve through XYZ points" imports (one point per line, no header).
    """
    px, py = _open(*_xy(x, y))
    if close:
        px, py = np.append(px, px[0]), np.append(py, py[0])
    return "".join(f"{float(a)!r} {float(b)!r} 0.0\n" for a, b in zip(px, py))


def contour_dxf(
    x: ArrayLike,
    y: ArrayLike,
    spline: bool = False,
    layer: str = "CAM",
    base_radius_mm: float | None = None,
) -> bytes:
    """DXF R2010 drawing in millimetres: a closed LWPOLYLINE through the contour points,
    optionally a closed SPLINE through the same fit points (layer ``<layer>_SPLINE``) and
    the base circle (layer ``<layer>_BASE``). The header's extents (``$EXTMIN/$EXTMAX``) and
    limits and the opening view (the ``*Active`` viewport) are the drawing's bounding box.

    Parameters
    ----------
    x, y : array_like
        Contour points in the cam's frame, same length, at least 2, finite [mm]; a repeated
        closing point is dropped (the polyline is closed by its flag).
    spline : bool
        Also write a closed SPLINE through the same points as fit points.
    layer : str
        Layer of the polyline; the spline and the base circle go on ``<layer>_SPLINE`` and
        ``<layer>_BASE``.
    base_radius_mm : float, optional
        Radius of a base circle about the cam centre to draw [mm]; none when omitted.

    Returns
    -------
    bytes
        The DXF file (UTF-8 text), units millimetres ($INSUNITS = 4, $MEASUREMENT = 1).

    Raises
    ------
    InvalidParameterError
        Mismatched lengths, fewer than 2 points or non-finite coordinates.

    References
    ----------
    Autodesk, DXF Reference (AutoCAD 2010): LWPOLYLINE (closed flag 70 = 1), SPLINE (fit
    points), CIRCLE, VPORT, header variables $INSUNITS, $MEASUREMENT, $EXTMIN/$EXTMAX and
    $LIMMIN/$LIMMAX; ezdxf documentation: ``ezdxf.new``, ``Modelspace.add_lwpolyline``,
    ``add_spline``, ``add_circle``, ``Layout.reset_extents``, ``ezdxf.zoom.window``.
    """
    import ezdxf
    from ezdxf import units

    px, py = _open(*_xy(x, y))
    doc = ezdxf.new("R2010")
    doc.units = units.MM
    doc.header["$MEASUREMENT"] = 1  # metric
    msp = doc.modelspace()
    doc.layers.add(layer)
    pts = list(zip(px.tolist(), py.tolist()))
    msp.add_lwpolyline(pts, format="xy", close=True, dxfattribs={"layer": layer})
    if spline:
        doc.layers.add(f"{layer}_SPLINE")
        fit = [(a, b, 0.0) for a, b in pts]
        fit.append(fit[0])
        sp = msp.add_spline(fit_points=fit, dxfattribs={"layer": f"{layer}_SPLINE"})
        sp.closed = True
    if base_radius_mm is not None:
        doc.layers.add(f"{layer}_BASE")
        msp.add_circle((0.0, 0.0), base_radius_mm, dxfattribs={"layer": f"{layer}_BASE"})
    _zoom_to_drawing(doc, px, py, base_radius_mm)
    stream = io.StringIO()
    doc.write(stream)
    return stream.getvalue().encode("utf-8")


def _zoom_to_drawing(doc: Drawing, px: np.ndarray, py: np.ndarray, base_radius_mm: float | None) -> None:
    """Extents, limits and the initial view of model space: the drawing's bounding box.

    ezdxf leaves ``$EXTMIN/$EXTMAX`` at ±1e20 (AutoCAD's "not known"); a reader that
    scales the drawing to the header extents (LibreOffice Draw) then shrinks it to one
    point and shows a blank page. The box is that of the contour points and the base
    circle; the spline through the same points bulges past them by about the sagitta
    between neighbouring points (~1e-4 mm at 721 points), which matters to no zoom, while
    ezdxf's own spline bounding box costs ~45 ms a drawing (4x the rest of the export).
    """
    from ezdxf import zoom
    from ezdxf.math import Vec2

    lo = [float(px.min()), float(py.min())]
    hi = [float(px.max()), float(py.max())]
    if base_radius_mm is not None:
        lo = [min(v, -base_radius_mm) for v in lo]
        hi = [max(v, base_radius_mm) for v in hi]
    msp = doc.modelspace()
    # ezdxf copies model space's extents and limits into $EXTMIN/$EXTMAX, $LIMMIN/$LIMMAX
    # when it writes; header values set directly would be overwritten
    msp.reset_extents((lo[0], lo[1], 0.0), (hi[0], hi[1], 0.0))
    msp.reset_limits((lo[0], lo[1]), (hi[0], hi[1]))
    # the "*Active" viewport: CAD programs open the file looking at the whole cam
    zoom.window(msp, Vec2(lo), Vec2(hi))


@dataclass(frozen=True)
class Contour:
    """What a download format may write: the contour and what is known about it.

    Attributes
    ----------
    x_mm, y_mm : numpy.ndarray
        The cam surface in the cam's frame [mm].
    cam_angle_deg : numpy.ndarray or None
        The cam angle of each point [deg].
    base_radius_mm : float or None
        The base circle's radius [mm], drawn where the format can draw it.
    """

    x_mm: np.ndarray
    y_mm: np.ndarray
    cam_angle_deg: np.ndarray | None = None
    base_radius_mm: float | None = None


def _write_dxf(c: Contour) -> bytes:
    return contour_dxf(c.x_mm, c.y_mm, spline=True, base_radius_mm=c.base_radius_mm)


def _write_xyz(c: Contour) -> bytes:
    return contour_xyz(c.x_mm, c.y_mm).encode()


def _write_csv(c: Contour) -> bytes:
    return contour_csv(c.x_mm, c.y_mm, c.cam_angle_deg, with_z=True).encode()


# Measured one at a time (camcore.work's reference machine): DXF 0.29 s at 2 000 points
# (ezdxf and its spline fit), 0.40 s at 1e4, 1.36 s at 4e4, 2.54 s at 6e4 (the fit grows
# faster than linearly); X Y Z text 1.0 µs and CSV 2.2 µs per point.
def _dxf_cost(points: int) -> float:
    return 0.3 + 3.5e-5 * points + 3e-10 * points ** 2


#: the download formats of a contour, by name (the order is the order users see)
FORMATS: dict[str, FileFormat[Contour]] = {f.name: f for f in (
    FileFormat("dxf", "application/dxf", "cam.dxf",
                  "AutoCAD 2010 DXF in mm: layer CAM a closed polyline through the points, CAM_SPLINE a fitted "
                  "spline, CAM_BASE the base circle", _write_dxf, _dxf_cost),
    FileFormat("xyz", "text/plain; charset=utf-8", "cam.xyz",
                  "one 'X Y Z' line per point (mm, z = 0, closed, no header) for CAD curve-through-points import",
                  _write_xyz, lambda points: 1.5e-6 * points),
    FileFormat("contour-csv", "text/csv; charset=utf-8", "cam_contour.csv",
                  "CSV with header cam_angle_deg,x_mm,y_mm,z_mm (z = 0) for spreadsheets and CMM software",
                  _write_csv, lambda points: 3.3e-6 * points),
)}


__all__ = ["FORMATS", "Contour", "contour_csv", "contour_dxf", "contour_xyz"]
