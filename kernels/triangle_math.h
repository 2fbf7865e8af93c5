// Per-triangle geometry and its contribution to per-vertex base quadrics (paper eq. 1).
#pragma once

#include <cmath>

#include "common/hd.h"
#include "kernels/quadric.h"
#include "kernels/vec3.h"

namespace fq {

struct TriangleGeom {
  Vec3 normal;  ///< unit normal, zero for a degenerate triangle
  Vec3 centroid;
  float area;  ///< zero for a degenerate triangle
};

FQ_HD TriangleGeom triangle_geom(Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 n2 = cross(b - a, c - a);  // twice the area along the normal
  const float len = std::sqrt(norm2(n2));
  TriangleGeom t;
  t.centroid = (1.0f / 3.0f) * (a + b + c);
  if (len > 1e-12f && std::isfinite(len)) {
    t.normal = (1.0f / len) * n2;
    t.area = 0.5f * len;
  } else {
    t.normal = {0.f, 0.f, 0.f};
    t.area = 0.f;
  }
  return t;
}

/// Running sums for one vertex's base quadric: sum of (a_t/3) Q_t, the weight sum a_v
/// (the vertex's barycentric area) and the area-weighted normal.
struct VertexAccum {
  Quadric q;
  float area;
  Vec3 normal;
};

FQ_HD VertexAccum zero_vertex_accum() { return {zero_quadric(), 0.f, {0.f, 0.f, 0.f}}; }

/// Adds triangle t's plane quadric, in the frame of vertex position v, with weight a_t/3.
FQ_HD void add_triangle(VertexAccum& acc, const TriangleGeom& t, Vec3 v) {
  const float w = t.area / 3.0f;
  if (!(w > 0.f)) return;
  add_scaled(acc.q, plane_quadric(t.normal, t.centroid, v), w);
  acc.area += w;
  acc.normal = acc.normal + t.area * t.normal;
}

/// The base quadric as an area-weighted average (zero when no incident area).
FQ_HD Quadric base_quadric(const VertexAccum& acc) {
  Quadric q = acc.q;
  if (acc.area > 0.f) divide(q, acc.area);
  return q;
}

}  // namespace fq
