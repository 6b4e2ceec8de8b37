"""camcore.dynamics: the residual-vibration spectrum against exact values and an independent method.

The method under test evaluates the Duhamel integral of the follower equation in closed form
on Chebyshev subcells, with a complex first-order state (camcore/dynamics/_response.py). The
checks, each independent of it:

- the cycloid's residual amplitude in closed form, undamped and damped (derived below);
- an impulse (a velocity jump) and the free vibration it leaves, in closed form;
- every catalog curve at many τ and ζ against the equation stepped in time by RK4 with
  Richardson's extrapolation (tests/vibration_reference.py), whose own error estimate is
  asserted first, so a disagreement can only be the method's.

The contract (docs/api.md) promises 1e-9 of the stroke; the comparisons assert 1e-10, which
leaves the reference's error (asserted ≤ 1e-11) ten times inside it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcore
from camcore.curves import Curve, build_curve
from camcore.dynamics import TAU_MAX, TAU_MIN, FollowerResponse, residual_vibration
from camcore.errors import InvalidParameterError
from tests.vibration_reference import reference

#: the contract's 1e-9, with the reference's error (≤ 1e-11, asserted) ten times inside
AGREE = 1e-10
REFERENCE_ERROR = 1e-11
CATALOG = [entry.build() for entry in camcore.CATALOG.values()]
NAMES = list(camcore.CATALOG)


def cycloid_residual(tau: np.ndarray, zeta: float) -> np.ndarray:
    """The cycloid's residual amplitude in closed form.

    The normalised cycloid has A'(u) = 2π·sin 2πu on [0, 1]. With λ = −ζΩ + iΩd, Ω = 2πτ, the
    state after the motion is w(1) = −∫₀¹ e^{λ(1−v)}·A'(v) dv and the residual amplitude is
    |w(1)|/Ωd. Integrating by parts twice, with a = 2π (sin a = 0, cos a = 1),
    ∫₀¹ e^{−λv}·sin(av) dv = a·(1 − e^{−λ})/(λ² + a²), so

        residual = 4π²·|e^{λ} − 1| / (|λ² + 4π²|·Ωd).

    Undamped (λ = iΩ): |e^{iΩ} − 1| = 2|sin πτ| and |4π² − Ω²| = 4π²|1 − τ²|, so the residual
    is |sin πτ|/(πτ·|1 − τ²|): 0 at every integer τ ≥ 2 (sin πτ = 0, the acceleration is
    orthogonal to e^{−i2πτu} over its one period) and 1/2 in the limit τ → 1 (sin πτ ≈ π(1 − τ)).
    """
    omega = 2 * np.pi * tau
    lam = -zeta * omega + 1j * omega * np.sqrt(1 - zeta**2)
    return 4 * np.pi**2 * np.abs(np.expm1(lam)) / (np.abs(lam**2 + 4 * np.pi**2) * omega * np.sqrt(1 - zeta**2))


def test_undamped_cycloid_leaves_one_half_at_tau_1_and_nothing_at_integer_tau() -> None:
    cycloid = camcore.named_curve("cycloid")
    tau = np.arange(1.0, 21.0)
    result = residual_vibration(cycloid, tau, 0.0)
    # 1/2 exactly at τ = 1; at τ = 2 … 20 the integral cancels to rounding (terms ~2π, eps ~2e-16)
    assert result.residual_amplitude[0] == pytest.approx(0.5, abs=1e-13)
    assert np.abs(result.residual_amplitude[1:]).max() < 1e-13


@pytest.mark.parametrize("zeta", [0.0, 0.02, 0.3, 0.9, 0.999])
def test_cycloid_matches_its_closed_form(zeta: float) -> None:
    tau = np.concatenate([np.linspace(0.001, 3.0, 97), np.linspace(3.1, 300.0, 61), [999.9]])
    tau = tau[np.abs(tau - 1) > 1e-3]  # the closed form is 0/0 at τ = 1 (tested above)
    result = residual_vibration(camcore.named_curve("cycloid"), tau, zeta)
    exact = cycloid_residual(tau, zeta)
    # relative: the amplitude spans 1 (τ small) to 1e-9 (τ large); rounding in the sum is
    # ~1e-15 of the largest term, which the closed form loses in 1 − τ² near τ = 1 too
    assert np.abs(result.residual_amplitude - exact).max() < AGREE
    assert np.allclose(result.residual_amplitude, exact, rtol=1e-9, atol=1e-14)


class KinkedLine(Curve):
    """S rises at V = 1/2 to T = 1/2, then at V = 3/2: A = 0 on both pieces, and a velocity jump
    of 1 at T = 1/2, an impulse of the acceleration."""

    def __init__(self) -> None:
        self.piece_starts = np.array([0.0, 0.5])
        self.t_end = 1.0

    def eval_pieces(self, t: np.ndarray, piece: np.ndarray, order: int) -> list[np.ndarray]:
        v = np.where(piece == 0, 0.5, 1.5)
        s = np.where(piece == 0, 0.5 * t, 0.25 + 1.5 * (t - 0.5))
        return [s, v, *(np.zeros_like(t) for _ in range(order - 1))][: order + 1]


@pytest.mark.parametrize("zeta", [0.0, 0.25])
def test_a_velocity_jump_is_an_impulse(zeta: float) -> None:
    # an impulse ΔV' = 1 at u = 1/2 sets X' to −1 there (x(0) = ẋ(0) = 0 before): w = −1, then
    # free vibration, |w(1)| = e^{−ζΩ/2}, so residual = e^{−ζΩ/2}/Ωd; the largest |X| is the
    # first swing, e^{−ζΩs}·sin(Ωd·s)/Ωd at Ωd·s = atan(Ωd/(ζΩ)) (s = u − 1/2), if before u = 1
    tau = np.array([0.05, 0.6, 3.3, 40.0])
    omega = 2 * np.pi * tau
    omega_d = omega * math.sqrt(1 - zeta**2)
    result = residual_vibration(KinkedLine(), tau, zeta)
    assert np.allclose(result.residual_amplitude, np.exp(-zeta * omega / 2) / omega_d, rtol=1e-12)
    first = np.arctan2(omega_d, zeta * omega) / omega_d
    s = np.minimum(first, 0.5)
    swing = np.exp(-zeta * omega * s) * np.sin(omega_d * s) / omega_d
    assert np.allclose(result.peak_deviation, swing, rtol=1e-12)


@pytest.mark.property  # every catalog curve over a grid of τ and damping, against a stepped integration
def test_every_catalog_curve_matches_the_stepped_equation() -> None:
    tau = np.array([0.3, 0.8, 1.0, 1.7, 2.5, 4.2, 7.7, 10.0])
    zeta = np.array([0.0, 0.05, 0.3, 0.95])
    taus, zetas = (grid.ravel() for grid in np.meshgrid(tau, zeta))
    ref = reference(CATALOG, taus, zetas, steps_per_unit=4000)
    assert ref.residual_error.max() < REFERENCE_ERROR and ref.peak_error.max() < REFERENCE_ERROR
    for i, curve in enumerate(CATALOG):
        for z in zeta:
            case = zetas == z
            got = residual_vibration(curve, taus[case], z)
            assert np.abs(got.residual_amplitude - ref.residual[i, case]).max() < AGREE, (NAMES[i], z)
            assert np.abs(got.peak_deviation - ref.peak[i, case]).max() < AGREE, (NAMES[i], z)


@pytest.mark.property  # a grid of fast vibration and heavy damping, against a stepped integration
def test_fast_vibration_and_heavy_damping_match_the_stepped_equation() -> None:
    # acceleration jumps (constant acceleration), a start and end in motion (no-dwell simple
    # harmonic), asymmetric (TR); ζ close to 1, where ωd is small and the envelope large
    curves = [camcore.named_curve(n) for n in ("MS", "constant-acceleration", "TR", "no-dwell-simple-harmonic")]
    tau, zeta = np.array([25.5, 60.25]), np.array([0.0, 0.1, 0.999])
    taus, zetas = (grid.ravel() for grid in np.meshgrid(tau, zeta))
    ref = reference(curves, taus, zetas, steps_per_unit=10000)
    assert ref.residual_error.max() < REFERENCE_ERROR and ref.peak_error.max() < REFERENCE_ERROR
    for i, curve in enumerate(curves):
        for z in zeta:
            case = zetas == z
            got = residual_vibration(curve, taus[case], z)
            assert np.abs(got.residual_amplitude - ref.residual[i, case]).max() < AGREE
            assert np.abs(got.peak_deviation - ref.peak[i, case]).max() < AGREE


def test_user_curves_are_normalised_like_the_indexer() -> None:
    # curves that do not run over T, S = 0..1 (Bezier in degrees and millimetres, a measured
    # table, a universal curve from S = 2 to 5 over T = 1..3, a return stroke, a universal
    # curve ending in motion) against the stepped equation on the same normalisation
    curves = [
        build_curve("bezier", {"control_points": [[0, 0], [30, 0], [60, 10], [90, 10]]}),
        build_curve("points", {"t": [0, 10, 20, 30, 40], "s": [0, 1, 4, 7, 8]}),
        build_curve("universal", {"t": [1, 1.25, 1.25, 2, 2, 2.75, 2.75, 3], "s0": 2, "s7": 5}),
        build_curve("named", {"name": "MT"}, "return"),
        build_curve("universal", {"t": [0, 0.2, 0.2, 0.4, 0.4, 0.7, 0.7, 1], "m": 0.5}),
    ]
    tau, zeta = np.array([0.001, 0.1, 0.55, 2.2]), np.array([0.0, 0.1])
    taus, zetas = (grid.ravel() for grid in np.meshgrid(tau, zeta))
    ref = reference(curves, taus, zetas, steps_per_unit=4000)
    assert ref.residual_error.max() < REFERENCE_ERROR
    for i, curve in enumerate(curves):
        for z in zeta:
            case = zetas == z
            got = residual_vibration(curve, taus[case], z)
            # relative at τ = 0.001 for the curve ending in motion: its residual is ~70 (ΔV/Ω)
            assert np.allclose(got.residual_amplitude, ref.residual[i, case], rtol=1e-12, atol=AGREE)
            assert np.abs(got.peak_deviation - ref.peak[i, case]).max() < AGREE
    # the universal curve from S = 2 to 5 over T = 1..3 is MS (Makino No. 26) scaled
    ms = residual_vibration(camcore.named_curve("MS"), tau, 0.1)
    scaled = residual_vibration(curves[2], tau, 0.1)
    assert np.allclose(scaled.residual_amplitude, ms.residual_amplitude, rtol=1e-12, atol=1e-15)


def test_undamped_return_leaves_what_the_rise_leaves() -> None:
    # the return plays the rise backwards: A'(u) → A'(1 − u), and |∫ A'(1 − v)·e^{iΩv} dv| is
    # |∫ A'(w)·e^{−iΩw} dw|, the conjugate's modulus, for a real A'
    tau = np.linspace(0.2, 12, 60)
    for name in ("TR", "asymmetric-cycloid", "one-dwell-modified-sine"):
        rise = residual_vibration(camcore.named_curve(name), tau)
        back = residual_vibration(build_curve("named", {"name": name}, "return"), tau)
        assert np.allclose(rise.residual_amplitude, back.residual_amplitude, rtol=1e-11, atol=1e-14)


def test_response_over_time_and_its_free_decay() -> None:
    curve = camcore.named_curve("MS")
    response = FollowerResponse(curve, 2.7, 0.08)
    u = np.linspace(0.0, 1.0, 200_001)
    x = response.deviation(u)
    assert abs(x[0]) < 1e-17  # at rest at u = 0 (the series of the integral at its start: rounding)
    # the dense samples never exceed the refined peak, and come within X''·h²/8 of it
    # (h = 5e-6, |X''| ≤ Ω²·|X| + |A'| < 300·0.3 + 6): 3e-9
    assert np.abs(x).max() <= response.peak_deviation + 1e-15
    assert response.peak_deviation - np.abs(x).max() < 3e-9
    # after the motion: free vibration inside its envelope R·e^{−ζΩ(u − 1)}, touching it
    later = np.linspace(1.0, 4.0, 30_001)
    envelope = response.residual_amplitude * np.exp(-0.08 * 2 * np.pi * 2.7 * (later - 1.0))
    free = np.abs(response.deviation(later))
    assert (free <= envelope * (1 + 1e-12)).all()
    assert (free / envelope).max() > 0.999
    assert response.deviation([1.0])[0] == pytest.approx(x[-1], abs=1e-15)


@pytest.mark.parametrize("zeta", [-0.1, 1.0, 1.5, math.nan, math.inf])
def test_damping_out_of_range_is_refused(zeta: float) -> None:
    with pytest.raises(InvalidParameterError, match="damping_ratio") as info:
        residual_vibration(camcore.named_curve("MS"), [1.0], zeta)
    assert info.value.field in ((), ("damping_ratio",))


@pytest.mark.parametrize("tau", [[0.0], [-1.0], [TAU_MIN / 2], [TAU_MAX * 1.001], [1.0, math.nan], [math.inf], []])
def test_tau_out_of_range_is_refused(tau: list[float]) -> None:
    with pytest.raises(InvalidParameterError, match="tau") as info:
        residual_vibration(camcore.named_curve("MS"), tau, 0.0)
    assert info.value.field[0] == "tau"


def test_a_curve_that_does_not_move_is_refused() -> None:
    still = build_curve("polynomial", {"start": {"s": 0, "v": 0}, "end": {"s": 0, "v": 0}})
    with pytest.raises(InvalidParameterError, match="the curve must move"):
        residual_vibration(still, [1.0])


def test_the_spectrum_keeps_the_order_of_tau() -> None:
    tau = np.array([5.0, 0.5, 120.0, 0.5, 2.0])
    shuffled = residual_vibration(camcore.named_curve("MT"), tau, 0.05)
    one_by_one = [residual_vibration(camcore.named_curve("MT"), [t], 0.05) for t in tau]
    assert np.array_equal(shuffled.tau, tau)
    for k, single in enumerate(one_by_one):
        assert shuffled.residual_amplitude[k] == pytest.approx(single.residual_amplitude[0], rel=1e-12, abs=1e-16)
        assert shuffled.peak_deviation[k] == pytest.approx(single.peak_deviation[0], rel=1e-12, abs=1e-16)


def test_at_the_largest_tau_every_catalog_curve_is_rigid() -> None:
    # docs/api.md bounds τ at 1000 because there the follower is rigid for every purpose: the
    # residual of every catalog curve is below 1e-6 of the stroke (the largest, ~4e-7, is the
    # constant-acceleration curve's: its acceleration jumps by 4, 8 and 4, each leaving ~ΔA/Ω²)
    tau = np.linspace(990.0, TAU_MAX, 5)
    for name, curve in zip(NAMES, CATALOG, strict=True):
        assert camcore.dynamics.residual_amplitude(curve, tau, 0.0).max() < 1e-6, name


def test_the_residual_alone_is_the_spectrum_s_column() -> None:
    tau = np.linspace(0.01, 40, 300)
    for name in ("MS", "trapecloid-2", "no-dwell-modified-trapezoid"):
        curve = camcore.named_curve(name)
        full = residual_vibration(curve, tau, 0.07).residual_amplitude
        alone = camcore.dynamics.residual_amplitude(curve, tau, 0.07)
        # the same integrals summed by the Clenshaw–Curtis weights instead of the last row of the
        # cumulative matrix: the same to rounding
        assert np.allclose(alone, full, rtol=1e-12, atol=1e-16), name
