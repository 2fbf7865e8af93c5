#include "frame_prep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace fq {

Status check_mesh(const MeshView& mesh) {
  if (mesh.num_vertices == 0) return invalid_input("mesh has no vertices");
  if (mesh.num_triangles == 0) return invalid_input("mesh has no triangles (point clouds are not supported)");
  for (uint64_t i = 0; i < uint64_t(mesh.num_vertices) * 3; ++i) {
    if (!std::isfinite(mesh.positions[i]))
      return invalid_input("vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
  }
  for (uint64_t i = 0; i < uint64_t(mesh.num_triangles) * 3; ++i) {
    if (mesh.triangles[i] >= mesh.num_vertices)
      return invalid_input("triangle " + std::to_string(i / 3) + " references vertex " +
                           std::to_string(mesh.triangles[i]) + " but the mesh has " +
                           std::to_string(mesh.num_vertices) + " vertices");
  }
  return {};
}

double mean_edge_length(const MeshView& mesh) {
  double sum = 0.0;
  for (uint32_t t = 0; t < mesh.num_triangles; ++t) {
    const uint32_t* tri = mesh.triangles + 3 * size_t(t);
    for (int e = 0; e < 3; ++e) {
      const float* a = mesh.positions + 3 * size_t(tri[e]);
      const float* b = mesh.positions + 3 * size_t(tri[(e + 1) % 3]);
      const double dx = double(a[0]) - b[0], dy = double(a[1]) - b[1], dz = double(a[2]) - b[2];
      sum += std::sqrt(dx * dx + dy * dy + dz * dz);
    }
  }
  return mesh.num_triangles ? sum / (3.0 * mesh.num_triangles) : 0.0;
}

Status compute_normalization(const MeshView& mesh, Normalization& out) {
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -lo[k];
  }
  for (uint32_t i = 0; i < mesh.num_vertices; ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(mesh.positions[3 * size_t(i) + k]));
      hi[k] = std::max(hi[k], double(mesh.positions[3 * size_t(i) + k]));
    }
  }
  for (int k = 0; k < 3; ++k) out.center[k] = 0.5 * (lo[k] + hi[k]);
  out.mean_edge = mean_edge_length(mesh);
  if (!(out.mean_edge > 0.0) || !std::isfinite(out.mean_edge))
    return invalid_input("mesh is degenerate: every edge has zero length");
  double extent = 0.0;
  for (int k = 0; k < 3; ++k) extent = std::max(extent, hi[k] - lo[k]);
  if (!(extent / out.mean_edge <= kMaxExtentInEdges))
    return invalid_input("mesh spans " + std::to_string(extent / out.mean_edge) +
                         " mean edge lengths (at most 1e6 supported): is there a far outlier vertex?");
  return {};
}

}  // namespace fq
