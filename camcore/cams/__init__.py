"""Cam types beyond the plate cam: barrel (cylindrical), parallel indexing and roller-gear
(globoidal) cams. Each is one module here; they reuse the lifts of :mod:`camcore.profile.lift`
and the index laws of :mod:`camcore.indexer`.
"""

__all__: list[str] = []
