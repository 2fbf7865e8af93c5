// Nearest point queries over one frame's vertices, on the project's uniform grid: the
// matcher between two capture frames, whose vertex ids have nothing in common.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "kernels/grid_build.h"
#include "kernels/vec3.h"

namespace fq {

class NearestVertexIndex {
 public:
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

  /// Indexes n points (3 floats each, copied) in cells of about `cell` (the mean edge
  /// length is a good choice: a query then looks at a few cells).
  void build(const float* xyz, uint32_t n, float cell);
  uint32_t size() const { return static_cast<uint32_t>(grid_.order.size()); }
  float cell() const { return grid_.layout.cell; }

  /// Index (as given to build) of the point nearest to p, or kNone when none lies within
  /// max_radius. Ties go to the first in grid order, so answers are reproducible.
  uint32_t nearest(Vec3 p, float max_radius) const;

  /// nearest() for every query point, in parallel.
  void nearest_all(const float* xyz, uint32_t n, float max_radius, std::vector<uint32_t>& out, int threads) const;

 private:
  CpuGrid grid_;
  std::vector<Point4> sorted_;
};

}  // namespace fq
