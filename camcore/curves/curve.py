"""The curve every motion law is: evaluation, characteristic values and inverses together.

A law subclasses :class:`Curve` and provides its pieces (see
:class:`~camcore.curves.base.PiecewiseCurve`); everything else comes from here.

References
----------
.. [1] Makino (1977), eqs. (1)-(12) and subroutine CURVE.
.. [2] INDEXMAN technical guide, section 5 (tables, characteristic values, worked example).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import extrema, inverse, stroke
from .base import CurveValues, FloatArray, PiecewiseCurve
from .extrema import Characteristics


class Curve(PiecewiseCurve):
    """A dimensionless cam motion curve: S, V, A, J, Q over T, its characteristic values,
    and the inverse S → T."""

    # ---------------------------------------------------------------- tables
    def evaluate(self, t: ArrayLike) -> CurveValues:
        """S, V, A, J, Q at the times t (a table's columns).

        Parameters
        ----------
        t : array_like
            Dimensionless times T [-].

        Returns
        -------
        CurveValues
            Q = A·V/Am is the indexer catalog's torque coefficient; ``q_raw`` = A·V.
        """
        t_arr = np.asarray(t, dtype=np.float64)
        s, v, a, j = self.derivatives(t_arr, 3)
        q_raw = a * v
        am = self.characteristics.am
        q = q_raw / am if am > 0 else np.zeros_like(q_raw)
        return CurveValues(t=t_arr, s=s, v=v, a=a, j=j, q=q, q_raw=q_raw)

    def sample_times(self, samples: int) -> FloatArray:
        """``samples`` evenly spaced times over [T0, T7], both ends included."""
        return np.linspace(self.t_start, self.t_end, samples)

    def table(self, samples: int) -> CurveValues:
        """:meth:`evaluate` at ``samples`` evenly spaced times over [T0, T7]."""
        return self.evaluate(self.sample_times(samples))

    # ---------------------------------------------------------------- extrema
    @cached_property
    def characteristics(self) -> Characteristics:
        """Exact characteristic values over [T0, T7] (section-wise extrema)."""
        return extrema.characteristics(self)

    def critical_points(self, slopes: Callable[[list[FloatArray]], FloatArray]
                        ) -> tuple[FloatArray, NDArray[np.intp]]:
        """Times, with their pieces, where functions of the motion may peak
        (:func:`camcore.curves.extrema.critical_points`)."""
        return extrema.critical_points(self, slopes)

    # ---------------------------------------------------------------- inverse
    @cached_property
    def monotone_direction(self) -> int:
        """+1 if S never decreases over [T0, T7], -1 if it never increases, 0 otherwise."""
        return stroke.monotone_direction(self, self.characteristics)

    @cached_property
    def _inverse_grid(self) -> inverse.InverseGrid:
        """The inverse's start table (built once per curve with the robust solver; cached)."""
        direction = stroke.require_monotone(self, self.characteristics)
        return inverse.build_grid(self, self.characteristics, direction)

    @property
    def inverse_ready(self) -> bool:
        """Whether :meth:`inverse` has its start table (the first call on a curve builds
        it, a few milliseconds; every later call only solves)."""
        return "_inverse_grid" in self.__dict__

    def inverse(self, s: ArrayLike) -> FloatArray:
        """Exact inverse: for each displacement s, the first T in [T0, T7] with S(T) = s.

        Vectorised safeguarded Newton iteration on the closed form, started from a
        table of T at 4096 evenly spaced S levels (see :mod:`camcore.curves.inverse`); it
        stops when the residual is at the rounding level of S, or when the Newton step, its
        predicted error |A/2V|·δ², or the bracket reach the spacing of floating-point
        numbers. Raises :class:`NonMonotoneError` for a curve that is not monotone and
        :class:`StrokeRangeError` for s outside the stroke.
        """
        stroke.require_monotone(self, self.characteristics)
        s_arr = np.asarray(s, dtype=np.float64)
        flat = s_arr.reshape(-1)
        stroke.validate_stroke(self, flat)
        return inverse.solve(self, self._inverse_grid, flat).reshape(s_arr.shape)

    def inverse_with_rates(self, s: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """:meth:`inverse` with V and A at each answer, from the solve itself (its last Newton
        evaluation carried over the last step, :func:`camcore.curves.inverse.solve`) instead
        of a second evaluation of the curve."""
        stroke.require_monotone(self, self.characteristics)
        s_arr = np.asarray(s, dtype=np.float64)
        flat = s_arr.reshape(-1)
        stroke.validate_stroke(self, flat)
        rates = (np.empty_like(flat), np.empty_like(flat))
        t = inverse.solve(self, self._inverse_grid, flat, rates)
        return t.reshape(s_arr.shape), rates[0].reshape(s_arr.shape), rates[1].reshape(s_arr.shape)

    def inverse_table(self, s: ArrayLike, step: float, decimals: int | None = None) -> CurveValues:
        """The catalog's method: proportional interpolation between rows of a table.

        Builds the table T = T0, T0 + step, …, T7 (the last row at T7), optionally
        rounded to ``decimals`` as printed in a catalog, finds the rows whose S bracket
        each s and interpolates T, V and A linearly between them.

        References
        ----------
        INDEXMAN technical guide, worked example before the characteristic-value table:
        S = 0.1833 between rows T = 0.30 and 0.31 of the MS table gives T = 0.304,
        V = 1.339.
        """
        direction = stroke.require_monotone(self, self.characteristics)
        rows = self.evaluate(stroke.table_rows(self, step))
        return stroke.inverse_table(self, rows, s, direction, decimals)
