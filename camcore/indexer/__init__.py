"""Cam indexers: kinematics over the input angle (:mod:`.kinematics`), indexers driven by a
timing chart (:mod:`.timing`), the load (:mod:`.load`), torque and power sizing
(:mod:`.sizing`); results in :mod:`.results`."""

from .drive import Motor, TorqueTable
from .kinematics import Indexer
from .load import G, Load, LoadPart
from .origin import INPUT_ANGLE_ORIGINS, origin_shift_deg, to_origin
from .results import IndexerMotion, IndexerPosition, MotionSummary, MotionTable, Sizing
from .sizing import accuracy_mm, size
from .timing import TimedIndexer, check_timing, check_timing_frame

__all__ = [
    "INPUT_ANGLE_ORIGINS",
    "G",
    "Indexer",
    "IndexerMotion",
    "IndexerPosition",
    "Load",
    "LoadPart",
    "MotionSummary",
    "MotionTable",
    "Motor",
    "Sizing",
    "TimedIndexer",
    "TorqueTable",
    "accuracy_mm",
    "check_timing",
    "check_timing_frame",
    "origin_shift_deg",
    "size",
    "to_origin",
]
