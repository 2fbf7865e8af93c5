#!/usr/bin/env bash
# Configures and builds fq into BUILD_DIR (default: build). Extra arguments go to cmake.
# The CUDA engine is compiled whenever nvcc is found (FQ_CUDA=AUTO); it runs only where a
# GPU is present, and the CPU engine is used otherwise. compile_commands.json is for scripts/tidy.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
jobs=${JOBS:-$(nproc)}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON "$@" >/dev/null
cmake --build "$build" -j "$jobs"
