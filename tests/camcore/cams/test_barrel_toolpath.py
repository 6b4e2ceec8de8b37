"""A barrel cam's four-axis toolpath (camcore.cams.barrel.toolpath and its G-code,
camcore.export.barrel_toolpath), checked against routes that share nothing with it:

- the program is read by pygcode 0.2.1 (its parser and ``Machine`` with the axes X Y Z A), every
  line a block or a comment, the header's comments without words and without ``;``;
- the moves are interpolated as the control does (A and X at constant rates, a line in each
  cylinder's developed plane) and compared, both ways, with the exact path built here from the
  lift alone: the centre line (R·θ, s(θ)), and for a smaller cutter its offset built from a dense
  polyline's own normals (finite differences of the samples, not the lift's derivatives);
- a cutter of the roller's size leaves the exact flanks (their envelope formula) to ~1e-13 mm
  (the brute-force distance of the flank points from the cutter's axis), and a smaller one's gaps
  equal a brute-force scan over the path;
- each inverse-time F is the feed over the block's developed length;
- bad requests raise naming the field.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
import pytest
from pygcode import Line, Machine

import camcore
from camcore.cams.barrel import BarrelCam, flank_points, make_barrel_cam
from camcore.cams.barrel.toolpath import BarrelToolpath, compute_barrel_toolpath, wall_gaps
from camcore.curves.kinds import build_curve
from camcore.errors import CamError, LimitExceededError
from camcore.export.barrel_toolpath import BARREL_TOOLPATH_FORMATS, BarrelToolpathFile, barrel_gcode
from camcore.profile import Segment

MS = camcore.named_curve("MS")
R, RR, LENGTH = 50.0, 10.0, 12.0
OUTER = R + LENGTH / 2
SEGMENTS = [Segment("rise", 120, lift_mm=30, curve=MS), Segment("dwell", 60), Segment("return", 120, lift_mm=30),
            Segment("dwell", 60)]
CAM = make_barrel_cam(R, RR, roller_length_mm=LENGTH, segments=SEGMENTS)
#: coordinates and A are written to 1e-6 (mm, degrees): half a unit each, and 1e-6° is 1e-6 mm at 57 mm
WRITTEN_MM = 2e-6
#: the exact path densely: 2^19 cam angles a turn, 1.2e-5 rad apart; a chord of it deviates by
#: κ·h²/8 < 1e-9 mm (κ < 0.2 /mm at 56 mm), far below the tolerances checked
DENSE = 2**19


class FourAxis(Machine):  # type: ignore[misc]
    """pygcode's machine with the rotary axis A (its default has X Y Z only)."""

    axes: ClassVar[set[str]] = set("XYZA")


def read_program(text: str) -> tuple[list[Line], list[dict[str, float]]]:
    """Every line as pygcode parses it, and each motion block: the machine's position before and
    after, G0/G1, its F word, the feed mode then (93 or 94)."""
    machine = FourAxis()
    lines, moves = [], []
    mode = 94.0
    for raw in text.splitlines():
        if raw == "%":
            continue
        line = Line(raw)  # raises on a word it cannot read
        lines.append(line)
        words = {w.letter: float(w.value) for w in line.block.words}
        codes = [g.word.value for g in line.block.gcodes if g.word.letter == "G"]
        mode = next((float(c) for c in codes if c in (93, 94)), mode)
        start = machine.pos
        machine.process_block(line.block)
        motion = [c for c in codes if c in (0, 1)]
        if motion:
            end = machine.pos
            moves.append({"g": float(motion[0]), "mode": mode, "f": words.get("F", math.nan),
                          **{f"{k}0": float(getattr(start, k)) for k in "XYZA"},
                          **{k: float(getattr(end, k)) for k in "XYZA"}})
    return lines, moves


def exact_path(cam: BarrelCam, offset_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """A [rad] and X [mm] of the cutter's axis over a turn, built from a dense polyline of the
    developed centre line (R·θ, s(θ)) and its own normals (central differences of its points)."""
    theta = np.linspace(0.0, 2 * math.pi, DENSE + 1)
    s = cam.lift.derivatives(theta, 0)[0]
    u = R * theta
    du, ds = np.gradient(u), np.gradient(s)
    norm = np.hypot(du, ds)
    return (u - offset_mm * ds / norm) / R, s + offset_mm * du / norm


def distances(points: np.ndarray, polyline: np.ndarray, reach_mm: float) -> np.ndarray:
    """Distance of each point from a polyline whose first coordinate increases, among its pieces
    within ``reach_mm`` along that coordinate of the point: exact wherever the distance found is
    at most ``reach_mm`` (a farther piece is farther than that)."""
    window = math.ceil(reach_mm / float(np.diff(polyline[:, 0]).min())) + 2
    k = np.clip(np.searchsorted(polyline[:, 0], points[:, 0]), window, len(polyline) - window - 1)
    idx = k[:, None] + np.arange(-window, window)[None, :]
    a, b = polyline[idx], polyline[idx + 1]
    d = b - a
    q = points[:, None, :] - a
    t = np.clip((q * d).sum(-1) / np.maximum((d * d).sum(-1), 1e-300), 0.0, 1.0)
    return np.asarray(np.hypot(*(q - t[..., None] * d).transpose(2, 0, 1)).min(axis=1))


def cutting_passes(moves: list[dict[str, float]], cut_z: float) -> list[np.ndarray]:
    """The (A [deg], X) nodes of each run of G1 moves at the cutting depth, from the plunge's end."""
    passes: list[list[tuple[float, float]]] = []
    for m in moves:
        if m["g"] == 1 and m["Z0"] != m["Z"]:  # the plunge: a new pass starts where it ends
            passes.append([(m["A"], m["X"])])
        elif m["g"] == 1:
            assert m["Z"] == pytest.approx(cut_z, abs=WRITTEN_MM)
            passes[-1].append((m["A"], m["X"]))
    return [np.array(p) for p in passes]


@pytest.mark.parametrize(("tool", "tolerance"), [(10.0, 0.01), (10.0, 1e-4), (8.0, 0.005), (5.0, 0.001)])
def test_the_program_read_by_pygcode_runs_the_exact_path_within_the_tolerance(tool: float, tolerance: float) -> None:
    tp = compute_barrel_toolpath(CAM, tool, tolerance)
    safe, cut, feed = 62.0, 45.0, 250.0
    text = barrel_gcode(BarrelToolpathFile(tp, feed, safe, cut))
    lines, moves = read_program(text)
    # the header: comments only, no ';' in any (a reader may take it for the start of a line comment)
    header = lines[:9]
    assert all(not line.block.words and line.comment is not None for line in header)
    assert ";" not in text
    assert "wrap diameter 100 mm" in str(header[4].comment) and "G93" in str(header[6].comment)
    assert all(m["Y"] == 0.0 for m in moves)
    # rapid moves only at the safe height (or going to it), every cut in G93 with its own F
    for m in moves:
        if m["g"] == 0:
            assert m["Z"] == safe
        else:
            assert m["mode"] == 93 and m["f"] > 0
            length = m["Z0"] - m["Z"] if m["Z"] != m["Z0"] else \
                math.hypot(R * math.radians(m["A"] - m["A0"]), m["X"] - m["X0"])
            # F is written to 1e-6 /min, the block's ends to 1e-6
            assert m["f"] == pytest.approx(feed / length, rel=1e-5, abs=1e-6)
    passes = cutting_passes(moves, cut)
    assert len(passes) == len(tp.passes) == (1 if tool == RR else 2)
    for nodes, p in zip(passes, tp.passes, strict=True):
        assert len(nodes) - 1 == len(p.a_deg) - 1
        # climb milling with M3, the wall on the tool's right: the lower wall with A rising
        rising = nodes[-1, 0] > nodes[0, 0]
        assert rising == (p.wall in ("groove", "lower"))
        a_exact, x_exact = exact_path(CAM, p.offset_mm)
        # every node on the exact path (at the pitch radius: the centre line moved by the offset)
        pitch_exact = np.column_stack([R * a_exact, x_exact])
        on = distances(np.column_stack([R * np.radians(nodes[:, 0]), nodes[:, 1]]), pitch_exact, 0.01)
        assert on.max() <= WRITTEN_MM + 1e-9
        # the offset itself, from the centre line: the nodes lie Rr − Rt off it
        centre = np.column_stack(exact_path(CAM, 0.0)) * [R, 1.0]
        off = distances(np.column_stack([R * np.radians(nodes[:, 0]), nodes[:, 1]]), centre, RR - tool + 0.01)
        assert off == pytest.approx(np.full_like(off, RR - tool), abs=WRITTEN_MM + 1e-9)
        # the moves as the control makes them: a line in each cylinder's developed plane; at the
        # outer radius, both ways, within the tolerance
        order = np.argsort(nodes[:, 0])
        path = np.column_stack([OUTER * np.radians(nodes[order, 0]), nodes[order, 1]])
        exact = np.column_stack([OUTER * a_exact, x_exact])
        t = np.linspace(0.0, 1.0, 65)[:, None, None]
        moved = (path[:-1][None] + t * (path[1:] - path[:-1])[None]).reshape(-1, 2)
        forward = distances(moved, exact, 2 * tolerance)
        backward = distances(exact[::7], path, 2 * tolerance)
        deviation = max(forward.max(), backward.max())
        assert deviation <= tolerance + WRITTEN_MM
        # and it is the deviation the toolpath measured (the written digits apart)
        assert deviation == pytest.approx(p.max_deviation_mm, abs=WRITTEN_MM + 1e-7)
        assert p.max_deviation_pitch_mm <= p.max_deviation_mm + 1e-9  # the circumference's error grows with r


def test_a_cutter_of_the_rollers_size_cuts_the_exact_flanks() -> None:
    angles, positions = np.linspace(0.0, 360.0, 721), np.linspace(44.0, 56.0, 7)
    gaps = wall_gaps(CAM, RR, angles, positions)
    # the flank points (the envelope formula) lie at the roller's radius from the cutter's axis
    # found by a search over the path: they agree to rounding
    assert max(np.abs(gaps["lower"]).max(), np.abs(gaps["upper"]).max()) < 1e-9
    tp = compute_barrel_toolpath(CAM, RR, 0.01)
    assert tp.wall_error_mm == 0.0 and tp.wall_gap_at_deg is None


def test_a_smaller_cutters_wall_gaps_against_a_brute_force_scan() -> None:
    tool = 8.0
    d = RR - tool
    angles, positions = np.array([17.0, 65.0, 101.0, 240.0, 283.0]), np.array([44.0, 50.0, 56.0])
    gaps = wall_gaps(CAM, tool, angles, positions)
    flanks = flank_points(CAM, angles, positions)
    for wall, sign in (("lower", -1.0), ("upper", 1.0)):
        a_exact, x_exact = exact_path(CAM, sign * d)
        px, py, pz = (np.asarray(c) for c in flanks[wall])
        rho, phi = np.hypot(px, py), np.arctan2(py, px)
        for i, theta in enumerate(np.radians(angles)):
            near = np.abs(np.mod(a_exact - theta + math.pi, 2 * math.pi) - math.pi) < 0.6
            for j in range(len(positions)):
                turn = phi[i, j] - a_exact[near]
                dist = np.hypot(rho[i, j] * np.sin(turn), pz[i, j] - x_exact[near])
                # the scan's step along the path is 1.2e-5 rad: its minimum is high by ~ρ·(step/2)²/2·κ ≈ 1e-9 mm
                assert gaps[wall][i, j] == pytest.approx(dist.min() - tool, abs=1e-8)
    # the wall a radial cutter leaves is right at the pitch radius only to first order: off it the
    # developed slope of the roller's wall is s'/r, the cutter's stays s'/R; a tenth of a millimetre
    # at most here, and the toolpath reports it
    tp = compute_barrel_toolpath(CAM, tool, 0.01)
    assert 0.01 < tp.wall_error_mm < 0.1
    assert tp.wall_gap_max_mm > 0 > tp.wall_gap_min_mm


def test_a_lift_with_corners_is_cut_through_them_by_a_cutter_of_the_rollers_size() -> None:
    cv = build_curve("named", {"name": "constant-velocity"})
    cam = make_barrel_cam(R, RR, roller_length_mm=LENGTH, segments=[Segment("rise", 180, lift_mm=20, curve=cv),
                                                                    Segment("return", 180, lift_mm=20, curve=cv)])
    tp = compute_barrel_toolpath(cam, RR, 0.01)
    # the straight rise is one move, and the corners are nodes
    assert tp.segments_count == 2 and tp.passes[0].cam_angle_deg.tolist() == [0.0, 180.0, 360.0]
    assert tp.passes[0].x_mm.tolist() == pytest.approx([0.0, 20.0, 0.0], abs=1e-12)
    with pytest.raises(CamError) as err:
        compute_barrel_toolpath(cam, 8.0, 0.01)
    assert err.value.field == ("tool_radius_mm",) and "velocity jumps at cam angle 0°" in str(err.value)


@pytest.mark.parametrize(("kwargs", "tool", "field", "words"), [
    ({}, 10.5, "tool_radius_mm", "wider than the groove"),
    ({}, 4.9, "tool_radius_mm", "leave a rib"),
    ({"roller": "conical"}, 10.0, "roller", "conical roller"),
    ({"follower": "oscillating", "arm_length_mm": 80.0}, 10.0, "follower", "translating follower"),
])
def test_refusals_name_the_field(kwargs: dict[str, object], tool: float, field: str, words: str) -> None:
    segments = [Segment(s.type, s.angle_deg, swing_deg=10 if s.type != "dwell" else None)
                for s in SEGMENTS] if kwargs.get("follower") == "oscillating" else SEGMENTS
    cam = make_barrel_cam(R, RR, roller_length_mm=LENGTH, segments=segments, **kwargs)  # type: ignore[arg-type]
    with pytest.raises(CamError) as err:
        compute_barrel_toolpath(cam, tool, 0.01)
    assert err.value.field == (field,) and words in str(err.value)


def test_a_toolpath_over_the_move_limit_stops_at_the_tolerance() -> None:
    with pytest.raises(LimitExceededError) as err:
        compute_barrel_toolpath(CAM, RR, 1e-4, max_elements=100)
    assert err.value.field == ("tolerance_mm",)


def test_the_registry_writes_the_program() -> None:
    tp: BarrelToolpath = compute_barrel_toolpath(CAM, RR, 0.01)
    fmt = BARREL_TOOLPATH_FORMATS["gcode"]
    data = fmt.write(BarrelToolpathFile(tp, 300.0, 61.0, 44.0))
    assert fmt.is_text and data.decode().startswith("%\n(camcore barrel cam groove")
    assert data.decode() == barrel_gcode(BarrelToolpathFile(tp, 300.0, 61.0, 44.0))
