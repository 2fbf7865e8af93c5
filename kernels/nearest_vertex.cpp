#include "kernels/nearest_vertex.h"

#include <algorithm>

#include "core/parallel_for.h"

namespace fq {

void NearestVertexIndex::build(const float* xyz, uint32_t n, float cell) {
  std::vector<Vec3> points(n);
  for (uint32_t i = 0; i < n; ++i) points[i] = {xyz[3 * size_t(i)], xyz[3 * size_t(i) + 1], xyz[3 * size_t(i) + 2]};
  build_grid(points.data(), n, cell, grid_);
  sorted_.resize(n);
  for (uint32_t k = 0; k < n; ++k) {
    const Vec3 p = points[grid_.order[k]];
    sorted_[k] = {p.x, p.y, p.z, 0.f};
  }
}

uint32_t NearestVertexIndex::nearest(Vec3 p, float max_radius) const {
  if (sorted_.empty()) return kNone;
  const GridView g = grid_.view(sorted_.data());
  // Growing spheres: the first that holds a point holds the nearest one.
  // Half a cell first: most queries (a vertex of the next capture of the same surface) find
  // their nearest within it, among ~8 cells instead of ~27.
  for (float r = std::min(0.5f * grid_.layout.cell, max_radius);; r = std::min(2.f * r, max_radius)) {
    uint32_t best = kNone;
    float best_d2 = 0.f;
    for_each_neighbor(g, p, r, [&](uint32_t k, const Point4&, Vec3, float d2) {
      if (best == kNone || d2 < best_d2) {
        best = k;
        best_d2 = d2;
      }
    });
    if (best != kNone) return grid_.order[best];
    if (!(r < max_radius)) return kNone;
  }
}

void NearestVertexIndex::nearest_all(const float* xyz, uint32_t n, float max_radius, std::vector<uint32_t>& out,
                                     int threads) const {
  out.resize(n);
  parallel_for(n, threads, [&](uint32_t i) {
    const float* q = xyz + 3 * size_t(i);
    out[i] = nearest({q[0], q[1], q[2]}, max_radius);
  });
}

}  // namespace fq
