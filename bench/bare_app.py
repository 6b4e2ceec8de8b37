"""A bare FastAPI app with one route: the floor the service's start-up is compared with.

``BENCH_BARE_IMPORTS`` (comma-separated module names) makes it import those first, to time
what each of the service's own dependencies adds to the floor (numpy, camcore).
"""

import importlib
import os

from fastapi import FastAPI

for _name in filter(None, os.environ.get("BENCH_BARE_IMPORTS", "").split(",")):
    importlib.import_module(_name)

app = FastAPI()


@app.get("/health")
def health() -> dict[str, str]:
    return {"status": "ok"}
