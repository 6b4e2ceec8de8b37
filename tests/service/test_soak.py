"""The memory soak (issue 34): one worker under mixed traffic, STEP and STL exports and 32
clients that stall on large answers, for CAMCORE_SOAK_S seconds (75 by default; 600 for the
10-minute soak), its RSS and its CAD kernel process's polled every 0.1 s (scripts/soak.py).

It fails when the worker with its kernel process goes over the ceiling the README,
docs/robustness.md and the deployment state, 700 MiB. Measured on the 2-core AMD EPYC machine
(docs/robustness.md, "Memory"): before issue 34 the worker alone reached 857 MiB in the same
75 s; after it, 618 MiB at most (worker 342 MiB, kernel process 278 MiB). 700 MiB leaves
~80 MiB (13 %) over that peak for a longer run's caches and another machine's allocator."""

from __future__ import annotations

import os

import pytest

from scripts.soak import run

pytestmark = pytest.mark.soak

#: the stated ceiling of one worker with its CAD kernel process [MiB] (README, docs/robustness.md)
CEILING_MIB = 700


def test_one_worker_stays_under_the_stated_ceiling() -> None:
    seconds = float(os.environ.get("CAMCORE_SOAK_S", "75"))
    figures = run(seconds=seconds)
    (peak,) = figures["worker_with_children_peak_mib"].values()
    assert figures["unexpected"] == {}, figures
    # the traffic happened: a solid written before it (the kernel process is up through the soak),
    # answers of each kind, solids asked for throughout (on one busy worker they may all meet a 503:
    # a CI run had none answered), stalled downloads held
    assert figures["primed_solid_status"] == 200, figures
    statuses = figures["statuses"]
    assert statuses.get("table 200", 0), statuses
    assert sum(count for key, count in statuses.items() if key.split()[0] in ("step", "stl")) > 0, statuses
    assert figures["stalls"] > 0 and figures["child_processes_seen"] >= 1, figures
    assert peak <= CEILING_MIB, figures
