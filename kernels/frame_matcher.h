// Nearest-vertex lookups from one capture frame into another (cluster id tracking,
// kernels/label_tracking.h, and the CPU engine's temporal step, kernels/temporal.h): a frame's
// vertices counting-sorted into a uniform grid of about one mean edge (kernels/grid_build.h),
// with the answers of the query the CUDA engine's temporal step uses (kernels/grid_nearest.h),
// its spheres walked as boxes of cells (kernels/box_nearest.h). Two noisy bunnies (35K
// vertices) on the 2-core development machine: build and lookups 8-10 ms against 28-31 ms with
// the sparse NearestVertexIndex, the same answers (about 3 ms with the box walk). A uniform grid
// fails where the cell is wrong for the points: its cells are capped at 8 per point, so a far
// outlier widens every cell, and a cell given as the mean edge of a frame with a far outlier is
// itself too wide. When the grid's cell grew more than three of its steps (past about twice the
// wanted one: on dragon, four steps, the grid's budget of candidates cuts a few lookups short)
// or its occupied cells hold more than kCellLoad points on average, the lookups go to the sparse
// index, which frames its cells on the bulk of the points (its header says how), and the grid
// only orders the queries. A grid grown past twice the wanted cell (three steps) gives its
// lookups the sparse index's reach, as those frames went to that index before. Every buffer
// keeps its memory from one build to the next.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/grid_build.h"
#include "kernels/nearest_vertex.h"

namespace fq {

class FrameMatcher {
 public:
  static constexpr uint32_t kNone = NearestVertexIndex::kNone;

  /// Indexes n points (3 floats each, copied) in cells of about `cell` (the mean edge).
  void build(const float* xyz, uint32_t n, float cell);
  uint32_t size() const { return static_cast<uint32_t>(sorted_.size()); }
  /// Whether the lookups go to the sparse index (the grid's cells are too coarse for the points).
  bool sparse() const { return sparse_; }
  /// Forgets the points; the buffers keep their memory for the next build.
  void clear();

  /// For each point of `queries` (out[i]: the i-th point given to queries.build), the index
  /// (as given to build) of the nearest point of this frame within `reach`, or kNone; asked in
  /// the queries' cell order, so neighbouring queries read the same cells. In parallel, under
  /// the caller's CancelScope (when its token expires, the answers are unspecified).
  void nearest_all(const FrameMatcher& queries, float reach, std::vector<uint32_t>& out, int threads) const;
  /// nearest_all in cell order on both sides: out[k] for the k-th of `queries` in its cell
  /// order, the position in this frame's cell order of its nearest point, or kNone. A caller
  /// that keeps per-point data in cell order reads neighbouring entries for neighbouring queries.
  void nearest_all_in_cell_order(const FrameMatcher& queries, float reach, std::vector<uint32_t>& out,
                                 int threads) const;
  /// The index (as given to build) of the k-th point in cell order.
  uint32_t original(uint32_t k) const { return grid_.order[k]; }
  /// The index (as given to build) of the point nearest to p within `reach`, or kNone; ties go
  /// to the first in cell order, as NearestVertexIndex::nearest.
  uint32_t nearest(Vec3 p, float reach) const;

 private:
  /// nearest's point as its position in this frame's cell order, or kNone: the one lookup
  /// behind nearest and nearest_all_in_cell_order.
  uint32_t nearest_position(Vec3 p, float reach) const;

  float cell_ = 1.f;
  std::vector<Vec3> points_;  ///< build's copy of the points (kept for the next build)
  CpuGrid grid_;
  std::vector<Point4> sorted_;  ///< the points in cell order (grid_.order)
  NearestVertexIndex index_;    ///< built only when sparse_
  std::vector<uint32_t> rank_;  ///< only when sparse_: each point's position in cell order
  bool sparse_ = false;
  float reach_cap_ = 0.f;  ///< the widest reach a lookup on the grid is given (see build)
};

}  // namespace fq
