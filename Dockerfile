# camcore service image, in two stages. The build stage makes the virtual environment from the
# runtime pins only (requirements.lock; the development and test tools of requirements-dev.lock
# stay out) and compiles its bytecode (the non-root user cannot write it); the runtime stage gets
# that venv, the code, Debian's Python and the few shared libraries the CAD kernel loads, and no
# pip or apt cache. Started through `python -m service`, so the CAMCORE_* settings (host, port,
# workers, limits) apply. tests/project/test_container.py checks these rules, runs this CMD with
# this ENV against a live port, and builds and runs the image itself (podman, see below).
#
# Base: debian:bookworm-slim (Debian 12, whose python3 is 3.11). Where no registry can be
# reached, scripts/make_base_image.sh makes it with debootstrap and imports it under this name;
# then build with `podman build --pull=never --format docker -t camcore:0.1.0 .`.
# --format docker: podman and buildah write OCI images by default, and the OCI image format has no
# HEALTHCHECK, so they drop it (with a warning); the Docker format keeps it. `docker build`
# keeps it always.
FROM debian:bookworm-slim AS build

# python3-venv for `python -m venv` and its pip; libgl1 and libx11-6 only so that ldd can show the
# kernel's libraries and the runtime stage can take the two it needs (the versions are the
# base's Debian release's; pinning them would break the build at every point release)
# hadolint ignore=DL3008
RUN apt-get update && apt-get install -y --no-install-recommends ca-certificates python3 python3-venv libgl1 libx11-6 \
    && rm -rf /var/lib/apt/lists/*

WORKDIR /app
# dependencies first, so code changes do not invalidate this layer
COPY requirements.lock ./
# pip and setuptools leave the venv once it is made (23 MB the service never imports)
RUN python3 -m venv .venv && .venv/bin/pip install --no-cache-dir -r requirements.lock \
    && .venv/bin/python -m pip uninstall --yes --quiet pip setuptools \
    && .venv/bin/python -m compileall -q .venv/lib

# the CAD kernel's wheel (cadquery-ocp-novtk: STEP and STL solids) links libGL.so.1 and, through
# it, libGLX.so.0 (ldd on its OCP module); Debian's libgl1 would pull Mesa's drivers and LLVM
# (libgl1-mesa-dri, libllvm15: ~150 MB) that loading never touches, so the runtime stage takes
# these two files alone, beside libglvnd0 and libx11-6 from apt
SHELL ["/bin/bash", "-o", "pipefail", "-c"]
RUN mkdir /opt/gl && ldd .venv/lib/python3.11/site-packages/OCP/OCP*.so \
    | awk '$1 ~ /^libGL(X)?\.so\./ {print $3}' | xargs -r cp -L -t /opt/gl \
    && ls /opt/gl/libGL.so.1 /opt/gl/libGLX.so.0

FROM debian:bookworm-slim

ENV PYTHONUNBUFFERED=1 \
    MPLCONFIGDIR=/tmp/matplotlib \
    CAMCORE_HOST=0.0.0.0 \
    CAMCORE_PORT=8000 \
    CAMCORE_WORKERS=1

# hadolint ignore=DL3008
RUN apt-get update && apt-get install -y --no-install-recommends python3 libglvnd0 libx11-6 \
    && rm -rf /var/lib/apt/lists/* /var/cache/apt/* /var/log/apt /var/log/dpkg.log
COPY --from=build /opt/gl/ /usr/local/lib/
RUN ldconfig && groupadd --gid 10001 camcore && useradd --uid 10001 --gid 10001 --no-create-home camcore

WORKDIR /app
COPY --from=build /app/.venv ./.venv
# every library the kernel links is found (ldd prints "not found" otherwise), and it loads
SHELL ["/bin/bash", "-o", "pipefail", "-c"]
RUN ! ldd .venv/lib/python3.11/site-packages/OCP/OCP*.so | grep 'not found' \
    && .venv/bin/python -c "import OCP.STEPControl, OCP.StlAPI"

COPY camcore ./camcore
COPY service ./service
RUN .venv/bin/python -m compileall -q camcore service

USER 10001:10001
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=3s --start-period=10s --retries=3 \
    CMD ["/app/.venv/bin/python", "-c", "import os, sys, urllib.request as u; sys.exit(u.urlopen('http://127.0.0.1:%s/health' % os.environ.get('CAMCORE_PORT', '8000'), timeout=2).status != 200)"]
CMD ["/app/.venv/bin/python", "-m", "service"]
