"""Files for CAD, CAM, spreadsheets and drives: one registry of formats per kind of thing written.

* :data:`FORMATS`: the contour as points (CSV, X Y Z text, DXF), :mod:`.contour`;
* :data:`SOLID_FORMATS`: the plate cam as a solid (STEP, STL) from the OpenCASCADE kernel, :mod:`.solid`;
* :data:`TOOLPATH_FORMATS`: the cutter-centre path (G-code, DXF of lines and arcs), :mod:`.toolpath`;
* :data:`MOTION_FORMATS`: a motion program as a servo drive's cam table (CSV), :mod:`.cam_table`;
* :func:`mesh_stl`: a triangle mesh camcore sampled itself (a roller-gear cam's rib) as STL, :mod:`.mesh`;
* :data:`PLATE_FORMATS`: a parallel cam's plates' contours (DXF, a layer each), :mod:`.plates`; their solids
  are :class:`ParallelPlatesSolid` (:mod:`.parallel_solid`), written by :data:`SOLID_FORMATS`.

Each entry is a :class:`FileFormat` (name, writer, media type, file name, description, cost);
the service reads its ``?format=`` values, answer headers and OpenAPI media types from these
registries, so a new format is one entry.
"""

from .cam_table import MOTION_FORMATS, CamTable, cam_table_csv
from .contour import FORMATS, Contour, contour_csv, contour_dxf, contour_xyz
from .mesh import mesh_stl
from .parallel_solid import ParallelPlatesSolid
from .plates import PLATE_FORMATS, PlateDrawing, plates_dxf
from .registry import FileFormat
from .solid import SOLID_FORMATS, KernelSolid, SolidCam, solid_step, solid_stl
from .toolpath import TOOLPATH_FORMATS, ToolpathFile, toolpath_dxf, toolpath_gcode

#: a contour download (the registry entry's older name)
ContourFormat = FileFormat

__all__ = [
    "FORMATS", "MOTION_FORMATS", "PLATE_FORMATS", "SOLID_FORMATS", "TOOLPATH_FORMATS", "CamTable", "Contour",
    "ContourFormat", "FileFormat", "KernelSolid", "ParallelPlatesSolid", "PlateDrawing", "SolidCam", "ToolpathFile",
    "cam_table_csv", "contour_csv", "contour_dxf", "contour_xyz", "mesh_stl", "plates_dxf", "solid_step", "solid_stl",
    "toolpath_dxf", "toolpath_gcode",
]
