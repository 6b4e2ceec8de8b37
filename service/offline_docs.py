"""``/docs`` (Swagger UI) and ``/redoc`` (ReDoc) served with no internet access.

FastAPI's default pages load their JavaScript and CSS from a CDN (and ReDoc its fonts from
Google), so on a machine-shop network without internet they stay blank. The assets come
from the ``fastapi-offline`` wheel instead (swagger-ui-dist 5 and redoc 2 bundles, MIT),
mounted as static files under ``/static/docs``; only its files are used, not its app class.

The app must be created with ``docs_url=None, redoc_url=None`` so these routes replace
FastAPI's own; afterwards ``app.docs_url`` / ``app.redoc_url`` name the offline pages, and
``app.state.docs_asset_paths`` (= :func:`asset_paths`) the assets, which an API-key check must
leave open as it leaves the pages open.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

from fastapi import FastAPI, Request
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html, get_swagger_ui_oauth2_redirect_html
from fastapi.staticfiles import StaticFiles
from starlette.responses import HTMLResponse

STATIC_URL = "/static/docs"
ASSETS = ("swagger-ui-bundle.js", "swagger-ui.css", "redoc.standalone.js", "favicon.png")


def assets_dir() -> Path:
    """The folder of the vendored Swagger UI and ReDoc bundles (from the fastapi-offline package)."""
    folder = Path(str(files("fastapi_offline") / "static"))
    missing = [name for name in ASSETS if not (folder / name).is_file()]
    if missing:  # pragma: no cover - a broken install
        raise RuntimeError(f"fastapi-offline is installed without {', '.join(missing)} in {folder}")
    return folder


def install_offline_docs(app: FastAPI, docs_url: str = "/docs", redoc_url: str = "/redoc") -> None:
    """Mount the assets and add the Swagger UI and ReDoc pages (not in the OpenAPI document)."""
    if app.docs_url is not None or app.redoc_url is not None:
        raise ValueError("create the app with docs_url=None, redoc_url=None before installing the offline docs")
    app.mount(STATIC_URL, StaticFiles(directory=assets_dir()), name="offline-docs")
    openapi_url = app.openapi_url or "/openapi.json"
    oauth2_url = app.swagger_ui_oauth2_redirect_url or f"{docs_url}/oauth2-redirect"
    # no online validator badge (it would call validator.swagger.io)
    swagger_params = {**(app.swagger_ui_parameters or {}), "validatorUrl": None}

    async def swagger_ui(request: Request) -> HTMLResponse:
        root = request.scope.get("root_path", "")
        return get_swagger_ui_html(
            openapi_url=f"{root}{openapi_url}",
            title=f"{app.title} — API documentation",
            swagger_js_url=f"{root}{STATIC_URL}/swagger-ui-bundle.js",
            swagger_css_url=f"{root}{STATIC_URL}/swagger-ui.css",
            swagger_favicon_url=f"{root}{STATIC_URL}/favicon.png",
            oauth2_redirect_url=f"{root}{oauth2_url}",
            swagger_ui_parameters=swagger_params,
        )

    async def swagger_ui_redirect() -> HTMLResponse:
        return get_swagger_ui_oauth2_redirect_html()

    async def redoc(request: Request) -> HTMLResponse:
        root = request.scope.get("root_path", "")
        return get_redoc_html(
            openapi_url=f"{root}{openapi_url}",
            title=f"{app.title} — API reference",
            redoc_js_url=f"{root}{STATIC_URL}/redoc.standalone.js",
            redoc_favicon_url=f"{root}{STATIC_URL}/favicon.png",
            with_google_fonts=False,
        )

    app.add_api_route(docs_url, swagger_ui, methods=["GET"], include_in_schema=False)
    app.add_api_route(oauth2_url, swagger_ui_redirect, methods=["GET"], include_in_schema=False)
    app.add_api_route(redoc_url, redoc, methods=["GET"], include_in_schema=False)
    # FastAPI added its own pages in the constructor (none, with docs_url=None); from here on the
    # attributes tell where the pages are, for code that reads them (service.security.open_paths)
    app.docs_url, app.redoc_url, app.swagger_ui_oauth2_redirect_url = docs_url, redoc_url, oauth2_url
    app.state.docs_asset_paths = asset_paths()


def asset_paths() -> frozenset[str]:
    """The exact URL paths of the pages' assets, to serve without an API key like the pages."""
    return frozenset(f"{STATIC_URL}/{name}" for name in ASSETS)
