#!/usr/bin/env bash
# The Dockerfile's base image (FROM debian:bookworm-slim), made here without a registry:
# debootstrap's minbase of Debian 12 "bookworm", slimmed as Debian's official image is
# (debuerreotype: no docs, man pages or locales; apt keeps no package lists or .deb cache),
# imported into podman's storage as localhost/debian:bookworm-slim. `podman build --pull=never`
# then finds it under the FROM name.
#   Cached: with the image already in podman's storage this only looks it up (milliseconds);
#   the debootstrap folder's tarball is kept in $CAMCORE_BASE_CACHE (default
#   ~/.cache/camcore/base), so after `podman rmi` the image is imported again in seconds.
#   Rebuild from scratch: `podman rmi localhost/debian:bookworm-slim` and delete the cache folder.
#   The machine's own CA certificates (/usr/local/share/ca-certificates/*.crt, e.g. a proxy's)
#   are copied into the base, so the build's apt and pip trust what this machine trusts; with
#   none there, the base is plain Debian.
# Root (debootstrap and podman's rootful storage). Usage: scripts/make_base_image.sh [image]
set -euo pipefail

IMAGE=${1:-localhost/debian:bookworm-slim}
SUITE=bookworm
MIRROR=${DEBIAN_MIRROR:-http://deb.debian.org/debian}
CACHE=${CAMCORE_BASE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/camcore/base}
TARBALL=$CACHE/$SUITE-slim.tar

if podman image exists "$IMAGE"; then
    exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
    echo "make_base_image: debootstrap and podman import need root" >&2
    exit 1
fi
mkdir -p "$CACHE"
if ! [ -s "$TARBALL" ]; then
    root=$(mktemp -d "$CACHE/rootfs.XXXXXX")
    trap 'rm -rf "$root"' EXIT
    echo "make_base_image: debootstrap --variant=minbase $SUITE (a few minutes, once)" >&2
    debootstrap --variant=minbase "$SUITE" "$root" "$MIRROR" >&2
    # Debian's image sources: the release, its updates and the security archive
    rm -f "$root/etc/apt/sources.list"
    cat >"$root/etc/apt/sources.list.d/debian.sources" <<SOURCES
Types: deb
URIs: $MIRROR
Suites: $SUITE $SUITE-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://deb.debian.org/debian-security
Suites: $SUITE-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
    # debuerreotype's slimify rules (docker.io/library/debian:*-slim) and its apt settings
    cat >"$root/etc/dpkg/dpkg.cfg.d/docker" <<'DPKG'
path-exclude /usr/share/doc/*
path-include /usr/share/doc/*/copyright
path-exclude /usr/share/groff/*
path-exclude /usr/share/info/*
path-exclude /usr/share/linda/*
path-exclude /usr/share/lintian/overrides/*
path-exclude /usr/share/locale/*
path-exclude /usr/share/man/*
DPKG
    cat >"$root/etc/apt/apt.conf.d/docker-clean" <<'APT'
DPkg::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
APT::Update::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
Dir::Cache::pkgcache "";
Dir::Cache::srcpkgcache "";
APT
    echo 'Acquire::GzipIndexes "true";' >"$root/etc/apt/apt.conf.d/docker-gzip-indexes"
    echo 'APT::AutoRemove::SuggestsImportant "false";' >"$root/etc/apt/apt.conf.d/docker-autoremove-suggests"
    find "$root/usr/share/doc" -mindepth 2 ! -name copyright ! -type d -delete
    find "$root/usr/share/doc" -mindepth 1 -type d -empty -delete
    rm -rf "$root"/usr/share/{groff,info,linda,lintian,locale,man}/* "$root"/var/lib/apt/lists/* \
        "$root"/var/cache/apt/*.bin "$root"/var/cache/apt/archives/*.deb "$root"/var/log/*.log
    # this machine's extra CA certificates (none on a machine that needs none)
    for crt in /usr/local/share/ca-certificates/*.crt; do
        [ -e "$crt" ] && install -D -m 0644 "$crt" "$root/usr/local/share/ca-certificates/$(basename "$crt")"
    done
    tar --numeric-owner --xattrs -C "$root" -cf "$TARBALL.part" .
    mv "$TARBALL.part" "$TARBALL"
fi
podman import --change 'CMD ["bash"]' --change 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' \
    --message "debootstrap --variant=minbase $SUITE, slimmed (scripts/make_base_image.sh)" \
    "$TARBALL" "$IMAGE" >/dev/null
echo "make_base_image: $IMAGE from $TARBALL" >&2
