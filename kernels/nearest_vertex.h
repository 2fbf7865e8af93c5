// Nearest point queries over one frame's vertices: the matcher between two capture frames,
// whose vertex ids have nothing in common. Every query costs a bounded amount of work
// whatever the frame holds, so matching two frames of n vertices is O(n log n):
//   - the grid is sparse (the occupied cells, sorted by key), so its cell is the one asked for
//     however far the points spread: one vertex a million units away does not make every cell
//     of the surface hold thousands of vertices, as a dense grid over the bounds did;
//   - a cell asked for that leaves more than kCellLoad vertices per occupied cell is cut to a
//     quarter of the spread of the middle 90 % of the vertices, then halved while halving
//     still splits them (a cell inflated by outliers' long edges);
//   - a query looks at most kMaxReachCells cells away and at most kMaxCandidates vertices,
//     the nearest among them being its answer (points piled on one spot are all as near).
// On a frame whose occupied cells hold a few vertices each (any surface sampled by its
// mean edge) the answers are exact within the reach.
#pragma once

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "kernels/vec3.h"

namespace fq {

class NearestVertexIndex {
 public:
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  static constexpr uint32_t kCellLoad = 8;         ///< vertices per occupied cell before the cell is halved
  static constexpr float kMaxReachCells = 8.f;     ///< farthest a query looks, in cells
  static constexpr uint32_t kMaxCandidates = 256;  ///< vertices a query may look at
  static constexpr int kBlockCells = 8;            ///< cells a side of a block (the reach)

  /// Indexes n points (3 floats each, copied) in cells of about `cell` (the mean edge
  /// length is a good choice: a query then looks at a few cells). A cell that is not a
  /// positive finite number is taken as 1.
  void build(const float* xyz, uint32_t n, float cell);
  uint32_t size() const { return static_cast<uint32_t>(order_.size()); }
  float cell() const { return cell_; }

  /// Index (as given to build) of the point nearest to p, or kNone when none lies within
  /// min(max_radius, kMaxReachCells cells). Ties go to the first in cell order, so answers
  /// are reproducible.
  uint32_t nearest(Vec3 p, float max_radius) const;

  /// nearest() for every query point, in parallel (under the caller's CancelScope: when its
  /// token expires, the answers are unspecified).
  void nearest_all(const float* xyz, uint32_t n, float max_radius, std::vector<uint32_t>& out,
                   int threads) const;

 private:
  struct CellCoords {
    int64_t x, y, z;
  };
  CellCoords coords_of(Vec3 p) const;
  /// Whether a point lies in the blocks (kBlockCells cells a side) that meet the cube of
  /// half-width `r` about p.
  bool any_block_near(Vec3 p, float r) const;

  Vec3 origin_{};
  float cell_ = 1.f;
  std::vector<uint64_t> keys_;        ///< occupied cells, ascending (x is the fastest axis)
  std::vector<uint32_t> cell_start_;  ///< keys_.size() + 1 offsets into sorted_
  std::vector<Vec3> sorted_;          ///< the points in cell order
  std::vector<uint32_t> order_;       ///< original index of each sorted point
  /// Open addressing from a key to a run [first, last): a lookup in O(1).
  class KeyTable {
   public:
    void reset(size_t keys);
    void insert(uint64_t key, uint32_t first, uint32_t last);
    /// The key's run; {0, 0} when the key is not in the table.
    std::pair<uint32_t, uint32_t> find(uint64_t key) const;
    bool contains(uint64_t key) const;

   private:
    struct Slot {
      uint64_t key;  ///< kFree: a free slot
      uint32_t first, last;
    };
    size_t slot_of(uint64_t key) const;
    std::vector<Slot> slots_;
    int bits_ = 0;
  };
  // Rows of cells (same y and z): a query finds a row in O(1) and then searches only that
  // row's few keys (a binary search over all of keys_ per row took the bunny's tracking from
  // 20 to 64 ms a frame on the 2-core development machine).
  KeyTable rows_;
  // Occupied blocks of kBlockCells^3 cells: a query with nothing near (a vertex of a new
  // frame far from the previous one) looks at 27 blocks instead of ~400 rows (3.6 s for a
  // 163,842-vertex soup around a unit sphere).
  KeyTable blocks_;
};

}  // namespace fq
