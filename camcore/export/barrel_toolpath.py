"""A barrel cam's groove as a G-code program for a four-axis mill (rotary axis A about X).

The machine's convention is :mod:`camcore.cams.barrel.toolpath`'s: the cam's axis on A along
X, X = 0 at the cam's z = 0, A the cam angle in degrees (A+ the tool's right-hand turn about
+X relative to the part, ISO 841: the part turns clockwise seen from +X), the tool radial along
Z through the cam axis (Y = 0), Z the tool tip's distance from the cam axis. The header states
it, the wrap (pitch) diameter the A words are drawn on, the cam's outer diameter, the cutter,
the tolerance and the deviations measured.

Words: ``G17 G21 G90 G40 G94`` (mm, absolute, no cutter compensation: the program is the
cutter's axis), ``G0`` up to the safe Z and over to Y = 0, then per pass ``G0`` to the safe Z, ``G0`` to the pass's start in X and A,
``G93`` and ``G1`` down to the cutting depth, the straight moves ``G1 X… A…``, ``G0`` up and
``G94``; ``M30`` at the end. Feed in inverse time (``G93``): each ``G1`` block carries
F = 1/(its minutes), its minutes being its length in the developed plane of the pitch radius
(√((R·ΔA)² + ΔX²), ΔA in radians; the plunge: |ΔZ|) over the feed. A control that reads ``F``
in mm/min on a move of A and X together (``G94``) mixes degrees and millimetres, each control
its own way (Fanuc: the vector of both; LinuxCNC: the linear axes alone), so the tool's speed
along the groove would depend on the control and on the radius; inverse time says the block's
time, which every control keeps. Coordinates to 1e-6 mm and 1e-6°; F to 1e-6 min⁻¹ (and at
least that). Comments hold no ``;`` and no parenthesis (a ``;`` starts a line comment for some
readers, pygcode among them).

References
----------
.. [1] ISO 6983-1:2009 (G00, G01, G17, G21, G40, G90, G93, G94; A, X, Z, F; M30).
.. [2] NIST RS274/NGC Interpreter, version 3 (NISTIR 6556, 2000), 3.5.19: inverse time feed
   rate, every G1 block in G93 with an F word of its own.
.. [3] ISO 841:2001 (A about X).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..cams.barrel.toolpath import BarrelToolpath, RotaryPass
from .registry import FileFormat

#: the smallest inverse-time F written [1/min] (a block's F is never rounded to 0)
MIN_INVERSE_TIME = 1e-6


@dataclass(frozen=True)
class BarrelToolpathFile:
    """What a barrel cam's program writes: the passes and how the machine runs them.

    Attributes
    ----------
    toolpath : BarrelToolpath
        The fitted passes (camcore.cams.barrel.toolpath).
    feed_mm_min : float
        The cutter axis's speed along the groove at the pitch radius (and of the plunge) [mm/min].
    safe_z_mm : float
        The tool tip's distance from the cam axis during rapid moves, above the cam [mm].
    cut_z_mm : float
        The tool tip's distance from the cam axis while cutting: the groove's bottom radius for
        the full depth [mm].
    """

    toolpath: BarrelToolpath
    feed_mm_min: float
    safe_z_mm: float
    cut_z_mm: float


def _num(v: float) -> str:
    """A coordinate to 1e-6, without trailing zeros (``12.5``, ``-0.000001``, ``0``)."""
    text = f"{v:.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _inverse_time(length_mm: float, feed_mm_min: float) -> str:
    """F of a G93 block: 1 / its minutes [1/min], at least :data:`MIN_INVERSE_TIME`."""
    return _num(max(feed_mm_min / length_mm, MIN_INVERSE_TIME))


def _pass_blocks(p: RotaryPass, file: BarrelToolpathFile, number: int) -> list[str]:
    tp, feed = file.toolpath, file.feed_mm_min
    direction = "A rising" if p.a_deg[-1] > p.a_deg[0] else "A falling"
    what = ("the groove, both walls - the cutter is the roller" if p.wall == "groove"
            else f"the {p.wall} wall, cutter axis {_num(abs(p.offset_mm))} mm off the centre line")
    lines = [f"(pass {number}: {what}, {direction}, {len(p.a_deg) - 1} moves, deviation {p.max_deviation_mm:.3g} mm)",
             f"G0 Z{_num(file.safe_z_mm)}", f"G0 X{_num(p.x_mm[0])} A{_num(p.a_deg[0])}", "G93",
             f"G1 Z{_num(file.cut_z_mm)} F{_inverse_time(abs(file.safe_z_mm - file.cut_z_mm), feed)}"]
    r = tp.pitch_radius_mm
    for k in range(1, len(p.a_deg)):
        length = math.hypot(r * math.radians(p.a_deg[k] - p.a_deg[k - 1]), p.x_mm[k] - p.x_mm[k - 1])
        if length == 0.0:
            continue
        lines.append(f"G1 X{_num(p.x_mm[k])} A{_num(p.a_deg[k])} F{_inverse_time(length, feed)}")
    return [*lines, f"G0 Z{_num(file.safe_z_mm)}", "G94"]


def barrel_gcode(file: BarrelToolpathFile) -> str:
    """The passes as a four-axis G-code program (module notes for the machine and the words).

    Parameters
    ----------
    file : BarrelToolpathFile
        The passes, the feed [mm/min], the safe and cutting Z [mm].

    Returns
    -------
    str
        The program, one block per line, ``%`` at both ends.

    References
    ----------
    ISO 6983-1:2009; NIST RS274/NGC (NISTIR 6556), inverse time feed (G93); ISO 841 (A about X).
    """
    tp = file.toolpath
    cutter = "the roller's radius" if tp.tool_radius_mm == tp.roller_radius_mm else \
        f"the roller's {_num(tp.roller_radius_mm)} mm, one pass on each wall"
    lines = [
        "%",
        f"(camcore barrel cam groove, 4-axis: tool radius {_num(tp.tool_radius_mm)} mm against {cutter})",
        "(X along the cam axis, X0 at the cam's z = 0 - the follower's zero lift)",
        ("(A about X in degrees = the cam angle, A0 with the cam's angle 0 under the tool, A+ turns the cam clockwise "
        "seen from +X as in service)"),
        "(Z radial: the tool tip's distance from the cam axis, the tool axis through it, Y0)",
        (f"(wrap diameter {_num(2 * tp.pitch_radius_mm)} mm - the pitch diameter, the A words drawn on it, "
        f"cam outer diameter {_num(2 * tp.outer_radius_mm)} mm, groove bottom diameter "
        f"{_num(2 * tp.groove_bottom_radius_mm)} mm)"),
        (f"(tolerance {_num(tp.tolerance_mm)} mm at the outer diameter, measured deviation {tp.max_deviation_mm:.3g} mm "
        f"there and {tp.max_deviation_pitch_mm:.3g} mm at the pitch diameter, {tp.segments_count} moves)"),
        (f"(feed G93 inverse time: F = 1/minutes of each block, for {_num(file.feed_mm_min)} mm/min along the groove "
        "at the pitch diameter)"),
        "(the plunge is straight down into the part: a centre-cutting end mill, climb milling with M3)",
        "(start the spindle and coolant before running)",
        "G17 G21 G90 G40 G94",
        f"G0 Z{_num(file.safe_z_mm)}",
        "G0 Y0",
    ]
    for k, p in enumerate(tp.passes, start=1):
        lines += _pass_blocks(p, file, k)
    lines += ["M30", "%"]
    return "\n".join(lines) + "\n"


def _write_gcode(file: BarrelToolpathFile) -> bytes:
    return barrel_gcode(file).encode()


#: a barrel cam's toolpath downloads, by name; ``cost(moves)``: measured ~3 µs a move; ×2
BARREL_TOOLPATH_FORMATS: dict[str, FileFormat[BarrelToolpathFile]] = {f.name: f for f in (
    FileFormat("gcode", "text/x-gcode; charset=utf-8", "barrel_cam_toolpath.nc",
               "G-code for a 4-axis mill (A about the cam axis along X, Z radial; G93 inverse-time feed): the cutter "
               "axis's straight moves in A and X", _write_gcode, lambda moves: 2 * 3e-6 * moves),
)}
