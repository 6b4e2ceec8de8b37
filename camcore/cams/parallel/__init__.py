"""Parallel (conjugate plate) indexing cams: the frames, layout and method are in
:mod:`camcore.cams.parallel.geometry`; each roller's exact envelope in :mod:`.envelope`; a plate's
exact contour traced in :mod:`.trace` (its solvers in :mod:`.crossings`, near points through the
cells of :mod:`.neighbours`) and written as points in :mod:`.polyline`; the plates' contacts and
checks in :mod:`camcore.cams.parallel.compute`; a plate's contour, or a cutter's path round it, as
lines and arcs in :mod:`.fit`.
"""

from .compute import (
    Contacts,
    ParallelChecks,
    ParallelResult,
    Plate,
    PlateChecks,
    plate_contour,
    sample_parallel,
    trace_factor,
)
from .geometry import ParallelCam, check_parallel_geometry, make_parallel_cam
from .polyline import CHORD_SHARE, ContourPoints, contour_points
from .trace import Piece, PlateContour, trace_plate

__all__ = ["CHORD_SHARE", "Contacts", "ContourPoints", "ParallelCam", "ParallelChecks", "ParallelResult", "Piece",
           "Plate", "PlateChecks", "PlateContour", "check_parallel_geometry", "contour_points", "make_parallel_cam",
           "plate_contour", "sample_parallel", "trace_factor", "trace_plate"]
