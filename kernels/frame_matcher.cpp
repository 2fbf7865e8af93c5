#include "kernels/frame_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel_for.h"
#include "kernels/box_nearest.h"
#include "kernels/grid_nearest.h"

namespace fq {

namespace {

/// Three of choose_grid_layout's steps of 1.26 (1.26^3 = 2.0004): a surface whose bounds hold
/// more than 8 cells of a mean edge a point (igea, 134K vertices) keeps the grid; an outlier
/// widens the cells far more.
constexpr float kMaxCellGrowth = 2.01f;
/// The growth up to which the grid was kept before three steps were: a grid grown more keeps
/// the sparse index's reach, kMaxReachCells of the wanted cell, so that its frames are matched
/// as they were when they went to that index (the reach asked for is wider only when the next
/// frame's mean edge is much longer than this one's).
constexpr float kFullReachGrowth = 2.f;

}  // namespace

void FrameMatcher::clear() {
  grid_.order.clear();
  grid_.cell_start.clear();
  sorted_.clear();
  index_ = NearestVertexIndex{};
  rank_.clear();
  sparse_ = false;
}

void FrameMatcher::build(const float* xyz, uint32_t n, float cell) {
  // Every buffer keeps its memory from the last build (a stream's frames are about one size).
  clear();
  cell_ = std::isfinite(cell) && cell > 0.f ? cell : 1.f;
  if (n == 0) return;
  points_.resize(n);
  for (uint32_t i = 0; i < n; ++i)
    points_[i] = {xyz[3 * size_t(i)], xyz[3 * size_t(i) + 1], xyz[3 * size_t(i) + 2]};
  build_grid(points_.data(), n, cell_, grid_);
  sorted_.resize(n);
  for (uint32_t k = 0; k < n; ++k) {
    const Vec3 p = points_[grid_.order[k]];
    sorted_[k] = {p.x, p.y, p.z, 0.f};
  }
  // The sparse index's own rule for a cell that is too coarse (kCellLoad points per occupied
  // cell: a cell given as the mean edge of a frame with a far outlier), and a grid whose cells
  // had to grow past about twice the wanted one to stay within 8 cells a point.
  sparse_ = !(grid_.layout.cell <= kMaxCellGrowth * cell_) ||
            n > NearestVertexIndex::kCellLoad * uint64_t(grid_.occupied);
  reach_cap_ = grid_.layout.cell <= kFullReachGrowth * cell_ ? std::numeric_limits<float>::infinity()
                                                             : NearestVertexIndex::kMaxReachCells * cell_;
  if (sparse_) {
    index_.build(xyz, n, cell_);
    rank_.resize(n);
    for (uint32_t k = 0; k < n; ++k) rank_[grid_.order[k]] = k;
  }
}

uint32_t FrameMatcher::nearest_position(Vec3 p, float reach) const {
  if (sparse_) {
    const uint32_t i = index_.nearest(p, reach);
    return i == kNone ? kNone : rank_[i];
  }
  // Growing spheres from half a cell, as NearestVertexIndex: most queries (the same surface
  // captured again) find their vertex within it.
  const uint32_t j =
      nearest_in_grid_boxes(grid_.view(sorted_.data()), p, std::min(reach, reach_cap_), 0.5f * cell_);
  return j == kNoNearest ? kNone : j;
}

uint32_t FrameMatcher::nearest(Vec3 p, float reach) const {
  const uint32_t k = nearest_position(p, reach);
  return k == kNone ? kNone : grid_.order[k];
}

void FrameMatcher::nearest_all(const FrameMatcher& queries, float reach, std::vector<uint32_t>& out,
                               int threads) const {
  const uint32_t n = queries.size();
  out.assign(n, kNone);
  if (size() == 0) return;
  parallel_for(n, threads,
               [&](uint32_t k) { out[queries.grid_.order[k]] = nearest(xyz(queries.sorted_[k]), reach); });
}

void FrameMatcher::nearest_all_in_cell_order(const FrameMatcher& queries, float reach,
                                             std::vector<uint32_t>& out, int threads) const {
  const uint32_t n = queries.size();
  out.assign(n, kNone);
  if (size() == 0) return;
  parallel_for(n, threads, [&](uint32_t k) { out[k] = nearest_position(xyz(queries.sorted_[k]), reach); });
}

}  // namespace fq
