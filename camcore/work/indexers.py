"""Indexers: the motion table, positions, sizing and its sweep."""

from __future__ import annotations

#: columns of the motion table and of a position answer (angles, times, ω, α, jerk…)
MOTION_COLUMNS = 8
#: one row of the motion table or one position beyond the curve's own evaluation: angle
#: and time scaling (measured 0.5 µs per row at 2e5 rows), ×1.5
INDEXER_ROW_S = 1.5 * 5e-7
#: one RMS integral over one law (every piece's Gauss-Legendre nodes in one evaluation, the
#: kinks bracketed on one grid): measured 0.15 ms for MS and MCV50 and 33 ms for a 10 000-point
#: curve (3.3 µs per piece); ×1.5
RMS_INTEGRAL_S = 1.5 * 1.5e-4
RMS_PER_PIECE_S = 1.5 * 3.5e-6
#: the exact peaks of the power balance (one grid of the curve, Newton on the brackets):
#: measured 0.45 ms for MS, plus the grid's law evaluations (V, A, J: three per point); ×1.5
PEAKS_S = 1.5 * 4.5e-4
#: pieces of a catalog or universal law at most (a points curve has one per point)
MOST_PIECES_OF_A_LAW = 9
#: one sized design of a sweep: measured 34-70 µs per combination (1-4 curves, 500-32 000 rows); ×1.5
SIZING_SWEEP_ROW_S = 1.5 * 7e-5


def bracketing_points(pieces: int) -> int:
    """Points of the bracketing grid over a law.

    Parameters
    ----------
    pieces : int
        Smooth pieces of the law [-].

    Returns
    -------
    int
        Grid points [-].

    References
    ----------
    camcore.curves.extrema (the grid it brackets every extreme on).
    """
    return min(pieces * 257, 2**18 + 17 * pieces)


def peaks_s(pieces: int, sample_s: float) -> float:
    """Seconds to find the exact torque peaks of a law: V, A and J at every point of its
    bracketing grid, then Newton on the brackets.

    Parameters
    ----------
    pieces : int
        Smooth pieces of the law [-].
    sample_s : float
        The law's cost per evaluated time [s].

    Returns
    -------
    float
        [s].

    References
    ----------
    The measurements beside :data:`PEAKS_S`.
    """
    return PEAKS_S + 1.5 * 3 * bracketing_points(pieces) * sample_s


def rms_s(pieces: int) -> float:
    """Seconds of one RMS integral of the input torque over a law.

    Parameters
    ----------
    pieces : int
        Smooth pieces of the law [-].

    Returns
    -------
    float
        [s].

    References
    ----------
    The measurements beside :data:`RMS_INTEGRAL_S`.
    """
    return RMS_INTEGRAL_S + RMS_PER_PIECE_S * pieces
