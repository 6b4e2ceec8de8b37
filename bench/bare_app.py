"""A bare FastAPI app with one route: the floor the service's start-up is compared with."""

from fastapi import FastAPI

app = FastAPI()


@app.get("/health")
def health() -> dict[str, str]:
    return {"status": "ok"}
