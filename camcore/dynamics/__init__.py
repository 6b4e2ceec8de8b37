"""Follower dynamics: the residual vibration of a cam curve on a flexible follower
(:mod:`.vibration`) and of an indexer's load on an elastic drive train (:mod:`.indexer`)."""

from .indexer import IndexerVibration, VibrationTable, indexer_vibration
from .vibration import TAU_MAX, TAU_MIN, FollowerResponse, ResidualVibration, residual_amplitude, residual_vibration

__all__ = ["TAU_MAX", "TAU_MIN", "FollowerResponse", "IndexerVibration", "ResidualVibration", "VibrationTable",
           "indexer_vibration", "residual_amplitude", "residual_vibration"]
