"""Independent checks of a toolpath (for the toolpath tests): a small G-code reader, the exact
cutter path built from ``compute_profile`` alone, and the distances between two polylines.

Nothing here uses camcore.toolpath: the G-code is read as a control would (modal G0-G3, X Y Z
I J F words, I J relative to the arc's start), and the exact path comes from the profile's
surface and pitch points (their difference is the roller's radius along the normal), so a
mistake in the toolpath code cannot cancel itself here.
"""

from __future__ import annotations

import math
import re

import numpy as np

WORD = re.compile(r"([A-Z])(-?\d+(?:\.\d*)?)")


def parse_gcode(text: str) -> list[dict[str, float | str]]:
    """The moves of a program, each ``{"g": 0..3, "x", "y", "z", "i", "j", "f"}`` (modal values
    carried), comments ``( … )`` and ``%`` lines ignored."""
    state: dict[str, float | str] = {"g": 0.0, "x": math.nan, "y": math.nan, "z": math.nan, "f": math.nan}
    moves: list[dict[str, float | str]] = []
    for raw in text.splitlines():
        line = re.sub(r"\(.*?\)", "", raw).strip()
        if not line or line == "%":
            continue
        words = WORD.findall(line)
        gs = [float(v) for k, v in words if k == "G"]
        motion = [g for g in gs if g in (0.0, 1.0, 2.0, 3.0)]
        if motion:
            state["g"] = motion[-1]
        axes = {k.lower(): float(v) for k, v in words if k in "XYZIJF"}
        if not any(k in axes for k in "xyz"):
            if "f" in axes:
                state["f"] = axes["f"]
            continue
        move = {**state, "x0": state["x"], "y0": state["y"], "i": 0.0, "j": 0.0, **axes}
        state.update({k: move[k] for k in ("x", "y", "z", "f")})
        moves.append(move)
    return moves


def cutting_polylines(moves: list[dict[str, float | str]], step_mm: float) -> list[np.ndarray]:
    """The XY polylines the tool runs at depth (from the plunge to the retract), arcs sampled
    every ``step_mm`` or finer. Each starts and ends at its lead-in point: its first and last
    pieces are the lead-in and the lead-out."""
    paths: list[list[tuple[float, float]]] = []
    current: list[tuple[float, float]] | None = None
    for m in moves:
        g = float(m["g"])
        if g == 0.0:
            current = None
            continue
        x0, y0, x1, y1 = float(m["x0"]), float(m["y0"]), float(m["x"]), float(m["y"])
        if current is None:
            current = [(x1, y1)]
            paths.append(current)
            continue
        if g == 1.0:
            current.append((x1, y1))
            continue
        cx, cy = x0 + float(m["i"]), y0 + float(m["j"])
        r = math.hypot(x0 - cx, y0 - cy)
        a0, a1 = math.atan2(y0 - cy, x0 - cx), math.atan2(y1 - cy, x1 - cx)
        sweep = (a1 - a0) % (2 * math.pi) if g == 3.0 else -((a0 - a1) % (2 * math.pi))
        n = max(2, math.ceil(abs(sweep) * r / step_mm))
        a = a0 + sweep * np.linspace(0.0, 1.0, n + 1)[1:]
        current.extend(zip((cx + r * np.cos(a)).tolist(), (cy + r * np.sin(a)).tolist()))
    return [np.array(p) for p in paths if len(p) > 1]


def densify(points: np.ndarray, step_mm: float) -> np.ndarray:
    """The polyline with points added along its straight pieces, at most ``step_mm`` apart."""
    pieces = np.diff(points, axis=0)
    counts = np.maximum(1, np.ceil(np.hypot(pieces[:, 0], pieces[:, 1]) / step_mm).astype(int))
    owner = np.repeat(np.arange(len(pieces)), counts)
    # the fraction of each new point along its piece: 1/n, 2/n, …, 1
    u = (np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts) + 1) / np.repeat(counts, counts)
    return np.vstack([points[:1], points[owner] + pieces[owner] * u[:, None]])


def distances_to_polyline(points: np.ndarray, polyline: np.ndarray, window: int = 60) -> np.ndarray:
    """Distance of each point from a closed polyline (last vertex = first), for curves that
    pass near themselves only where they are near in order: the nearest of every
    ``window``-th vertex first, then every segment within two windows of it (round the
    closure)."""
    coarse = polyline[::window]
    out = np.empty(len(points))
    for k in range(0, len(points), 2000):
        chunk = points[k:k + 2000]
        near = np.argmin(((chunk[:, None, :] - coarse[None, :, :]) ** 2).sum(axis=2), axis=1) * window
        offsets = np.arange(-2 * window, 2 * window + 1)
        idx = (near[:, None] + offsets[None, :]) % (len(polyline) - 1)
        a, b = polyline[idx], polyline[idx + 1]
        ab = b - a
        length2 = (ab ** 2).sum(axis=2)
        u = np.clip(((chunk[:, None, :] - a) * ab).sum(axis=2) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
        foot = a + u[..., None] * ab
        out[k:k + 2000] = np.sqrt(((chunk[:, None, :] - foot) ** 2).sum(axis=2)).min(axis=1)
    return out


def max_sagitta(polyline: np.ndarray, radius_mm: float) -> float:
    """The largest gap between a polyline's chords and a curve of radius ≥ ``radius_mm`` through
    its vertices: c²/(8r) for the longest chord c [mm]."""
    chords = np.hypot(*np.diff(polyline, axis=0).T)
    return float(chords.max() ** 2 / (8.0 * radius_mm))
