"""The roller-gear cam's patches (camcore.cams.roller_gear.surfaces), checked without the CAD kernel.

The patches are evaluated here by scipy's B-splines (their knots and poles as a B-spline surface
defines them), and compared with the exact flank at the same cam angle and share of the way from the
rib's top to the body, the crossings of the tori found by the tests' own bisection
(tests/roller_gear_reference.py); the dimensions against scans and closed forms.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import BSpline

from camcore.cams.roller_gear import flank_state, make_roller_gear_cam
from camcore.cams.roller_gear.surfaces import FIT_SHARE, Patch, fit_rib_surfaces
from tests import roller_gear_reference as ref

EXAMPLE = (8, 100.0, 60.0, 10.0, 20.0, 120.0, "MS")


def evaluate(patch: Patch, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The patch at parameter pairs (u, v), by scipy's B-spline basis in each direction [mm]."""
    knots_u = np.repeat(patch.u_knots, patch.u_mults)
    k = patch.v_degree + 1
    knots_v = np.concatenate([np.zeros(k), np.ones(k)])
    basis_u = BSpline.design_matrix(u, knots_u, 3).toarray()
    basis_v = BSpline.design_matrix(v, knots_v, patch.v_degree).toarray()
    return np.einsum("ni,nj,ijx->nx", basis_u, basis_v, patch.poles)


@pytest.fixture(scope="module")
def cam() -> object:
    return make_roller_gear_cam(*EXAMPLE)


def patches_of(fit: object) -> dict[tuple[str, str], Patch]:
    return {(p.band, p.part): p for p in fit.patches}  # type: ignore[attr-defined]


def test_each_patch_has_the_poles_its_knots_call_for(cam: object) -> None:
    fit = fit_rib_surfaces(cam, 0.01)  # type: ignore[arg-type]
    assert len(fit.patches) == 10
    for p in fit.patches:
        assert p.poles.shape == (int(p.u_mults.sum()) - 4, p.v_degree + 1, 3)
        assert (np.diff(p.u_knots) > 0).all() and p.u_mults[0] == p.u_mults[-1] == 4
        assert set(p.u_mults[1:-1].tolist()) <= {2, 3}  # C1 inside a piece, C0 where pieces join


def test_patches_share_their_boundaries_pole_for_pole(cam: object) -> None:
    fit = fit_rib_surfaces(cam, 0.01)  # type: ignore[arg-type]
    p = patches_of(fit)
    for part in ("index", "dwell"):
        pole = {band: p[(band, part)].poles for band in ("forward", "back", "top", "below", "above")}
        assert np.array_equal(pole["top"][:, 0], pole["forward"][:, 0])  # the rib's top edges
        assert np.array_equal(pole["top"][:, -1], pole["back"][:, 0])
        assert np.array_equal(pole["below"][:, -1], pole["back"][:, -1])  # the rib's root edges
        assert np.array_equal(pole["above"][:, 0], pole["forward"][:, -1])
        # the body's end circles in the planes z = ∓H, every pole
        assert (pole["below"][:, 0, 2] == -fit.half_length_mm).all()
        assert (pole["above"][:, -1, 2] == fit.half_length_mm).all()
    for band in ("forward", "back", "top", "below", "above"):  # index and dwell meet at θh
        # the same point from the law's last piece and from the dwell: φ'·1e-13 rad apart at most
        assert np.abs(p[(band, "index")].poles[-1] - p[(band, "dwell")].poles[0]).max() < 1e-9


#: 36 stops, a 72° pressure angle along the roller: the across polynomial the starting nodes chose falls
#: short between them (1.16e-3 mm against a 1e-3 target, however many cam angles), so the fit takes
#: more points across rather than cam angles without end
STEEP = (36, 448.7, 372.3, 7.23, 131.0, 211.3, "3-4-5")


@pytest.mark.parametrize(("case", "tolerance_mm"), [(EXAMPLE, 0.1), (EXAMPLE, 0.01), (EXAMPLE, 1e-3), (STEEP, 2e-3)])
def test_patches_lie_on_the_exact_flank_and_on_their_tori(case: tuple, tolerance_mm: float) -> None:
    cam = make_roller_gear_cam(*case)
    fit = fit_rib_surfaces(cam, tolerance_mm)
    rng = np.random.default_rng(4)
    r_in, r_out = cam.roller_ends_mm  # type: ignore[attr-defined]
    rr = cam.roller_radius_mm  # type: ignore[attr-defined]
    worst = 0.0
    for p in fit.patches:
        u = rng.uniform(p.u_knots[0], p.u_knots[-1], 300)
        v = rng.uniform(0.0, 1.0, 300)
        s = evaluate(p, u, v)
        if p.band in ("forward", "back"):
            top = ref.crossing(cam, p.band, u, fit.top_radius_mm, r_in - rr, r_out)  # type: ignore[arg-type]
            root = ref.crossing(cam, p.band, u, fit.root_radius_mm, r_in, r_out + 2 * rr)  # type: ignore[arg-type]
            exact = flank_state(cam, p.band, u, (top + v * (root - top))[:, None]).q[:, 0]  # type: ignore[arg-type]
            worst = max(worst, float(np.linalg.norm(s - exact, axis=-1).max()))
        else:
            radius = fit.top_radius_mm if p.band == "top" else fit.root_radius_mm
            assert np.abs(ref.torus_distance(fit.center_distance_mm, s) - radius).max() <= tolerance_mm
    # at the same (θ, s): a bound on the distance from the flank
    assert worst <= tolerance_mm
    assert fit.fit_deviation_mm <= FIT_SHARE * tolerance_mm


def test_the_dimensions_are_the_cam_s(cam: object) -> None:
    """R_top: the lowest point of the rollers' inner-end line (the tests' scan); R_root: the circle of the
    rollers' outer rims; H: the rib's extent, which in the dwell is r_out·sin h − Rr·cos h, and half a
    roller radius."""
    fit = fit_rib_surfaces(cam, 0.01)  # type: ignore[arg-type]
    stops, c, rp, rr, length, _, _ = EXAMPLE
    h = 2 * math.pi / stops
    assert fit.top_radius_mm == pytest.approx(ref.top_radius(cam), abs=1e-9)  # type: ignore[arg-type]
    assert fit.top_radius_mm < math.hypot(rp - length / 2, rr)  # below the dwell's: the index lowers it
    assert fit.root_radius_mm == math.hypot(rp + length / 2, rr)
    assert fit.rib_half_extent_mm == pytest.approx((rp + length / 2) * math.sin(h) - rr * math.cos(h), abs=1e-9)
    assert fit.half_length_mm == pytest.approx(fit.rib_half_extent_mm + 0.5 * rr, abs=1e-12)
    assert fit.throat_radius_mm == pytest.approx(c - fit.root_radius_mm)


def test_the_fit_converges_as_the_fourth_power_of_the_spacing(cam: object) -> None:
    nodes = {tol: fit_rib_surfaces(cam, tol).theta_nodes for tol in (1e-3, 1e-4, 1e-5)}  # type: ignore[arg-type]
    # the Hermite error goes as h⁴: ten times finer takes about 10^¼ = 1.78 times the nodes
    assert 1.3 < nodes[1e-4] / nodes[1e-3] < 2.5 and 1.3 < nodes[1e-5] / nodes[1e-4] < 2.5


@pytest.mark.parametrize("curve", ["simple-harmonic", "constant-acceleration"])
def test_a_law_whose_acceleration_jumps_is_fitted_piece_by_piece(curve: str) -> None:
    """Each piece's nodes take their own piece's formulas: with the dwell's first node taking the law's
    last piece (A ≠ 0 at its end for these) the dwell's fit converged as h, not h⁴ (1 318 nodes)."""
    fit = fit_rib_surfaces(make_roller_gear_cam(8, 100.0, 60.0, 10.0, 20.0, 150.0, curve), 0.01)
    assert fit.theta_nodes <= 60 and fit.fit_deviation_mm <= FIT_SHARE * 0.01
