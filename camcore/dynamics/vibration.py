"""Residual vibration of a cam follower: the spectrum over τ and the response at one τ.

A follower (or an indexer's load) on a spring, driven by a cam curve from rest, deviates
from the cam's motion by x = y − s with ẍ + 2ζω·ẋ + ω²·x = −s̈ (camcore.dynamics._response
gives the model and the method). Over τ = th·fn (the motion time over the natural period)
two numbers tell how well a curve suits a flexible follower: the *residual amplitude*, the
amplitude of the free vibration left when the motion ends, √(x² + ((ẋ + ζωx)/ωd)²)/h at
t = th; and the *peak deviation*, max |x|/h during the motion. Both are computed to 1e-9
(to ~1e-13 in practice, tests/camcore/dynamics/test_vibration.py compares them with an independent
integration of the equation); they are dimensionless (fractions of the stroke h).

Known values: the undamped cycloid leaves 0.5 at τ = 1 and nothing at every integer τ ≥ 2
(its acceleration 2π·sin 2πT is orthogonal to e^{−i2πτT} over one period).

References
----------
.. [1] M. P. Koster, *Vibrations of Cam Mechanisms* (1974): the single-degree-of-freedom
   follower, residual vibration over the motion time in natural periods (docs/sources.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._checks import finite
from ..curves.curve import Curve
from ..deadline import checkpoint
from ..errors import InvalidParameterError
from ..results import doc, table_columns
from . import _chebyshev as cheb
from ._forcing import Forcing
from ._peak import peak_deviation
from ._response import BATCH_ELEMENTS, Damping, Solution, series, solve, subcells

FloatArray = NDArray[np.float64]

#: τ = th·fn is taken from 10⁻³ to 10³. Below, the natural period is over 1000 motions long:
#: the load does not follow at all (residual ≈ the stroke), and the amplitude |w|/Ωd divides
#: a sum that cancels to rounding (~1e-16) by Ωd, losing digits as τ falls. Above, the natural
#: period is under 1/1000 of the motion, a rigid follower for every purpose (at τ = 1000 the
#: residual of every catalog curve is below 1e-6 of the stroke, falling as 1/τ² or faster: an
#: acceleration jump ΔA leaves ~ΔA/Ω²), and the work grows with τ (about πτ/2 subcells of 32
#: nodes each).
TAU_MIN = 1e-3
TAU_MAX = 1e3


def check_damping(damping_ratio: float) -> float:
    """ζ as a float in [0, 1), or an error naming ``damping_ratio``.

    Parameters
    ----------
    damping_ratio : float
        ζ, the damping ratio of the follower [-].

    Returns
    -------
    float
        ζ [-].

    References
    ----------
    Koster (1974); the model here is underdamped (ζ < 1); at ζ ≥ 1 there is no vibration
    and no envelope √(x² + ((ẋ + ζωx)/ωd)²), since ωd = ω·√(1 − ζ²) vanishes.
    """
    zeta = finite("damping_ratio", damping_ratio)
    if not 0 <= zeta < 1:
        raise InvalidParameterError(
            f"damping_ratio must satisfy 0 ≤ ζ < 1 (an underdamped follower; at ζ ≥ 1 nothing vibrates), got {zeta!r}.",
            field=("damping_ratio",))
    return zeta


def check_tau(tau: ArrayLike, name: str = "tau") -> FloatArray:
    """τ values as a flat array, each finite and within [:data:`TAU_MIN`, :data:`TAU_MAX`].

    Parameters
    ----------
    tau : array_like
        τ = th·fn values [-].
    name : str
        The field named in an error.

    Returns
    -------
    ndarray
        The values, flat [-].

    References
    ----------
    Koster (1974) (τ, the motion time over the natural period).
    """
    values = np.asarray(tau, dtype=np.float64).reshape(-1)
    if values.size == 0:
        raise InvalidParameterError(f"{name} must list at least one value.", field=(name,))
    bad = ~(np.isfinite(values) & (values >= TAU_MIN) & (values <= TAU_MAX))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InvalidParameterError(
            f"{name}[{i}] = {float(values[i])!r} must lie within {TAU_MIN:g} ≤ τ ≤ {TAU_MAX:g} "
            "(τ = motion time × natural frequency).", field=(name, i))
    return values


@dataclass(frozen=True)
class ResidualVibration:
    """The residual-vibration spectrum of a curve: one row per τ (docs/api.md, computeResidualVibration)."""

    tau: FloatArray = field(metadata=doc("τ = th·fn, the motion time over the natural period [-]"))
    residual_amplitude: FloatArray = field(metadata=doc(
        "amplitude of the vibration left after the motion, √(x² + ((ẋ + ζωx)/ωd)²)/h at t = th [-]"))
    peak_deviation: FloatArray = field(metadata=doc("largest |x|/h during the motion, 0 ≤ t ≤ th [-]"))

    def columns(self) -> dict[str, FloatArray]:
        """The table's columns by name."""
        return table_columns(self)


def residual_vibration(curve: Curve, tau: ArrayLike, damping_ratio: float = 0.0) -> ResidualVibration:
    """Residual amplitude and peak deviation of a follower driven by ``curve``, at each τ.

    Parameters
    ----------
    curve : Curve
        Any camcore curve that moves; normalised to one motion (S' from 0 to 1 over
        u = (T − T0)/ΔT) as the indexer does.
    tau : array_like
        τ = th·fn, motion time over natural period, each within [10⁻³, 10³] [-].
    damping_ratio : float
        ζ, 0 ≤ ζ < 1 [-]. Default 0 (undamped).

    Returns
    -------
    ResidualVibration
        ``tau`` as given (same order), ``residual_amplitude`` and ``peak_deviation`` as
        fractions of the stroke [-], each to 1e-9.

    Raises
    ------
    InvalidParameterError
        ζ or a τ out of range, or a curve that does not move or whose acceleration is not
        smooth enough to integrate.

    References
    ----------
    Koster (1974) (the model, residual vibration); the method:
    camcore.dynamics._response.
    """
    values = check_tau(tau)
    residual, peak = _spectrum(curve, values, check_damping(damping_ratio), True)
    assert peak is not None
    return ResidualVibration(tau=values, residual_amplitude=residual, peak_deviation=peak)


def residual_amplitude(curve: Curve, tau: ArrayLike, damping_ratio: float = 0.0) -> FloatArray:
    """The residual amplitude alone (:func:`residual_vibration` without the peak: about half the work).

    Parameters
    ----------
    curve : Curve
        Any camcore curve that moves.
    tau : array_like
        τ = th·fn, each within [10⁻³, 10³] [-].
    damping_ratio : float
        ζ, 0 ≤ ζ < 1 [-].

    Returns
    -------
    ndarray
        The residual amplitude at each τ, as a fraction of the stroke [-].

    References
    ----------
    Koster (1974); the method: camcore.dynamics._response.
    """
    return _spectrum(curve, check_tau(tau), check_damping(damping_ratio), False)[0]


def _spectrum(curve: Curve, values: FloatArray, zeta: float, with_peak: bool) -> tuple[FloatArray, FloatArray | None]:
    """Residual amplitudes (and peaks) at the τ values, in their order: τ sorted into bands
    whose Ω lie within a factor 2, each band on the subcells of its largest Ω."""
    forcing = Forcing(curve)
    order = np.argsort(values, kind="stable")
    omega = 2.0 * math.pi * values[order]
    residual = np.empty(values.size)
    peak = np.empty(values.size)
    band = np.maximum(np.floor(np.log2(omega)), 0.0)
    for level in np.unique(band):
        members = np.flatnonzero(band == level)
        sub = subcells(forcing, float(omega[members].max()))
        size = max(1, BATCH_ELEMENTS // (sub.count * cheb.NODES))
        for first in range(0, members.size, size):
            checkpoint()
            part = members[first:first + size]
            solution = solve(sub, Damping(omega[part], zeta), dense=with_peak)
            residual[part] = solution.residual
            if with_peak:
                peak[part] = peak_deviation(solution, forcing)
    out_residual = np.empty(values.size)
    out_residual[order] = residual
    if not with_peak:
        return out_residual, None
    out_peak = np.empty(values.size)
    out_peak[order] = peak
    return out_residual, out_peak


class FollowerResponse:
    """The response of a follower to ``curve`` at one τ and ζ: the residual amplitude, the peak
    deviation and X = x/h at any u = t/th ≥ 0 (free vibration after the motion).

    Parameters
    ----------
    curve : Curve
        Any camcore curve that moves (normalised as in :func:`residual_vibration`).
    tau : float
        τ = th·fn within [10⁻³, 10³] [-].
    damping_ratio : float
        ζ, 0 ≤ ζ < 1 [-].
    """

    def __init__(self, curve: Curve, tau: float, damping_ratio: float = 0.0):
        self.damping_ratio = check_damping(damping_ratio)
        self.tau = float(check_tau([tau])[0])
        self.forcing = Forcing(curve)
        omega = 2.0 * math.pi * self.tau
        self.damping = Damping(np.array([omega]), self.damping_ratio)
        self.solution: Solution = solve(subcells(self.forcing, omega), self.damping)
        self.residual_amplitude = float(self.solution.residual[0])
        self.peak_deviation = float(peak_deviation(self.solution, self.forcing)[0])
        self._series: NDArray[np.complex128] | None = None

    def deviation(self, u: ArrayLike) -> FloatArray:
        """X = x/h at the times u = t/th ≥ 0 [-]; after u = 1 the free vibration of the final state."""
        at = np.asarray(u, dtype=np.float64).reshape(-1)
        if not (np.isfinite(at).all() and (at >= 0).all()):
            raise InvalidParameterError("u must be finite and 0 or more.")
        out = np.empty(at.size)
        inside = at <= 1.0
        d = self.damping
        if inside.any():
            sub = self.solution.sub
            if self._series is None:  # the integral's Chebyshev series on every subcell, once
                every = np.arange(sub.count)
                self._series = series(self.solution, np.zeros(sub.count, dtype=np.intp), every)
            cell = np.clip(np.searchsorted(sub.start, at[inside], side="right") - 1, 0, sub.count - 1)
            offset = np.clip(at[inside] - sub.start[cell], 0.0, 2.0 * sub.half[cell])
            s = offset / sub.half[cell] - 1.0
            w = np.exp(d.lam[0] * offset) * (self.solution.w_start[0, cell] - cheb.clenshaw_rows(self._series, cell, s))
            out[inside] = w.imag / d.omega_d[0]
        if (~inside).any():
            w = np.exp(d.lam[0] * (at[~inside] - 1.0)) * self.solution.w_end[0]
            out[~inside] = w.imag / d.omega_d[0]
        return out

    def settling(self, tolerance: float, scale: float = 1.0) -> float | None:
        """u after the motion (in units of th) until the envelope stays within ``tolerance``
        (in the units of ``scale``, h in them: a fraction of h by default); 0 if it already is;
        None if it never does (ζ = 0)."""
        fraction = tolerance / scale
        if self.residual_amplitude <= fraction:
            return 0.0
        rate = float(self.damping.zeta_omega[0])
        if rate == 0.0:
            return None
        if fraction > 0.0:
            return math.log(self.residual_amplitude / fraction) / rate
        # logs apart: the fraction underflows to 0 for a tiny tolerance (5e-324 arcsec), its log does not
        return (math.log(scale * self.residual_amplitude) - math.log(tolerance)) / rate
