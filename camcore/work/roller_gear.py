"""The roller-gear cam's solid (camcore.export.roller_gear_solid): its patches' cam angles, the kernel's
work and the facets of its mesh, known before any of it runs.

Measured on the reference machine with ``time.process_time`` around ``solid_step`` and ``solid_stl``
(the fit, the kernel's faces and sewing, the file), best of three, over eleven cams (5 to 72 stops,
C from 10 to 1 000 mm, θh from 30° to 359°, the laws MS, MT, cycloid and constant acceleration) at
tolerances from 10 mm to 1e-4 mm.

References
----------
.. [1] C. de Boor, "A Practical Guide to Splines", Springer (1978), ch. IV: a cubic Hermite
   interpolant's error goes as h⁴, so its nodes as (size/tolerance)^¼.
"""

from __future__ import annotations

import math

#: the patches' cam angles over the turn, at most, as RIB_NODES_BASE + RIB_NODES_PER_ROOT·(C/tol)^¼:
#: measured 7-234 against this bound's 25-357 on the eleven cams (the closest 170 against 210: five
#: stops, MT, 1e-4 mm); over 304 random cams that have a solid (5-72 stops, C 20-500 mm, θh 20-340°,
#: eleven laws, 1e-4 ≤ tol ≤ 0.1 mm) 4 took more, at most 23 % more
RIB_NODES_BASE = 20
RIB_NODES_PER_ROOT = 6.0
#: solid_step's time: at most 0.05 s + 2.2 ms per estimated cam angle over the 304 random cams (0.45 s
#: the longest, the median 0.35 ms an angle; 0.09 s for the service's example); ×1.5 of 0.05 s + 2.5 ms
RIB_SOLID_BASE_S = 1.5 * 0.05
RIB_SOLID_NODE_S = 1.5 * 2.5e-3
#: solid_stl's time per facet of the estimate (rib_solid_facets), the fit and sewing included: 5.9-9.4
#: µs up to 200 000 facets, 13.7 µs at 1.1 million (three cams, 0.2 ≥ tol ≥ 0.002 mm); ×1.5 of 1e-5
RIB_STL_FACET_S = 1.5 * 1e-5
#: the facets counted over the formula's, at most: 1.22-1.44 on five cams (5-16 stops, 0.5 ≥ δ ≥ 5e-4 mm),
#: with a quarter more kept; and the facets a coarse mesh has whatever δ (1 804 at δ = 0.5 on the example
#: of the service, where the formula gives 1 650)
FACETS_MARGIN = 1.8
FACETS_FLOOR = 2000


def rib_nodes_estimate(center_distance_mm: float, tolerance_mm: float) -> int:
    """The cam angles a roller-gear cam's patches take over the turn, at most, before they are fitted.

    Parameters
    ----------
    center_distance_mm : float
        C: the cam's size [mm].
    tolerance_mm : float
        The flanks' tolerance [mm].

    Returns
    -------
    int
        RIB_NODES_BASE + RIB_NODES_PER_ROOT·(C/tol)^¼, rounded up [-].

    References
    ----------
    de Boor (1978), ch. IV (the Hermite error as h⁴); the measurements beside the constants.
    """
    return RIB_NODES_BASE + math.ceil(RIB_NODES_PER_ROOT * (center_distance_mm / tolerance_mm) ** 0.25)


def rib_solid_facets(stops: int, center_distance_mm: float, roller_pitch_radius_mm: float, roller_radius_mm: float,
                     roller_length_mm: float, deflection_mm: float) -> int:
    """The facets of the kernel's mesh of a roller-gear cam at a chordal deviation, before meshing.

    Parameters
    ----------
    stops : int
        Stops per turret turn [-].
    center_distance_mm, roller_pitch_radius_mm, roller_radius_mm, roller_length_mm : float
        C, Rp, Rr, ℓ [mm].
    deflection_mm : float
        The mesh's chordal deviation δ [mm].

    Returns
    -------
    int
        Σ A/(4·δ·√(R1·R2)) over the body's root, the rib's top and the flanks, times FACETS_MARGIN,
        plus FACETS_FLOOR [-]. Each surface's area A and radii of curvature from the dimensions: the
        tori (their tube radius, and their ring's radius at half their swing), the flanks (the roller
        radius, the cam's radius at the pitch radius); the body's half length the dwell's rib extent,
        r_out·sin h − Rr·cos h, and half a roller radius.

    References
    ----------
    A chord of length a on a circle of radius R has the sagitta a²/(8R): a doubly curved surface
    meshed to the deviation δ has facets of sides √(8·R1·δ) and √(8·R2·δ), two per such square.
    """
    c, rp, rr = center_distance_mm, roller_pitch_radius_mm, roller_radius_mm
    r_in, r_out = rp - 0.5 * roller_length_mm, rp + 0.5 * roller_length_mm
    h = 2 * math.pi / stops
    half = r_out * math.sin(h) - rr * math.cos(h) + 0.5 * rr
    total = (r_out - r_in) * 4 * math.pi * (c - rp) / (4 * math.sqrt(rr * (c - rp)))  # the two flanks
    for radius in (math.hypot(r_out, rr), math.hypot(r_in, rr)):  # the body's root, the rib's top
        chi = math.asin(min(1.0, half / radius))
        area = 2 * math.pi * radius * (2 * c * chi - 2 * radius * math.sin(chi))
        total += area / (4 * math.sqrt(radius * (c - radius * math.cos(0.5 * chi))))
    return math.ceil(FACETS_MARGIN * total / deflection_mm) + FACETS_FLOOR
