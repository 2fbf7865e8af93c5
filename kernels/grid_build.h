// CPU construction of the uniform grid (counting sort of points into cells).
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/grid.h"
#include "kernels/vec3.h"

namespace fq {

/// Cell layout of a grid: chosen from the points' bounds and a wanted cell size.
struct GridLayout {
  Vec3 origin;
  float cell;
  int nx, ny, nz;
  uint64_t cells() const { return uint64_t(nx) * ny * nz; }
};

/// Bounds of the points padded by nothing; the cell grows (never shrinks) until the cell
/// count is at most max(8 n, 4096), so a tiny cell on a wide bounding box cannot exhaust
/// memory. A larger cell only makes the visitor scan more points, never miss one.
GridLayout choose_grid_layout(Vec3 lo, Vec3 hi, float wanted_cell, uint32_t num_points);

/// Owning CPU grid: `order[k]` is the original index of the k-th point in cell order
/// (stable: ties keep input order), `cell_start` the offsets per cell.
struct CpuGrid {
  GridLayout layout{};
  std::vector<uint32_t> cell_start;
  std::vector<uint32_t> order;
  uint32_t occupied = 0;  ///< cells that hold a point

  /// View over `sorted_points` (the caller's points permuted by `order`).
  GridView view(const Point4* sorted_points) const {
    return {layout.origin, layout.cell,       layout.nx,     layout.ny,
            layout.nz,     cell_start.data(), sorted_points, static_cast<uint32_t>(order.size())};
  }
};

/// Bounds of n points.
void bounds_of(const Vec3* points, uint32_t n, Vec3& lo, Vec3& hi);

/// Counting sort of `points` into cells of about `wanted_cell`.
void build_grid(const Vec3* points, uint32_t n, float wanted_cell, CpuGrid& grid);

}  // namespace fq
