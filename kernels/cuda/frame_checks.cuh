// The frame's checks and normalization on the device (the CPU engine's frame_prep.cpp
// work): finiteness, index range, bounds and the edge-length sum are reductions over the
// raw upload; the normalization and its inverse are per-vertex maps.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

#include "kernels/cuda/device_frame.cuh"
#include "kernels/frame_prep.h"

namespace fq::cuda {

/// Reduces f.in_coords / f.in_tris into f.stats and copies them to f.h_stats (the caller
/// synchronizes before reading them).
void reduce_frame(DeviceFrame& f, cudaStream_t s);

/// The host's view of f.h_stats once the stream has reached it: the first faults (kNone
/// when none), the coordinate bounds and the mean edge length.
struct FrameSummary {
  uint64_t bad_coordinate = kNone, bad_index = kNone;
  double lo[3], hi[3];
  double mean_edge;
};
FrameSummary read_summary(const DeviceFrame& f);

/// f.in_points[i] = norm.to_normalized(vertex i), w = 0.
void normalize_points(DeviceFrame& f, const Normalization& norm, cudaStream_t s);

/// f.out_coords = the filtered points f.moved (grid order) in input order and input units.
void positions_to_input(DeviceFrame& f, const Normalization& norm, cudaStream_t s);

}  // namespace fq::cuda
