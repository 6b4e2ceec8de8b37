"""Peers timed beside camcore in the same run: a plain numpy version of the same law (what a
careful engineer writes by hand), and the ``mechanism`` package (PyPI, MIT) where it has the
law: its cycloidal motion. Each figure first checks that the peer and camcore agree.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

import camcore

from .timing import figure, paired_ratios

FloatArray = np.ndarray


def ms_numpy(t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """S, V, A, J of the modified sine curve (break points 1/8 and 7/8), written out piece by
    piece: 0 ≤ T < 1/8 and 7/8 ≤ T ≤ 1: S = (k + πT − ¼ sin 4πT)/(π + 4) with k = 0 or 4;
    between: S = (2 + πT − 9/4 sin((π + 4πT)/3))/(π + 4)."""
    pi, d = math.pi, math.pi + 4.0
    s, v, a, j = (np.empty_like(t) for _ in range(4))
    middle = (t >= 0.125) & (t < 0.875)
    for mask, shift in ((t < 0.125, 0.0), (t >= 0.875, 4.0)):
        x = t[mask]
        angle = 4 * pi * x
        sin, cos = np.sin(angle), np.cos(angle)
        s[mask] = (shift + pi * x - 0.25 * sin) / d
        v[mask] = pi * (1 - cos) / d
        a[mask] = 4 * pi**2 * sin / d
        j[mask] = 16 * pi**3 * cos / d
    x = t[middle]
    angle = (pi + 4 * pi * x) / 3
    sin, cos = np.sin(angle), np.cos(angle)
    s[middle] = (2 + pi * x - 2.25 * sin) / d
    v[middle] = pi * (1 - 3 * cos) / d
    a[middle] = 4 * pi**2 * sin / d
    j[middle] = 16 * pi**3 / 3 * cos / d
    return s, v, a, j


def cycloid_numpy(t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """S, V, A, J of the cycloid: S = T − sin(2πT)/2π."""
    angle = 2 * math.pi * t
    sin, cos = np.sin(angle), np.cos(angle)
    return t - sin / (2 * math.pi), 1 - cos, 2 * math.pi * sin, 4 * math.pi**2 * cos


def _agreement(ours: list[FloatArray], theirs: tuple[FloatArray, ...]) -> float:
    """Largest difference of S, V, A, J, each relative to its own peak."""
    return max(float(np.abs(a - b).max() / np.abs(a).max()) for a, b in zip(ours, theirs))


def ms_table_vs_numpy(n: int, repeats: int) -> dict[str, Any]:
    """camcore's MS table ÷ the plain numpy MS over the same points (≤ 1: camcore is faster)."""
    ms = camcore.named_curve("MS")
    t = np.linspace(0.0, 1.0, n)
    agree = _agreement(ms.derivatives(t, 3), ms_numpy(t))
    # the same closed form in another order of operations: rounding, 1e-15 of the peaks
    assert agree <= 1e-14, f"MS: camcore and the numpy version differ by {agree:.1e} of the peak"
    ratios, tb, ts = paired_ratios(lambda: ms_numpy(t), lambda: ms.derivatives(t, 3), repeats)
    return figure(ratios, "<= 1", points=n, numpy_ms=round(tb * 1e3, 3), camcore_ms=round(ts * 1e3, 3),
                  agreement_of_peak=agree,
                  what="S, V, A, J of MS: camcore (Curve.derivatives(t, 3)) ÷ a plain numpy version written "
                       "piece by piece (bench/peers.py), same points")


def _mechanism_cycloid(theta: FloatArray) -> Any:
    """The ``mechanism`` package's cycloidal rise of 1 over one turn (ω = 1 rad/s) at θ."""
    from mechanism.cams import Cycloidal

    interval = np.array([2 * math.pi])
    return Cycloidal([("Rise", 1.0, 360.0)], interval.copy(), interval, [theta <= 2 * math.pi], theta, omega=1.0)


def cycloid_table_vs_mechanism(n: int, repeats: int) -> dict[str, Any]:
    """camcore's cycloid table ÷ the ``mechanism`` package's (≤ 1: camcore is faster), with the
    plain numpy cycloid beside it."""
    cycloid = camcore.named_curve("cycloid")
    t = np.linspace(0.0, 1.0, n)
    theta = 2 * math.pi * t
    motion = _mechanism_cycloid(theta)
    # mechanism differentiates by θ (B = 2π); camcore by T: dⁿ/dTⁿ = (2π)ⁿ dⁿ/dθⁿ
    theirs = tuple(x * (2 * math.pi) ** k for k, x in enumerate((motion.S, motion.V, motion.A, motion.J)))
    agree = _agreement(cycloid.derivatives(t, 3), theirs)
    assert agree <= 1e-14, f"cycloid: camcore and mechanism differ by {agree:.1e} of the peak"
    ratios, tb, ts = paired_ratios(lambda: _mechanism_cycloid(theta), lambda: cycloid.derivatives(t, 3), repeats)
    numpy_ratios, tn, _ = paired_ratios(lambda: cycloid_numpy(t), lambda: cycloid.derivatives(t, 3), repeats)
    return figure(ratios, "<= 1", points=n, mechanism_ms=round(tb * 1e3, 3), camcore_ms=round(ts * 1e3, 3),
                  numpy_ms=round(tn * 1e3, 3), vs_numpy_median=round(float(np.median(numpy_ratios)), 4),
                  agreement_of_peak=agree,
                  what="S, V, A, J of the cycloid: camcore ÷ the mechanism package (mechanism.cams.Cycloidal, "
                       "ω = 1) over the same points; vs_numpy: ÷ the plain numpy cycloid")
