"""input_angle_origin (issue 22 item 4): the catalog's timing charts put the input keyway's
reference position at the centre of the dwell (INDEXMAN technical guide, section 4-2), so with
``dwell-centre`` every input angle moves by half the dwell. Checked on the guide's worked
example (section 5: n = 6, θh = 270°, 60 rpm): the dwell is 90°, the index runs from 45° to 315°
of the keyway, and MS's symmetric velocity peak (T = 0.5) falls at 180°, opposite the keyway."""

from __future__ import annotations

import numpy as np
import pytest

from camcore.errors import InvalidParameterError
from camcore.indexer import Indexer, Load, LoadPart, origin_shift_deg, size, to_origin

GUIDE = Indexer(stops=6, indexing_angle_deg=270, speed_rpm=60, curve="MS", input_stop_time_s=0.25)
LOAD = Load(parts=[LoadPart(shape="disc", mass_kg=50, diameter_mm=600)], friction_coefficient=0.1,
            friction_radius_mm=200, service_factor=1.5)


def test_half_the_dwell() -> None:
    assert origin_shift_deg(GUIDE, "index-start") == 0.0
    assert origin_shift_deg(GUIDE, "dwell-centre") == 45.0  # (360 − 270)/2
    two = Indexer(stops=8, indexing_angle_deg=120, speed_rpm=60, curve="MS", dwells=2)
    assert origin_shift_deg(two, "dwell-centre") == 30.0  # cycle 180°, dwell 60°
    with pytest.raises(InvalidParameterError, match="input_angle_origin"):
        origin_shift_deg(GUIDE, "keyway")


def test_the_guides_example_from_the_keyway() -> None:
    motion = GUIDE.motion(5)
    summary = to_origin(motion.summary, 45.0, 360.0)
    assert motion.summary.omega_input_angle_deg == 135.0 and summary.omega_input_angle_deg == 180.0
    table = to_origin(motion.table, 45.0, 360.0)
    np.testing.assert_array_equal(table.input_angle_deg, [45.0, 112.5, 180.0, 247.5, 315.0])
    np.testing.assert_array_equal(table.output_angle_deg, motion.table.output_angle_deg)  # only the angles move
    position = to_origin(GUIDE.position(np.array([30.0])), 45.0, 360.0)
    assert position.input_angle_deg[0] == pytest.approx(180.0, abs=1e-12)  # half the travel at half the index


def test_the_torque_table_starts_at_the_keyway() -> None:
    """The cycle's table rotated: it opens and closes at the keyway inside the dwell, where the
    input carries its internal friction only; every row keeps its torque and its place in time."""
    sized = size(GUIDE, LOAD, internal_friction_torque_nm=2.0)
    moved = to_origin(sized, 45.0, 360.0)
    before, after = sized.input_torque_table, moved.input_torque_table
    assert before is not None and after is not None
    assert after.input_angle_deg[0] == 0.0 and after.input_angle_deg[-1] == 360.0
    assert after.input_torque_nm[0] == after.input_torque_nm[-1] == 2.0
    assert after.time_s[0] == 0.0 and after.time_s[-1] == before.time_s[-1]  # the same machine cycle
    assert np.all(np.diff(after.input_angle_deg) >= 0) and np.all(np.diff(after.time_s) >= 0)
    # the index now runs from 45° to 315°; each row's torque is the unshifted table's at angle − 45°
    index = (after.input_angle_deg > 45.0) & (after.input_angle_deg < 315.0)
    np.testing.assert_allclose(after.input_torque_nm[index],
                               np.interp(after.input_angle_deg[index] - 45.0, before.input_angle_deg,
                                         before.input_torque_nm), rtol=1e-12)
    assert moved.input_torque_input_angle_deg == pytest.approx(sized.input_torque_input_angle_deg + 45.0)
    assert moved.rms_input_torque_nm == sized.rms_input_torque_nm  # nothing else changes
