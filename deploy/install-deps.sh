#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs, from Debian 12's packages, everything ispq needs to build, test and run.
# Idempotent: does nothing (and needs no network) when all packages are present.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config ccache
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler libssl-dev
  coinor-libclp-dev coinor-libcbc-dev libabsl-dev libspdlog-dev libgtest-dev libgmock-dev
  python3 python3-matplotlib  # the benchmark report (tests/bench/report) draws its plots with it
  openssl  # the service's TLS integration tests make their certificates with it
  clang libclang-rt-14-dev  # libFuzzer and the sanitizers of tests/fuzz
  libpqxx-dev  # the PostgreSQL job store (--job_store=postgresql://...)
  postgresql   # started by the tests of that store in a temporary directory
  yamllint     # checks the Kubernetes manifests (tests/deploy)
  libmicrohttpd-dev  # the HTTP side of ispq-server (server/http/)
  libgnutls28-dev  # its TLS library, which checks the HTTPS certificate (server/http/http_tls.h)
  libjs-three  # three.js r111, embedded into the web view's 3-D view at build time (server/http/web)
  chromium python3-prometheus-client  # its browser and /metrics tests (tests/http)
  python3-grpcio python3-protobuf python3-pip python3-setuptools  # the Python client (client/python)
  # The container deployment test (tests/deploy/containers): podman builds and runs the image
  # (buildah, runc, the CNI plugins, fuse-overlayfs, slirp4netns and uidmap with it); debootstrap
  # makes its debian:bookworm base from the Debian mirror, as no registry is reachable.
  podman buildah runc uidmap fuse-overlayfs slirp4netns debootstrap
)

missing=()
for package in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
