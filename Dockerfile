# camcore service image: the runtime pins only (requirements.lock; the development and test
# tools of requirements-dev.lock stay out), dependencies before code, bytecode compiled at
# build time (the non-root user cannot write it), and started through `python -m service`, so
# the CAMCORE_* settings (host, port, workers, limits) apply. tests/service/test_container.py
# checks these rules and runs this CMD with this ENV against a live port.
FROM python:3.11-slim

ENV PYTHONUNBUFFERED=1 \
    MPLCONFIGDIR=/tmp/matplotlib \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    CAMCORE_HOST=0.0.0.0 \
    CAMCORE_PORT=8000 \
    CAMCORE_WORKERS=1

WORKDIR /app
# the CAD kernel's wheel (cadquery-ocp-novtk: STEP and STL solids) loads libGL and libX11, which
# the slim image lacks; the versions are the base image's Debian release's (pinning them would
# break the build at every base-image update)
# hadolint ignore=DL3008
RUN apt-get update && apt-get install -y --no-install-recommends libgl1 libx11-6 \
    && rm -rf /var/lib/apt/lists/*
RUN groupadd --gid 10001 camcore && useradd --uid 10001 --gid 10001 --no-create-home camcore

# dependencies first, so code changes do not invalidate this layer
COPY requirements.lock ./
RUN python3 -m venv .venv && .venv/bin/pip install -r requirements.lock \
    && .venv/bin/python -m compileall -q .venv/lib

COPY camcore ./camcore
COPY service ./service
RUN .venv/bin/python -m compileall -q camcore service

USER 10001:10001
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=3s --start-period=10s --retries=3 \
    CMD ["/app/.venv/bin/python", "-c", "import os, sys, urllib.request as u; sys.exit(u.urlopen('http://127.0.0.1:%s/health' % os.environ.get('CAMCORE_PORT', '8000'), timeout=2).status != 200)"]
CMD ["/app/.venv/bin/python", "-m", "service"]
