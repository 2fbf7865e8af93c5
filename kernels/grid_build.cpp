#include "kernels/grid_build.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fq {

void bounds_of(const Vec3* points, uint32_t n, Vec3& lo, Vec3& hi) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  lo = {kInf, kInf, kInf};
  hi = {-kInf, -kInf, -kInf};
  for (uint32_t i = 0; i < n; ++i) {
    lo = {std::min(lo.x, points[i].x), std::min(lo.y, points[i].y), std::min(lo.z, points[i].z)};
    hi = {std::max(hi.x, points[i].x), std::max(hi.y, points[i].y), std::max(hi.z, points[i].z)};
  }
  if (n == 0) lo = hi = {0.f, 0.f, 0.f};
}

GridLayout choose_grid_layout(Vec3 lo, Vec3 hi, float wanted_cell, uint32_t num_points) {
  const double max_cells = std::max<double>(8.0 * num_points, 4096.0);
  const Vec3 ext = hi - lo;
  double cell = std::max<double>(wanted_cell, 1e-6);
  // Enough cells to hold the bounds at the chosen size; grow the cell by 2^(1/3) steps.
  auto dims = [&](double c, float e) { return std::max(1.0, std::floor(e / c) + 1.0); };
  while (dims(cell, ext.x) * dims(cell, ext.y) * dims(cell, ext.z) > max_cells) cell *= 1.26;
  GridLayout g;
  g.origin = lo;
  g.cell = static_cast<float>(cell);
  g.nx = static_cast<int>(dims(cell, ext.x));
  g.ny = static_cast<int>(dims(cell, ext.y));
  g.nz = static_cast<int>(dims(cell, ext.z));
  return g;
}

void build_grid(const Vec3* points, uint32_t n, float wanted_cell, CpuGrid& grid) {
  Vec3 lo, hi;
  bounds_of(points, n, lo, hi);
  grid.layout = choose_grid_layout(lo, hi, wanted_cell, n);
  const GridView shape{grid.layout.origin, grid.layout.cell, grid.layout.nx, grid.layout.ny,
                       grid.layout.nz,     nullptr,          nullptr,        n};
  const size_t cells = grid.layout.cells();
  grid.cell_start.assign(cells + 1, 0);
  grid.occupied = 0;
  std::vector<uint32_t> cell_of(n);
  for (uint32_t i = 0; i < n; ++i) {
    cell_of[i] = cell_index(shape, points[i]);
    grid.occupied += grid.cell_start[cell_of[i] + 1]++ == 0 ? 1u : 0u;
  }
  for (size_t c = 0; c < cells; ++c) grid.cell_start[c + 1] += grid.cell_start[c];
  std::vector<uint32_t> cursor(grid.cell_start.begin(), grid.cell_start.end() - 1);
  grid.order.resize(n);
  for (uint32_t i = 0; i < n; ++i) grid.order[cursor[cell_of[i]]++] = i;
}

}  // namespace fq
