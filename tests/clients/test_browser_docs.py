"""/docs and /redoc work with no internet: a real headless Chromium, network limited to loopback.

The service runs as users start it (``python -m service`` on a loopback port). Chromium gets a
proxy that does not exist for every host except 127.0.0.1 and a resolver that resolves no name,
so a page that needs a CDN (FastAPI's default /docs does) stays empty and the test fails.

Needs Debian's ``chromium`` (tests/chromium.py); without it the test FAILS.
"""

from __future__ import annotations

import os
import shutil
import struct
import subprocess
from pathlib import Path

import httpx
import numpy as np
import pytest

from tests.chromium import run_chromium

ROOT = Path(__file__).resolve().parents[2]
pytestmark = [pytest.mark.e2e, pytest.mark.chromium]

#: Chromium runs the page until it has been idle this long (virtual time) [ms]
BUDGET = "--virtual-time-budget=10000"
OPERATIONS = ["getHealth", "listCurves", "sampleCurve", "invertCurve", "sampleNamedCurve", "getIndexerMotion",
              "sizeIndexer", "computeProfile", "plotCurve", "plotIndexerMotion", "plotProfile"]


def run_page(*args: str) -> subprocess.CompletedProcess[bytes]:
    return run_chromium(BUDGET, *args, timeout_s=120)


def test_docs_pages_reference_only_local_assets(base_url: str) -> None:
    for page in ("/docs", "/redoc"):
        html = httpx.get(base_url + page, timeout=10).text
        assert "cdn.jsdelivr.net" not in html and "fonts.googleapis.com" not in html and "https://" not in html
    for asset in ("swagger-ui-bundle.js", "swagger-ui.css", "redoc.standalone.js", "favicon.png"):
        r = httpx.get(f"{base_url}/static/docs/{asset}", timeout=10)
        assert r.status_code == 200 and len(r.content) > 1000, asset
    assert httpx.get(f"{base_url}/docs/oauth2-redirect", timeout=10).status_code == 200
    # the pages are not API operations
    paths = httpx.get(f"{base_url}/openapi.json", timeout=10).json()["paths"]
    assert not any(p.startswith(("/docs", "/redoc", "/static")) for p in paths)


def test_swagger_ui_lists_every_operation_offline(base_url: str) -> None:
    dom = run_page("--dump-dom", f"{base_url}/docs").stdout.decode()
    assert 'id="swagger-ui"' in dom
    # Swagger UI (deepLinking) gives every operation the element id operations-<tag>-<operationId>
    missing = [op for op in OPERATIONS if f"-{op}\"" not in dom]
    assert not missing, f"Swagger UI did not render {missing}; DOM starts: {dom[:1500]}"
    for summary in ("Catalog of named curves", "Plate cam profile as DXF drawing", "Catalog curve chart (S, V, A, J)"):
        assert summary in dom


def test_redoc_lists_every_operation_offline(base_url: str) -> None:
    dom = run_page("--dump-dom", f"{base_url}/redoc").stdout.decode()
    missing = [op for op in OPERATIONS if f"operation/{op}" not in dom]
    assert not missing, f"ReDoc did not render {missing}; DOM starts: {dom[:1500]}"


def test_swagger_ui_screenshot_is_not_blank(base_url: str, tmp_path: Path) -> None:
    shot = tmp_path / "docs.png"
    run_page("--window-size=1280,2000", f"--screenshot={shot}", f"{base_url}/docs")
    body = shot.read_bytes()
    assert body[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", body[16:24])
    assert (width, height) == (1280, 2000)
    import matplotlib.image

    pixels = np.asarray(matplotlib.image.imread(shot, format="png"))[..., :3]
    assert float(pixels.var()) > 0.001, "the screenshot is blank"
    # Swagger UI's GET buttons are blue (#61affe) and POST green (#49cc90): the operations are drawn
    blue = np.all(np.abs(pixels - np.array([0x61, 0xAF, 0xFE]) / 255) < 0.03, axis=-1).sum()
    green = np.all(np.abs(pixels - np.array([0x49, 0xCC, 0x90]) / 255) < 0.03, axis=-1).sum()
    assert blue > 1000 and green > 1000, (blue, green)
    if os.environ.get("CAMCORE_SAVE_SCREENSHOT"):
        shutil.copy(shot, os.environ["CAMCORE_SAVE_SCREENSHOT"])
