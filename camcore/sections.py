"""Curves made of sections of constant or sinusoidal acceleration.

On each section, with τ = T − Tk the time since the section's start,

    A(τ) = α + β·sin(ωτ) + γ·cos(ωτ)

and V, S follow by exact integration from the section's starting V_k, S_k; J = dA/dT.
Every curve of the sine family (Makino's universal curve and all its special cases,
the INDEXMAN MS/MCV/MT/TR curves, cycloid, simple harmonic, constant acceleration)
is a list of such sections. Evaluation is vectorised over T: for sorted T (every table)
each section evaluates its contiguous slice with its own scalar coefficients
(:meth:`SectionCurve._eval_piece`); otherwise a section index per T, then one pass of
array arithmetic with the section's coefficients gathered (:meth:`SectionCurve._eval_pieces`).
Both give the same numbers.

References
----------
H. Makino, "Universal Cam Curve and Its Application" (1977), eqs. (1)-(9).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from .curve import WORK_ROWS, Curve, FloatArray


class _Coef(NamedTuple):
    """One section's coefficients as Python floats (for the per-slice evaluation)."""

    start: float
    s: float
    v: float
    alpha: float
    beta: float
    gamma: float
    omega: float
    half_omega: float
    b_w: float
    g_w: float
    b_w2: float
    g_w2: float
    b_wj: float
    g_wj: float
    b_ww: float
    g_ww: float


def sin_cos_from_half_angle(half_angle: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """sin θ, cos θ and 1 − cos θ from θ/2, through u = tan(θ/2).

    sin θ = 2u/(1 + u²), cos θ = (1 − u²)/(1 + u²), 1 − cos θ = 2u²/(1 + u²). numpy's
    float64 tan is vectorised (SIMD) where sin and cos are not: one tan and a few
    array passes cost a quarter of sin plus cos. The results are within a few ulp of
    sin and cos (measured against mpmath in tests/test_sections.py), and 1 − cos θ
    keeps its relative accuracy at small θ, where the difference 1 − cos loses it.
    Near θ = π, u ≈ 1e16 and the formulas still give sin θ ≈ 2/u, cos θ = −1.
    """
    u = np.tan(half_angle)
    u2 = u * u
    d = u2 + 1.0
    half_sin = u / d
    half_omc = u2 / d
    # doubling is exact, so a coefficient c times sin θ equals 2c times half_sin bit for bit:
    # SectionCurve._eval_piece uses that to skip the doubling pass
    return half_sin + half_sin, (1.0 - u2) / d, half_omc + half_omc


def _lincomb(out: FloatArray, const: float, terms: list[tuple[float, FloatArray | None, bool]],
             scratch: FloatArray) -> None:
    """out[...] = const + c1·x1 + c2·x2 + …, summed left to right as the full formula reads.

    A term with a zero coefficient adds exactly ±0 and is left out (no array pass). Each
    term is (c, x, x_may_be_zero); the x here are ≥ +0 or never zero, so c·x is −0 only
    when c < 0 and x has a zero, and only then is a zero ``const`` still added (turning
    −0 into +0, as the full formula does). ``scratch`` is a temporary of out's shape.
    """
    started = False
    for coef, x, may_be_zero in terms:
        if coef == 0.0:
            continue
        if not started:
            np.multiply(x, coef, out=out)
            if const != 0.0 or (coef < 0.0 and may_be_zero):
                np.add(out, const, out=out)
            started = True
        else:
            np.multiply(x, coef, out=scratch)
            np.add(out, scratch, out=out)
    if not started:
        out[...] = const


@dataclass(frozen=True)
class Section:
    """One section: starts at ``start`` and lasts ``length`` (> 0).

    Acceleration α + β sin(ωτ) + γ cos(ωτ) [dimensionless]; ω = 0 means constant α.
    """

    start: float
    length: float
    alpha: float = 0.0
    beta: float = 0.0
    gamma: float = 0.0
    omega: float = 0.0


class SectionCurve(Curve):
    """A curve built from :class:`Section` s, continuous in S and V.

    Parameters
    ----------
    sections : list of Section
        Consecutive sections (each starts where the previous ends); empty ones are
        dropped.
    s0, v0 : float
        Displacement and velocity at the first section's start.
    """

    def __init__(self, sections: list[Section], s0: float, v0: float):
        kept = [sec for sec in sections if sec.length > 0]
        if not kept:
            raise ValueError("a section curve needs at least one section of positive length")
        self.sections = kept
        n = len(kept)
        self.piece_starts = np.array([sec.start for sec in kept], dtype=np.float64)
        self.t_end = float(kept[-1].start + kept[-1].length)
        alpha = np.array([sec.alpha for sec in kept])
        beta = np.array([sec.beta for sec in kept])
        gamma = np.array([sec.gamma for sec in kept])
        omega = np.array([sec.omega for sec in kept])
        inv_w = np.divide(1.0, omega, out=np.zeros(n), where=omega > 0)
        # start values of each section by exact integration of the previous one
        s_start = np.empty(n)
        v_start = np.empty(n)
        s, v = float(s0), float(v0)
        for k, sec in enumerate(kept):
            s_start[k], v_start[k] = s, v
            tau = sec.length
            w = sec.omega
            if w > 0:
                sn, cs = np.sin(w * tau), np.cos(w * tau)
                # 1/ω, not ω², so a vanishingly short section cannot overflow
                iw = 1.0 / w
                s = s + v * tau + 0.5 * sec.alpha * tau**2 + sec.beta * iw * (tau - sn * iw) + sec.gamma * iw * iw * (1 - cs)
                v = v + sec.alpha * tau + sec.beta * iw * (1 - cs) + sec.gamma * iw * sn
            else:
                s = s + v * tau + 0.5 * sec.alpha * tau**2
                v = v + sec.alpha * tau
        # coefficient table, one row per section (gathered by section index)
        self._coef = {
            "start": self.piece_starts,
            "s": s_start,
            "v": v_start,
            "alpha": alpha,
            "beta": beta,
            "gamma": gamma,
            "omega": omega,
            "half_omega": 0.5 * omega,
            "b_w": beta * inv_w,
            "g_w": gamma * inv_w,
            "b_w2": beta * inv_w**2,
            "g_w2": gamma * inv_w**2,
            "b_wj": beta * omega,
            "g_wj": gamma * omega,
            "b_ww": beta * omega**2,
            "g_ww": gamma * omega**2,
        }
        # the same coefficients per section as Python floats; a constant-acceleration
        # section (ω = 0) has sin ωτ = 0, cos ωτ = 1: its A is the constant α + γ
        self._rows: list[_Coef] = []
        for k in range(n):
            row = {name: float(col[k]) + 0.0 for name, col in self._coef.items()}  # + 0.0: no −0
            if row["omega"] == 0.0:
                row["alpha"] = (row["alpha"] + row["beta"] * 0.0) + row["gamma"] + 0.0
                row.update(beta=0.0, gamma=0.0)
            self._rows.append(_Coef(**row))

    def _eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        c = self._coef
        tau = t - c["start"][piece]
        alpha = c["alpha"][piece]
        sn, cs, one_minus_cs = sin_cos_from_half_angle(tau * c["half_omega"][piece])
        b_w, g_w = c["b_w"][piece], c["g_w"][piece]
        v0 = c["v"][piece]
        s = c["s"][piece] + tau * (v0 + 0.5 * alpha * tau + b_w) - c["b_w2"][piece] * sn + c["g_w2"][piece] * one_minus_cs
        out = [s]
        if order >= 1:
            out.append(v0 + alpha * tau + b_w * one_minus_cs + g_w * sn)
        if order >= 2:
            out.append(alpha + c["beta"][piece] * sn + c["gamma"][piece] * cs)
        if order >= 3:
            out.append(c["b_wj"][piece] * cs - c["g_wj"][piece] * sn)
        if order >= 4:
            out.append(-c["b_ww"][piece] * sn - c["g_ww"][piece] * cs)
        return out

    def _eval_piece(self, t: FloatArray, k: int, order: int, out: list[FloatArray],
                    work: FloatArray | None = None) -> None:
        """[S, V, A, J, dJ/dT][: order + 1] of section k at sorted t (all in it) into ``out``.

        The formulas of :meth:`_eval_pieces` with this section's scalar coefficients, the
        same operations in the same order (so the same numbers), but no gathers, no work
        for terms whose coefficient is zero (a quarter-sine section has only one of β, γ;
        most have α = 0), and every temporary in ``work`` (``WORK_ROWS`` rows at least
        ``len(t)`` long, reused block after block: no allocation per call).
        """
        c = self._rows[k]
        m = t.shape[0]
        if work is None or work.shape[1] < m:
            work = np.empty((WORK_ROWS, m))
        tau, u, u2, d, sn, cs, omc, scratch = (row[:m] for row in work)
        np.subtract(t, c.start, out=tau)
        if m and tau[0] == 0.0:
            # t = −0.0 at a section starting at +0.0 gives τ = −0.0; the formulas want +0
            tau[: np.searchsorted(tau, 0.0, side="right")] = 0.0
        need_sin = c.b_w2 != 0.0 or (order >= 1 and c.g_w != 0.0) or (order >= 2 and c.beta != 0.0) \
            or (order >= 3 and c.g_wj != 0.0) or (order >= 4 and c.b_ww != 0.0)
        need_cos = (order >= 2 and c.gamma != 0.0) or (order >= 3 and c.b_wj != 0.0) \
            or (order >= 4 and c.g_ww != 0.0)
        need_omc = c.g_w2 != 0.0 or (order >= 1 and c.b_w != 0.0)
        if c.omega > 0.0 and (need_sin or need_cos or need_omc):
            # sin_cos_from_half_angle into the workspace; sn and omc hold half of sin ωτ and
            # of 1 − cos ωτ, and their coefficients below are doubled (exactly the same products)
            np.multiply(tau, c.half_omega, out=u)
            np.tan(u, out=u)
            np.multiply(u, u, out=u2)
            np.add(u2, 1.0, out=d)
            if need_sin:
                np.divide(u, d, out=sn)
            if need_cos:
                np.subtract(1.0, u2, out=cs)
                np.divide(cs, d, out=cs)
            if need_omc:
                np.divide(u2, d, out=omc)
        # S = s + τ·(v0 + α/2·τ + β/ω) − β/ω²·sin ωτ + γ/ω²·(1 − cos ωτ)
        if c.alpha != 0.0:
            s_out = out[0]
            np.multiply(tau, 0.5 * c.alpha, out=s_out)
            s_out += c.v
            s_out += c.b_w
            s_out *= tau
            s_out += c.s
            for coef, x in ((-2.0 * c.b_w2, sn), (2.0 * c.g_w2, omc)):
                if coef != 0.0:
                    np.multiply(x, coef, out=scratch)
                    s_out += scratch
        else:
            _lincomb(out[0], c.s, [(c.v + c.b_w, tau, True), (-2.0 * c.b_w2, sn, True), (2.0 * c.g_w2, omc, True)],
                     scratch)
        if order >= 1:  # V = v0 + α·τ + β/ω·(1 − cos ωτ) + γ/ω·sin ωτ
            _lincomb(out[1], c.v, [(c.alpha, tau, True), (2.0 * c.b_w, omc, True), (2.0 * c.g_w, sn, True)], scratch)
        if order >= 2:  # A = α + β·sin ωτ + γ·cos ωτ
            _lincomb(out[2], c.alpha, [(2.0 * c.beta, sn, True), (c.gamma, cs, True)], scratch)
        if order >= 3:  # J = βω·cos ωτ − γω·sin ωτ
            _lincomb(out[3], 0.0, [(c.b_wj, cs, True), (-2.0 * c.g_wj, sn, True)], scratch)
        if order >= 4:  # dJ/dT = −βω²·sin ωτ − γω²·cos ωτ
            _lincomb(out[4], -0.0, [(-2.0 * c.b_ww, sn, True), (-c.g_ww, cs, True)], scratch)
