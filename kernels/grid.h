// Uniform grid over a point set, built by counting sort (Hoetzlein 2014), and the one
// fixed-radius neighbour visitor that every pass calls. Points are stored sorted by cell
// (x fastest), so a row of cells along x is one contiguous range of points: the visitor
// walks, for each (y, z) row that meets the search sphere, only the x-span of cells the
// sphere covers in that row.
#pragma once

#include <cmath>
#include <cstdint>

#include "common/hd.h"
#include "kernels/vec3.h"

namespace fq {

struct GridView {
  Vec3 origin;                 ///< corner of cell (0,0,0)
  float cell;                  ///< cell edge length
  int nx, ny, nz;              ///< cells per axis
  const uint32_t* cell_start;  ///< nx*ny*nz + 1 offsets into points
  const Point4* points;        ///< positions sorted by cell, w = per-point scalar
  uint32_t count;              ///< number of points
};

FQ_HD int clamp_cell(float c, int n) {
  const int i = static_cast<int>(floorf(c));
  return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

FQ_HD uint32_t cell_index(const GridView& g, Vec3 p) {
  const float inv = 1.0f / g.cell;
  const int ix = clamp_cell((p.x - g.origin.x) * inv, g.nx);
  const int iy = clamp_cell((p.y - g.origin.y) * inv, g.ny);
  const int iz = clamp_cell((p.z - g.origin.z) * inv, g.nz);
  return (static_cast<uint32_t>(iz) * g.ny + iy) * g.nx + ix;
}

/// Squared distance from coordinate v to the interval of cell i along one axis.
FQ_HD float gap2(float v, float lo_cell, float cell, int i) {
  const float lo = lo_cell + i * cell, hi = lo + cell;
  const float d = v < lo ? lo - v : (v > hi ? v - hi : 0.f);
  return d * d;
}

/// Calls run(begin, end) for each contiguous range [begin, end) of candidate points: one
/// per (y, z) row of cells that meets the sphere of `radius` about p, cut to the x-span of
/// cells the sphere covers in that row. Candidates still need the |d| <= radius test.
template <class R>
FQ_HD void for_each_candidate_run(const GridView& g, Vec3 p, float radius, R&& run) {
  const float r2 = radius * radius;
  const float inv = 1.0f / g.cell;
  const int z0 = clamp_cell((p.z - radius - g.origin.z) * inv, g.nz);
  const int z1 = clamp_cell((p.z + radius - g.origin.z) * inv, g.nz);
  const int y0 = clamp_cell((p.y - radius - g.origin.y) * inv, g.ny);
  const int y1 = clamp_cell((p.y + radius - g.origin.y) * inv, g.ny);
  for (int iz = z0; iz <= z1; ++iz) {
    const float gz = gap2(p.z, g.origin.z, g.cell, iz);
    if (gz > r2) continue;
    for (int iy = y0; iy <= y1; ++iy) {
      const float gyz = gz + gap2(p.y, g.origin.y, g.cell, iy);
      if (gyz > r2) continue;
      const float rx = sqrtf(r2 - gyz);  // half-width of the sphere in this row
      const int x0 = clamp_cell((p.x - rx - g.origin.x) * inv, g.nx);
      const int x1 = clamp_cell((p.x + rx - g.origin.x) * inv, g.nx);
      const uint32_t row = (static_cast<uint32_t>(iz) * g.ny + iy) * g.nx;
      run(g.cell_start[row + x0], g.cell_start[row + x1 + 1]);
    }
  }
}

/// Calls f(j, point_j, d = point_j - p, |d|^2) for every point j with |d| <= radius.
/// The order of calls is fixed by the grid alone, so sums built in f are reproducible.
template <class F>
FQ_HD void for_each_neighbor(const GridView& g, Vec3 p, float radius, F&& f) {
  const float r2 = radius * radius;
  for_each_candidate_run(g, p, radius, [&](uint32_t begin, uint32_t end) {
    for (uint32_t j = begin; j < end; ++j) {
      const Point4 q = g.points[j];
      const Vec3 d{q.x - p.x, q.y - p.y, q.z - p.z};
      const float d2 = norm2(d);
      if (d2 <= r2) f(j, q, d, d2);
    }
  });
}

}  // namespace fq
