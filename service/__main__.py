"""``python -m service``: serve the app with uvicorn (host, port, workers from settings)."""

from __future__ import annotations

import uvicorn

from service.protocol import NoDelayHttpToolsProtocol
from service.settings import Settings


def main() -> None:
    settings = Settings()
    uvicorn.run(
        "service.main:app",
        host=settings.host,
        port=settings.port,
        workers=settings.workers,
        log_level=settings.log_level,
        timeout_keep_alive=settings.keep_alive_s,
        http=NoDelayHttpToolsProtocol,
        loop="uvloop",
    )


if __name__ == "__main__":
    main()
