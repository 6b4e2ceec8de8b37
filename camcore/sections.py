"""Curves made of sections of constant or sinusoidal acceleration.

On each section, with τ = T − Tk the time since the section's start,

    A(τ) = α + β·sin(ωτ) + γ·cos(ωτ)

and V, S follow by exact integration from the section's starting V_k, S_k; J = dA/dT.
Every curve of the sine family (Makino's universal curve and all its special cases,
the INDEXMAN MS/MCV/MT/TR curves, cycloid, simple harmonic, constant acceleration)
is a list of such sections. Evaluation is vectorised over T: a section index per T,
then one pass of array arithmetic with the section's coefficients gathered.

References
----------
H. Makino, "Universal Cam Curve and Its Application" (1977), eqs. (1)-(9).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .curve import Curve, FloatArray


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
                s = s + v * tau + 0.5 * sec.alpha * tau**2 + sec.beta / w * (tau - sn / w) + sec.gamma / w**2 * (1 - cs)
                v = v + sec.alpha * tau + sec.beta / w * (1 - cs) + sec.gamma / w * sn
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
            "b_w": beta * inv_w,
            "g_w": gamma * inv_w,
            "b_w2": beta * inv_w**2,
            "g_w2": gamma * inv_w**2,
            "b_wj": beta * omega,
            "g_wj": gamma * omega,
            "b_ww": beta * omega**2,
            "g_ww": gamma * omega**2,
        }

    def _eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        c = self._coef
        tau = t - c["start"][piece]
        alpha = c["alpha"][piece]
        wt = c["omega"][piece] * tau
        sn = np.sin(wt)
        cs = np.cos(wt)
        one_minus_cs = 1.0 - cs
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
