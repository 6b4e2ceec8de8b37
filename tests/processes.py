"""An external program run by a test, bounded in time: on a timeout its whole process group is
ended (soffice starts soffice.bin, freecadcmd its own children, which would outlive it)."""

from __future__ import annotations

import os
import signal
import subprocess
from collections.abc import Mapping, Sequence


def run_bounded(cmd: Sequence[str], timeout_s: float, env: Mapping[str, str] | None = None,
                merge_stderr: bool = False) -> subprocess.CompletedProcess[str]:
    """``cmd`` in a session of its own, its text output captured (stderr into stdout when
    ``merge_stderr``); an AssertionError with what it printed when it runs past ``timeout_s``."""
    stderr = subprocess.STDOUT if merge_stderr else subprocess.PIPE
    with subprocess.Popen(list(cmd), stdout=subprocess.PIPE, stderr=stderr, text=True, start_new_session=True,
                          env=None if env is None else dict(env)) as proc:
        try:
            out, err = proc.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
            raise AssertionError(f"{' '.join(cmd)} did not finish in {timeout_s} s: {out} {err or ''}") from None
    return subprocess.CompletedProcess(list(cmd), proc.returncode, out, err or "")
