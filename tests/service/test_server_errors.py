"""What an unexpected error (500) leaves of its connection, against a live server.

Source: issue 34, point 4: after a 500 the next request on the same keep-alive connection was
reset. Starlette's ServerErrorMiddleware answers the 500 (through service.errors'
handler) and then raises the exception again, for the server to log; uvicorn's protocol takes an
exception raised after the answer has started as a broken answer and closes the transport, so the
client's next request on that connection met a closed socket. The server here is
``python -m service`` as it starts, with one route more that fails
(tests/service/failing_service.py).
"""

from __future__ import annotations

import threading
from collections.abc import Iterator

import httpx
import pytest

from tests.live_server import running_service
from tests.service.failing_service import FAIL_PATH


@pytest.fixture(scope="module")
def failing() -> Iterator[tuple[str, list[bytes]]]:
    """The test server's URL and its log, read as it comes (a full pipe would stall it)."""
    with running_service("tests.service.failing_service", log_level="info") as (url, proc):
        log: list[bytes] = []
        assert proc.stdout is not None
        reader = threading.Thread(target=lambda: log.extend(iter(proc.stdout.readline, b"")), daemon=True)
        reader.start()
        yield url, log


def test_a_500_leaves_its_keep_alive_connection_usable(failing: tuple[str, list[bytes]]) -> None:
    url, log = failing
    connects: list[str] = []

    def trace(event: str, info: dict[str, object]) -> None:
        if event == "connection.connect_tcp.started":
            connects.append(event)

    with httpx.Client(base_url=url, timeout=10) as client:
        first = client.get("/health", extensions={"trace": trace})
        failed = client.get(FAIL_PATH, extensions={"trace": trace})
        after = [client.get("/health", extensions={"trace": trace}) for _ in range(3)]
    assert first.status_code == 200
    assert failed.status_code == 500 and failed.json() == {"detail": "Internal error; it has been logged.",
                                                           "errors": []}
    assert failed.headers.get("connection") != "close"
    assert [r.status_code for r in after] == [200, 200, 200]
    # one connection for all five: the 500 neither closed nor reset it
    assert len(connects) == 1, connects
    # and the error is logged once, with its traceback, by the service's handler
    text = b"".join(log).decode()
    assert text.count("forced by the test server") >= 1 and "unexpected error on GET /test-only/fail" in text, text
    assert "Exception in ASGI application" not in text, text
