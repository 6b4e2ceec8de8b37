"""Characteristic values list where the acceleration jumps (issue 22 item 3): the jerk is
unbounded there, so a finite jm is not the whole story; and which Qm is which."""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcore
from camcore.curves.jumps import AccelerationJump


def test_constant_acceleration_lists_its_three_jumps() -> None:
    """S = 2T² then 1 − 2(1 − T)²: A = +4, then −4 (hand-derived); from the dwell (A = 0) up to 4
    at T0, from 4 to −4 at the middle, from −4 back to the dwell at T7."""
    jumps = camcore.named_curve("constant-acceleration").characteristics.a_jumps
    assert jumps == (AccelerationJump(0.0, 0.0, 4.0), AccelerationJump(0.5, 4.0, -4.0), AccelerationJump(1.0, -4.0, 0.0))


def test_simple_harmonic_jumps_at_its_ends() -> None:
    """S = (1 − cos πT)/2: A = π²/2·cos πT, so ±π²/2 against the dwells at T0 and T7."""
    jumps = camcore.named_curve("simple-harmonic").characteristics.a_jumps
    assert [j.t for j in jumps] == [0.0, 1.0]
    half = math.pi**2 / 2
    assert jumps[0].before == 0.0 and jumps[0].after == pytest.approx(half, rel=1e-15)  # cos 0 = 1 exactly
    assert jumps[1].before == pytest.approx(-half, rel=1e-15) and jumps[1].after == 0.0


@pytest.mark.parametrize("name", sorted(camcore.CATALOG))
def test_every_listed_jump_is_a_jump_and_none_is_missed(name: str) -> None:
    """Independent: A one step of 1e-9 either side of every break point and of the ends (0
    outside): a jump listed is a difference there of more than 1e-6·max(1, Am); a point not listed
    differs by less (A is Lipschitz in T: J·1e-9 ≪ 1e-6 on every catalog curve)."""
    curve = camcore.named_curve(name)
    ch = curve.characteristics
    listed = {j.t for j in ch.a_jumps}
    points = np.unique(np.append(curve.piece_starts, [curve.t_start, curve.t_end]))
    step = 1e-9
    for t in points:
        left = 0.0 if t <= curve.t_start else float(curve.derivatives(np.array([t - step]), 2)[2][0])
        right = 0.0 if t >= curve.t_end else float(curve.derivatives(np.array([t + step]), 2)[2][0])
        jumped = abs(right - left) > 1e-6 * max(1.0, ch.am)
        assert jumped == (t in listed), (name, t, left, right)


def test_the_cycloids_two_qm_conventions() -> None:
    """The cycloid's (AV)max as Makino prints it, 8.16, is our qm_raw; the catalog's Q = AV/Am is
    1.30: V = 1 − cos 2πT, A = 2π sin 2πT peak together at 2πT = 2π/3 (hand-derived:
    AV = 2π·(√3/2)·(3/2), Am = 2π)."""
    ch = camcore.named_curve("cycloid").characteristics
    assert ch.qm_raw_pos.value == pytest.approx(2 * math.pi * math.sqrt(3) / 2 * 1.5, rel=1e-14)
    assert round(ch.qm_raw_pos.value, 2) == 8.16 and round(ch.qm_pos.value, 2) == 1.30
    assert ch.qm_pos.value == pytest.approx(ch.qm_raw_pos.value / ch.am, rel=1e-15)
