#!/usr/bin/env bash
# README command 2: install what is missing, check the C++/CUDA formatting, build, run every test,
# clang-tidy the changed files, then each fuzzer for a minute.
# GPU tests skip cleanly on a machine without a GPU.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup-deps.sh"
bash "$root/scripts/format.sh"   # clang-format 14 over every tracked C++/CUDA source; any difference fails
bash "$root/scripts/build.sh" -DFQ_BUILD_TESTS=ON   # on also where scripts/demo.sh configured without them
build=${BUILD_DIR:-$root/build}
export FQ_MESH_DIR=${FQ_MESH_DIR:-$root/../shared/meshes}
ctest --test-dir "$build" --output-on-failure -j "${JOBS:-$(nproc)}" --timeout 900
BUILD_DIR=$build bash "$root/scripts/tidy.sh"   # clang-tidy on the C++ files this change touches
# Every fuzzer for FQ_FUZZ_SECONDS (default 60) under ASan + UBSan; 0 skips them.
if [[ ${FQ_FUZZ_SECONDS:-60} != 0 ]]; then bash "$root/scripts/fuzz.sh" "${FQ_FUZZ_SECONDS:-60}"; fi
