#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the main job on the bundled sample:
#   1. fqfilter on data/fandisk.ply with synthetic noise (timings per pass, RMSE/MFNE, clusters);
#   2. the streaming demo: fqd on configs/fqd.toml, fqpub publishing the sample for a few
#      seconds, fqsub receiving and writing coloured PLYs (CPU engine when there is no GPU).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/setup-deps.sh"
bash "$root/scripts/build.sh"
build=${BUILD_DIR:-$root/build}
out=${FQ_DEMO_OUT:-$root/build/demo}
mkdir -p "$out"

echo
echo "== fqfilter: quadric filter + clustering of the bundled fandisk (noise 0.2 mean edge) =="
"$build/clients/fqfilter/fqfilter" "$root/data/fandisk.ply" "$out/fandisk_filtered.ply" \
  --noise 0.2 --seed 1 --sigma-s 2 --sigma-r 1 --cluster --sigma-d 5 --sigma-q 1 --theta 0.9
echo "filtered mesh with cluster colours: $out/fandisk_filtered.ply"

if [[ -x "$build/daemon/fqd" ]]; then
  echo
  echo "== streaming demo: fqd + fqpub + fqsub on 127.0.0.1 =="
  bash "$root/scripts/stream_demo.sh" "$build"
fi
