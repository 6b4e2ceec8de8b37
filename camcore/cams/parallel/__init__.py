"""Parallel (conjugate plate) indexing cams: the frames, layout and method are in
:mod:`camcore.cams.parallel.geometry`; the plates' sampling and checks in
:mod:`camcore.cams.parallel.compute`.
"""

from .compute import Contacts, ParallelChecks, ParallelResult, Plate, PlateChecks, sample_parallel
from .geometry import ParallelCam, check_parallel_geometry, make_parallel_cam

__all__ = ["Contacts", "ParallelCam", "ParallelChecks", "ParallelResult", "Plate", "PlateChecks",
           "check_parallel_geometry", "make_parallel_cam", "sample_parallel"]
