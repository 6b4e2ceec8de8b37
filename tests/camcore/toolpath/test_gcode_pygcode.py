"""The toolpath's G-code read by an independent reader, pygcode 0.2.1 (PyPI; its parser and
``Machine``, which keeps the modal state and the position as a control does), rather than by the
tests' own reader (tests/toolpath_reference.py).

Issue 33: a header comment held a ``;`` inside its parentheses; pygcode (and controls that read
``;`` as the start of a line comment) took the rest of the line for words and refused it.
Every line must parse, and the positions the machine reaches must be the toolpath's own.
"""

from __future__ import annotations

import math

import pytest
from pygcode import Line, Machine

import camcore
from camcore.export import ToolpathFile, toolpath_gcode
from camcore.export.toolpath import lead_point
from camcore.profile import Follower, Segment, make_cam
from camcore.toolpath import compute_toolpath

MS = camcore.named_curve("MS")
ROLLER = make_cam(Follower(type="roller", roller_radius_mm=10), 40, segments=[
    Segment(type="rise", angle_deg=120, lift_mm=20, curve=MS), Segment(type="dwell", angle_deg=60),
    Segment(type="return", angle_deg=120, lift_mm=20), Segment(type="dwell", angle_deg=60)])
#: the program writes coordinates with 6 decimals (camcore.export.toolpath._num): half a unit of
#: the last place, and as much again for an arc centre (its start plus the written I, J)
WRITTEN_MM = 1e-6


def read(text: str) -> tuple[list[Line], list[tuple[float, float, float]], list[tuple[float, float]]]:
    """Every line of the program as pygcode parses it, the machine's position after each motion
    block, and the centre of each arc (its start plus I, J)."""
    machine = Machine()
    lines, positions, centres = [], [], []
    for raw in text.splitlines():
        if raw == "%":  # the tape's start and end (ISO 6983-1), not a block
            continue
        line = Line(raw)  # raises on a word it cannot read
        lines.append(line)
        words = {word.letter: float(word.value) for word in line.block.words}
        start = machine.pos
        if "I" in words:
            centres.append((start.X + words["I"], start.Y + words["J"]))
        machine.process_block(line.block)
        if any(code.word.letter == "G" and code.word.value in (0, 1, 2, 3) for code in line.block.gcodes):
            positions.append((machine.pos.X, machine.pos.Y, machine.pos.Z))
    return lines, positions, centres


@pytest.mark.parametrize("side", ["outside", "groove"])
def test_pygcode_reads_the_program_back_as_the_toolpath(side: str) -> None:
    tp = compute_toolpath(ROLLER, 6.0 if side == "outside" else 8.0, 0.01, side=side)
    file = ToolpathFile(tp, 400.0, safe_z_mm=5.0, cut_z_mm=-2.0)
    lines, positions, centres = read(toolpath_gcode(file))
    # the header's comments are comments: no words, their text kept whole
    header = lines[:3]
    assert all(not line.block.words and line.comment is not None for line in header)
    assert "no cutter compensation, climb milling" in str(header[1].comment)
    expected: list[tuple[float, float, float]] = []
    expected_centres = []
    for path in tp.paths:
        x, y, _ = expected[-1] if expected else (0.0, 0.0, 0.0)  # the machine starts at its origin
        lx, ly = lead_point(path, file.lead_in_mm)
        expected += [(x, y, 5.0), (lx, ly, 5.0), (lx, ly, -2.0), (*path.elements[0].start, -2.0)]
        expected += [(*e.end, -2.0) for e in path.elements]
        expected += [(lx, ly, -2.0), (lx, ly, 5.0)]
        expected_centres += [e.centre for e in path.elements if e.centre is not None]
    assert len(positions) == len(expected) and len(centres) == len(expected_centres)
    for got, want in zip(positions, expected, strict=True):
        assert math.dist(got, want) <= WRITTEN_MM, (got, want)
    for got_c, want_c in zip(centres, expected_centres, strict=True):
        assert math.dist(got_c, want_c) <= 2 * WRITTEN_MM, (got_c, want_c)
