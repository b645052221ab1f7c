#!/usr/bin/env bash
# Installs the Debian 12 packages Tessera builds and runs with; with --test, also what the test
# suite needs (scripts/test.sh passes it). Idempotent.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  libembree-dev libopenimageio-dev openimageio-tools libglm-dev libtbb-dev
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libsqlite3-dev libssl-dev libcpp-httplib-dev nlohmann-json3-dev libcli11-dev
  libboost1.74-dev   # Boost.Beast and Asio (header-only): the dashboard's HTTP server
  libtinyobjloader-dev libzstd-dev zlib1g-dev libgtest-dev libgmock-dev libbenchmark-dev libpugixml-dev
  python3
  fonts-dejavu-core   # the labels of tessera-worker converge's plot
)
if [ "${1:-}" = "--test" ]; then
  PACKAGES+=(
    iproute2 clang-14 libclang-rt-14-dev   # tests/faults (ip netns); fuzz/run.sh (libFuzzer)
    # The dashboard's tests: headless Chromium (driven by playwright-core from npm, which never
    # downloads a browser), Node.js, and a venv for Prometheus' parser (tests/dashboard/browser/).
    chromium nodejs python3-venv
  )
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Debian packages npm apart from nodejs; other builds of nodejs bring their own npm.
if [ "${1:-}" = "--test" ]; then command -v npm >/dev/null || missing+=(npm); fi
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
