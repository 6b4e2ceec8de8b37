# camcore service image. The install step is the one `make` runs in CI
# (python -m venv + pip install -r requirements.lock); tests/service/test_container.py
# checks the two stay the same and starts this CMD against a live port.
FROM python:3.11-slim

ENV PYTHONUNBUFFERED=1 \
    MPLCONFIGDIR=/tmp/matplotlib \
    PYTHONDONTWRITEBYTECODE=1 \
    PIP_NO_CACHE_DIR=1 \
    CAMCORE_HOST=0.0.0.0 \
    CAMCORE_PORT=8000

WORKDIR /app
RUN useradd --create-home --uid 10001 camcore

# dependencies first, so code changes do not invalidate this layer
COPY requirements.lock ./
RUN python3 -m venv .venv && .venv/bin/pip install -r requirements.lock

COPY camcore ./camcore
COPY service ./service

USER camcore
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=3s --start-period=10s --retries=3 \
    CMD ["/app/.venv/bin/python", "-c", "import sys, urllib.request; sys.exit(urllib.request.urlopen('http://127.0.0.1:8000/health', timeout=2).status != 200)"]
CMD ["/app/.venv/bin/python", "-m", "uvicorn", "service.main:app", "--host", "0.0.0.0", "--port", "8000", "--timeout-keep-alive", "30", "--http", "httptools", "--loop", "uvloop"]
