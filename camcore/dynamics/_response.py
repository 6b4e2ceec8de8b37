"""The response of a single-degree-of-freedom follower to a cam motion, exact to rounding.

Model (the single-degree-of-freedom follower, Koster (1974)): the follower (or an indexer's
load) is a mass on a spring of natural frequency ω and damping ratio ζ, driven through the
spring by the cam motion s(t) = h·S(t/th). Its deviation x = y − s from the cam's motion obeys

    ẍ + 2ζω·ẋ + ω²·x = −s̈,   x(0) = ẋ(0) = 0   (from rest: the follower moves with the cam)

In dimensionless time u = t/th, with X = x/h and Ω = ω·th = 2πτ (τ = th·fn, the motion time
over the natural period): X'' + 2ζΩ·X' + Ω²·X = −A'(u), A' the curve's normalised
acceleration (camcore.dynamics._forcing).

The complex state w = X' + ζΩ·X + iΩd·X (Ωd = Ω·√(1 − ζ²)) turns the equation into one of
first order, w' = λ·w − A', λ = −ζΩ + iΩd, whose solution over an interval [a, u] is the
Duhamel integral w(u) = e^{λ(u−a)}·(w(a) − ∫_a^u e^{−λ(v−a)} A'(v) dv). So X = Im w/Ωd and
the residual amplitude after the motion is |w(1)|/Ωd = √(X² + ((X' + ζΩX)/Ωd)²).

The integral is evaluated on *subcells*: each smooth cell of A' is cut so that |λ|·length ≤
:data:`SPAN` = 4, and on each subcell the integrand, sampled at 32 Chebyshev–Lobatto points, is
integrated as its interpolating polynomial, from the subcell's start to every node
(camcore.dynamics._chebyshev). Why that is exact to rounding: on a cell A' is a polynomial of
degree 16 whose last coefficients are below 1e-13 of its largest value (_forcing.RESOLVED);
e^{−λ(v−a)} on a subcell is e^{zs}, s ∈ [−1, 1], |z| ≤ 2, whose Chebyshev coefficients
2·I_k(z) are below 2e/k! (5e-17 from k = 19, 3e-13 from k = 16). A coefficient of their
product beyond degree 31, all that 32 nodes cannot hold (T_j·T_m = (T_{j+m} + T_{|j−m|})/2),
pairs an A' coefficient of degree ≤ 13 with an exponential one of degree ≥ 19, or an A' one
of degree 14-16 (≤ 1e-13) with one of degree ≥ 16: together below 1e-15 of the largest A'.
(The tests pass with |z| up to 10: the bound is far from tight.)
A velocity jump ΔV' at a break point (an impulse of A') changes w by −ΔV'.
The subcells are chained by the recurrence above; the chaining is vectorised as a running
sum, in stretches short enough (ζΩ·length ≤ :data:`CHAIN`) that e^{ζΩ·length} stays finite.

The deviation is known at every node (≥ 30 per natural period), with X' and X''
from the equation. Its largest |X| is refined where X' changes sign between two nodes
whose |X| comes within the sampling bound (X''·δ²/8, doubled) of the largest sample: by a
safeguarded Newton iteration on X' = 0 with X evaluated anywhere from the Chebyshev series
of the integral (camcore.dynamics._peak).

References
----------
.. [1] M. P. Koster, *Vibrations of Cam Mechanisms* (1974): the single-degree-of-freedom
   follower and its residual vibration (docs/sources.md says what was checked). The
   complex state and Duhamel's integral are those of any linear oscillator.
.. [2] L. N. Trefethen, *Approximation Theory and Approximation Practice* (SIAM, 2013),
   ch. 8 and 19 (convergence and integration of Chebyshev interpolants).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from . import _chebyshev as cheb
from ._forcing import Forcing

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IndexArray = NDArray[np.intp]

#: |λ|·length of a subcell at most (the module notes say why 4 with 32 nodes)
SPAN = 4.0
#: ζΩ·length of a stretch chained by one running sum at most: e^300 ≈ 1e130 stays finite
CHAIN = 300.0
#: τ values × subcells × nodes computed at once: 8 MB per complex array
BATCH_ELEMENTS = 1 << 19
#: intervals refined per τ for the peak at most (those with the largest samples first)
MAX_CANDIDATES = 32
#: Newton (or false-position) steps at most for the peak: it converges in a handful
NEWTON_STEPS = 40


@dataclass(frozen=True)
class Subcells:
    """The curve's smooth cells cut for one Ω: starts, half lengths, pieces, the velocity jump
    entering at each start, A' at the 32 nodes of each; the distinct half lengths (the
    subcells of a cell are equal) and which one each subcell has."""

    start: FloatArray
    half: FloatArray
    piece: IndexArray
    jump: FloatArray
    accel: FloatArray
    halves: FloatArray
    group: IndexArray

    @property
    def count(self) -> int:
        return int(self.start.size)


def subcell_parts(forcing: Forcing, omega: float) -> IndexArray:
    """Subcells each cell is cut into for Ω: |λ|·length ≤ :data:`SPAN` (|λ| = Ω)."""
    length = forcing.cell_end - forcing.cell_start
    parts: IndexArray = np.maximum(1, np.ceil(omega * length / SPAN)).astype(np.intp)
    return parts


def subcells(forcing: Forcing, omega: float) -> Subcells:
    """The subcells of ``forcing``'s cells for Ω, with A' at their nodes."""
    parts = subcell_parts(forcing, omega)
    cell = np.repeat(np.arange(parts.size), parts)
    first = np.cumsum(parts) - parts
    within = np.arange(cell.size) - first[cell]
    length = (forcing.cell_end - forcing.cell_start)[cell] / parts[cell]
    start = forcing.cell_start[cell] + within * length
    piece = forcing.cell_piece[cell]
    jump = np.zeros(cell.size)
    if forcing.impulse.size:  # at the first subcell starting at or after each break point
        at = np.minimum(np.searchsorted(start, forcing.impulse_u - 1e-15), cell.size - 1)
        np.add.at(jump, at, forcing.impulse)
    half = length / 2.0
    halves, group = np.unique(half, return_inverse=True)
    nodes = start[:, None] + half[:, None] * (1.0 + cheb.LOBATTO)
    accel = forcing.acceleration(nodes.ravel(), np.repeat(piece, cheb.NODES)).reshape(nodes.shape)
    return Subcells(start, half, piece, jump, accel, halves, group.reshape(-1))


@dataclass(frozen=True)
class Damping:
    """λ = −ζΩ + iΩd and its parts, one per τ value."""

    omega: FloatArray
    zeta: float

    @property
    def zeta_omega(self) -> FloatArray:
        return self.zeta * self.omega

    @property
    def omega_d(self) -> FloatArray:
        return self.omega * math.sqrt(1.0 - self.zeta**2)

    @property
    def lam(self) -> ComplexArray:
        return -self.zeta_omega + 1j * self.omega_d


@dataclass
class Solution:
    """The state of a batch of τ values on the subcells: w just after each subcell's start, the
    integral G from each start to each node (real and imaginary parts), e^{∓λ(v − a)} at the
    nodes of each distinct half length, and w at u = 1. Without the nodes (``dense`` false in
    :func:`solve`) it holds only w."""

    damping: Damping
    sub: Subcells
    w_start: ComplexArray
    integral_re: FloatArray | None
    integral_im: FloatArray | None
    decay: ComplexArray
    growth: ComplexArray | None
    w_end: ComplexArray

    def deviation(self) -> tuple[FloatArray, FloatArray]:
        """X and X' at every node, shaped (τ values, subcells, nodes)."""
        assert self.growth is not None and self.integral_re is not None and self.integral_im is not None
        growth = self.growth[:, self.sub.group]
        re = self.w_start.real[:, :, None] - self.integral_re
        im = self.w_start.imag[:, :, None] - self.integral_im
        d = self.damping
        x = (re * growth.imag + im * growth.real) / d.omega_d[:, None, None]
        return x, re * growth.real - im * growth.imag - d.zeta_omega[:, None, None] * x

    @property
    def residual(self) -> FloatArray:
        """|w(1)|/Ωd: the residual amplitude over h [-]."""
        amplitude: FloatArray = np.abs(self.w_end) / self.damping.omega_d
        return amplitude


def solve(sub: Subcells, damping: Damping, dense: bool = True) -> Solution:
    """The Duhamel integrals on every subcell and the state chained from u = 0 (at rest); with
    ``dense`` also the integral to every node (for X at the nodes), else only over each subcell."""
    lam = damping.lam
    offset = sub.halves[:, None] * (1.0 + cheb.LOBATTO)  # v − a at the nodes, per half length
    decay = np.exp(-lam[:, None, None] * offset[None])
    values = decay[:, sub.group]
    forced_re = (values.real * sub.accel[None]).reshape(-1, cheb.NODES)
    forced_im = (values.imag * sub.accel[None]).reshape(-1, cheb.NODES)
    # real products on 2-D arrays: numpy multiplies a complex array by a real matrix without
    # BLAS, and a stack of matrices (3-D) row block by row block, both ~20 times slower
    shape = (lam.size, sub.count, cheb.NODES)
    weight = sub.half[None, :]
    integral_re: FloatArray | None = None
    integral_im: FloatArray | None = None
    growth: ComplexArray | None = None
    if dense:
        integral_re = weight[:, :, None] * (forced_re @ cheb.CUMULATIVE.T).reshape(shape)
        integral_im = weight[:, :, None] * (forced_im @ cheb.CUMULATIVE.T).reshape(shape)
        cell_integral = integral_re[:, :, -1] + 1j * integral_im[:, :, -1]
        growth = np.exp(lam[:, None, None] * offset[None])
    else:
        cell_integral = weight * ((forced_re @ cheb.WEIGHTS) + 1j * (forced_im @ cheb.WEIGHTS)).reshape(shape[:2])
    w_start, w_end = _chain(sub, lam, float(damping.zeta_omega.max()), cell_integral)
    return Solution(damping, sub, w_start, integral_re, integral_im, decay, growth, w_end)


def _chain(sub: Subcells, lam: ComplexArray, zeta_omega: float, cell_integral: ComplexArray
           ) -> tuple[ComplexArray, ComplexArray]:
    """w(a_k) = e^{λ(a_k − c)}·(w(c) − Σ_{j≤k} (ΔV'_j + G_j)·e^{−λ(a_j − c)}) + G_k, a running
    sum over stretches starting at c, short enough that e^{ζΩ(a_j − c)} is finite."""
    n = sub.count
    start = sub.start
    w_start = np.empty(cell_integral.shape, dtype=np.complex128)
    w = np.zeros(lam.shape, dtype=np.complex128)
    k0 = 0
    while k0 < n:
        if zeta_omega > 0:
            k1 = max(k0 + 1, int(np.searchsorted(start, start[k0] + CHAIN / zeta_omega, side="right")))
        else:
            k1 = n
        shift = np.exp(lam[:, None] * (start[k0:k1] - start[k0])[None])
        running = np.cumsum((sub.jump[None, k0:k1] + cell_integral[:, k0:k1]) / shift, axis=1)
        w_start[:, k0:k1] = shift * (w[:, None] - running) + cell_integral[:, k0:k1]
        end = start[k1 - 1] + 2.0 * sub.half[k1 - 1]
        w = np.exp(lam * (end - start[k0])) * (w - running[:, -1])
        k0 = k1
    return w_start, w


def series(solution: Solution, batch: IndexArray, cell: IndexArray) -> ComplexArray:
    """Chebyshev coefficients of the integral G on subcells ``cell`` for τ values ``batch``."""
    sub = solution.sub
    values = solution.decay[batch, sub.group[cell]] * sub.accel[cell]
    matrix = cheb.INTEGRAL_COEFFICIENTS.T
    coefficients = np.empty((cell.size, matrix.shape[1]), dtype=np.complex128)
    coefficients.real = values.real @ matrix
    coefficients.imag = values.imag @ matrix
    coefficients *= sub.half[cell, None]
    return coefficients


def state_at(solution: Solution, forcing: Forcing, batch: IndexArray, cell: IndexArray, coefficients: ComplexArray,
             s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """X, X', X'' at the points s ∈ [−1, 1] of subcells ``cell`` (τ values ``batch``)."""
    sub, d = solution.sub, solution.damping
    offset = sub.half[cell] * (1.0 + s)
    lam, zo, od, om = d.lam[batch], d.zeta_omega[batch], d.omega_d[batch], d.omega[batch]
    w = np.exp(lam * offset) * (solution.w_start[batch, cell] - cheb.clenshaw(coefficients, s))
    x = w.imag / od
    xd = w.real - zo * x
    accel = forcing.acceleration(sub.start[cell] + offset, sub.piece[cell])
    return x, xd, -accel - 2.0 * zo * xd - om**2 * x
