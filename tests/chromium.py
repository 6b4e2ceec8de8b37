"""A real headless Chromium for the client tests, its network limited to loopback.

Every host but 127.0.0.1 goes to a proxy that is not there and no name resolves, so a page
that needs the internet (a CDN) stays empty and its test fails. Needs Debian's ``chromium``
(``make test`` installs it: scripts/install_test_tools.sh); without it the test FAILS. Set
``CAMCORE_CHROMIUM`` to use another binary.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile

import pytest

LOOPBACK_ONLY_FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--disable-dev-shm-usage", "--hide-scrollbars", "--mute-audio",
    "--proxy-server=127.0.0.1:9", "--proxy-bypass-list=127.0.0.1",
    "--host-resolver-rules=MAP * ~NOTFOUND , EXCLUDE 127.0.0.1",
]


def chromium() -> str:
    path = os.environ.get("CAMCORE_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if not path:
        pytest.fail("Chromium is not installed: this test needs a headless browser. "
                    "Install it with: apt-get update && apt-get install -y chromium "
                    "(or set CAMCORE_CHROMIUM to a Chrome/Chromium binary).", pytrace=False)
    return path


def run_chromium(*args: str, timeout_s: float) -> subprocess.CompletedProcess[bytes]:
    """Chromium with ``args`` after the loopback-only flags, in a throwaway profile; it must exit 0."""
    binary = chromium()
    with tempfile.TemporaryDirectory(prefix="camcore-chromium-") as profile:
        proc = subprocess.run([binary, *LOOPBACK_ONLY_FLAGS, f"--user-data-dir={profile}", *args],
                              capture_output=True, timeout=timeout_s, check=False)
    assert proc.returncode == 0, proc.stderr.decode(errors="replace")[-2000:]
    return proc
