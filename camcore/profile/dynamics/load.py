"""What holds a force-closed follower on its cam: mass or inertia, spring, preload, external
force and damping, for a translating or an oscillating follower; and the materials of a roller.

The two loads give the same equation of motion in the follower's own coordinate q (the lift
in metres, or the swing in radians),

    Q = M·q̈ + C·q̇ + K·q + Q0 + Q_ext,

where Q is the force [N] (or the torque about the pivot [N·m]) the cam must exert on the
follower along its motion, so a negative Q means the follower leaves the cam. Each load
turns its own units (N/mm, N·m/rad, …) into these SI coefficients (:meth:`coefficients`).

References
----------
.. [1] R. L. Norton, *Cam Design and Manufacturing Handbook*, Industrial Press: the
   dynamic force of a force-closed (spring-loaded) follower, F = m·a + c·v + k·x + F_pl.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..._checks import finite, non_negative, positive
from ...errors import InvalidParameterError

#: steel, the default of both bodies in contact: E = 206 GPa, ν = 0.3
STEEL_YOUNGS_MODULUS_MPA = 206_000.0
STEEL_POISSON_RATIO = 0.3


@dataclass(frozen=True)
class Coefficients:
    """M, C, K, Q0, Q_ext of Q = M·q̈ + C·q̇ + K·q + Q0 + Q_ext in SI units.

    q in m (translating) or rad (oscillating); Q in N or N·m. So M is in kg or kg·m², C in
    N·s/m or N·m·s/rad, K in N/m or N·m/rad, Q0 and Q_ext in N or N·m.
    """

    mass: float
    damping: float
    stiffness: float
    preload: float
    external: float


@dataclass(frozen=True)
class TranslatingLoad:
    """A translating follower held on its cam by a spring.

    ``mass_kg`` (> 0): the follower's moving mass, with the spring's share; ``spring_rate_n_mm``
    (> 0); ``preload_n``: the spring force at zero lift (may be negative: the spring then pulls
    the follower off at the base circle); ``external_force_n``: a constant force, positive
    pressing the follower onto the cam (its weight when it stands above the cam, a process
    force); ``damping_n_s_mm`` (≥ 0): viscous damping of the follower's motion.
    """

    mass_kg: float
    spring_rate_n_mm: float
    preload_n: float = 0.0
    external_force_n: float = 0.0
    damping_n_s_mm: float = 0.0

    motion = "translating"

    def __post_init__(self) -> None:
        positive("mass_kg", self.mass_kg)
        positive("spring_rate_n_mm", self.spring_rate_n_mm)
        finite("preload_n", self.preload_n)
        finite("external_force_n", self.external_force_n)
        non_negative("damping_n_s_mm", self.damping_n_s_mm)

    def coefficients(self) -> Coefficients:
        """The SI coefficients: N/mm and N·s/mm are ×1000 per metre."""
        return Coefficients(self.mass_kg, 1e3 * self.damping_n_s_mm, 1e3 * self.spring_rate_n_mm, self.preload_n,
                            self.external_force_n)


@dataclass(frozen=True)
class OscillatingLoad:
    """An oscillating follower (an arm about its pivot) held on its cam by a spring.

    ``inertia_kgm2`` (> 0): the arm's inertia about the pivot; ``spring_rate_nm_rad`` (> 0);
    ``preload_nm``: the spring torque at zero swing; ``external_torque_nm``: a constant torque,
    positive pressing the follower onto the cam; ``damping_nm_s_rad`` (≥ 0).
    """

    inertia_kgm2: float
    spring_rate_nm_rad: float
    preload_nm: float = 0.0
    external_torque_nm: float = 0.0
    damping_nm_s_rad: float = 0.0

    motion = "oscillating"

    def __post_init__(self) -> None:
        positive("inertia_kgm2", self.inertia_kgm2)
        positive("spring_rate_nm_rad", self.spring_rate_nm_rad)
        finite("preload_nm", self.preload_nm)
        finite("external_torque_nm", self.external_torque_nm)
        non_negative("damping_nm_s_rad", self.damping_nm_s_rad)

    def coefficients(self) -> Coefficients:
        """The SI coefficients (already SI: the swing in radians)."""
        return Coefficients(self.inertia_kgm2, self.damping_nm_s_rad, self.spring_rate_nm_rad, self.preload_nm,
                            self.external_torque_nm)


FollowerLoad = TranslatingLoad | OscillatingLoad


@dataclass(frozen=True)
class RollerMaterials:
    """A roller's width and the elastic constants of roller and cam, for the Hertz stress.

    ``width_mm`` (> 0): the length of the line contact; Young's moduli (> 0) [MPa] and
    Poisson's ratios (0 … 0.5) of the roller and of the cam; the cam's default to the roller's.
    """

    width_mm: float
    youngs_modulus_mpa: float = STEEL_YOUNGS_MODULUS_MPA
    poisson_ratio: float = STEEL_POISSON_RATIO
    cam_youngs_modulus_mpa: float | None = None
    cam_poisson_ratio: float | None = None

    def __post_init__(self) -> None:
        positive("roller width_mm", self.width_mm)
        positive("roller youngs_modulus_mpa", self.youngs_modulus_mpa)
        if self.cam_youngs_modulus_mpa is not None:
            positive("roller cam_youngs_modulus_mpa", self.cam_youngs_modulus_mpa)
        for name, nu in (("poisson_ratio", self.poisson_ratio), ("cam_poisson_ratio", self.cam_poisson_ratio)):
            if nu is not None and not (math.isfinite(nu) and 0.0 <= nu <= 0.5):
                raise InvalidParameterError(f"roller {name} must lie between 0 and 0.5, got {nu!r}.")

    @property
    def cam_modulus_mpa(self) -> float:
        """The cam's Young's modulus (the roller's when not given) [MPa]."""
        return self.youngs_modulus_mpa if self.cam_youngs_modulus_mpa is None else self.cam_youngs_modulus_mpa

    @property
    def cam_poisson(self) -> float:
        """The cam's Poisson's ratio (the roller's when not given) [-]."""
        return self.poisson_ratio if self.cam_poisson_ratio is None else self.cam_poisson_ratio
