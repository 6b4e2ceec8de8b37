"""camcore.dynamics.indexer: an indexer's load on an elastic drive train, against a direct simulation.

The simulation steps the load's equation in physical time, I·ÿ = −k·(y − s) − c·(ẏ − ṡ), as
x = y − s: ẍ + 2ζωn·ẋ + ωn²·x = −s̈(t), through the index (s̈ = (h/th²)·A, A from the curve's
own pieces) and the dwell (s̈ = 0), by RK4 with steps of at most 0.005/ωn, aligned with the
curve's break points and the table's times. It shares nothing with camcore.dynamics but the
curve's acceleration. Its error is measured by halving the step (Richardson), and asserted.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import camcore
from camcore.dynamics import indexer_vibration
from camcore.errors import InvalidParameterError

GUIDE = {"stops": 6, "indexing_angle_deg": 270, "speed_rpm": 60}  # INDEXMAN's example: th = 0.75 s


def simulate(indexer: camcore.Indexer, inertia: float, stiffness: float, zeta: float, times: np.ndarray,
             per_radian: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x [arcsec] and the envelope √(x² + ((ẋ + ζωx)/ωd)²) [arcsec] at every step, and the steps' times."""
    curve = indexer.curve
    th = indexer.indexing_time_s
    h = indexer.displacement_deg * 3600.0
    d_t, d_s = curve.t_end - curve.t_start, curve.s_end - curve.s_start
    omega = math.sqrt(stiffness / inertia)
    knots = np.unique(np.concatenate([(curve.break_points - curve.t_start) / d_t * th, times, [th]]))
    steps = [np.linspace(a, b, max(2, math.ceil((b - a) * omega / per_radian) + 1))[:-1]
             for a, b in itertools.pairwise(knots)]
    grid = np.append(np.concatenate(steps), knots[-1])

    def accel(t: np.ndarray, left: bool) -> np.ndarray:
        """s̈ [arcsec/s²]; at a knot the piece on the step's side (left: the step ending there)."""
        inside = t < th if not left else t <= th
        u = np.clip(t / th, 0, 1)
        piece = np.clip(np.searchsorted(curve.break_points, curve.t_start + d_t * u, side="left" if left else "right")
                        - 1, 0, curve.n_pieces - 1)
        a = curve.eval_pieces(curve.t_start + d_t * u, piece, 2)[2] * d_t**2 / d_s
        return np.where(inside, h / th**2 * a, 0.0)

    t0, t1 = grid[:-1], grid[1:]
    dt = t1 - t0
    a0, am, a1 = accel(t0, False), accel(t0 + dt / 2, False), accel(t1, True)
    x, v = 0.0, 0.0
    xs, vs = [0.0], [0.0]
    c1, c0 = 2 * zeta * omega, omega**2
    for k in range(dt.size):
        def f(xx: float, vv: float, a: float) -> float:
            return -a - c1 * vv - c0 * xx
        k1x, k1v = v, f(x, v, a0[k])
        k2x, k2v = v + dt[k] / 2 * k1v, f(x + dt[k] / 2 * k1x, v + dt[k] / 2 * k1v, am[k])
        k3x, k3v = v + dt[k] / 2 * k2v, f(x + dt[k] / 2 * k2x, v + dt[k] / 2 * k2v, am[k])
        k4x, k4v = v + dt[k] * k3v, f(x + dt[k] * k3x, v + dt[k] * k3v, a1[k])
        x, v = x + dt[k] / 6 * (k1x + 2 * k2x + 2 * k3x + k4x), v + dt[k] / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        xs.append(x)
        vs.append(v)
    xa, va = np.array(xs), np.array(vs)
    omega_d = omega * math.sqrt(1 - zeta**2)
    return grid, xa, np.hypot(xa, (va + zeta * omega * xa) / omega_d)


def settling_from(grid: np.ndarray, envelope: np.ndarray, th: float, tolerance: float) -> float:
    """The first time after th at which the simulated envelope is at the tolerance: between the
    two steps around it the free envelope is exactly exponential, so interpolate its logarithm."""
    after = grid >= th
    t, e = grid[after], envelope[after]
    k = int(np.flatnonzero(e <= tolerance)[0])
    if k == 0:
        return 0.0
    slope = (math.log(e[k]) - math.log(e[k - 1])) / (t[k] - t[k - 1])
    return t[k - 1] + (math.log(tolerance) - math.log(e[k - 1])) / slope - th


def test_natural_frequency_and_tau_of_the_guides_example() -> None:
    # the guide's load: a 50 kg disc of Ø600 mm, I = m·D²/8 = 2.25 kg·m²; a drive of 2e5 N·m/rad:
    # fn = √(2e5/2.25)/2π = 298.142…/2π = 47.4508 Hz, th = (270/360)·(60/60) = 0.75 s, τ = 35.588
    unit = camcore.Indexer(**GUIDE)
    result = indexer_vibration(unit, 2.25, 2e5, 0.05, 10.0)
    assert result.natural_frequency_hz == pytest.approx(math.sqrt(2e5 / 2.25) / (2 * math.pi), rel=1e-15)
    assert result.natural_frequency_hz == pytest.approx(47.4508, abs=5e-5)
    assert result.tau == pytest.approx(0.75 * result.natural_frequency_hz, rel=1e-15)
    assert result.indexing_time_s == 0.75 and result.dwell_time_s == pytest.approx(0.25, rel=1e-15)
    assert result.displacement_arcsec == 60 * 3600
    spectrum = camcore.dynamics.residual_vibration(unit.curve, [result.tau], 0.05)
    assert result.residual_amplitude_arcsec == pytest.approx(216000 * spectrum.residual_amplitude[0], rel=1e-12)
    assert result.peak_error_arcsec == pytest.approx(216000 * spectrum.peak_deviation[0], rel=1e-12)


@pytest.mark.parametrize(("curve", "stiffness", "zeta", "tolerance"), [
    ("MS", 3e4, 0.05, 5.0),        # τ ≈ 6.3: 509″ left, settles within the 0.75 s dwell (0.58 s)
    ("cycloid", 2.5e3, 0.02, 2.0),  # τ ≈ 1.8: 12 318″ left, settles long after the dwell (9.6 s)
    ("TR", 3e4, 0.1, 1.0),         # τ ≈ 6.3, heavier damping (0.30 s)
    ("constant-acceleration", 1.5e4, 0.2, 20.0),  # acceleration jumps at the start, middle and end
])
def test_settling_time_and_table_match_a_direct_simulation(curve: str, stiffness: float, zeta: float,
                                                           tolerance: float) -> None:
    unit = camcore.Indexer(stops=4, indexing_angle_deg=90, speed_rpm=60, curve=curve)  # th = 0.25 s, dwell 0.75 s
    inertia = 1.2
    result = indexer_vibration(unit, inertia, stiffness, zeta, tolerance, samples=201)
    table = result.table
    th = unit.indexing_time_s
    assert table.time_s[0] == 0 and table.time_s[-1] == pytest.approx(th + result.dwell_time_s, rel=1e-15)
    # simulate to well past the settling time, or through the dwell if it settles later
    horizon = th + max(result.dwell_time_s, (result.settling_time_s or 0.0) * 1.2)
    times = np.concatenate([table.time_s, [horizon]])
    coarse = simulate(unit, inertia, stiffness, zeta, times, per_radian=0.01)
    grid, x, envelope = simulate(unit, inertia, stiffness, zeta, times, per_radian=0.005)
    # the simulation's own error (RK4 error falls 16-fold per halving: the difference bounds it)
    at_table = np.isin(grid, table.time_s)
    sim_error = np.abs(coarse[1][np.isin(coarse[0], table.time_s)] - x[at_table]).max()
    assert sim_error < 1e-6 * result.displacement_arcsec
    # the table against the simulation: the simulation's error plus the method's 1e-9 of h
    assert np.abs(table.output_error_arcsec - x[at_table]).max() < sim_error + 1e-9 * result.displacement_arcsec
    # the residual amplitude is the simulated envelope when the index ends
    assert result.residual_amplitude_arcsec == pytest.approx(envelope[grid == th][0], abs=sim_error + 1e-9 * 216000)
    # the settling time against the simulated envelope's crossing of the tolerance; its slope there
    # is ζωn·ε, so an envelope error δ moves the crossing by δ/(ζωn·ε)
    omega = math.sqrt(stiffness / inertia)
    simulated = settling_from(grid, envelope, th, tolerance)
    assert result.settling_time_s == pytest.approx(simulated, abs=(sim_error + 1e-9 * 216000) / (zeta * omega * tolerance))
    assert result.settles_within_dwell == (simulated <= result.dwell_time_s)
    # and the load's own error stays within the tolerance from then on
    later = grid >= th + simulated
    assert np.abs(x[later]).max() <= tolerance * (1 + 1e-9)


def test_cases_cover_settling_inside_and_after_the_dwell() -> None:
    unit = camcore.Indexer(stops=4, indexing_angle_deg=90, speed_rpm=60, curve="MS")
    inside = indexer_vibration(unit, 1.2, 3e4, 0.05, 5.0)
    later = indexer_vibration(camcore.Indexer(stops=4, indexing_angle_deg=90, speed_rpm=60, curve="cycloid"),
                              1.2, 2.5e3, 0.02, 2.0)
    assert 0 < inside.settling_time_s < inside.dwell_time_s and inside.settles_within_dwell  # type: ignore[operator]
    assert later.settling_time_s > later.dwell_time_s and not later.settles_within_dwell  # type: ignore[operator]


def test_undamped_vibration_above_the_tolerance_never_settles() -> None:
    unit = camcore.Indexer(**GUIDE)
    never = indexer_vibration(unit, 2.25, 2e3, 0.0, 1.0)
    assert never.residual_amplitude_arcsec > 1.0
    assert never.settling_time_s is None and not never.settles_within_dwell
    # below the tolerance it is settled when the index ends, damped or not
    quiet = indexer_vibration(unit, 2.25, 2e3, 0.0, 2 * never.residual_amplitude_arcsec)
    assert quiet.settling_time_s == 0.0 and quiet.settles_within_dwell


def test_the_smallest_tolerance_settles_where_the_envelope_says() -> None:
    # issue 34, point 4: tolerance_arcsec = 5e-324 (the smallest double) answered 500: ε/h underflowed
    # to 0 and the settling time divided by it. The envelope h·R·e^(−ζωn·t) reaches ε at
    # t = ln(h·R/ε)/(ζωn), so two tolerances settle ln(ε1/ε2)/(ζωn) apart (ln taken of each: ε1/ε2 overflows)
    unit = camcore.Indexer(**GUIDE)
    coarse = indexer_vibration(unit, 2.25, 2e5, 0.05, 0.1)  # the residual is 1.34 arcsec: it settles later
    finest = indexer_vibration(unit, 2.25, 2e5, 0.05, 5e-324)
    assert coarse.settling_time_s is not None and finest.settling_time_s is not None
    zeta_omega = 0.05 * math.sqrt(2e5 / 2.25)
    # rel 1e-12: the logs are ~750, each exact to a few ulps, against ~50 s
    assert finest.settling_time_s - coarse.settling_time_s == pytest.approx(
        (math.log(0.1) - math.log(5e-324)) / zeta_omega, rel=1e-12)
    assert finest.tolerance_arcsec == 5e-324


def test_an_indexer_without_dwell_settles_only_if_already_settled() -> None:
    unit = camcore.Indexer(stops=4, indexing_angle_deg=360, speed_rpm=60)  # θh·z = 360°: no dwell
    result = indexer_vibration(unit, 1.0, 1e4, 0.1, 1.0, samples=11)
    assert result.dwell_time_s == 0.0 and result.table.time_s[-1] == pytest.approx(unit.indexing_time_s)
    assert result.settles_within_dwell == (result.settling_time_s == 0.0)


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"inertia_kgm2": 0.0}, "inertia_kgm2 must be greater than 0"),
    ({"inertia_kgm2": -1.0}, "inertia_kgm2 must be greater than 0"),
    ({"stiffness_nm_rad": 0.0}, "stiffness_nm_rad must be greater than 0"),
    ({"stiffness_nm_rad": math.nan}, "stiffness_nm_rad must be a finite number"),
    ({"damping_ratio": 1.0}, "damping_ratio must satisfy 0 ≤ ζ < 1"),
    ({"tolerance_arcsec": 0.0}, "tolerance_arcsec must be greater than 0"),
    ({"samples": 1}, "samples must be at least 2"),
    ({"stiffness_nm_rad": 1e12}, "must lie within 0.001 ≤ τ ≤ 1000"),
    ({"stiffness_nm_rad": 1e-6}, "must lie within 0.001 ≤ τ ≤ 1000"),
])
def test_bad_values_are_refused(kwargs: dict[str, float], words: str) -> None:
    args = {"inertia_kgm2": 2.25, "stiffness_nm_rad": 2e5, "damping_ratio": 0.05, "tolerance_arcsec": 10.0, **kwargs}
    with pytest.raises(InvalidParameterError, match=words.replace("(", r"\(")):
        indexer_vibration(camcore.Indexer(**GUIDE), **args)  # type: ignore[arg-type]
