#!/usr/bin/env bash
# Installs the Debian 12 packages fq builds against, skipping those already present.
# Safe to run repeatedly; needs root (or sudo) only when something is missing.
#   setup-deps.sh               what building fq and running every test needs
#   setup-deps.sh --build-only  what building the tools (cmake -DFQ_BUILD_TESTS=OFF) and serving
#                               the viewer needs, nothing that only tests use (scripts/demo.sh
#                               and the Docker images)
#   setup-deps.sh --peers       also the other smoothers scripts/peer_quality.py and
#                               scripts/quality_matrix.py compare with (Open3D, MeshLab run
#                               headless under Xvfb) and matplotlib for the matrix's pictures
# Then installs the live viewer's npm packages (scripts/web-deps.sh; --build-only: without the
# test-only ones).
# FQ_SETUP_BROWSER=0 leaves out Chromium, yamllint and prometheus, FQ_SETUP_FUZZ=0 clang (only
# tests use them; Ubuntu's chromium package is a snap stub). FQ_SETUP_LIST=1 prints the
# packages it would install, one a line, and installs nothing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
mode=${1:-}

# Building the libraries, the tools and fqd.
build_packages=(
  build-essential cmake ninja-build pkg-config
  libdraco-dev libassimp-dev
  libzmq3-dev cppzmq-dev
  libprotobuf-dev protobuf-compiler
  libspdlog-dev libfmt-dev
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev
  libcpp-httplib-dev
  libssl-dev   # fqd's HTTPS listener and its token comparison
)
# The tests, the Python module and the tidy check.
test_packages=(
  draco   # draco_encoder/draco_decoder: the tests' plain-Draco peer
  libgtest-dev
  python3-dev pybind11-dev python3-numpy python3-pytest python3-open3d
  python3-venv python3-setuptools python3-wheel   # pip install . (pyproject.toml) and its test
  patchelf   # pip install . and pip wheel: the module's libraries packaged in fq.libs/ (setup.py)
  python3-matplotlib   # the picture of python/examples/fq_vs_open3d.py
  clang-tidy clang-format   # scripts/tidy.sh and scripts/format.sh
  python3-zmq python3-protobuf   # clients/examples/consume.py and its test
  openssl curl   # the tests' self-signed certificate and TLS client
  python3-prometheus-client
)
packages=("${build_packages[@]}")
web_mode=""
if [[ $mode == --build-only ]]; then
  web_mode="--no-dev"
  FQ_SETUP_BROWSER=0 FQ_SETUP_FUZZ=0
else
  packages+=("${test_packages[@]}")
fi
if [[ $mode == --peers ]]; then
  packages+=(python3-numpy python3-open3d python3-matplotlib meshlab xvfb xauth)
fi
if [[ ${FQ_SETUP_BROWSER:-1} != 0 ]]; then
  # prometheus: promtool checks and unit-tests deploy/monitoring's alert rules (the tests run no server;
  # on a host with systemd Debian enables one: `systemctl disable --now prometheus` if unwanted)
  packages+=(chromium yamllint python3-yaml prometheus)
fi
if [[ ${FQ_SETUP_FUZZ:-1} != 0 ]]; then
  packages+=(clang-14 libclang-rt-14-dev)   # scripts/fuzz.sh: libFuzzer with ASan + UBSan
fi

if [[ ${FQ_SETUP_LIST:-0} == 1 ]]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup-deps: all ${#packages[@]} packages present"
  exec bash "$here/web-deps.sh" $web_mode
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
exec bash "$here/web-deps.sh" $web_mode
