#!/usr/bin/env bash
# Builds the libFuzzer targets with clang under ASan + UBSan (build-fuzz/) and runs each for
# SECONDS (default 60) from a seed corpus of real frames, then prints the executions reached.
# A crash, leak, sanitizer report or out-of-memory (over 2 GB) fails the run; the failing
# input is left in build-fuzz/artifacts/. CI runs it with the default time; run it long with
#   bash scripts/fuzz.sh 3600
# Corpora grow in build-fuzz/corpus/<target> and are reused by later runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
build=${FUZZ_BUILD_DIR:-$root/build-fuzz}
jobs=${JOBS:-$(nproc)}
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"
CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFQ_CUDA=OFF -DFQ_BUILD_TESTS=OFF -DFQ_FUZZ=ON -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j "$jobs" --target fuzz_headers fuzz_frame_decode fuzz_config fuzz_symbol_decode fuzz_make_seeds
mkdir -p "$build/seeds" "$build/artifacts"
ASAN_OPTIONS=detect_leaks=0 "$build/tests/fuzz/fuzz_make_seeds" "$root/data/fandisk.ply" "$root/configs/fqd.toml" "$build/seeds"
status=0
for target in headers frame_decode config symbol_decode; do
  corpus="$build/corpus/$target"
  mkdir -p "$corpus"
  log="$build/fuzz_$target.log"
  echo "fuzz: $target for ${seconds}s"
  if ! UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 "$build/tests/fuzz/fuzz_$target" "$corpus" "$build/seeds/$target" \
      -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 -timeout=10 -print_final_stats=1 \
      -artifact_prefix="$build/artifacts/${target}-" >"$log" 2>&1; then
    echo "fuzz: $target FAILED (log: $log)"; tail -40 "$log"; status=1
  fi
  execs=$(awk '/stat::number_of_executed_units/ {print $NF}' "$log")
  echo "fuzz: $target ran ${execs:-?} executions, $(ls "$corpus" | wc -l) inputs in its corpus"
done
exit $status
