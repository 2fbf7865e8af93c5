#include "eval/sharp_edge_recall.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace fq {

namespace {

using D3 = std::array<double, 3>;

D3 at(const MeshView& m, uint32_t v) {
  const float* p = m.positions + 3 * size_t(v);
  return {p[0], p[1], p[2]};
}
D3 sub(const D3& a, const D3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Unit normal of triangle t; zero for a degenerate one.
D3 unit_normal(const MeshView& m, uint32_t t) {
  const uint32_t* tri = m.triangles + 3 * size_t(t);
  const D3 a = at(m, tri[0]), e0 = sub(at(m, tri[1]), a), e1 = sub(at(m, tri[2]), a);
  const D3 n = {e0[1] * e1[2] - e0[2] * e1[1], e0[2] * e1[0] - e0[0] * e1[2], e0[0] * e1[1] - e0[1] * e1[0]};
  const double len = std::sqrt(dot(n, n));
  if (!(len > 0.0) || !std::isfinite(len)) return {0, 0, 0};
  return {n[0] / len, n[1] / len, n[2] / len};
}

/// One side of an edge: the triangle and its vertex opposite the edge.
struct HalfEdge {
  uint64_t key;  ///< (min endpoint, max endpoint)
  uint32_t tri;
  uint32_t opposite;
};

std::vector<HalfEdge> sorted_half_edges(const MeshView& m) {
  std::vector<HalfEdge> h;
  h.reserve(3 * size_t(m.num_triangles));
  for (uint32_t t = 0; t < m.num_triangles; ++t) {
    const uint32_t* v = m.triangles + 3 * size_t(t);
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = v[k], b = v[(k + 1) % 3];
      h.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), t, v[(k + 2) % 3]});
    }
  }
  std::sort(h.begin(), h.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.tri < y.tri;
  });
  return h;
}

}  // namespace

SharpEdgeRecall sharp_edge_recall(const MeshView& clean, const uint32_t* labels, double min_angle_deg) {
  SharpEdgeRecall r;
  const double cos_max = std::cos(min_angle_deg * std::numbers::pi / 180.0);
  const std::vector<HalfEdge> h = sorted_half_edges(clean);
  for (size_t i = 0; i < h.size();) {
    size_t j = i;
    while (j < h.size() && h[j].key == h[i].key) ++j;
    if (j - i == 2) {  // boundary and non-manifold edges have no dihedral angle
      const D3 n0 = unit_normal(clean, h[i].tri), n1 = unit_normal(clean, h[i + 1].tri);
      const bool both = dot(n0, n0) > 0.5 && dot(n1, n1) > 0.5;
      if (both && dot(n0, n1) < cos_max) {
        const D3 e = sub(at(clean, uint32_t(h[i].key >> 32)), at(clean, uint32_t(h[i].key & 0xffffffffu)));
        const double len = std::sqrt(dot(e, e));
        ++r.sharp_edges;
        r.sharp_length += len;
        if (labels[h[i].opposite] != labels[h[i + 1].opposite]) {
          ++r.separated_edges;
          r.separated_length += len;
        }
      }
    }
    i = j;
  }
  r.recall =
      r.sharp_length > 0.0 ? r.separated_length / r.sharp_length : std::numeric_limits<double>::quiet_NaN();
  return r;
}

}  // namespace fq
