"""``python -m service``: serve the app with uvicorn (host, port, workers from settings).

The settings are validated here, once, before uvicorn starts (with several workers each
worker imports ``service.main`` again): a bad ``CAMCORE_*`` variable prints one line naming
it and what it allows, and exits with status 2 (a usage error), without a traceback.
"""

from __future__ import annotations

import sys

import uvicorn
from pydantic import ValidationError
from pydantic_settings.exceptions import SettingsError

from service.protocol import LimitedHttpToolsProtocol
from service.settings import Settings, settings_error_line

USAGE_ERROR = 2


def main() -> None:
    try:
        settings = Settings()
    except (ValidationError, SettingsError) as exc:
        print(f"camcore: invalid setting: {settings_error_line(exc)}", file=sys.stderr)
        sys.exit(USAGE_ERROR)
    uvicorn.run(
        "service.main:app",
        host=settings.host,
        port=settings.port,
        workers=settings.workers,
        log_level=settings.log_level,
        timeout_keep_alive=settings.keep_alive_s,
        http=LimitedHttpToolsProtocol,
        loop="uvloop",
        server_header=False,  # no "server: uvicorn" banner
    )


if __name__ == "__main__":
    main()
