"""A turret roller's envelope (camcore.cams.parallel.envelope) is the oscillating roller follower's.

``envelope`` writes the follower model's pitch point and kinematics out (camcore.profile.followers:
``KnifeEdgeOscillating.pitch_point``, ``_PointFollower.kinematics_of``, the turret roller with its arm
angle α₀ + φ as the lift) for speed, and ``track`` leaves out what the solvers do not use. Both must
give the model's numbers to the bit: the envelope computed here through the model itself (as camcore
did before it was written out) is the reference.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from camcore.cams.parallel import make_parallel_cam
from camcore.cams.parallel.envelope import envelope, track


def _bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.int64)  # −0.0 ≠ 0.0, NaNs by their bits


def _through_the_model(cam, alpha0, side, tau):  # type: ignore[no-untyped-def]
    """The envelope by the follower model: pitch point and kinematics of the roller whose lift is α₀ + φ."""
    alpha0, side, tau = np.broadcast_arrays(np.asarray(alpha0, dtype=np.float64), np.asarray(side, dtype=np.float64),
                                            np.asarray(tau, dtype=np.float64))
    phi, d1, d2 = cam.turret(tau)
    lift = [np.degrees(alpha0 + phi), np.degrees(d1), np.degrees(d2)]
    model = cam.roller_model
    pitch = model.pitch_point(0.0, *lift)
    cx, cy, c1x, c1y, *_ = pitch
    k = model.kinematics_of(1.0, tau, lift, pitch)
    u1x, u1y = c1x + cy, c1y - cx
    speed = np.hypot(u1x, u1y)
    cos_t, sin_t = np.cos(tau), np.sin(tau)
    tx = (cos_t * u1x + sin_t * u1y) / speed
    ty = (-sin_t * u1x + cos_t * u1y) / speed
    px, py = cos_t * cx + sin_t * cy, -sin_t * cx + cos_t * cy
    rr = cam.roller_radius_mm
    kappa = -side * k.kappa_pitch
    drives0 = np.abs(k.pressure) < math.pi / 2
    folded = np.degrees(np.where(drives0, k.pressure, k.pressure - np.sign(k.pressure) * math.pi))
    return {"x": px - side * rr * ty, "y": py + side * rr * tx, "tx": tx, "ty": ty, "speed": speed,
            "stretch": speed * (1.0 - rr * kappa), "px": px, "py": py, "pressure_deg": folded, "kappa": kappa}


@pytest.mark.parametrize("curve", ["MS", "MT", "asymmetric-cycloid", "constant-velocity"])
def test_the_written_out_envelope_is_the_models_to_the_bit(curve: str) -> None:
    cam = make_parallel_cam(6, 100.0, 60.0, 8.0, 120.0, curve, plates=3)
    rng = np.random.default_rng(8)
    # many turns, whole turns, the index's ends, a few angles (the turret's scalar path) and many
    theta_h = math.radians(120.0)
    edges = np.array([0.0, -0.0, 2 * math.pi, theta_h, np.nextafter(theta_h, 0.0), np.nextafter(theta_h, 9.0)])
    for tau in (edges, rng.uniform(-30.0, 40.0, 3), rng.uniform(-30.0, 40.0, 5000)):
        for alpha0, side in ((0.3, 1.0), (-1.1, -1.0), (rng.uniform(-3, 3, tau.size), rng.choice([-1.0, 1.0], tau.size))):
            want = _through_the_model(cam, alpha0, side, tau)
            got, lean = envelope(cam, alpha0, side, tau), track(cam, alpha0, side, tau)
            for name, value in want.items():
                assert np.array_equal(_bits(getattr(got, name)), _bits(value)), name
            for name in ("x", "y", "tx", "ty", "stretch"):
                assert np.array_equal(_bits(getattr(lean, name)), _bits(want[name])), name
