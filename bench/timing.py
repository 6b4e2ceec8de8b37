"""Timing helpers of the bench: interleaved pairs, figures with their targets, the machine."""

from __future__ import annotations

import os
import platform
import re
import statistics
import subprocess
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import orjson


def timed(fn: Callable[[], Any]) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def paired_ratios(baseline: Callable[[], Any], subject: Callable[[], Any], repeats: int,
                  invert: bool = False) -> tuple[list[float], float, float]:
    """Per-pair ratios subject/baseline (baseline/subject when ``invert``), after one warm-up.

    Returns the ratios and the median times of baseline and subject [s].
    """
    baseline()
    subject()
    ratios, tb, ts = [], [], []
    for _ in range(repeats):
        b = timed(baseline)
        s = timed(subject)
        tb.append(b)
        ts.append(s)
        ratios.append(b / s if invert else s / b)
    return ratios, statistics.median(tb), statistics.median(ts)


def figure(ratios: list[float], target: str, **extra: Any) -> dict[str, Any]:
    """median/min/max of the ratios and whether the median meets ``target`` ("<= 3", ">= 80")."""
    med = statistics.median(ratios)
    op, bound = target.split()
    met = med <= float(bound) if op == "<=" else med >= float(bound)
    return {"median": round(med, 4), "min": round(min(ratios), 4), "max": round(max(ratios), 4),
            "runs": len(ratios), "target": target, "met": bool(met), **extra}


def machine_info() -> dict[str, Any]:
    model = platform.processor() or "unknown"
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=10, check=False).stdout
        m = re.search(r"Model name:\s*(.+)", out)
        if m:
            model = m.group(1).strip()
    except (OSError, subprocess.SubprocessError):
        pass
    return {
        "cpu_model": model,
        "cpus": os.cpu_count(),
        "loadavg_at_start": [round(x, 2) for x in os.getloadavg()],
        "python": platform.python_version(),
        "numpy": np.__version__,
        "orjson": orjson.__version__,
        "platform": platform.platform(),
        "date": time.strftime("%Y-%m-%d"),
        "cpu_features": cpu_features(),
    }


#: the CPU features that decide how fast numpy's vectorised loops are (sin, cos, tan, exp)
FEATURES_OF_INTEREST = ("SSE42", "AVX", "FMA3", "AVX2", "AVX512F", "AVX512_SKX", "AVX512_ICL")


def cpu_features() -> dict[str, bool]:
    """Which of :data:`FEATURES_OF_INTEREST` numpy found on this CPU (its own runtime dispatch:
    numpy vectorises tan, for one, only with AVX-512)."""
    from numpy._core._multiarray_umath import __cpu_features__

    return {name: bool(__cpu_features__.get(name, False)) for name in FEATURES_OF_INTEREST}


