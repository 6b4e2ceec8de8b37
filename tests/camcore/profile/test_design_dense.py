"""Plate-cam design against dense brute-force grids (``property``: tens of seconds each).

Every grid point is judged by the existing checks alone (:func:`profile_checks` for the geometry,
:func:`follower_dynamics` for the margin and the Hertz pressure), never by the design's own code; the
grid's best feasible cam must not be smaller than the answer by more than the search's tolerance.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from camcore.profile import CamSpec, profile_checks
from camcore.profile.design import DesignLimits, DesignProblem, FollowerLoad, design_profile
from camcore.profile.dynamics import RollerMaterials, TranslatingLoad, follower_dynamics
from tests.camcore.profile.test_design import ARM, OSCILLATING, ROLLER, cam, meets, smallest_on_grid

pytestmark = pytest.mark.property


def test_a_dense_grid_over_offset_and_roller() -> None:
    limits = DesignLimits(max_pressure_angle_deg=30, min_radius_of_curvature_mm=20)
    free = {"base_radius_mm": (10.0, 200.0), "offset_mm": (-30.0, 30.0), "roller_radius_mm": (5.0, 20.0)}
    result = design_profile(DesignProblem(cam(), free, limits))
    rb = result.design.base_radius_mm
    radii = np.arange(10.0, rb + 0.5, 0.002)
    best, where = math.inf, None
    for e in np.linspace(-30, 30, 61):
        for r in np.linspace(5, 20, 31):
            spec = replace(result.cam, follower=replace(ROLLER, offset_mm=float(e), roller_radius_mm=float(r)))
            found = smallest_on_grid(spec, limits, radii)
            if found < best:
                best, where = found, (e, r)
    # 61 × 31 points 1 mm and 0.5 mm apart, radii 2 µm apart: none is a smaller feasible cam than the answer
    # (by more than the search's tolerance, 1e-3 mm), and the best of them is within its steps' effect
    assert best >= rb - 1e-3, (best, where, rb)
    assert best <= rb + 0.5, (best, where, rb)


def _feasible(spec: CamSpec, load: TranslatingLoad, rpm: float, margin: float, roller: RollerMaterials,
              limits: DesignLimits) -> bool:
    """The geometry by profile_checks, the margin and the stress by follower_dynamics."""
    if not meets(spec, limits):
        return False
    try:
        run = follower_dynamics(spec, load, rpm, 2, safety_margin_n=margin, roller=roller)
    except ValueError:
        return False
    stress = run.summary.max_contact_stress_mpa
    return (run.summary.min_contact_force_n >= margin * (1 - 1e-9) and stress is not None
            and stress <= float(limits.allowed_stress_mpa or math.inf) * (1 + 1e-9))


def test_the_stress_and_spring_trade_against_a_grid() -> None:
    # the stress decides the base radius here (200 MPa is near the least any spring gives): no grid point of
    # offset, roller and spring rate (each with the smallest preload that holds, by follower_dynamics) is
    # feasible by the checks below the answer; the stress is not monotone in the radius (a concave flank
    # flattens), so each grid point scans the radii rather than bisecting them
    roller = RollerMaterials(12.0)
    limits = DesignLimits(max_pressure_angle_deg=30, min_radius_of_curvature_mm=15, safety_margin_n=5,
                          allowed_stress_mpa=205)
    free = {"base_radius_mm": (10.0, 200.0), "offset_mm": (-30.0, 30.0), "roller_radius_mm": (5.0, 20.0),
            "spring_rate_n_mm": (0.5, 50.0), "preload_n": (0.0, 500.0)}
    result = design_profile(DesignProblem(cam(), free, limits, FollowerLoad(0.5, (600.0, 600.0), roller=roller)))
    rb = result.design.base_radius_mm
    e0, r0, k0 = result.design.offset_mm, result.design.roller_radius_mm, result.design.spring_rate_n_mm
    assert e0 is not None and r0 is not None and k0 is not None
    below = rb - np.linspace(2e-3, 2.0, 12)  # radii from 2 µm to 2 mm below the answer
    for e in e0 + np.array([-2.0, -0.5, 0.0, 0.5, 2.0]):
        for r in (r0, max(5.0, r0 - 1.0)):
            for k in k0 * np.array([0.5, 0.8, 0.95, 1.0, 1.05, 1.25, 2.0]):
                preload = follower_dynamics(replace(cam(), base_radius_mm=rb), TranslatingLoad(0.5, float(k), 0.0),
                                            600.0, 2, safety_margin_n=5).summary.min_preload_n
                assert preload is not None
                load = TranslatingLoad(0.5, float(k), max(0.0, preload))
                spec = replace(result.cam, follower=replace(ROLLER, offset_mm=float(e), roller_radius_mm=float(r)))
                for radius in below:
                    assert not _feasible(replace(spec, base_radius_mm=float(radius)), load, 600.0, 5.0, roller,
                                         limits), (e, r, k, radius, rb)


def test_an_arm_s_roller_against_a_grid() -> None:
    limits = DesignLimits(max_pressure_angle_deg=40, min_radius_of_curvature_roller_multiple=0.5)
    free = {"base_radius_mm": (5.0, 60.0), "roller_radius_mm": (3.0, 15.0)}
    result = design_profile(DesignProblem(cam(ARM, OSCILLATING, rb=25.0), free, limits))
    rb = result.design.base_radius_mm
    checks = profile_checks(result.cam)
    assert checks.max_pressure_angle_deg <= 40 * (1 + 1e-9)
    radii = np.arange(5.0, rb + 0.2, 0.002)
    for r in np.linspace(3, 15, 49):
        spec = replace(result.cam, follower=replace(ARM, roller_radius_mm=float(r)))
        # an arm's limits hold on an interval of radii: the grid's first feasible one, scanned upward
        feasible = [x for x in radii[::25] if meets(replace(spec, base_radius_mm=float(x)), limits)]
        if feasible:
            fine = [x for x in radii if feasible[0] - 0.06 <= x <= feasible[0]
                    and meets(replace(spec, base_radius_mm=float(x)), limits)]
            assert min(fine) >= rb - 1e-3, (r, min(fine), rb)
