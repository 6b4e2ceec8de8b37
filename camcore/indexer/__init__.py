"""Cam indexers: kinematics over the input angle (:mod:`.kinematics`), the load
(:mod:`.load`), torque and power sizing (:mod:`.sizing`); results in :mod:`.results`."""

from .kinematics import Indexer, accuracy_mm
from .load import G, Load, LoadPart
from .results import IndexerMotion, IndexerPosition, MotionSummary, MotionTable, Sizing
from .sizing import size

__all__ = [
    "G", "Indexer", "IndexerMotion", "IndexerPosition", "Load", "LoadPart", "MotionSummary",
    "MotionTable", "Sizing", "accuracy_mm", "size",
]
