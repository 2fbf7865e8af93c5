#include "eval/triangle_index.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/grid.h"

namespace fq {

namespace {

using P = Point3d;
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
P cross(P a, P b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

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

}  // namespace

TriangleIndex::TriangleIndex(const MeshView& m, double cell) : mesh_(m) {
  std::vector<Vec3> c(m.num_triangles);
  for (uint32_t t = 0; t < m.num_triangles; ++t) {
    const uint32_t* tri = m.triangles + 3 * size_t(t);
    const P g = (1.0 / 3.0) * (vertex(m, tri[0]) + vertex(m, tri[1]) + vertex(m, tri[2]));
    c[t] = {float(g.x), float(g.y), float(g.z)};
    for (int k = 0; k < 3; ++k)
      max_reach_ = std::max(max_reach_, std::sqrt(dot(vertex(m, tri[k]) - g, vertex(m, tri[k]) - g)));
  }
  build_grid(c.data(), m.num_triangles, float(cell), grid_);
  centroids_.resize(m.num_triangles);
  for (uint32_t k = 0; k < m.num_triangles; ++k) {
    const Vec3 v = c[grid_.order[k]];
    centroids_[k] = {v.x, v.y, v.z, 0.f};
  }
}

// The closest triangle with centroid within `radius`; distance +inf when there is none.
ClosestPoint TriangleIndex::search(P p, double radius) const {
  ClosestPoint best;
  double best2 = std::numeric_limits<double>::infinity();
  const GridView g = grid_.view(centroids_.data());
  for_each_neighbor(g, Vec3{float(p.x), float(p.y), float(p.z)}, float(radius),
                    [&](uint32_t j, const Point4&, Vec3, float) {
                      const uint32_t t = grid_.order[j];
                      const uint32_t* tri = mesh_.triangles + 3 * size_t(t);
                      const P q = closest_on_triangle(p, vertex(mesh_, tri[0]), vertex(mesh_, tri[1]),
                                                      vertex(mesh_, tri[2]));
                      const double d2 = dot(p - q, p - q);
                      // Ties go to the lower triangle index: the answer does not depend on the grid.
                      if (d2 < best2 || (d2 == best2 && t < best.triangle)) {
                        best2 = d2;
                        best.point = q;
                        best.triangle = t;
                      }
                    });
  best.distance = std::sqrt(best2);
  return best;
}

ClosestPoint TriangleIndex::closest(P p, double start_radius) const {
  if (mesh_.num_triangles == 0) return {{0.0, 0.0, 0.0}, UINT32_MAX, std::numeric_limits<double>::infinity()};
  double r = start_radius > 0.0 ? start_radius : max_reach_ + 1e-30;
  ClosestPoint best = search(p, r);
  while (!std::isfinite(best.distance)) best = search(p, r *= 2.0);  // nothing near: widen
  const double exact_r = best.distance + max_reach_;
  if (exact_r > r) best = search(p, exact_r * (1.0 + 1e-6));
  return best;
}

LineHit TriangleIndex::nearest_line_hit(P p, P dir, double max_s) const {
  LineHit best;
  if (mesh_.num_triangles == 0 || !(max_s >= 0.0)) return best;
  // A triangle the segment |s| <= max_s meets has a corner within max_s of p, so its
  // centroid lies within max_s + max_reach.
  const double radius = max_s + max_reach_;
  const GridView g = grid_.view(centroids_.data());
  // Barycentric slack: a line through a shared edge or corner meets every triangle there.
  constexpr double kEdgeSlack = 1e-12;
  for_each_neighbor(g, Vec3{float(p.x), float(p.y), float(p.z)}, float(radius * (1.0 + 1e-6)),
                    [&](uint32_t j, const Point4&, Vec3, float) {
                      const uint32_t t = grid_.order[j];
                      const uint32_t* tri = mesh_.triangles + 3 * size_t(t);
                      const P a = vertex(mesh_, tri[0]), e1 = vertex(mesh_, tri[1]) - a,
                              e2 = vertex(mesh_, tri[2]) - a;
                      // Möller–Trumbore, without the ray's s >= 0: the line goes both ways.
                      const P h = cross(dir, e2);
                      const double det = dot(e1, h);
                      if (!(std::fabs(det) > 1e-300)) return;
                      const P ap = p - a;
                      const double u = dot(ap, h) / det;
                      if (u < -kEdgeSlack || u > 1.0 + kEdgeSlack) return;
                      const P q = cross(ap, e1);
                      const double v = dot(dir, q) / det;
                      if (v < -kEdgeSlack || u + v > 1.0 + kEdgeSlack) return;
                      const double s = dot(e2, q) / det;
                      if (std::fabs(s) > max_s) return;
                      const bool closer = best.triangle == UINT32_MAX || std::fabs(s) < std::fabs(best.s) ||
                                          (std::fabs(s) == std::fabs(best.s) && t < best.triangle);
                      if (!closer) return;
                      best.triangle = t;
                      best.s = s;
                      best.point = p + s * dir;
                      best.weights[0] = 1.0 - u - v;
                      best.weights[1] = u;
                      best.weights[2] = v;
                    });
  return best;
}

void TriangleIndex::barycentric(uint32_t triangle, P q, double weights[3]) const {
  const uint32_t* tri = mesh_.triangles + 3 * size_t(triangle);
  const P a = vertex(mesh_, tri[0]), e1 = vertex(mesh_, tri[1]) - a, e2 = vertex(mesh_, tri[2]) - a,
          d = q - a;
  // Cramer's rule on the normal equations of q - a = u e1 + v e2.
  const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
  const double det = d11 * d22 - d12 * d12;
  if (!(det > 0.0)) {
    weights[0] = 1.0;
    weights[1] = weights[2] = 0.0;
    return;
  }
  const double u = (d22 * dot(d, e1) - d12 * dot(d, e2)) / det;
  const double v = (d11 * dot(d, e2) - d12 * dot(d, e1)) / det;
  weights[0] = 1.0 - u - v;
  weights[1] = u;
  weights[2] = v;
}

}  // namespace fq
