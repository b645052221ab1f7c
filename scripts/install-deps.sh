#!/usr/bin/env bash
# Installs the Debian 12 packages Tessera builds and runs with; with --test, also what the test
# suite needs (scripts/test.sh passes it); then Intel Open Image Denoise (install_oidn below).
# With --oidn-only, Open Image Denoise alone (and Python to install it). With --oidn-runtime DEST,
# nothing is installed: the installed library's files a binary needs at run time (the library,
# its core, CPU device and TBB) are copied into DEST (the container images, deploy/Dockerfile).
# Idempotent.
set -euo pipefail

# Intel Open Image Denoise (Apache-2.0), for `tessera-worker render --denoise`: no Debian 12
# package carries it, so the pinned pyoidn wheel (an MIT binding bundling OIDN's own release
# binaries) goes into a virtual environment under OIDN_PREFIX; CMake finds its
# libOpenImageDenoise.so.2 there at configure time (TESSERA_OIDN_LIBRARY). Skipped when present.
OIDN_PREFIX="${TESSERA_OIDN_PREFIX:-/opt/tessera-oidn}"
OIDN_WHEEL="pyoidn==2.5.1.0"
# The runtime files of the installed OIDN (55 of the wheel's 171 MB: no GPU devices) into $1. Its
# run path is $ORIGIN/../lib, so DEST should be a folder named lib.
copy_oidn_runtime() {
  local lib
  lib="$(ls -d "$OIDN_PREFIX"/lib/python3*/site-packages/pyoidn/oidn/lib 2>/dev/null | sort | tail -1)"
  if [ -z "$lib" ]; then
    echo "install-deps: no Open Image Denoise under $OIDN_PREFIX: run scripts/install-deps.sh" >&2
    exit 1
  fi
  mkdir -p "$1"
  cp "$lib/libOpenImageDenoise.so.2" "$lib"/libOpenImageDenoise_core.so.* \
     "$lib"/libOpenImageDenoise_device_cpu.so.* "$lib/libtbb.so.12" "$1/"
}
if [ "${1:-}" = "--oidn-runtime" ]; then
  copy_oidn_runtime "${2:?usage: install-deps.sh --oidn-runtime DEST}"
  exit 0
fi

install_oidn() {
  local installed
  installed="$("$OIDN_PREFIX/bin/python3" -m pip show pyoidn 2>/dev/null || true)"
  if grep -qx "Version: 2.5.1.0" <<<"$installed"; then return 0; fi
  echo "install-deps: installing $OIDN_WHEEL (Open Image Denoise 2.5.1) into $OIDN_PREFIX" >&2
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo python3 -m venv "$OIDN_PREFIX"
  $sudo "$OIDN_PREFIX/bin/python3" -m pip install -q --no-deps "$OIDN_WHEEL"
}

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  libembree-dev libopenimageio-dev openimageio-tools libglm-dev libtbb-dev
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libsqlite3-dev libssl-dev libcpp-httplib-dev nlohmann-json3-dev libcli11-dev
  libboost1.74-dev   # Boost.Beast and Asio (header-only): the dashboard's HTTP server
  libtinyobjloader-dev libzstd-dev zlib1g-dev libgtest-dev libgmock-dev libbenchmark-dev libpugixml-dev
  python3 python3-venv   # python3-venv: Open Image Denoise's virtual environment
  fonts-dejavu-core   # the labels of tessera-worker converge's plot
)
if [ "${1:-}" = "--oidn-only" ]; then PACKAGES=(ca-certificates python3 python3-venv); fi
if [ "${1:-}" = "--test" ]; then
  PACKAGES+=(
    iproute2 clang-14 libclang-rt-14-dev   # tests/faults (ip netns); fuzz/run.sh (libFuzzer)
    # The dashboard's tests: headless Chromium (driven by playwright-core from npm, which never
    # downloads a browser), Node.js, and a venv for Prometheus' parser (tests/dashboard/browser/).
    chromium nodejs
  )
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Debian packages npm apart from nodejs; other builds of nodejs bring their own npm.
if [ "${1:-}" = "--test" ]; then command -v npm >/dev/null || missing+=(npm); fi
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "install-deps: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
install_oidn
