#include "kernels/box_nearest.h"

#include <cmath>
#include <limits>

#include "kernels/grid_nearest.h"
#include "kernels/nearest_vertex.h"

namespace fq {

uint32_t nearest_in_grid_boxes(const GridView& g, Vec3 p, float reach, float first_radius) {
  if (g.count == 0 || !is_finite(p) || !(reach >= 0.f)) return nearest_in_grid(g, p, reach, first_radius);
  const float inv = 1.f / g.cell;
  uint32_t walked = 0;
  for (float r = first_radius > 0.f && first_radius < reach ? first_radius : reach;;
       r = 2.f * r < reach ? 2.f * r : reach) {
    const float r2 = r * r, rx = std::sqrt(r2);  // no row of nearest_in_grid's is wider than rx
    const int z0 = clamped_cell((p.z - r - g.origin.z) * inv, g.nz),
              z1 = clamped_cell((p.z + r - g.origin.z) * inv, g.nz);
    const int y0 = clamped_cell((p.y - r - g.origin.y) * inv, g.ny),
              y1 = clamped_cell((p.y + r - g.origin.y) * inv, g.ny);
    const int x0 = clamped_cell((p.x - rx - g.origin.x) * inv, g.nx);
    const int x1 = clamped_cell((p.x + rx - g.origin.x) * inv, g.nx);
    uint32_t best = kNoNearest;
    float best_d2 = std::numeric_limits<float>::infinity();
    // Rows in cell order, points in cell order within a row: the first of equal distances is
    // the one nearest_in_grid keeps.
    for (int iz = z0; iz <= z1; ++iz) {
      for (int iy = y0; iy <= y1; ++iy) {
        const uint32_t row = (static_cast<uint32_t>(iz) * g.ny + iy) * g.nx;
        const uint32_t begin = g.cell_start[row + x0], end = g.cell_start[row + x1 + 1];
        walked += end - begin;
        if (walked >= NearestVertexIndex::kMaxCandidates) return nearest_in_grid(g, p, reach, first_radius);
        for (uint32_t j = begin; j < end; ++j) {
          const float d2 = norm2(xyz(g.points[j]) - p);
          const bool nearer = d2 < best_d2;
          best = nearer ? j : best;
          best_d2 = nearer ? d2 : best_d2;
        }
      }
    }
    if (best_d2 <= r2) {
      // The margin (see the header): float rounding of a cell bound at the coordinates' scale,
      // many times over.
      const float slack =
          (std::fabs(g.origin.x) + std::fabs(g.origin.y) + std::fabs(g.origin.z) + std::fabs(p.x) +
           std::fabs(p.y) + std::fabs(p.z) + g.cell * float(g.nx + g.ny + g.nz)) *
          (1.f / 65536.f);
      const float inner = r * (1.f - 1.f / 4096.f) - slack;
      return inner > 0.f && best_d2 <= inner * inner ? best : nearest_in_grid(g, p, reach, first_radius);
    }
    if (!(r < reach)) return kNoNearest;
  }
}

}  // namespace fq
