"""What an indexer's output drives: rigid parts, friction and work torque.

References
----------
.. [1] INDEXMAN guide, 特性值说明 (B-27): size by the load torque on the output; it prints no load formulas.
.. [2] Standard rigid-body moments of inertia and the parallel-axis (Steiner) rule.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from .._checks import count, finite, non_negative, positive
from ..errors import InvalidParameterError

#: standard gravity [m/s²] (CGPM 1901), used for friction torque μ·m·g·R.
G = 9.80665

_SHAPES = ("disc", "ring", "block", "point")


# --------------------------------------------------------------------------- loads
@dataclass(frozen=True, kw_only=True)
class LoadPart:
    """One rigid part (or ``count`` equal parts) turning with the output.

    Parameters
    ----------
    shape : {"disc", "ring", "block", "point"}
        disc: solid cylinder of diameter D; ring: hollow cylinder D, d; block: a × b
        rectangle (the sides perpendicular to the axis); point: a point mass.
    mass_kg : float
        Mass of one part (≥ 0) [kg].
    diameter_mm, inner_diameter_mm : float
        D (disc, ring) and d ≤ D (ring) [mm].
    a_mm, b_mm : float
        Block sides perpendicular to the axis [mm].
    offset_mm : float
        Distance of the part's own axis (centre of mass) from the output axis (≥ 0) [mm].
    count : int
        Number of equal parts (e.g. fixtures on a pitch circle), ≥ 1.

    References
    ----------
    Standard rigid-body moments of inertia about the centroid axis: disc m·D²/8,
    ring m·(D² + d²)/8, block m·(a² + b²)/12, point 0; parallel-axis (Steiner)
    rule I = I_c + m·r².
    """

    shape: str
    mass_kg: float
    diameter_mm: float | None = None
    inner_diameter_mm: float | None = None
    a_mm: float | None = None
    b_mm: float | None = None
    offset_mm: float = 0.0
    count: int = 1

    def __post_init__(self) -> None:
        put = object.__setattr__
        shape = str(self.shape).strip().lower()
        if shape not in _SHAPES:
            raise InvalidParameterError(f"shape must be one of {', '.join(_SHAPES)}, not {self.shape!r}.")
        put(self, "shape", shape)
        put(self, "mass_kg", non_negative("mass_kg", self.mass_kg))
        put(self, "offset_mm", non_negative("offset_mm", self.offset_mm))
        put(self, "count", count("count", self.count))
        needs = {"disc": ("diameter_mm",), "ring": ("diameter_mm", "inner_diameter_mm"),
                 "block": ("a_mm", "b_mm"), "point": ()}[shape]
        for name in needs:
            if getattr(self, name) is None:
                raise InvalidParameterError(f"a {shape} part needs {name}.")
        for name in ("diameter_mm", "inner_diameter_mm", "a_mm", "b_mm"):
            if getattr(self, name) is not None:
                put(self, name, non_negative(name, getattr(self, name)))
        if shape == "ring" and self.inner_diameter_mm > self.diameter_mm:  # type: ignore[operator]
            raise InvalidParameterError(
                f"a ring needs inner_diameter_mm ≤ diameter_mm, got {self.inner_diameter_mm!r} > {self.diameter_mm!r}."
            )

    @property
    def total_mass_kg(self) -> float:
        """count·m [kg]."""
        return self.count * self.mass_kg

    @property
    def own_inertia_kgm2(self) -> float:
        """Inertia of one part about its own axis [kg·m²]."""
        m = self.mass_kg
        if self.shape == "disc":
            return m * (self.diameter_mm * 1e-3) ** 2 / 8.0  # type: ignore[operator]
        if self.shape == "ring":
            d_out, d_in = float(self.diameter_mm or 0.0), float(self.inner_diameter_mm or 0.0)
            return m * ((d_out * 1e-3) ** 2 + (d_in * 1e-3) ** 2) / 8.0
        if self.shape == "block":
            return m * ((self.a_mm * 1e-3) ** 2 + (self.b_mm * 1e-3) ** 2) / 12.0  # type: ignore[operator]
        return 0.0

    @property
    def inertia_kgm2(self) -> float:
        """count·(I_own + m·r²) about the output axis [kg·m²]."""
        return self.count * (self.own_inertia_kgm2 + self.mass_kg * (self.offset_mm * 1e-3) ** 2)


@dataclass(frozen=True, kw_only=True)
class Load:
    """What the output drives (field names as docs/api.md ``LoadSpec``).

    Parameters
    ----------
    inertia_kgm2 : float
        Inertia given directly (≥ 0), added to the parts' [kg·m²].
    parts : sequence of LoadPart
        Parts summed with the parallel-axis rule.
    friction_coefficient : float, optional
        μ (≥ 0); with ``friction_radius_mm`` gives Tf = μ·(Σm)·g·R over the parts' masses.
    friction_radius_mm : float, optional
        R, radius at which the friction acts (≥ 0) [mm].
    friction_torque_nm : float, optional
        Tf given directly (≥ 0) [N·m]; not together with ``friction_coefficient``.
    work_torque_nm : float
        Tw, torque the process needs while indexing (≥ 0) [N·m]. Default 0.
    service_factor : float
        fc ≥ 1. Default 1.5.
    efficiency : float
        η of the drive to the input shaft, 0 < η ≤ 1. Default 1.
    gear_ratio : float
        g, output-shaft turns per dial turn (> 0) [-]: the parts, inertia, friction and work
        torque above are the dial's, reflected to the output shaft through a lossless gear or
        belt as I/g² and T/g. Default 1 (the dial is on the output shaft).
    dwell_torque_nm : float
        External torque on the dial held while it stands still (≥ 0) [N·m]. Default 0.
    """

    inertia_kgm2: float = 0.0
    parts: Sequence[LoadPart] = ()
    friction_coefficient: float | None = None
    friction_radius_mm: float | None = None
    friction_torque_nm: float | None = None
    work_torque_nm: float = 0.0
    service_factor: float = 1.5
    efficiency: float = 1.0
    gear_ratio: float = 1.0
    dwell_torque_nm: float = 0.0

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "inertia_kgm2", non_negative("inertia_kgm2", self.inertia_kgm2))
        parts = tuple(self.parts)
        for i, p in enumerate(parts):
            if not isinstance(p, LoadPart):
                raise InvalidParameterError(f"parts[{i}] must be a LoadPart, not {type(p).__name__}.")
        put(self, "parts", parts)
        if self.friction_coefficient is not None:
            if self.friction_torque_nm is not None:
                raise InvalidParameterError(
                    "give friction_coefficient (with friction_radius_mm) or friction_torque_nm, not both."
                )
            put(self, "friction_coefficient", non_negative("friction_coefficient", self.friction_coefficient))
            if self.friction_radius_mm is None:
                raise InvalidParameterError("friction_coefficient needs friction_radius_mm (friction torque μ·m·g·R).")
            if not parts:
                raise InvalidParameterError(
                    "friction_coefficient needs parts with mass_kg (friction torque μ·m·g·R uses the parts' "
                    "masses); give friction_torque_nm directly instead."
                )
        elif self.friction_radius_mm is not None:
            raise InvalidParameterError("friction_radius_mm needs friction_coefficient (friction torque μ·m·g·R).")
        if self.friction_radius_mm is not None:
            put(self, "friction_radius_mm", non_negative("friction_radius_mm", self.friction_radius_mm))
        if self.friction_torque_nm is not None:
            put(self, "friction_torque_nm", non_negative("friction_torque_nm", self.friction_torque_nm))
        put(self, "work_torque_nm", non_negative("work_torque_nm", self.work_torque_nm))
        fc = finite("service_factor", self.service_factor)
        if fc < 1:
            raise InvalidParameterError(f"service_factor must be at least 1, got {fc!r}.")
        put(self, "service_factor", fc)
        eta = finite("efficiency", self.efficiency)
        if not 0 < eta <= 1:
            raise InvalidParameterError(f"efficiency must satisfy 0 < η ≤ 1, got {eta!r}.")
        put(self, "efficiency", eta)
        put(self, "gear_ratio", positive("gear_ratio", self.gear_ratio))
        put(self, "dwell_torque_nm", non_negative("dwell_torque_nm", self.dwell_torque_nm))

    @property
    def mass_kg(self) -> float:
        """Σ count·m over the parts [kg]."""
        return float(sum(p.total_mass_kg for p in self.parts))

    @property
    def total_inertia_kgm2(self) -> float:
        """inertia_kgm2 + Σ parts [kg·m²]."""
        return self.inertia_kgm2 + float(sum(p.inertia_kgm2 for p in self.parts))

    @property
    def total_friction_torque_nm(self) -> float:
        """Tf: given, or μ·(Σm)·g·R [N·m]; 0 when neither is given."""
        if self.friction_torque_nm is not None:
            return float(self.friction_torque_nm)
        if self.friction_coefficient is not None:
            radius_m = float(self.friction_radius_mm or 0.0) * 1e-3
            return self.friction_coefficient * self.mass_kg * G * radius_m
        return 0.0

    @property
    def output_inertia_kgm2(self) -> float:
        """The dial's inertia at the output shaft, I/g² [kg·m²]."""
        return self.total_inertia_kgm2 / self.gear_ratio**2

    @property
    def output_friction_torque_nm(self) -> float:
        """The dial's friction torque at the output shaft, Tf/g [N·m]."""
        return self.total_friction_torque_nm / self.gear_ratio

    @property
    def output_work_torque_nm(self) -> float:
        """The work torque at the output shaft, Tw/g [N·m]."""
        return float(self.work_torque_nm) / self.gear_ratio
