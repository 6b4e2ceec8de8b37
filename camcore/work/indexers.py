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
#: and per design, a law's bracketing grid scanned (per point) and Newton on its brackets (per
#: piece): measured 2026-11-27, 1 000 designs over points curves of 100, 1 000, 3 000 and 10 000
#: points, 0.37, 4.0, 3.8 and 4.8 ms per design (14.5-18.4 ns per grid point); ×1.5. The flat
#: SIZING_SWEEP_ROW_S alone had a 10 000-point curve's 4 000 speeds at 0.55 s, measured 4.4 s
SWEEP_GRID_POINT_S = 1.5 * 1.6e-8
SWEEP_PIECE_S = 1.5 * 1e-7


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


def sweep_row_s(pieces: int) -> float:
    """Seconds to size one design of a sweep along a law: its exact peaks (the law's grid
    scanned, Newton on the brackets) and figures.

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
    The measurements beside :data:`SIZING_SWEEP_ROW_S` and :data:`SWEEP_GRID_POINT_S`.
    """
    return max(SIZING_SWEEP_ROW_S, SWEEP_GRID_POINT_S * bracketing_points(pieces) + SWEEP_PIECE_S * pieces)


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
