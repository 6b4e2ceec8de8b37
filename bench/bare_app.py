"""A bare FastAPI app with one route: the floor the service's start-up and its cached answers are compared with.

``BENCH_BARE_IMPORTS`` (comma-separated module names) makes it import those first, to time
what each of the service's own dependencies adds to the floor (numpy, camcore).
``BENCH_BARE_ANSWER`` (a file) adds a POST route at ``BENCH_BARE_PATH`` answering that file's bytes as
JSON, whatever the body: the floor for a cached answer of the same bytes.
"""

import importlib
import os
from pathlib import Path

from fastapi import FastAPI, Response

for _name in filter(None, os.environ.get("BENCH_BARE_IMPORTS", "").split(",")):
    importlib.import_module(_name)

app = FastAPI()


@app.get("/health")
def health() -> dict[str, str]:
    return {"status": "ok"}


if os.environ.get("BENCH_BARE_ANSWER"):
    _ANSWER = Path(os.environ["BENCH_BARE_ANSWER"]).read_bytes()

    @app.post(os.environ.get("BENCH_BARE_PATH", "/v1/curves/table"))
    async def answer() -> Response:
        return Response(content=_ANSWER, media_type="application/json")
