"""Cam types beyond the plate cam: barrel (cylindrical), parallel indexing and roller-gear
(globoidal) cams. Each is one module here; they reuse the lifts of :mod:`camcore.profile.lift`
and the index laws of :mod:`camcore.indexer`.
"""

from .barrel import BarrelCam, BarrelChecks, BarrelResult, barrel_profile, make_barrel_cam, sample_barrel
from .parallel import ParallelCam, ParallelChecks, ParallelResult, make_parallel_cam, sample_parallel

__all__: list[str] = [
    "BarrelCam",
    "BarrelChecks",
    "BarrelResult",
    "ParallelCam",
    "ParallelChecks",
    "ParallelResult",
    "barrel_profile",
    "make_barrel_cam",
    "make_parallel_cam",
    "sample_barrel",
    "sample_parallel",
]
