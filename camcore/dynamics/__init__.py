"""Follower dynamics: the residual vibration of a cam curve on a flexible follower
(:mod:`.vibration`) and of an indexer's load (:mod:`.indexer`)."""

from .vibration import TAU_MAX, TAU_MIN, FollowerResponse, ResidualVibration, residual_vibration

__all__ = ["TAU_MAX", "TAU_MIN", "FollowerResponse", "ResidualVibration", "residual_vibration"]
