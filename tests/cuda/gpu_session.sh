#!/usr/bin/env bash
# One run on a GPU host for the CUDA engine: device facts, the GPU tests,
# compute-sanitizer (memcheck + racecheck) on a bunny-sized run, optional block-size sweep
# and ncu profile, then fqbench. Run from the repository root on the GPU host, after
# staging (see docs/BENCHMARKS.md):
#   [FQ_SWEEP="--cuda-team=0 --cuda-team=4 ..." FQ_SWEEP_ROWS=f-bunny,...] [FQ_NCU_ROW=f-dragon-grog] \
#   [FQ_SANITIZE=0] [FQ_TESTS=0] [FQ_BENCH=other fqbench] tests/cuda/gpu_session.sh STAGE_DIR [fqbench args...]
# Logs go to $OUT (or ./gpu-out); the last lines printed are fqbench's tables.
set -uo pipefail
stage=${1:?usage: gpu_session.sh STAGE_DIR [fqbench args...]}; shift
out=${OUT:-gpu-out}${FQ_OUT_SUFFIX:+/$FQ_OUT_SUFFIX}; mkdir -p "$out"
export FQ_MESH_DIR=$stage/meshes LD_LIBRARY_PATH=$stage/lib
bench=${FQ_BENCH:-$stage/bin/fqbench}
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm --format=csv | tee "$out/device.txt"
status=0
for t in $([[ ${FQ_TESTS:-1} == 1 ]] && echo cuda_engine_test cuda_mesh_parity_test); do
  [[ -x $stage/bin/$t ]] || continue
  "$stage/bin/$t" >>"$out/tests.log" 2>&1 || status=1
done
[[ -f $out/tests.log ]] && grep -E "parity:|PASSED|FAILED|SKIPPED \]" "$out/tests.log" | tail -40
if [[ ${FQ_SANITIZE:-1} == 1 ]]; then
  # bunny, filter + clustering (Table 3 row) and the bilateral baseline, one frame each.
  for tool in memcheck racecheck; do
    cmd=(compute-sanitizer --tool "$tool" --error-exitcode 9 "$bench" --rows c-bunny,f-bunny-bf
         --repeat 1 --warmup 0 --cpu-repeat 0)
    echo "+ ${cmd[*]}" >>"$out/sanitizer.log"
    "${cmd[@]}" >>"$out/sanitizer.log" 2>&1; rc=$?
    echo "$tool exit $rc: $(grep -E 'ERROR SUMMARY|RACECHECK SUMMARY' "$out/sanitizer.log" | tail -1)"
    [[ $rc == 0 ]] || status=1
  done
fi
# Each word of FQ_SWEEP is one setting to time the rows under: fqbench's tuning flags
# joined by commas (--cuda-team=4,--cuda-fast-exp).
rows=${FQ_SWEEP_ROWS:-f-bunny,f-armadillo16,f-igea16,c-dragon-075}
for a in ${FQ_SWEEP:-}; do
  echo "## $a" >>"$out/sweep.md"
  "$bench" ${a//,/ } --rows "$rows" --cpu-repeat 0 2>/dev/null >"$out/sweep-one.md"
  cat "$out/sweep-one.md" >>"$out/sweep.md"
  echo "$a:$(grep -E '^\| [fc]-' "$out/sweep-one.md" | awk -F'|' '{printf " %s%s;", $2, $9}')"
done
rm -f "$out/sweep-one.md"
if [[ -n ${FQ_NCU_ROW:-} ]]; then
  ncu --kernel-name regex:"${FQ_NCU_KERNELS:-diffusion}" --launch-skip 1 --launch-count 2 \
    --section SpeedOfLight --section Occupancy --section WarpStateStats --section LaunchStats \
    --section MemoryWorkloadAnalysis --section SchedulerStats --section SourceCounters \
    "$bench" --rows "$FQ_NCU_ROW" --repeat 2 --warmup 1 --cpu-repeat 0 >"$out/ncu.txt" 2>&1
  grep -E "  [a-z_]+.*\\(|Duration|Memory Throughput|Compute \(SM\)|Achieved Occupancy|Avg. Active Threads|Issue Slots Busy|Branch Efficiency|L1/TEX Hit" "$out/ncu.txt" | head -60
fi
"$bench" "$@" 2>"$out/fqbench.err" | tee "$out/fqbench.md" || status=1
exit $status
