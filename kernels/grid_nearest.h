// The nearest point of a uniform grid (kernels/grid.h) to a query: how the CUDA engine matches
// a frame's vertices to its stream's last result (kernels/cuda/temporal_pass.cu) on a grid it
// builds on the device, where the CPU engine asks a FrameMatcher (kernels/frame_matcher.h: the same query on
// a grid built on the host, or its NearestVertexIndex, a sparse grid built on the host, which on the device
// would need the host's decisions and a round trip). The same answers: the nearest point within reach, found
// by growing spheres from `first_radius`, at most kMaxCandidates points looked at, ties to the first in cell
// order.
//
// The grid's layout need not hold the points: counting sort puts a point outside it into the
// nearest edge cell, so here an edge cell reaches to infinity on its outer side and such a
// point is found like any other (the layout is the new frame's bounds, the points the last
// frame's result).
#pragma once

#include <cmath>
#include <cstdint>

#include "common/hd.h"
#include "kernels/grid.h"
#include "kernels/nearest_vertex.h"
#include "kernels/vec3.h"

namespace fq {

constexpr uint32_t kNoNearest = 0xffffffffu;

/// Cell of coordinate c (in cells from the origin) among n, clamped in float first, so that a
/// far point cannot overflow the conversion.
FQ_HD int clamped_cell(float c, int n) {
  if (!(c >= 0.f)) return 0;
  return c >= float(n) ? n - 1 : static_cast<int>(c);
}

/// Squared distance from v to cell i of n along one axis, the edge cells open outward.
FQ_HD float open_gap2(float v, float origin, float cell, int i, int n) {
  const float lo = origin + float(i) * cell, hi = lo + cell;
  const float d = (v < lo && i > 0) ? lo - v : ((v > hi && i < n - 1) ? v - hi : 0.f);
  return d * d;
}

/// Index (in g's sorted order) of the point nearest to p within `reach`, or kNoNearest.
FQ_HD uint32_t nearest_in_grid(const GridView& g, Vec3 p, float reach, float first_radius) {
  if (g.count == 0 || !is_finite(p) || !(reach >= 0.f)) return kNoNearest;
  uint32_t budget = NearestVertexIndex::kMaxCandidates;
  const float inv = 1.f / g.cell;
  for (float r = first_radius > 0.f && first_radius < reach ? first_radius : reach;;
       r = 2.f * r < reach ? 2.f * r : reach) {
    const float r2 = r * r;
    uint32_t best = kNoNearest;
    float best_d2 = 0.f;
    const int z0 = clamped_cell((p.z - r - g.origin.z) * inv, g.nz),
              z1 = clamped_cell((p.z + r - g.origin.z) * inv, g.nz);
    const int y0 = clamped_cell((p.y - r - g.origin.y) * inv, g.ny),
              y1 = clamped_cell((p.y + r - g.origin.y) * inv, g.ny);
    for (int iz = z0; iz <= z1 && budget > 0; ++iz) {
      const float gz = open_gap2(p.z, g.origin.z, g.cell, iz, g.nz);
      if (gz > r2) continue;
      for (int iy = y0; iy <= y1 && budget > 0; ++iy) {
        const float gyz = gz + open_gap2(p.y, g.origin.y, g.cell, iy, g.ny);
        if (gyz > r2) continue;
        const float rx = std::sqrt(r2 - gyz);  // half-width of the sphere in this row
        const int x0 = clamped_cell((p.x - rx - g.origin.x) * inv, g.nx);
        const int x1 = clamped_cell((p.x + rx - g.origin.x) * inv, g.nx);
        const uint32_t row = (static_cast<uint32_t>(iz) * g.ny + iy) * g.nx;
        const uint32_t end = g.cell_start[row + x1 + 1];
        for (uint32_t j = g.cell_start[row + x0]; j < end && budget > 0; ++j, --budget) {
          const float d2 = norm2(xyz(g.points[j]) - p);
          if (d2 <= r2 && (best == kNoNearest || d2 < best_d2)) {
            best = j;
            best_d2 = d2;
          }
        }
      }
    }
    if (best != kNoNearest) return best;
    if (!(r < reach) || budget == 0) return kNoNearest;
  }
}

}  // namespace fq
