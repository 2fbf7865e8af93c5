// The stages of the CPU engine, one function per pass (kernels/frame_plan.h gives their order
// and their extents).
#pragma once

#include "core/mesh_view.h"
#include "core/params.h"
#include "kernels/cpu_frame.h"
#include "kernels/frame_plan.h"
#include "kernels/refine_plan.h"

namespace fq::cpu {

/// Normalized positions, grid (cell ~ `cell`), sorted points, sorted triangles.
void sort_into_grid(const MeshView& mesh, float cell, CpuFrame& f);
/// Triangle geometry, vertex->triangle CSR, per-vertex area, base quadric, normal.
void base_quadrics(CpuFrame& f, int threads);
void neighbourhood_quadrics(CpuFrame& f, Extent sigma_b, int threads);
void diffuse_quadrics(CpuFrame& f, const RunPlan& run, int threads);
void update_positions(CpuFrame& f, const RunPlan& run, int threads);
/// "qf+": the noise of the frame's input positions (kernels/noise_estimate.h); needs the
/// vertex -> triangle CSR of base_quadrics. Leaves the input positions in f.moved.
NoiseEstimate estimate_noise(CpuFrame& f, int threads);
/// "qf+": f.moved, the input positions that estimate_noise left there, filtered by `plan`
/// (kernels/refine_math.h).
void refine_positions(CpuFrame& f, const RefinePlan& plan, int threads);
/// Jones et al. 2003 (positions into f.moved).
void bilateral_filter(CpuFrame& f, const RunPlan& run, int threads);
void cluster_scores(CpuFrame& f, const RunPlan& run, int threads);
void cluster_links(CpuFrame& f, const RunPlan& run, int threads);
/// Roots, compacted to labels 0..K-1 in input order of the root vertices; returns K.
uint32_t cluster_labels(CpuFrame& f, std::vector<uint32_t>& labels, int threads);
/// The links before the theta cut, in input order (FrameResult::link_parent / link_p).
void export_links(const CpuFrame& f, const ClusterParams& p, std::vector<uint32_t>& parent,
                  std::vector<float>& prox, int threads);

}  // namespace fq::cpu
