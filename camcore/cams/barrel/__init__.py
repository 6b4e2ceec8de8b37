"""Barrel (cylindrical) cams: a roller in a groove cut into a cylinder.

Frames and conventions
----------------------
* The cam axis is z. The cam turns by the cam angle θ clockwise seen from +z, so that in the
  cam's own frame the follower advances counter-clockwise: a point of the cam's frame at polar
  angle φ is, in the fixed frame, at φ − θ. Cam-frame points are fixed-frame points turned by +θ.
* In the fixed frame the roller's axis is parallel to x (radial at the follower), its points at
  distance x along it from the plane x = 0; the roller works between x_in = R − ℓ/2 and
  x_out = R + ℓ/2 (R the pitch radius, ℓ the roller's length).
* Translating follower: the roller's axis is the line (x, 0, s(θ)); the follower moves along z.
* Oscillating follower: the arm turns about the pivot axis, the line (x, −L, 0) parallel to x
  (L the arm length); the roller's axis is the line (x, L(cos ψa − 1), L sin ψa), ψa = ψ0 + ψ(θ)
  the arm angle (ψ0 at zero swing, ψ the swing). At ψa = 0 the arm is square to the cam axis and
  the roller's axis meets it; otherwise the axis lies b_y = L(cos ψa − 1) off it.
* Developed groove: the pitch cylinder (radius R) unrolled, u = R·φ along the circumference
  (φ the cam-frame polar angle), y = z along the axis. The groove's centreline is where the
  roller's axis crosses the pitch cylinder: u = R·(θ + asin(b_y/R)), y = b_z, so u = R·θ and
  y = s for the translating follower, and y = L sin ψa with u shifted back by R·asin(b_y/R)
  for the oscillating one.

Contact
-------
A point of the roller's surface at (x, β) is Q(x) + ρ(x)·n(β), n = (0, cos β, sin β), Q(x) the
axis point and ρ(x) the roller's radius there (ρ for a cylinder; x·tan α for a cone). It
touches the groove wall where the surface normal is square to the velocity of that point
relative to the cam (the envelope condition). The cam's material moves with (P_y, −P_x, 0) per
radian; the follower point with s'·ẑ (translating) or ψ'·x̂ × (P − pivot) (oscillating). This
gives a·sin β + c·cos β = 0, with

* translating: a = cos²α·s', c = x (α = 0: cylinder);
* oscillating (cylinder): a = ψ'L cos ψa, c = x − ψ'L sin ψa,

so the two flanks' normals are n = ±(−a, c)/√(a² + c²) ("upper": the +z side, "lower").
The pressure angle at x is the angle between that normal and the follower point's direction of
motion: tan φ = a/c for the translating follower — (ds/dθ)/r for a cylindrical roller, the
textbook value — and tan φ = (ψ'L − x sin ψa)/(x cos ψa) for the oscillating one. A cone's
normal also leans along its axis by α (a thrust on the roller's bearing, not a side load on
the follower); the angle reported is that of the normal's part square to the roller's axis.

A cone with its apex on the cam axis (x = 0) has ρ(x) ∝ x: every point of its contact line
rolls on the groove wall at the wall's own speed where the groove runs round the cylinder.
An oscillating arm moves the roller's axis off the cam axis by L(1 − cos ψa), so the apex
cannot stay there: a conical roller is offered on the translating follower only.

The flanks in the developed plane are the pitch curve offset by ±ρ (ρ the roller's radius at
the pitch radius); their radius of curvature is 1/κ − ρ (upper) and −1/κ − ρ (lower), κ the
signed curvature of the developed pitch curve (positive bending towards +y), so a positive
radius is a flank convex towards the roller and a negative one concave. The roller cannot
generate a convex flank whose radius would be ≤ 0: that is undercut, reported in the checks as
the plate cam's checks report it.

The envelope condition and the formulas above are derived here; the tests check them against
a direct construction (every flank point lies on the roller and outside the roller at all
neighbouring cam angles; the oscillating centreline from the arm turned in 3-D).

References
----------
.. [1] S. Shinzato, M. Kunigami (1988), eq. (6): the pressure angle of a knife-edge plate cam
   with a uniform rise, β = atan((ℓ − D/2)/(θ·ℓ)) = atan(s'/ℓ), the lift's rate over the radius ℓ
   of the contact; on the developed groove the radius is R (or r across the roller), tan φ = s'/R.
"""

from .compute import BarrelChecks, BarrelFlank, BarrelResult, barrel_checks, barrel_profile, corners, sample_barrel
from .geometry import BarrelCam, check_barrel_geometry, check_grid, flank_points, make_barrel_cam

__all__ = [
    "BarrelCam", "BarrelChecks", "BarrelFlank", "BarrelResult", "barrel_checks", "barrel_profile",
    "check_barrel_geometry", "check_grid", "corners", "flank_points", "make_barrel_cam", "sample_barrel",
]
