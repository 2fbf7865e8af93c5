// Host side of a CUDA frame, on all host threads: normalization into pinned staging (with
// the bounds the grid layout needs) and the way back to input units. The per-vertex maps
// are frame_prep.h's, so the device sees exactly the CPU engine's normalized points.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/frame_prep.h"
#include "kernels/mesh_view.h"
#include "kernels/vec3.h"

namespace fq::cuda {

/// points[i] = normalized vertex i (w = 0); lo/hi = their bounds.
void stage_points(const MeshView& mesh, const Normalization& norm, Point4* points, Vec3& lo, Vec3& hi);

/// dst[0..count) = src[0..count), in parallel chunks.
void copy_indices(const uint32_t* src, uint32_t* dst, size_t count);

/// out[3i..3i+2] = moved[i] in input units.
void unstage_positions(const Vec3* moved, uint32_t n, const Normalization& norm, float* out);

}  // namespace fq::cuda
