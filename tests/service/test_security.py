"""Access control (service/security.py): the API key and the CORS allow-list.

Both are off by default; with the defaults the app, its answers and its OpenAPI
document are exactly those of an app without them.
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import AsyncIterator
from pathlib import Path

import httpx
import pytest
from fastapi import FastAPI
from starlette.middleware.cors import CORSMiddleware

from service.app import create_app
from service.security import UNAUTHORIZED_DETAIL, APIKeyMiddleware, install_security
from service.settings import Settings

pytestmark = pytest.mark.anyio

KEY = "s3cret-key-for-tests"
ORIGIN = "https://plant.example"
ROOT = Path(__file__).resolve().parents[2]
MS_TABLE = {"curve": {"type": "named", "name": "MS"}, "samples": 5}


def build(settings: Settings) -> FastAPI:
    """The app as deployed: create_app with security installed (once)."""
    app = create_app(settings)
    installed = {m.cls for m in app.user_middleware}
    if APIKeyMiddleware not in installed and CORSMiddleware not in installed:
        install_security(app, settings)  # until create_app calls install_security itself
    return app


async def client_for(settings: Settings) -> AsyncIterator[httpx.AsyncClient]:
    transport = httpx.ASGITransport(app=build(settings))
    async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as c:
        yield c


@pytest.fixture
async def keyed() -> AsyncIterator[httpx.AsyncClient]:
    async for c in client_for(Settings(api_key=KEY)):
        yield c


@pytest.fixture
async def cors() -> AsyncIterator[httpx.AsyncClient]:
    async for c in client_for(Settings(cors_origins=[ORIGIN])):
        yield c


@pytest.fixture
async def both() -> AsyncIterator[httpx.AsyncClient]:
    async for c in client_for(Settings(api_key=KEY, cors_origins=[ORIGIN])):
        yield c


# ----------------------------------------------------------------------------- API key
def assert_unauthorized(r: httpx.Response) -> None:
    assert r.status_code == 401, r.text
    assert r.headers["content-type"] == "application/json"
    assert r.json() == {"detail": UNAUTHORIZED_DETAIL, "errors": []}


async def test_request_without_key_is_401(keyed: httpx.AsyncClient) -> None:
    assert_unauthorized(await keyed.post("/v1/curves/table", json=MS_TABLE))
    assert_unauthorized(await keyed.get("/v1/curves"))
    assert_unauthorized(await keyed.get("/v1/curves/MS/table", params={"format": "csv"}))


async def test_request_with_wrong_key_is_401(keyed: httpx.AsyncClient) -> None:
    for wrong in ("", "s3cret", KEY + "x", KEY.upper(), "ü" * 3):
        r = await keyed.post("/v1/curves/table", json=MS_TABLE, headers={"X-API-Key": wrong.encode()})
        assert_unauthorized(r)
    # the key goes in X-API-Key, not as a bearer token or a query parameter
    assert_unauthorized(await keyed.get("/v1/curves", headers={"Authorization": f"Bearer {KEY}"}))
    assert_unauthorized(await keyed.get("/v1/curves", params={"api_key": KEY}))


async def test_request_with_key_is_answered(keyed: httpx.AsyncClient) -> None:
    r = await keyed.post("/v1/curves/table", json=MS_TABLE, headers={"X-API-Key": KEY})
    assert r.status_code == 200, r.text
    assert len(r.json()["s"]) == 5
    # header names are case-insensitive
    r = await keyed.get("/v1/curves/MS", headers={"x-api-key": KEY})
    assert r.status_code == 200 and r.json()["id"] == "MS"
    # errors behind the key are the ordinary ones
    r = await keyed.get("/v1/curves/nope", headers={"X-API-Key": KEY})
    assert r.status_code == 404


async def test_health_and_docs_stay_open(keyed: httpx.AsyncClient) -> None:
    r = await keyed.get("/health")
    assert r.status_code == 200 and r.json()["status"] == "ok"
    for path in ("/docs", "/redoc", "/openapi.json"):
        assert (await keyed.get(path)).status_code == 200, path
    # only the exact paths: nothing below /health or /docs is opened with them
    assert_unauthorized(await keyed.get("/health/x"))
    assert_unauthorized(await keyed.get("/docsx"))


async def test_unauthenticated_large_body_gets_401_not_413(keyed: httpx.AsyncClient) -> None:
    body = b"{" + b" " * (5 * 1024 * 1024) + b"}"
    r = await keyed.post("/v1/curves/table", content=body, headers={"content-type": "application/json"})
    assert_unauthorized(r)


# ----------------------------------------------------------------------------- CORS
def preflight(origin: str, method: str = "POST", headers: str = "content-type,x-api-key") -> dict[str, str]:
    return {"Origin": origin, "Access-Control-Request-Method": method, "Access-Control-Request-Headers": headers}


async def test_cors_preflight_allowed_for_listed_origin(cors: httpx.AsyncClient) -> None:
    r = await cors.options("/v1/curves/table", headers=preflight(ORIGIN))
    assert r.status_code == 200
    assert r.headers["access-control-allow-origin"] == ORIGIN
    allowed_methods = {m.strip() for m in r.headers["access-control-allow-methods"].split(",")}
    assert allowed_methods == {"GET", "POST"}
    allowed_headers = {h.strip().lower() for h in r.headers["access-control-allow-headers"].split(",")}
    assert {"content-type", "accept", "x-api-key"} <= allowed_headers
    # and the actual request carries the header
    r = await cors.post("/v1/curves/table", json=MS_TABLE, headers={"Origin": ORIGIN})
    assert r.status_code == 200
    assert r.headers["access-control-allow-origin"] == ORIGIN


async def test_cors_preflight_refused_for_other_origin_method_or_header(cors: httpx.AsyncClient) -> None:
    r = await cors.options("/v1/curves/table", headers=preflight("https://evil.example"))
    assert r.status_code == 400
    assert "access-control-allow-origin" not in r.headers
    r = await cors.post("/v1/curves/table", json=MS_TABLE, headers={"Origin": "https://evil.example"})
    assert r.status_code == 200  # CORS is enforced by the browser: no allow-origin header
    assert "access-control-allow-origin" not in r.headers
    assert (await cors.options("/v1/curves/table", headers=preflight(ORIGIN, method="DELETE"))).status_code == 400
    assert (await cors.options("/v1/curves/table", headers=preflight(ORIGIN, headers="x-other"))).status_code == 400


async def test_cors_preflight_needs_no_key_and_401_carries_cors_headers(both: httpx.AsyncClient) -> None:
    r = await both.options("/v1/curves/table", headers=preflight(ORIGIN))
    assert r.status_code == 200
    assert r.headers["access-control-allow-origin"] == ORIGIN
    r = await both.post("/v1/curves/table", json=MS_TABLE, headers={"Origin": ORIGIN})
    assert_unauthorized(r)
    assert r.headers["access-control-allow-origin"] == ORIGIN  # the browser may read the 401
    r = await both.post("/v1/curves/table", json=MS_TABLE, headers={"Origin": ORIGIN, "X-API-Key": KEY})
    assert r.status_code == 200


# ----------------------------------------------------------------------------- defaults
async def test_defaults_change_nothing() -> None:
    settings = Settings()
    assert settings.api_key is None and settings.cors_origins == []
    app = build(settings)
    plain = create_app(settings)
    assert [m.cls for m in app.user_middleware] == [m.cls for m in plain.user_middleware]
    assert app.openapi() == plain.openapi()
    async for c in client_for(settings):
        assert (await c.post("/v1/curves/table", json=MS_TABLE)).status_code == 200
        r = await c.options("/v1/curves/table", headers=preflight(ORIGIN))
        assert "access-control-allow-origin" not in r.headers
        r = await c.get("/v1/curves", headers={"Origin": ORIGIN})
        assert r.status_code == 200 and "access-control-allow-origin" not in r.headers


async def test_openapi_document_is_the_same_with_security_on() -> None:
    on = build(Settings(api_key=KEY, cors_origins=[ORIGIN]))
    assert on.openapi() == create_app(Settings()).openapi()


async def test_create_app_installs_security() -> None:
    """create_app itself applies the settings (the wiring in service/app.py)."""
    app = create_app(Settings(api_key=KEY, cors_origins=[ORIGIN]))
    installed = [m.cls for m in app.user_middleware]
    assert APIKeyMiddleware in installed and CORSMiddleware in installed
    # CORS outermost (first in user_middleware), then the key check, then the body-size limit
    assert installed.index(CORSMiddleware) < installed.index(APIKeyMiddleware)


def test_settings_from_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CAMCORE_API_KEY", KEY)
    monkeypatch.setenv("CAMCORE_CORS_ORIGINS", f'["{ORIGIN}", "http://localhost:3000"]')
    settings = Settings()
    assert settings.api_key == KEY
    assert settings.cors_origins == [ORIGIN, "http://localhost:3000"]


async def test_nosniff_also_on_unexpected_errors_and_preflights() -> None:
    """X-Content-Type-Options wraps the whole app: also the 500 that Starlette's outermost
    error middleware sends, and CORS's own preflight answers."""
    app = create_app(Settings(cors_origins=[ORIGIN]))

    @app.get("/boom", include_in_schema=False)
    async def boom() -> None:
        raise RuntimeError("a bug")

    transport = httpx.ASGITransport(app=app, raise_app_exceptions=False)
    async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as c:
        r = await c.get("/boom")
        assert r.status_code == 500 and r.json()["detail"] == "Internal error; it has been logged."
        assert r.headers["x-content-type-options"] == "nosniff"
        r = await c.options("/v1/curves/table", headers=preflight(ORIGIN))
        assert r.status_code == 200 and r.headers["x-content-type-options"] == "nosniff"
        # a plain OPTIONS (no preflight) is the router's 405, with every method of the path
        r = await c.options("/v1/curves/table")
        assert r.status_code == 405 and r.headers["allow"] == "GET, POST"


def test_empty_key_means_off() -> None:
    app = build(Settings(api_key=""))
    assert APIKeyMiddleware not in {m.cls for m in app.user_middleware}
    with pytest.raises(ValueError):
        APIKeyMiddleware(app, api_key="")


# ---------------------------------------------------------------------- the key in a file
def test_key_file_sets_the_key(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    # a Kubernetes Secret mounted as a file holds the bytes as given; `echo key > file` adds a newline
    (tmp_path / "api-key").write_text(KEY + "\n", encoding="utf-8")
    monkeypatch.setenv("CAMCORE_API_KEY_FILE", str(tmp_path / "api-key"))
    assert Settings().api_key == KEY


async def test_key_from_a_file_is_required(tmp_path: Path) -> None:
    (tmp_path / "api-key").write_text(KEY, encoding="utf-8")
    app = build(Settings(api_key_file=tmp_path / "api-key"))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://testserver") as client:
        without = await client.post("/v1/curves/table", json=MS_TABLE)
        with_key = await client.post("/v1/curves/table", json=MS_TABLE, headers={"X-API-Key": KEY})
    assert without.status_code == 401 and with_key.status_code == 200


@pytest.mark.parametrize(("content", "also_key", "message"), [
    (None, False, "cannot be read: No such file or directory"),
    ("\n", False, "is empty"),
    (KEY, True, "CAMCORE_API_KEY and CAMCORE_API_KEY_FILE are both set: set one"),
])
def test_bad_key_file_stops_the_start_with_one_line(tmp_path: Path, content: str | None, also_key: bool,
                                                     message: str) -> None:
    path = tmp_path / "api-key"
    if content is not None:
        path.write_text(content, encoding="utf-8")
    env = {k: v for k, v in os.environ.items() if not k.startswith("CAMCORE_")}
    env.update(CAMCORE_API_KEY_FILE=str(path), CAMCORE_PORT="1")
    if also_key:
        env["CAMCORE_API_KEY"] = "another-" + KEY
    done = subprocess.run([sys.executable, "-m", "service"], cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=60, check=False)
    assert done.returncode == 2 and done.stdout == ""
    (line,) = done.stderr.splitlines()
    assert line.startswith("camcore: invalid setting: ") and line.endswith(message), line
    assert KEY not in line, "the key is never echoed"
