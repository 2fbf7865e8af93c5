#include "kernels/frame_matcher.h"

#include <cmath>

#include "core/parallel_for.h"
#include "kernels/grid_nearest.h"

namespace fq {

void FrameMatcher::clear() {
  grid_ = CpuGrid{};
  sorted_.clear();
  index_ = NearestVertexIndex{};
  sparse_ = false;
}

void FrameMatcher::build(const float* xyz, uint32_t n, float cell) {
  clear();
  cell_ = std::isfinite(cell) && cell > 0.f ? cell : 1.f;
  if (n == 0) return;
  std::vector<Vec3> points(n);
  for (uint32_t i = 0; i < n; ++i) points[i] = {xyz[3 * size_t(i)], xyz[3 * size_t(i) + 1], xyz[3 * size_t(i) + 2]};
  build_grid(points.data(), n, cell_, grid_);
  sorted_.resize(n);
  for (uint32_t k = 0; k < n; ++k) {
    const Vec3 p = points[grid_.order[k]];
    sorted_[k] = {p.x, p.y, p.z, 0.f};
  }
  // The sparse index's own rule for a cell that is too coarse (kCellLoad points per occupied
  // cell: a cell given as the mean edge of a frame with a far outlier), and a grid whose cells
  // had to grow to stay within 8 per point.
  uint64_t occupied = 0;
  for (size_t c = 0; c + 1 < grid_.cell_start.size(); ++c) occupied += grid_.cell_start[c + 1] > grid_.cell_start[c];
  sparse_ = !(grid_.layout.cell <= 2.f * cell_) || n > NearestVertexIndex::kCellLoad * occupied;
  if (sparse_) index_.build(xyz, n, cell_);
}

uint32_t FrameMatcher::nearest(Vec3 p, float reach) const {
  if (sparse_) return index_.nearest(p, reach);
  // Growing spheres from half a cell, as NearestVertexIndex: most queries (the same surface
  // captured again) find their vertex within it.
  const uint32_t j = nearest_in_grid(grid_.view(sorted_.data()), p, reach, 0.5f * cell_);
  return j == kNoNearest ? kNone : grid_.order[j];
}

void FrameMatcher::nearest_all(const FrameMatcher& queries, float reach, std::vector<uint32_t>& out,
                               int threads) const {
  const uint32_t n = queries.size();
  out.assign(n, kNone);
  if (size() == 0) return;
  parallel_for(n, threads, [&](uint32_t k) { out[queries.grid_.order[k]] = nearest(xyz(queries.sorted_[k]), reach); });
}

}  // namespace fq
