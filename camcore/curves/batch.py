"""Characteristic values of many curves at once (a design chart's grid).

The sections of every section curve are stacked side by side into one piecewise curve whose
pieces need not follow one another; :func:`camcore.curves.extrema.critical_points` brackets
and refines the peaks of all of them in one pass, and each curve's values are reduced from
the candidates on its own pieces. The bracketing grid is the one a curve gets alone (257
points per piece), so every value equals the curve's own :attr:`Curve.characteristics`.

References
----------
.. [1] Makino (1977), characteristic values and the design chart (fig. 3, appendix 3-2).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from .base import FloatArray, PiecewiseCurve
from .curve import Curve
from .extrema import _BRACKET_SAMPLES, characteristic_candidates
from .sections import SectionColumns, SectionCurve, eval_sections

#: the values :func:`characteristic_values` gives, as named on :class:`Characteristics`
VALUES = ("vm", "am_pos", "am_neg", "jm_pos", "jm_neg", "qm_pos", "qm_neg")

#: pieces stacked per pass: the most that keep the grid of a curve alone (2**18 grid points
#: over all pieces, 257 per piece; :func:`critical_points`)
_PIECES_PER_PASS = 2**18 // _BRACKET_SAMPLES


class _SectionStack(SectionColumns, PiecewiseCurve):
    """The sections of several section curves side by side (pieces in any order)."""

    def __init__(self, curves: Sequence[SectionCurve]):
        self.coefficients = np.concatenate([c.coefficients for c in curves], axis=1)
        self.piece_starts = np.concatenate([c.piece_starts for c in curves])
        self.piece_ends = np.concatenate([c.piece_ends for c in curves])
        self.t_end = float(self.piece_ends[-1])
        self.owner = np.repeat(np.arange(len(curves)), [c.n_pieces for c in curves])

    def eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        return eval_sections(self.coefficients, t, piece, order)


def _stacked_values(curves: Sequence[SectionCurve]) -> dict[str, FloatArray]:
    stack = _SectionStack(curves)
    # the rows of :func:`camcore.curves.extrema.characteristics`: peaks of S, V, A, J, A·V
    t_all, k_all = characteristic_candidates(stack)
    _, v, a, j = stack.eval_pieces(t_all, k_all, 3)
    owner = stack.owner[k_all]
    order = np.argsort(owner, kind="stable")
    starts = np.searchsorted(owner[order], np.arange(len(curves)))
    top = {name: np.maximum.reduceat(x[order], starts) for name, x in (("v", v), ("a", a), ("j", j), ("q", a * v))}
    low = {name: np.minimum.reduceat(x[order], starts) for name, x in (("v", v), ("a", a), ("j", j), ("q", a * v))}
    am = np.maximum(np.abs(top["a"]), np.abs(low["a"]))
    scale = np.divide(1.0, am, out=np.zeros_like(am), where=am > 0)
    return {"vm": np.maximum(np.abs(top["v"]), np.abs(low["v"])), "am_pos": top["a"], "am_neg": low["a"],
            "jm_pos": top["j"], "jm_neg": low["j"], "qm_pos": top["q"] * scale, "qm_neg": low["q"] * scale}


def characteristic_values(curves: Sequence[Curve]) -> dict[str, FloatArray]:
    """Vm, Am±, Jm±, Qm± of many curves, the section curves' together.

    Parameters
    ----------
    curves : sequence of Curve
        Any curves; section curves (makino, universal, the catalog's) are done in passes
        of up to ``_PIECES_PER_PASS`` stacked pieces, the others one by one.

    Returns
    -------
    dict of str to ndarray
        For each name of :data:`VALUES`, one value per curve, in order [-]; equal to the
        same value of each curve's :attr:`Curve.characteristics`.

    References
    ----------
    Makino (1977), characteristic values Vm, Am, Jm, Qm taken section by section;
    INDEXMAN technical guide, section 5 (Q = A·V/Am).
    """
    out = {name: np.empty(len(curves)) for name in VALUES}
    stacked = [i for i, c in enumerate(curves) if isinstance(c, SectionCurve)]
    for i, curve in enumerate(curves):
        if not isinstance(curve, SectionCurve):
            ch = curve.characteristics
            for name in VALUES:
                out[name][i] = getattr(ch, name).value
    first = 0
    while first < len(stacked):
        last, pieces = first, 0
        while last < len(stacked) and (last == first or pieces + curves[stacked[last]].n_pieces <= _PIECES_PER_PASS):
            pieces += curves[stacked[last]].n_pieces
            last += 1
        chunk = stacked[first:last]
        values = _stacked_values([curves[i] for i in chunk])  # type: ignore[misc]  # section curves, by the filter
        for name in VALUES:
            out[name][chunk] = values[name]
        first = last
    return out
