#include "eval/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "kernels/frame_prep.h"
#include "kernels/grid_build.h"
#include "eval/error_metrics.h"

namespace fq {

namespace {

struct P {
  double x, y, z;
};
P operator-(P a, P b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P operator+(P a, P b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P operator*(double s, P a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(P a, P b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

P vertex(const MeshView& m, uint32_t v) {
  const float* p = m.positions + 3 * size_t(v);
  return {p[0], p[1], p[2]};
}

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5):
// Voronoi regions of vertices, then edges, then the face.
P closest_on_triangle(P p, P a, P b, P c) {
  const P ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const P bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const P cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(std::fabs(denom) > 0)) return a;  // degenerate triangle: its vertices still count
  return a + (vb / denom) * ab + (vc / denom) * ac;
}

// Triangles indexed by centroid in a grid; a triangle whose closest point is at distance d
// has its centroid within d + max_reach, which bounds the search exactly.
struct TriangleIndex {
  const MeshView& mesh;
  CpuGrid grid;
  std::vector<Point4> centroids;  // grid order, w unused
  double max_reach = 0.0;         // max centroid-to-vertex distance over triangles

  explicit TriangleIndex(const MeshView& m, double cell) : mesh(m) {
    std::vector<Vec3> c(m.num_triangles);
    for (uint32_t t = 0; t < m.num_triangles; ++t) {
      const uint32_t* tri = m.triangles + 3 * size_t(t);
      const P g = (1.0 / 3.0) * (vertex(m, tri[0]) + vertex(m, tri[1]) + vertex(m, tri[2]));
      c[t] = {float(g.x), float(g.y), float(g.z)};
      for (int k = 0; k < 3; ++k) max_reach = std::max(max_reach, std::sqrt(dot(vertex(m, tri[k]) - g, vertex(m, tri[k]) - g)));
    }
    build_grid(c.data(), m.num_triangles, float(cell), grid);
    centroids.resize(m.num_triangles);
    for (uint32_t k = 0; k < m.num_triangles; ++k) {
      const Vec3 v = c[grid.order[k]];
      centroids[k] = {v.x, v.y, v.z, 0.f};
    }
  }

  // Squared distance to the closest triangle with centroid within `radius`, or +inf.
  double search(P p, double radius) const {
    double best = std::numeric_limits<double>::infinity();
    const GridView g = grid.view(centroids.data());
    for_each_neighbor(g, Vec3{float(p.x), float(p.y), float(p.z)}, float(radius),
                      [&](uint32_t j, const Point4&, Vec3, float) {
                        const uint32_t* tri = mesh.triangles + 3 * size_t(grid.order[j]);
                        const P q = closest_on_triangle(p, vertex(mesh, tri[0]), vertex(mesh, tri[1]), vertex(mesh, tri[2]));
                        best = std::min(best, dot(p - q, p - q));
                      });
    return best;
  }

  double distance(P p, double start_radius) const {
    double r = start_radius;
    double best2 = search(p, r);
    while (!std::isfinite(best2)) best2 = search(p, r *= 2.0);  // nothing near: widen
    const double exact_r = std::sqrt(best2) + max_reach;
    if (exact_r > r) best2 = std::min(best2, search(p, exact_r * (1.0 + 1e-6)));
    return std::sqrt(best2);
  }
};

}  // namespace

SurfaceDistance distance_to_surface(const MeshView& reference, const float* points, uint32_t num_points) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  // The same scale as rmse_over_diagonal, so the two measures compare.
  const double diag = bbox_diagonal(reference);
  const double edge = mean_edge_length(reference);
  if (reference.num_triangles == 0 || num_points == 0 || !(diag > 0.0) || !(edge > 0.0)) return {kNaN, kNaN};
  const TriangleIndex index(reference, 2.0 * edge);
  double sum2 = 0.0, dmax = 0.0;
  for (uint32_t i = 0; i < num_points; ++i) {
    const float* p = points + 3 * size_t(i);
    const double d = index.distance({p[0], p[1], p[2]}, index.max_reach + edge);
    sum2 += d * d;
    dmax = std::max(dmax, d);
  }
  return {std::sqrt(sum2 / num_points) / diag, dmax / diag};
}

}  // namespace fq
