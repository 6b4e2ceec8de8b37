"""``python -m tests.service.failing_service``: ``python -m service`` as it starts (settings, uvicorn
with the service's protocol, uvloop), its app given one more route that fails with an unexpected
error, for the tests of what a 500 leaves of its connection (tests/service/test_server_errors.py)."""

from __future__ import annotations

import service.main
from service.__main__ import main

#: the route that fails: not in the service, only in this test server
FAIL_PATH = "/test-only/fail"


@service.main.app.get(FAIL_PATH, include_in_schema=False)
async def fail() -> None:
    raise RuntimeError("forced by the test server")


if __name__ == "__main__":
    main()  # uvicorn imports service.main:app, this module's app (one worker: the same process)
