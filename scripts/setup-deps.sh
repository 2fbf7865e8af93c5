#!/usr/bin/env bash
# Installs the Debian 12 packages fq builds against, skipping those already present.
# Safe to run repeatedly; needs root (or sudo) only when something is missing.
# --peers also installs the other smoothers scripts/peer_quality.py compares with (Open3D,
# MeshLab run headless under Xvfb); neither the build nor the tests need them.
# Then installs the live viewer's npm packages (scripts/web-deps.sh).
# FQ_SETUP_BROWSER=0 leaves out Chromium and yamllint (only tests use them; the Docker image
# sets it, Ubuntu's chromium package being a snap stub).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

packages=(
  build-essential cmake ninja-build pkg-config
  libdraco-dev draco libassimp-dev
  libzmq3-dev cppzmq-dev
  libprotobuf-dev protobuf-compiler
  libspdlog-dev libfmt-dev
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev
  libgtest-dev
  python3-dev pybind11-dev python3-numpy python3-pytest python3-open3d
  clang-tidy
  python3-zmq python3-protobuf   # clients/examples/consume.py and its test
  libcpp-httplib-dev
  libssl-dev openssl curl   # fqd's HTTPS and token check; the tests' certificate and TLS client
  python3-prometheus-client
)
if [[ "${1:-}" == "--peers" ]]; then
  packages+=(python3-numpy python3-open3d meshlab xvfb xauth)
fi
if [[ ${FQ_SETUP_BROWSER:-1} != 0 ]]; then
  packages+=(chromium yamllint)
fi
if [[ ${FQ_SETUP_FUZZ:-1} != 0 ]]; then
  packages+=(clang-14 libclang-rt-14-dev)   # scripts/fuzz.sh: libFuzzer with ASan + UBSan
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup-deps: all ${#packages[@]} packages present"
  exec bash "$here/web-deps.sh"
fi

echo "setup-deps: installing ${missing[*]}"
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
exec bash "$here/web-deps.sh"
