#!/usr/bin/env bash
# The programs the tests run, installed only when missing (`make test` calls this first).
# Every check is a file or `command -v` look-up, so with everything present this takes a few
# milliseconds and installs nothing.
#   Debian packages (apt-get, as root):
#     python3-venv                          python3 -m venv (Debian ships ensurepip apart)
#     chromium                              tests/clients/test_browser_docs.py: /docs and /redoc offline
#     wrk                                   tests/project/test_bench_smoke.py: the HTTP figures
#     libreoffice-draw-nogui, -calc-nogui   soffice --headless: Draw renders our DXF, Calc a sheet
#     nodejs, npm                           the TypeScript client test (only with clients/typescript)
#     libgl1, libx11-6                      the CAD kernel (cadquery-ocp-novtk) loads libGL and libX11
#     podman, runc, debootstrap             tests/project/test_image.py: scripts/make_base_image.sh makes the base
#                                           with debootstrap, podman builds the image (buildah's code, inside it) and
#                                           runs it; runc, as Debian 12's crun refuses hosts with cgroups in hybrid mode
#     freecad-python3                       tests/clients/test_freecad_macro.py: freecadcmd runs the FreeCAD macro
#                                           (Part and freecadcmd; the `freecad` package adds only a 54 kB shell;
#                                           ~1.3 GB with its Qt and OpenCASCADE, --no-install-recommends)
#   npm packages: `npm ci` in clients/typescript when its package-lock.json is newer than the
#   last install.
# Not root and something missing: one line says what to install, and the exit status is 1.
set -euo pipefail
cd "$(dirname "$0")/.."

TS_DIR=clients/typescript

have() { command -v "$1" >/dev/null 2>&1; }

missing_packages() {
    local pkgs=()
    # (not asked once make has built its venv: the check costs a Python start)
    [ -e "${VENV:-.venv}/.installed" ] || python3 -c 'import ensurepip, venv' >/dev/null 2>&1 || pkgs+=(python3-venv)
    have chromium || have chromium-browser || pkgs+=(chromium)
    have wrk || pkgs+=(wrk)
    # LibreOffice's components are libraries beside soffice: sd is Draw, sc is Calc
    local lo_dir=/usr/lib/libreoffice/program flavor=-nogui
    if have soffice; then lo_dir=$(dirname "$(readlink -f "$(command -v soffice)")"); fi
    # on a machine with the desktop LibreOffice, add the matching (not the conflicting -nogui) parts
    if dpkg-query -W -f='${Status}' libreoffice-core 2>/dev/null | grep -q 'ok installed'; then flavor=; fi
    { have soffice && [ -e "$lo_dir/libsdlo.so" ]; } || pkgs+=("libreoffice-draw$flavor")
    { have soffice && [ -e "$lo_dir/libsclo.so" ]; } || pkgs+=("libreoffice-calc$flavor")
    # the CAD kernel's shared libraries, looked up as the loader finds them
    local libs
    libs=$(ldconfig -p 2>/dev/null || true)
    grep -q 'libGL\.so\.1 ' <<<"$libs" || pkgs+=(libgl1)
    grep -q 'libX11\.so\.6 ' <<<"$libs" || pkgs+=(libx11-6)
    have freecadcmd || pkgs+=(freecad-python3)
    have podman || pkgs+=(podman)
    have runc || pkgs+=(runc)
    have debootstrap || pkgs+=(debootstrap)
    if [ -f "$TS_DIR/package.json" ]; then
        have node || pkgs+=(nodejs)
        have npm || pkgs+=(npm)
    fi
    echo "${pkgs[@]}"
}

read -r -a missing <<<"$(missing_packages)"
if [ ${#missing[@]} -gt 0 ]; then
    install_cmd="apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ${missing[*]}"
    if [ "$(id -u)" -ne 0 ] || ! have apt-get; then
        echo "install_test_tools: the tests need ${missing[*]}; install them as root: $install_cmd" >&2
        exit 1
    fi
    echo "install_test_tools: installing ${missing[*]}" >&2
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
    read -r -a still <<<"$(missing_packages)"
    if [ ${#still[@]} -gt 0 ]; then
        echo "install_test_tools: still missing after apt-get install: ${still[*]}" >&2
        exit 1
    fi
fi

# npm's own record of the last install (node_modules/.package-lock.json) is the stamp
if [ -f "$TS_DIR/package-lock.json" ] && ! [ "$TS_DIR/node_modules/.package-lock.json" -nt "$TS_DIR/package-lock.json" ]; then
    echo "install_test_tools: npm ci in $TS_DIR" >&2
    (cd "$TS_DIR" && npm ci --no-audit --no-fund)
fi
