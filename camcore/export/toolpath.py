"""Toolpath files: G-code for a CNC control, DXF of lines and arcs for CAM software.

G-code (ISO 6983 / RS-274 words, as Fanuc, Haas, LinuxCNC and Siemens in ISO mode read them):
``G17 G21 G90 G94 G40`` (XY plane, mm, absolute, feed per minute, no cutter compensation: the
program is the cutter *centre*), then per path: ``G0`` to the safe height and to the lead-in
point, ``G1`` down to the cutting depth at the feed, a straight lead-in along the normal onto
the path's start, the path itself (``G1`` lines, ``G2`` clockwise and ``G3`` counter-clockwise
arcs with the centre as ``I J``, incremental from the arc's start, the standard arc-centre
mode), the same straight line back out, and ``G0`` up; ``M30`` at the end. Coordinates are
written to 1e-6 mm. The spindle and coolant are left to the operator (a comment says so).

DXF (R2010, mm): one layer per path (``TOOLPATH_SURFACE``, ``TOOLPATH_OUTER_WALL``) of LINE and
ARC entities, the lead-ins on ``TOOLPATH_LEAD``; the header's extents are the drawing's
real bounding box (the arcs' extreme points included).

References
----------
.. [1] ISO 6983-1:2009, Automation systems and integration — Numerical control of machines —
   Program format and definitions of address words (G00-G03, G17, G21, G90, G94; I, J, F).
.. [2] NIST RS274/NGC Interpreter, version 3 (T. Kramer et al., NISTIR 6556, 2000): arc
   centre format, I and J offsets from the current point.
.. [3] Autodesk, DXF Reference (AutoCAD 2010): LINE, ARC (counter-clockwise from the start
   angle to the end angle, in degrees), $EXTMIN/$EXTMAX.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass

import numpy as np

from ..toolpath import CutterPath, Element, Toolpath
from .contour import _zoom_to_drawing
from .registry import FileFormat


@dataclass(frozen=True)
class ToolpathFile:
    """What a toolpath file writes: the paths and how the machine runs them.

    Attributes
    ----------
    toolpath : Toolpath
        The fitted paths (camcore.toolpath).
    feed_mm_min : float
        Cutting feed [mm/min].
    safe_z_mm, cut_z_mm : float
        Height of rapid moves and cutting depth [mm].
    lead_in_mm : float or None
        Length of the straight lead-in along the normal; None: each path's free room
        (:attr:`CutterPath.lead_in_mm`) [mm].
    """

    toolpath: Toolpath
    feed_mm_min: float = 300.0
    safe_z_mm: float = 5.0
    cut_z_mm: float = 0.0
    lead_in_mm: float | None = None


def lead_point(path: CutterPath, lead_in_mm: float | None) -> tuple[float, float]:
    """Where the lead-in starts: off the path's start along the normal, on the tool's free side.

    The tool runs with the wall on its right (climb milling with M3), so the free side is
    on the left of the direction of travel.

    Parameters
    ----------
    path : CutterPath
        The path.
    lead_in_mm : float or None
        The lead-in's length; None: the path's own ``lead_in_mm`` [mm].

    Returns
    -------
    (float, float)
        The point (x, y) [mm].

    References
    ----------
    ISO 6983-1 (a straight approach move, G01, before the contour); climb milling: the
    cutter to the left of the contour (as G41) with a clockwise spindle.
    """
    first = path.elements[0]
    tx, ty = _start_tangent(first)
    length = path.lead_in_mm if lead_in_mm is None else lead_in_mm
    return first.start[0] - ty * length, first.start[1] + tx * length


def _start_tangent(e: Element) -> tuple[float, float]:
    if e.centre is None:
        dx, dy = e.end[0] - e.start[0], e.end[1] - e.start[1]
    else:
        rx, ry = e.start[0] - e.centre[0], e.start[1] - e.centre[1]
        dx, dy = (-ry, rx) if e.ccw else (ry, -rx)
    norm = math.hypot(dx, dy)
    return dx / norm, dy / norm


def _num(v: float) -> str:
    """A coordinate to 1e-6 mm, without trailing zeros (``12.5``, ``-0.000001``, ``0``)."""
    text = f"{v:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def toolpath_gcode(file: ToolpathFile) -> str:
    """The toolpath as a G-code program (module notes for the words used).

    Parameters
    ----------
    file : ToolpathFile
        The paths, the feed [mm/min], the safe height and cutting depth [mm] and the lead-in.

    Returns
    -------
    str
        The program, one block per line, ``%`` at both ends.

    References
    ----------
    ISO 6983-1:2009 (G00-G03, G17, G21, G90, G94, I, J, F, M30); NIST RS274/NGC (NISTIR 6556),
    arc centre offsets I, J from the arc's start.
    """
    tp = file.toolpath
    lines = ["%", (f"(camcore toolpath: side {tp.side}, tool radius {_num(tp.tool_radius_mm)} mm, tolerance "
                  f"{_num(tp.tolerance_mm)} mm, measured deviation {tp.max_deviation_mm:.3g} mm, "
                  f"{tp.segments_count} elements)"),
             "(cutter centre path: no cutter compensation, climb milling with a clockwise spindle)",
             "(start the spindle and coolant before running)",
             "G17 G21 G90 G94 G40"]
    feed = _num(file.feed_mm_min)
    for k, path in enumerate(tp.paths, start=1):
        lx, ly = lead_point(path, file.lead_in_mm)
        x0, y0 = path.elements[0].start
        lines += [(f"(path {k}: {path.wall}, tool {path.side}, {'clockwise' if path.clockwise else 'counter-clockwise'},"
                  f" {len(path.elements)} elements, deviation {path.max_deviation_mm:.3g} mm)"),
                  f"G0 Z{_num(file.safe_z_mm)}", f"G0 X{_num(lx)} Y{_num(ly)}", f"G1 Z{_num(file.cut_z_mm)} F{feed}",
                  f"G1 X{_num(x0)} Y{_num(y0)} (lead-in)"]
        for e in path.elements:
            ex, ey = e.end
            if e.centre is None:
                lines.append(f"G1 X{_num(ex)} Y{_num(ey)}")
            else:
                i, j = e.centre[0] - e.start[0], e.centre[1] - e.start[1]
                lines.append(f"{'G3' if e.ccw else 'G2'} X{_num(ex)} Y{_num(ey)} I{_num(i)} J{_num(j)}")
        lines += [f"G1 X{_num(lx)} Y{_num(ly)} (lead-out)", f"G0 Z{_num(file.safe_z_mm)}"]
    lines += ["M30", "%"]
    return "\n".join(lines) + "\n"


def toolpath_dxf(file: ToolpathFile) -> bytes:
    """The toolpath as a DXF drawing of LINE and ARC entities in mm (module notes).

    Parameters
    ----------
    file : ToolpathFile
        The paths and the lead-in (feed and heights are not drawn).

    Returns
    -------
    bytes
        The DXF file (UTF-8 text), units millimetres, extents the drawing's bounding box.

    References
    ----------
    Autodesk, DXF Reference (AutoCAD 2010): LINE, ARC (counter-clockwise from start to end
    angle), $INSUNITS; ezdxf documentation: ``add_line``, ``add_arc``.
    """
    import ezdxf
    from ezdxf import units

    doc = ezdxf.new("R2010")
    doc.units = units.MM
    doc.header["$MEASUREMENT"] = 1  # metric
    msp = doc.modelspace()
    doc.layers.add("TOOLPATH_LEAD")
    pts: list[tuple[float, float]] = []
    for path in file.toolpath.paths:
        layer = "TOOLPATH_" + path.wall.upper().replace("-", "_")
        if layer not in doc.layers:
            doc.layers.add(layer)
        for e in path.elements:
            pts += e.extreme_points()
            if e.centre is None:
                msp.add_line(e.start, e.end, dxfattribs={"layer": layer})
                continue
            a0 = math.degrees(math.atan2(e.start[1] - e.centre[1], e.start[0] - e.centre[0]))
            a1 = math.degrees(math.atan2(e.end[1] - e.centre[1], e.end[0] - e.centre[0]))
            # a DXF arc runs counter-clockwise: a clockwise element is drawn from its end to its start
            start, end = (a0, a1) if e.ccw else (a1, a0)
            msp.add_arc(e.centre, e.radius_mm, start, end, dxfattribs={"layer": layer})
        lead = lead_point(path, file.lead_in_mm)
        if math.dist(lead, path.elements[0].start) > 0:
            msp.add_line(lead, path.elements[0].start, dxfattribs={"layer": "TOOLPATH_LEAD"})
            pts.append(lead)
    xy = np.array(pts)
    _zoom_to_drawing(doc, xy[:, 0], xy[:, 1], None)
    stream = io.StringIO()
    doc.write(stream)
    return stream.getvalue().encode("utf-8")


def _write_gcode(file: ToolpathFile) -> bytes:
    return toolpath_gcode(file).encode()


# Measured (camcore.work's reference machine): G-code ~4 µs per element; DXF 25 ms plus ~40 µs
# per element (ezdxf); ×2
def _dxf_cost(elements: int) -> float:
    return 2 * (0.025 + 4e-5 * elements)


#: toolpath downloads, by name; ``cost(elements)``
TOOLPATH_FORMATS: dict[str, FileFormat[ToolpathFile]] = {f.name: f for f in (
    FileFormat("gcode", "text/x-gcode; charset=utf-8", "cam_toolpath.nc",
               "G-code (G17 G21 G90, G0/G1/G2/G3 with I J, F): the cutter-centre path with a straight lead-in",
               _write_gcode, lambda elements: 2 * 4e-6 * elements),
    FileFormat("dxf", "application/dxf", "cam_toolpath.dxf",
               "AutoCAD 2010 DXF in mm: the cutter-centre path as LINE and ARC entities, one layer per wall",
               toolpath_dxf, _dxf_cost),
)}
