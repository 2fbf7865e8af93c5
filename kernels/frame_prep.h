// Host-side normalization shared by the engines: a frame is checked (core/mesh_checks.h), then
// moved to normalized units (bounding-box centre at the origin, mean edge length = 1) so
// that every sigma is a plain number and float32 keeps its precision.
#pragma once

// The reductions below run on `threads` threads and give bit-identical results for any
// thread count (fixed chunks, partial results combined in chunk order); threads <= 0
// means all hardware threads.

#include <cstdint>

#include "common/hd.h"
#include "common/status.h"
#include "core/mesh_checks.h"
#include "core/mesh_view.h"
#include "kernels/vec3.h"

namespace fq {

struct Normalization {
  double center[3] = {0, 0, 0};
  double mean_edge = 1.0;  ///< input units per normalized unit

  // Host and device (the CUDA engine maps on the GPU; its file is built without FMA
  // contraction, so both give the same floats).
  FQ_HD Vec3 to_normalized(const float* p) const {
    const double s = 1.0 / mean_edge;
    return {float((p[0] - center[0]) * s), float((p[1] - center[1]) * s), float((p[2] - center[2]) * s)};
  }
  FQ_HD void to_input(Vec3 q, float* out) const {
    out[0] = float(center[0] + q.x * mean_edge);
    out[1] = float(center[1] + q.y * mean_edge);
    out[2] = float(center[2] + q.z * mean_edge);
  }
};

/// Largest bounding-box extent, in mean edge lengths, that a frame may span. float32
/// coordinates at 1e6 edges from the centre resolve about 0.06 edge; beyond that (or with a
/// far outlier vertex) precision and the grid both degrade, so such frames are refused.
inline constexpr double kMaxExtentInEdges = 1e6;

/// The exact bounds of a mesh's positions (lo, hi per axis; +inf / -inf for no vertex), reduced
/// over fixed chunks on `threads` threads: min and max do not depend on the order they are taken in.
void mesh_bounds(const MeshView& mesh, double lo[3], double hi[3], int threads = 0);

/// Bounding-box centre and mean edge length (over the three edges of every triangle, so
/// interior edges of a closed mesh count once per side; a mesh whose edges all have zero
/// length, or one spanning more than kMaxExtentInEdges, is rejected).
Status compute_normalization(const MeshView& mesh, Normalization& out, int threads = 0);

/// compute_normalization's result from the coordinate bounds and the mean edge length,
/// however they were reduced.
Status normalization_from(const double lo[3], const double hi[3], double mean_edge, Normalization& out);

/// Mean edge length of a mesh in its own units (0 when it has no non-degenerate edge).
double mean_edge_length(const MeshView& mesh, int threads = 0);

}  // namespace fq
