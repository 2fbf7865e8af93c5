#!/usr/bin/env bash
# Stall reasons of the neighbourhood kernels under ncu (docs/BENCHMARKS.md). From the repo
# root on the GPU host, after staging to stage-gpu/ (see gpu_session.sh); writes $OUT/ncu-*.txt.
OUT=${OUT:-gpu-out}; mkdir -p "$OUT"
export LD_LIBRARY_PATH=stage-gpu/lib FQ_MESH_DIR=stage-gpu/meshes
M=smsp__warp_issue_stalled_long_scoreboard_per_warp_active.pct,smsp__warp_issue_stalled_short_scoreboard_per_warp_active.pct,smsp__warp_issue_stalled_wait_per_warp_active.pct,smsp__warp_issue_stalled_math_pipe_throttle_per_warp_active.pct,smsp__warp_issue_stalled_lg_throttle_per_warp_active.pct,smsp__warp_issue_stalled_no_instruction_per_warp_active.pct,smsp__warp_issue_stalled_not_selected_per_warp_active.pct,smsp__warp_issue_stalled_selected_per_warp_active.pct,smsp__warp_issue_stalled_mio_throttle_per_warp_active.pct,smsp__warp_issue_stalled_dispatch_stall_per_warp_active.pct,smsp__warp_issue_stalled_branch_resolving_per_warp_active.pct,smsp__inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio,gpu__time_duration.sum,sm__warps_active.avg.pct_of_peak_sustained_active,smsp__issue_active.avg.pct_of_peak_sustained_active,sm__pipe_fma_cycles_active.avg.pct_of_peak_sustained_active,sm__inst_executed_pipe_lsu.avg.pct_of_peak_sustained_active,l1tex__t_sector_hit_rate.pct
for row in c-dragon-075 f-igea16; do
  ncu --kernel-name regex:"team_(score|link|diffusion)" --launch-skip 3 --launch-count 3 --metrics $M \
    stage-gpu/bin/fqbench --rows $row --repeat 2 --warmup 1 --cpu-repeat 0 > $OUT/ncu-$row.txt 2>&1
done
grep -E "team_|stalled|inst_executed|duration|warps_active|issue_active|pipe_fma|pipe_lsu|hit_rate" $OUT/ncu-*.txt | sed 's/  */ /g' | cut -c1-150
