// The passes of the CUDA engine, one function per pass, in the CPU engine's order
// (kernels/cpu_stages.h). Each enqueues its kernels on `s` and returns without waiting,
// except bilateral_filter, which reads the centroid bounds back to lay out its grid.
#pragma once

#include <cuda_runtime.h>

#include "core/params.h"
#include "kernels/cuda/device_frame.cuh"
#include "kernels/frame_plan.h"

namespace fq::cuda {

/// Grid of the uploaded points, sorted points, triangles renumbered to sorted indices.
void sort_into_grid(DeviceFrame& f, const GridLayout& layout, cudaStream_t s);
/// Triangle geometry; per-vertex base quadric, area (points.w) and normal, summed over a
/// vertex -> triangle table in the CPU's order.
void base_quadrics(DeviceFrame& f, cudaStream_t s);
void neighbourhood_quadrics(DeviceFrame& f, Extent sigma_b, cudaStream_t s);
void diffuse_quadrics(DeviceFrame& f, const RunPlan& run, cudaStream_t s);
void update_positions(DeviceFrame& f, const RunPlan& run, cudaStream_t s);
/// Jones et al. 2003 into f.moved (synchronizes `s` once, for the centroid bounds).
void bilateral_filter(DeviceFrame& f, const RunPlan& run, cudaStream_t s);

void cluster_scores(DeviceFrame& f, const RunPlan& run, cudaStream_t s);
void cluster_links(DeviceFrame& f, const RunPlan& run, cudaStream_t s);
/// Roots by pointer jumping; labels in input order numbered by the roots' input order
/// (as the CPU); f.labels[n] = cluster count.
void cluster_labels(DeviceFrame& f, cudaStream_t s);

}  // namespace fq::cuda
