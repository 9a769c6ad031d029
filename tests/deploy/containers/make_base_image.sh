#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Makes the base images the Dockerfiles' FROM lines name (debian:bookworm, debian:bookworm-slim)
# in podman's local storage, without a registry: a minimal Debian 12 tree by debootstrap from the
# Debian mirror this machine's apt uses, imported with `podman import`. Does nothing when both
# images are there. The images' apt sources point at the same mirror, so `apt-get install` in a
# build reaches what this machine reaches.
#
#   CONTAINERS_CONF=tests/deploy/containers/containers.conf bash make_base_image.sh
set -euo pipefail

NAMES=(debian:bookworm debian:bookworm-slim)
present=1
for name in "${NAMES[@]}"; do
  podman image exists "docker.io/library/$name" || present=0
done
if [ "$present" = 1 ]; then
  echo "make_base_image: ${NAMES[*]} present"
  exit 0
fi

# The Debian mirror of this machine's apt sources: a deb822 .sources file (URIs: + Suites: with
# bookworm) or a one-line `deb URI bookworm ...` entry.
mirror() {
  local file
  for file in /etc/apt/sources.list.d/*.sources; do
    [ -f "$file" ] || continue
    awk 'BEGIN { RS = ""; FS = "\n" }
         { uris = ""; suite = 0
           for (i = 1; i <= NF; i++) {
             if ($i ~ /^URIs:/) { sub(/^URIs:[ \t]*/, "", $i); split($i, u, /[ \t]+/); uris = u[1] }
             if ($i ~ /^Suites:/ && $i ~ /[ \t]bookworm([ \t]|$)/) suite = 1
           }
           if (suite && uris != "") { print uris; exit } }' "$file"
  done
  for file in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$file" ] || continue
    awk '$1 == "deb" { i = 2; if ($2 ~ /^\[/) { while ($i !~ /\]$/) i++; i++ }
                       if ($(i + 1) == "bookworm") { print $i; exit } }' "$file"
  done
}
MIRROR=$(mirror | head -n 1)
if [ -z "$MIRROR" ]; then
  echo "make_base_image: no Debian bookworm mirror in /etc/apt/sources.list{,.d/*}" >&2
  exit 1
fi

WORK=$(mktemp -d /var/tmp/ispq-base-image.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
start=$(date +%s)
echo "make_base_image: debootstrap bookworm from $MIRROR"
debootstrap --variant=minbase bookworm "$WORK/rootfs" "$MIRROR" >"$WORK/debootstrap.log" 2>&1 || {
  tail -n 30 "$WORK/debootstrap.log" >&2
  exit 1
}
rm -rf "$WORK"/rootfs/var/cache/apt/archives/*.deb "$WORK"/rootfs/var/lib/apt/lists/*
tar --numeric-owner -C "$WORK/rootfs" -c . |
  podman import --quiet --change 'CMD ["bash"]' - docker.io/library/debian:bookworm >/dev/null
# The -slim variant: the same tree without documentation, manual pages and locales.
rm -rf "$WORK"/rootfs/usr/share/doc/* "$WORK"/rootfs/usr/share/man/* \
  "$WORK"/rootfs/usr/share/info/* "$WORK"/rootfs/usr/share/locale/*
tar --numeric-owner -C "$WORK/rootfs" -c . |
  podman import --quiet --change 'CMD ["bash"]' - docker.io/library/debian:bookworm-slim >/dev/null
echo "make_base_image: ${NAMES[*]} made in $(($(date +%s) - start)) s"
