"""Hertz line contact of a roller on the cam surface.

Two cylinders with parallel axes, pressed together by a normal force P over a length b,
touch along a strip of half-width a; the largest pressure, in the middle of the strip, is

    p0 = sqrt(P·E* / (π·b·R)),    a² = 4·P·R / (π·b·E*),
    1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2,    1/R = 1/R1 + 1/R2,

with R2 negative for a concave surface (internal contact: the roller inside a concave flank).
On a cam, R1 is the roller's radius Rr and R2 the cam surface's signed radius of curvature
ρ = ρp − Rr (ρp the pitch curve's), so

    R = Rr·ρ/(Rr + ρ) = Rr·(1 − Rr·κp)     (κp = 1/ρp, the pitch curve's signed curvature),

which stays finite on a straight flank (κp = 0: R = Rr) and falls to 0 where the roller
undercuts (Rr·κp = 1).

References
----------
.. [1] K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985), ch. 4: §4.1
   (the relative curvature 1/R = 1/R1 + 1/R2) and §4.2 (the contact modulus E*; two-dimensional
   contact of cylinders, pp. 99-104: p0 = sqrt(P'·E*/(π·R)) for a load P' per unit length).
.. [2] W. C. Young, R. G. Budynas, *Roark's Formulas for Stress and Strain*, 7th ed.,
   McGraw-Hill (2002), table 14.1 (cylinder on cylinder): σc = 0.798·sqrt(p/(K_D·C_E)),
   K_D = D1·D2/(D1 + D2), C_E = (1 − ν1²)/E1 + (1 − ν2²)/E2 (the tests' second form).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ...curves.base import FloatArray


def effective_modulus_mpa(youngs_modulus_1_mpa: float, poisson_ratio_1: float, youngs_modulus_2_mpa: float,
                          poisson_ratio_2: float) -> float:
    """E* of two elastic bodies in contact: 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2.

    Parameters
    ----------
    youngs_modulus_1_mpa, youngs_modulus_2_mpa : float
        Young's moduli of the two bodies, in MPa [N/mm²].
    poisson_ratio_1, poisson_ratio_2 : float
        Their Poisson's ratios [-].

    Returns
    -------
    float
        The contact modulus E*, in MPa [N/mm²]; steel on steel (206 GPa, 0.3) gives 113 186.8 MPa.

    References
    ----------
    Johnson (1985), §4.2 (the contact modulus E*).
    """
    return 1.0 / ((1.0 - poisson_ratio_1**2) / youngs_modulus_1_mpa
                  + (1.0 - poisson_ratio_2**2) / youngs_modulus_2_mpa)


def roller_contact_radius_mm(roller_radius_mm: float, pitch_curvature_per_mm: ArrayLike) -> FloatArray:
    """The relative radius R of a roller on the cam surface: 1/R = 1/Rr + 1/ρ.

    Parameters
    ----------
    roller_radius_mm : float
        Rr, the roller's radius [mm].
    pitch_curvature_per_mm : array_like
        κp, the signed curvature of the pitch curve, positive where convex [1/mm].

    Returns
    -------
    ndarray
        R = Rr·(1 − Rr·κp) [mm] (= Rr·ρ/(Rr + ρ) with ρ = 1/κp − Rr the cam surface's signed
        radius of curvature); ≤ 0 where the roller undercuts the cam.

    References
    ----------
    Johnson (1985), §4.1 (1/R = 1/R1 + 1/R2, R2 < 0 for a concave surface).
    """
    kappa = np.asarray(pitch_curvature_per_mm, dtype=np.float64)
    return roller_radius_mm * (1.0 - roller_radius_mm * kappa)


def line_contact_pressure_mpa(normal_force_n: ArrayLike, width_mm: float, effective_modulus: float,
                              contact_radius_mm: ArrayLike) -> FloatArray:
    """The largest Hertz pressure of a line contact: p0 = sqrt(P·E*/(π·b·R)).

    Parameters
    ----------
    normal_force_n : array_like
        P, the normal force; where it is ≤ 0 the bodies do not touch and p0 = 0 [N].
    width_mm : float
        b, the length of the contact line [mm].
    effective_modulus : float
        E*, the contact modulus (:func:`effective_modulus_mpa`), in MPa [N/mm²].
    contact_radius_mm : array_like
        R, the relative radius of curvature (> 0) [mm].

    Returns
    -------
    ndarray
        p0, in MPa [N/mm²] (N·MPa/(mm·mm) under the root).

    References
    ----------
    Johnson (1985), §4.2: p0 = sqrt(P'·E*/(π·R)) with P' = P/b the load per unit length.
    """
    load = np.maximum(np.asarray(normal_force_n, dtype=np.float64), 0.0)
    return np.sqrt(load * effective_modulus / (math.pi * width_mm * np.asarray(contact_radius_mm, dtype=np.float64)))
