"""Curves made of sections of constant or sinusoidal acceleration.

On each section, with τ = T − Tk the time since the section's start,

    A(τ) = α + β·sin(ωτ) + γ·cos(ωτ)

and V, S follow by exact integration from the section's starting V_k, S_k; J = dA/dT.
Every curve of the sine family (Makino's universal curve and all its special cases,
the INDEXMAN MS/MCV/MT/TR curves, cycloid, simple harmonic, constant acceleration)
is a list of such sections. Evaluation is vectorised over T: for sorted T (every table)
each section evaluates its contiguous slice with its own scalar coefficients
(:meth:`SectionCurve.eval_piece`); otherwise a section index per T, then one pass of
array arithmetic with the section's coefficients gathered (:meth:`SectionCurve.eval_pieces`).
Both give the same numbers.

References
----------
H. Makino, "Universal Cam Curve and Its Application" (1977), eqs. (1)-(9).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from .base import WORK_ROWS, FloatArray
from .curve import Curve


class _Coef(NamedTuple):
    """One section's coefficients as Python floats (for the per-slice evaluation).

    Each output is a constant plus multiples of τ, q = sin(ωτ)/2 and r = (1 − cos ωτ)/2
    (:func:`half_angle_bases`): S = s + τ·(v + β/ω + α/2·τ) + s_q·q + s_r·r, and
    X = x_c + x_t·τ + x_q·q + x_r·r for X = V, A, J, dJ/dT.
    """

    start: float
    half_omega: float
    s: float
    v: float
    alpha: float
    b_w: float   # β/ω
    s_k: float   # v + β/ω: S's τ coefficient when α = 0
    s_q: float
    s_r: float
    v_q: float
    v_r: float
    a_c: float
    a_q: float
    a_r: float
    j_c: float
    j_q: float
    j_r: float
    d_c: float
    d_q: float
    d_r: float


def half_angle_bases(half_angle: FloatArray) -> tuple[FloatArray, FloatArray]:
    """q = sin(θ)/2 and r = (1 − cos θ)/2 from θ/2, through u = tan(θ/2).

    q = u/(1 + u²), r = u²/(1 + u²); so sin θ = 2q, 1 − cos θ = 2r, cos θ = 1 − 2r.
    numpy's float64 tan is vectorised (SIMD) where sin and cos are not: one tan and four
    array passes cost a fraction of sin plus cos. sin and cos come out within a few ulp
    (measured against mpmath in tests/camcore/curves/test_sections.py), and r keeps its relative
    accuracy at small θ, where 1 − cos θ computed as a difference loses it. Near θ = π,
    u ≈ 1e16 and the formulas still give q ≈ 1/u, r = 1.

    Parameters
    ----------
    half_angle : ndarray
        θ/2, half the phase θ = ωτ of a sine section [rad] (θ from 0 up to π).

    Returns
    -------
    (ndarray, ndarray)
        q = sin(θ)/2 and r = (1 − cos θ)/2 [-], shaped like ``half_angle``.

    References
    ----------
    M. Abramowitz, I. A. Stegun, Handbook of Mathematical Functions (1964), §4.3 (the
    tangent half-angle identities); Makino (1977), eqs. (1)-(9) (the sections evaluated).
    """
    u = np.tan(half_angle)
    u2 = u * u
    d = u2 + 1.0
    return u / d, u2 / d


#: the rows of a section coefficient matrix (:attr:`SectionCurve.coefficients`), in order
COEFFICIENTS = ("start", "half_omega", "s", "v", "alpha", "b_w", "s_q", "s_r", "v_q", "v_r",
                "a_c", "a_q", "a_r", "j_c", "j_q", "j_r", "d_c", "d_q", "d_r")


def eval_sections(coefficients: FloatArray, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
    """[S, V, A, J, dJ/dT][: order + 1] at t, each on its section (a column of ``coefficients``).

    Parameters
    ----------
    coefficients : ndarray
        One row per name of :data:`COEFFICIENTS`, one column per section; the columns may
        come from several curves (their sections need not follow one another) [-].
    t : ndarray
        Dimensionless times [-].
    piece : ndarray of int
        The column of each t [-].
    order : int
        Highest derivative (0..4) [-].

    Returns
    -------
    list of ndarray
        [S, V, A, J, dJ/dT][: order + 1] at t [-].

    References
    ----------
    Makino (1977), eqs. (1)-(9): each section α + β·sin ωτ + γ·cos ωτ, integrated exactly.
    """
    # one gather for all coefficients: row i of the result is coefficient i per point
    return _section_formulas(dict(zip(COEFFICIENTS, np.take(coefficients, piece, axis=1))), t, order)


def _section_formulas(c: dict[str, FloatArray], t: FloatArray, order: int) -> list[FloatArray]:
    """The formulas of :func:`eval_sections`, with each coefficient given per point."""
    tau = t - c["start"]
    q, r = half_angle_bases(tau * c["half_omega"])
    out = [c["s"] + tau * (c["v"] + 0.5 * c["alpha"] * tau + c["b_w"]) + c["s_q"] * q + c["s_r"] * r]
    if order >= 1:
        out.append(c["v"] + c["alpha"] * tau + c["v_q"] * q + c["v_r"] * r)
    for name in "ajd"[: max(order - 1, 0)]:
        out.append(c[name + "_c"] + c[name + "_q"] * q + c[name + "_r"] * r)
    return out


def eval_section_point(c: list[float], t: float) -> list[float]:
    """[S, V, A, J, dJ/dT] at one t on one section, as Python floats.

    Parameters
    ----------
    c : list of float
        The section's column of a coefficient matrix, in the order of :data:`COEFFICIENTS` [-].
    t : float
        Dimensionless time [-].

    Returns
    -------
    list of float
        [S, V, A, J, dJ/dT] at t [-]: :func:`eval_sections`' operations in its order, so
        its numbers to the bit (a float's + − × ÷ round as numpy's do; tan is numpy's).

    References
    ----------
    Makino (1977), eqs. (1)-(9).
    """
    start, half_omega, s, v, alpha, b_w, s_q, s_r, v_q, v_r, a_c, a_q, a_r, j_c, j_q, j_r, d_c, d_q, d_r = c
    tau = t - start
    u = float(np.tan(tau * half_omega))  # numpy's tan, as the arrays get it (libm's may differ by an ulp)
    u2 = u * u
    d = u2 + 1.0
    q, r = u / d, u2 / d
    return [s + tau * (v + 0.5 * alpha * tau + b_w) + s_q * q + s_r * r, v + alpha * tau + v_q * q + v_r * r,
            a_c + a_q * q + a_r * r, j_c + j_q * q + j_r * r, d_c + d_q * q + d_r * r]


class SectionColumns:
    """Scalar evaluation for a curve whose pieces are columns of a section coefficient matrix."""

    coefficients: FloatArray
    has_point_formulas = True

    @cached_property
    def _columns(self) -> list[list[float]]:
        return self.coefficients.T.tolist()

    def eval_point(self, t: float, k: int) -> list[float]:
        """[S, V, A, J, dJ/dT] of piece k at one t (:func:`eval_section_point`)."""
        return eval_section_point(self._columns[k], t)

    def eval_grid(self, grid: FloatArray, order: int) -> list[FloatArray]:
        """[S, V, A, J, dJ/dT][: order + 1] on a grid, row k on piece k: :func:`eval_sections`
        with each section's coefficients repeated along its row (the same values as its gather,
        made three times faster)."""
        n, m = grid.shape
        per_point = dict(zip(COEFFICIENTS, np.repeat(self.coefficients, m, axis=1)))
        return [v.reshape(n, m) for v in _section_formulas(per_point, grid.reshape(-1), order)]


class _Sum(NamedTuple):
    """One output as const + Σ coef·basis, zero coefficients left out (basis 0 = τ, 1 = q, 2 = r).

    The sum runs left to right as the full formula reads. A left-out term would add
    exactly ±0; the bases are ≥ +0, so a first term with a negative coefficient can be −0,
    and only then is a zero constant still added (turning −0 into +0, as the full
    formula does).
    """

    const: float
    add_const: bool
    terms: tuple[tuple[float, int], ...]

    @classmethod
    def of(cls, const: float, terms: list[tuple[float, int]]) -> _Sum:
        kept = tuple((coef, basis) for coef, basis in terms if coef != 0.0)
        return cls(const, const != 0.0 or (bool(kept) and kept[0][0] < 0.0), kept)

    def bases(self) -> set[int]:
        return {basis for _, basis in self.terms}

    def run(self, out: FloatArray, bases: tuple[FloatArray, ...], scratch: FloatArray) -> None:
        if not self.terms:
            out[...] = self.const
            return
        coef, basis = self.terms[0]
        np.multiply(bases[basis], coef, out=out)
        if self.add_const:
            np.add(out, self.const, out=out)
        for coef, basis in self.terms[1:]:
            np.multiply(bases[basis], coef, out=scratch)
            np.add(out, scratch, out=out)


class _Plan(NamedTuple):
    """What section k computes for a given order (built once, run block after block)."""

    need_q: bool
    need_r: bool
    outputs: tuple[_Sum, ...]   # S (unless alpha_s), then V, A, J, dJ/dT as far as the order goes


@dataclass(frozen=True)
class Section:
    """One section: starts at ``start`` and lasts ``length`` (> 0).

    Acceleration α + β sin(ωτ) + γ cos(ωτ) [dimensionless]; ω = 0 means constant α.
    τ = T − start, or with ``from_end`` τ = T − (start + length) ≤ 0: the coefficients
    then describe A about the section's end, where S and V are the curve's given end
    values (only the last section may be so anchored).
    """

    start: float
    length: float
    alpha: float = 0.0
    beta: float = 0.0
    gamma: float = 0.0
    omega: float = 0.0
    from_end: bool = False


class SectionCurve(SectionColumns, Curve):
    """A curve built from :class:`Section` s, continuous in S and V.

    Parameters
    ----------
    sections : list of Section
        Consecutive sections (each starts where the previous ends); empty ones are
        dropped.
    s0, v0 : float
        Displacement and velocity at the first section's start.
    s_end, v_end : float, optional
        The law's exact S and V at the last section's end, required when that section
        is given ``from_end``: it is then evaluated about its end, so that the curve
        ends exactly there instead of at the sum of every section's gain, which misses
        the end by a few ulps (V = 2.8e-16 at T = 1 for MS).
    """

    has_piece_path = True  # eval_piece: the section's scalar coefficients, no gather

    def __init__(self, sections: list[Section], s0: float, v0: float,
                 s_end: float | None = None, v_end: float | None = None):
        kept = [sec for sec in sections if sec.length > 0]
        if not kept:
            raise ValueError("a section curve needs at least one section of positive length")
        if any(sec.from_end for sec in kept[:-1]):
            raise ValueError("only the last section may be evaluated about its end")
        if kept[-1].from_end and (s_end is None or v_end is None):
            raise ValueError("a last section given from its end needs the end values s_end and v_end")
        # ω = 0: sin ωτ = 0, cos ωτ = 1, so the acceleration is the constant α + γ
        kept = [sec if sec.omega > 0 else Section(sec.start, sec.length, alpha=sec.alpha + sec.gamma,
                                                  from_end=sec.from_end) for sec in kept]
        self.sections = kept
        n = len(kept)
        self.piece_starts = np.array([sec.start for sec in kept], dtype=np.float64)
        self.t_end = float(kept[-1].start + kept[-1].length)
        # τ is measured from each section's start, or from the end for a section from_end
        anchor = self.piece_starts.copy()
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
            if sec.from_end:  # the last section: its values are given at its end
                anchor[k] = self.t_end
                s_start[k], v_start[k] = float(s_end), float(v_end)  # type: ignore[arg-type]
                break
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
        b_w, g_w = beta * inv_w, gamma * inv_w
        b_w2, g_w2 = beta * inv_w**2, gamma * inv_w**2
        b_wj, g_wj = beta * omega, gamma * omega
        b_ww, g_ww = beta * omega**2, gamma * omega**2
        # coefficient table, one row per section (gathered by section index); with
        # sin = 2q, 1 − cos = 2r, cos = 1 − 2r (doubling is exact):
        coef = {
            "start": anchor,
            "half_omega": 0.5 * omega,
            "s": s_start,
            "v": v_start,
            "alpha": alpha,
            "b_w": b_w,
            "s_q": -2.0 * b_w2,        # S: −β/ω²·sin ωτ + γ/ω²·(1 − cos ωτ)
            "s_r": 2.0 * g_w2,
            "v_q": 2.0 * g_w,          # V: v + α·τ + β/ω·(1 − cos ωτ) + γ/ω·sin ωτ
            "v_r": 2.0 * b_w,
            "a_c": alpha + gamma,      # A: α + β·sin ωτ + γ·cos ωτ
            "a_q": 2.0 * beta,
            "a_r": -2.0 * gamma,
            "j_c": b_wj,               # J: βω·cos ωτ − γω·sin ωτ
            "j_q": -2.0 * g_wj,
            "j_r": -2.0 * b_wj,
            "d_c": -g_ww,              # dJ/dT: −βω²·sin ωτ − γω²·cos ωτ
            "d_q": -2.0 * b_ww,
            "d_r": 2.0 * g_ww,
        }
        assert tuple(coef) == COEFFICIENTS
        self.coefficients = np.array(list(coef.values()))
        self._plans: dict[tuple[int, int], _Plan] = {}

    @cached_property
    def _rows(self) -> list[_Coef]:
        """The coefficients per section as Python floats (+ 0.0: no −0), for sorted tables
        (:meth:`eval_piece`); made when first needed (a curve asked only for its
        characteristic values never needs them)."""
        rows = []
        for column in self._columns:
            row = {name: value + 0.0 for name, value in zip(COEFFICIENTS, column)}
            row["s_k"] = row["v"] + row["b_w"]  # as the gathered v + α/2·τ + β/ω reads at α = 0
            rows.append(_Coef(**row))
        return rows

    def eval_pieces(self, t: FloatArray, piece: NDArray[np.intp], order: int) -> list[FloatArray]:
        return eval_sections(self.coefficients, t, piece, order)

    def _plan(self, k: int, order: int) -> _Plan:
        plan = self._plans.get((k, order))
        if plan is None:
            c = self._rows[k]
            tau, q, r = 0, 1, 2
            sums = [
                _Sum.of(c.s, [(c.s_k, tau), (c.s_q, q), (c.s_r, r)]),  # S when α = 0
                _Sum.of(c.v, [(c.alpha, tau), (c.v_q, q), (c.v_r, r)]),
                _Sum.of(c.a_c, [(c.a_q, q), (c.a_r, r)]),
                _Sum.of(c.j_c, [(c.j_q, q), (c.j_r, r)]),
                _Sum.of(c.d_c, [(c.d_q, q), (c.d_r, r)]),
            ][: order + 1]
            used = set().union(*(x.bases() for x in sums)) | ({q} if c.s_q else set()) | ({r} if c.s_r else set())
            plan = _Plan(c.half_omega > 0.0 and q in used, c.half_omega > 0.0 and r in used, tuple(sums))
            self._plans[(k, order)] = plan
        return plan

    def eval_piece(self, t: FloatArray, k: int, order: int, out: list[FloatArray],
                    work: FloatArray | None = None) -> None:
        """[S, V, A, J, dJ/dT][: order + 1] of section k at sorted t (all in it) into ``out``.

        The formulas of :meth:`eval_pieces` with this section's scalar coefficients, the
        same operations in the same order (so the same numbers), but no gathers, no work
        for terms whose coefficient is zero (a quarter-sine section has only one of β, γ;
        most have α = 0), and every temporary in ``work`` (``WORK_ROWS`` rows at least
        ``len(t)`` long, reused block after block: no allocation per call).
        """
        c = self._rows[k]
        plan = self._plan(k, order)
        m = t.shape[0]
        if work is None or work.shape[1] < m:
            work = np.empty((WORK_ROWS, m))
        tau, q, r, d, scratch = (row[:m] for row in work)
        np.subtract(t, c.start, out=tau)
        if m and tau[0] == 0.0:
            # t = −0.0 at a section starting at +0.0 gives τ = −0.0; the formulas want +0
            tau[: np.searchsorted(tau, 0.0, side="right")] = 0.0
        if plan.need_q or plan.need_r:
            # half_angle_bases, written into the workspace
            u = q if plan.need_q else r
            np.multiply(tau, c.half_omega, out=u)
            np.tan(u, out=u)
            np.multiply(u, u, out=scratch)  # u²
            np.add(scratch, 1.0, out=d)
            if plan.need_q:
                np.divide(u, d, out=q)
            if plan.need_r:
                np.divide(scratch, d, out=r)
        bases = (tau, q, r)
        if c.alpha != 0.0:  # S = s + τ·(v + α/2·τ + β/ω) + s_q·q + s_r·r
            s_out = out[0]
            np.multiply(tau, 0.5 * c.alpha, out=s_out)
            s_out += c.v
            s_out += c.b_w
            s_out *= tau
            s_out += c.s
            for coef, x in ((c.s_q, q), (c.s_r, r)):
                if coef != 0.0:
                    np.multiply(x, coef, out=scratch)
                    s_out += scratch
        else:
            plan.outputs[0].run(out[0], bases, scratch)
        for o, total in zip(out[1:], plan.outputs[1:]):
            total.run(o, bases, scratch)
