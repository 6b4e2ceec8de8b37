"""Roller-gear (globoidal) indexing cams: a rib on a globoidal cam driving rollers on a turret.

Frames and conventions
----------------------
* The cam (input) axis is the z axis through O; the turret (output) axis is the line through
  A = (C, 0, 0) along y, square to the cam axis and C = ``center_distance_mm`` from it. The cam
  turns counter-clockwise seen from +z by the cam angle θ; the flanks are given in the cam's own
  frame, the cam at θ = 0 (a fixed-frame point p is R_z(−θ)·p there). θ = 0 is the start of an
  index.
* The rollers stand on the turret's rim with their axes radial, in the plane y = 0: a roller at
  turret angle α (from the line A→O) has the axis direction u(α) = (−cos α, 0, sin α) and works
  from r_in = Rp − ℓ/2 to r_out = Rp + ℓ/2 along it (Rp the rollers' pitch radius, ℓ their
  length), so its axis points are A + r·u(α) and its point at the pitch radius faces the cam.
  The turret turns about +y, moving every roller along w(α) = (sin α, 0, cos α) = du/dα.
* The rib runs once round the cam between two neighbouring rollers, which together make both
  its flanks over the whole turn: the roller ahead of the rib at α = φ(θ) and the roller behind
  it at α = φ(θ) − h (φ the turret's turn, the indexer's law over the index, h = 360°/stops, then
  standing in the dwell and advancing by h each turn). In the dwell before the index they stand
  at −h and 0 and after it at 0 and h: the index is centred on the line of centres and the cam
  is symmetric through the cam's centre, its rib one pitch wide in turret angle (|α| ≤ h,
  whence stops ≥ 5: at h = 90° a roller would face the cam along its own axis).
* The "forward" flank faces the roller ahead (it pushes the turret on) and the "back" flank the
  roller behind (it holds the turret back when it would overrun).

Contact
-------
A point of the roller's surface is P = A + r·u + Rr·n, n = σ(cos β·w + sin β·ŷ) (σ = +1 for the
roller behind the rib, whose rib is along +w; σ = −1 for the roller ahead), Rr the roller's radius.
It touches the rib where n is square to the velocity of P relative to the cam (the envelope
condition): the turret moves P by φ'·ŷ × (P − A) per radian of cam, the cam's material by ẑ × P,
and n·(φ'·ŷ × (P − A) − ẑ × P) = 0 reduces to

    tan β = φ'·r / (C − r·cos α),

the same for both flanks (derived here; the tests check it against an independent construction:
every flank point at the roller's radius from its axis and outside it at neighbouring cam angles).
The force between rib and roller acts along n, the roller's axis point moves along w: β is the
pressure angle, atan(φ'·Rp / (C − Rp·cos α)) at the pitch radius, 0 in the dwell.

The flank is the surface Q(θ, r) = R_z(−θ)·P in the cam's frame. It is undercut where it folds:
where the normal of the parametrisation, Q_θ × Q_r, turns against n (the roller would cut away
flank it has made). Q_θ and Q_r are taken analytically from φ, φ', φ'' (the tests compare them
with finite differences of the grid).

References
----------
.. [1] INDEXMAN technical guide, sections 1 and 2-1 to 2-4 (the roller-gear mechanism, n = 360/ψ,
   θh) and section 5 (the index law the turret follows).
.. [2] F. L. Litvin, A. Fuentes, "Gear Geometry and Applied Theory", 2nd ed., Cambridge
   University Press (2004), ch. 6: the envelope of a family of surfaces, n·v_rel = 0, and its
   singular points.
"""

from .compute import RibChecks, RibFlank, RollerGearResult, rib_triangles, sample_roller_gear
from .geometry import (
    FLANKS,
    RollerGearCam,
    check_roller_gear_geometry,
    flank_state,
    make_roller_gear_cam,
    pressure_angle_rad,
)

__all__ = [
    "FLANKS", "RibChecks", "RibFlank", "RollerGearCam", "RollerGearResult", "check_roller_gear_geometry",
    "flank_state", "make_roller_gear_cam", "pressure_angle_rad", "rib_triangles", "sample_roller_gear",
]
