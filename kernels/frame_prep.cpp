#include "kernels/frame_prep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/parallel_for.h"

namespace fq {

double mean_edge_length(const MeshView& mesh, int threads) {
  if (mesh.num_triangles == 0) return 0.0;
  std::vector<double> partial(fixed_chunks(mesh.num_triangles), 0.0);
  parallel_for(
      static_cast<uint32_t>(partial.size()), threads_or_all(threads),
      [&](uint32_t c) {
        const uint32_t end = std::min<uint64_t>(mesh.num_triangles, uint64_t(c + 1) * kFixedChunk);
        double sum = 0.0;
        for (uint32_t t = c * kFixedChunk; t < end; ++t) {
          const uint32_t* tri = mesh.triangles + 3 * size_t(t);
          for (int e = 0; e < 3; ++e) {
            const float* a = mesh.positions + 3 * size_t(tri[e]);
            const float* b = mesh.positions + 3 * size_t(tri[(e + 1) % 3]);
            const double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
            sum += std::sqrt(dx * dx + dy * dy + dz * dz);
          }
        }
        partial[c] = sum;
      },
      kOneChunkAtATime);
  double sum = 0.0;
  for (double s : partial) sum += s;
  return sum / (3.0 * mesh.num_triangles);
}

void mesh_bounds(const MeshView& mesh, double lo[3], double hi[3], int threads) {
  // Min and max do not depend on the order of evaluation: per-chunk bounds are exact.
  struct Box {
    double lo[3], hi[3];
  };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<Box> boxes(fixed_chunks(mesh.num_vertices), Box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}});
  parallel_for(
      static_cast<uint32_t>(boxes.size()), threads_or_all(threads),
      [&](uint32_t c) {
        const uint32_t end = std::min<uint64_t>(mesh.num_vertices, uint64_t(c + 1) * kFixedChunk);
        Box& b = boxes[c];
        for (uint32_t i = c * kFixedChunk; i < end; ++i) {
          for (int k = 0; k < 3; ++k) {
            b.lo[k] = std::min(b.lo[k], double(mesh.positions[3 * size_t(i) + k]));
            b.hi[k] = std::max(b.hi[k], double(mesh.positions[3 * size_t(i) + k]));
          }
        }
      },
      kOneChunkAtATime);
  for (int k = 0; k < 3; ++k) {
    lo[k] = kInf;
    hi[k] = -kInf;
  }
  for (const Box& b : boxes) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], b.lo[k]);
      hi[k] = std::max(hi[k], b.hi[k]);
    }
  }
}

Status compute_normalization(const MeshView& mesh, Normalization& out, int threads) {
  double lo[3], hi[3];
  mesh_bounds(mesh, lo, hi, threads);
  return normalization_from(lo, hi, mean_edge_length(mesh, threads), out);
}

Status normalization_from(const double lo[3], const double hi[3], double mean_edge, Normalization& out) {
  for (int k = 0; k < 3; ++k) out.center[k] = 0.5 * (lo[k] + hi[k]);
  out.mean_edge = mean_edge;
  if (!(out.mean_edge > 0.0) || !std::isfinite(out.mean_edge))
    return invalid_input("mesh is degenerate: every edge has zero length");
  double extent = 0.0;
  for (int k = 0; k < 3; ++k) extent = std::max(extent, hi[k] - lo[k]);
  if (!(extent / out.mean_edge <= kMaxExtentInEdges)) {
    // Four digits: the CUDA engine's mean edge can differ in its last bits (another
    // summation order), and both engines must print the same message.
    char span[32];
    std::snprintf(span, sizeof span, "%.4g", extent / out.mean_edge);
    return invalid_input(std::string("mesh spans ") + span +
                         " mean edge lengths (at most 1e6 supported): is there a far outlier vertex?");
  }
  return {};
}

}  // namespace fq
