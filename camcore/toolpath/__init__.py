"""Toolpaths: the cutter-centre path of a plate cam's wall(s), fitted with lines and arcs.

Map: :mod:`.offset` (the exact offset curve from the lift's derivatives), :mod:`.geometry`
(lines, arcs, biarcs, distances), :mod:`.fit` (greedy biarc fitting), :mod:`.measure` (the
deviation measured both ways), :mod:`.compute` (walls, gouge and undercut checks, corners,
the closed paths).
Files: :data:`camcore.export.TOOLPATH_FORMATS` (G-code, DXF).
"""

from .compute import SIDES, CutterPath, Toolpath, compute_toolpath, concave_radius, walls
from .geometry import Element, biarc, path_area
from .offset import OffsetCurve, base_curve

__all__ = ["SIDES", "CutterPath", "Element", "OffsetCurve", "Toolpath", "base_curve", "biarc", "compute_toolpath",
           "concave_radius", "path_area", "walls"]
