"""Residual vibration: the spectrum of a curve, an indexer's load, the spectrum chart."""
