#!/usr/bin/env bash
# README command 1: install what the demo runs, build it, and run the main job on the bundled
# sample, then say how to see it live:
#   1. fqfilter on data/fandisk.ply with synthetic noise (timings per pass, RMSE/MFNE, clusters);
#   2. the streaming demo: fqd on configs/fqd.toml, fqpub publishing the sample for 4 seconds,
#      fqsub receiving and writing coloured PLYs (CPU engine when there is no GPU);
#   3. the command that opens the live viewer (scripts/live_demo.sh).
# Installs only what that needs (scripts/setup-deps.sh --build-only: no browser, clang, Open3D
# or test library; FQ_DEMO_SKIP_SETUP=1 skips it) and builds only the tools it runs; a build
# folder that does not exist yet is configured without tests (scripts/test.sh turns them on).
# Arguments go to cmake (bash scripts/demo.sh -DFQ_CUDA=OFF).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
[[ ${FQ_DEMO_SKIP_SETUP:-0} == 1 ]] || bash "$root/scripts/setup-deps.sh" --build-only
tests=()
[[ -f $build/CMakeCache.txt ]] || tests=(-DFQ_BUILD_TESTS=OFF)
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "${tests[@]}" "$@" >/dev/null
cmake --build "$build" -j "${JOBS:-$(nproc)}" --target fqfilter fqd fqpub fqsub fqctl
out=${FQ_DEMO_OUT:-$build/demo}
mkdir -p "$out"
SECONDS=0

echo
echo "== fqfilter: quadric filter + clustering of the bundled fandisk (noise 0.2 mean edge) =="
"$build/clients/fqfilter/fqfilter" "$root/data/fandisk.ply" "$out/fandisk_filtered.ply" \
  --noise 0.2 --seed 1 --sigma-s 2 --sigma-r 1 --cluster --sigma-d 5 --sigma-q 1 --theta 0.9
echo "filtered mesh with cluster colours: $out/fandisk_filtered.ply"

echo
echo "== streaming demo: fqd + fqpub + fqsub on 127.0.0.1 =="
FQ_DEMO_OUT=$out bash "$root/scripts/stream_demo.sh" "$build"
echo "demo: ran in ${SECONDS} s after the build"

echo
echo "== live viewer: fqd + fqpub until Ctrl-C, the viewer at http://127.0.0.1:8080/?stream=demo =="
echo "bash $root/scripts/live_demo.sh $build"
