#include "eval/scan_error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "core/parallel_for.h"
#include "eval/error_metrics.h"
#include "eval/triangle_index.h"
#include "kernels/frame_prep.h"

namespace fq {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Point3d centroid(const float* positions, const uint32_t* tri) {
  Point3d c{0.0, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) {
    const float* p = positions + 3 * size_t(tri[k]);
    c.x += p[0] / 3.0;
    c.y += p[1] / 3.0;
    c.z += p[2] / 3.0;
  }
  return c;
}

/// 1 for each vertex on an edge that only one triangle has.
std::vector<uint8_t> boundary_vertices(const MeshView& m) {
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  edges.reserve(3 * size_t(m.num_triangles));
  for (uint32_t t = 0; t < m.num_triangles; ++t) {
    const uint32_t* tri = m.triangles + 3 * size_t(t);
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::minmax(tri[k], tri[(k + 1) % 3]));
  }
  std::sort(edges.begin(), edges.end());
  std::vector<uint8_t> boundary(m.num_vertices, 0);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) boundary[edges[i].first] = boundary[edges[i].second] = 1;
    i = j;
  }
  return boundary;
}

/// Each scan face's area-weighted normal (its cross product) summed per nearest reference
/// triangle, over the faces measured (angle not NaN); the mean angle between the sums and the
/// reference normals where at least kCoarseFaces faces fell (fewer: an edge of the overlap).
double coarse_normal_error(const MeshView& reference, const MeshView& scan, const float* positions,
                           const std::vector<double>& angle, const std::vector<uint32_t>& nearest,
                           bool flipped, uint32_t& used) {
  constexpr uint32_t kCoarseFaces = 3;
  std::vector<std::array<double, 3>> sums(reference.num_triangles, {0.0, 0.0, 0.0});
  std::vector<uint32_t> counts(reference.num_triangles, 0);
  for (uint32_t t = 0; t < scan.num_triangles; ++t) {
    if (std::isnan(angle[t])) continue;
    const uint32_t* tri = scan.triangles + 3 * size_t(t);
    const std::array<double, 3> n = face_area_normal(positions, tri);
    for (int k = 0; k < 3; ++k) sums[nearest[t]][k] += flipped ? -n[k] : n[k];
    ++counts[nearest[t]];
  }
  double sum = 0.0;
  used = 0;
  for (uint32_t r = 0; r < reference.num_triangles; ++r) {
    if (counts[r] < kCoarseFaces) continue;
    const std::array<double, 3> n =
        face_area_normal(reference.positions, reference.triangles + 3 * size_t(r));
    const std::array<double, 3>& s = sums[r];
    const std::array<double, 3> c = {s[1] * n[2] - s[2] * n[1], s[2] * n[0] - s[0] * n[2],
                                     s[0] * n[1] - s[1] * n[0]};
    sum += std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                      s[0] * n[0] + s[1] * n[1] + s[2] * n[2]);
    ++used;
  }
  return used ? sum / used : kNaN;
}

}  // namespace

std::vector<uint8_t> faces_over_reference(const MeshView& reference, const MeshView& scan) {
  std::vector<uint8_t> over(scan.num_triangles, 0);
  const double edge = mean_edge_length(scan), ref_edge = mean_edge_length(reference);
  if (reference.num_triangles == 0 || !(edge > 0.0) || !(ref_edge > 0.0)) return over;
  const std::vector<uint8_t> boundary = boundary_vertices(reference);
  const TriangleIndex index(reference, 2.0 * ref_edge);
  parallel_for(scan.num_triangles, 0, [&](uint32_t t) {
    const ClosestPoint c =
        index.closest(centroid(scan.positions, scan.triangles + 3 * size_t(t)), index.max_reach() + ref_edge);
    const uint32_t* rt = reference.triangles + 3 * size_t(c.triangle);
    over[t] =
        c.distance <= kOverReferenceEdges * edge && !boundary[rt[0]] && !boundary[rt[1]] && !boundary[rt[2]];
  });
  return over;
}

ScanError scan_error(const MeshView& reference, const MeshView& scan, const float* positions,
                     const uint8_t* counted, double unit) {
  ScanError e;
  e.normal_error = e.distance = e.normal_error_coarse = kNaN;
  if (!positions) positions = scan.positions;
  const double ref_edge = mean_edge_length(reference);
  if (reference.num_triangles == 0 || !(ref_edge > 0.0) || !(unit > 0.0)) return e;
  const TriangleIndex index(reference, 2.0 * ref_edge);
  std::vector<double> angle(scan.num_triangles, kNaN), dist(scan.num_triangles, kNaN);
  std::vector<uint32_t> nearest(scan.num_triangles, UINT32_MAX);
  parallel_for(scan.num_triangles, 0, [&](uint32_t t) {
    if (counted && !counted[t]) return;
    const uint32_t* tri = scan.triangles + 3 * size_t(t);
    const ClosestPoint c = index.closest(centroid(positions, tri), index.max_reach() + ref_edge);
    angle[t] =
        face_normal_angle(positions, tri, reference.positions, reference.triangles + 3 * size_t(c.triangle));
    dist[t] = c.distance;
    nearest[t] = c.triangle;
  });
  // In triangle order, so that the sums do not depend on the thread count.
  double sum = 0.0, sum2 = 0.0;
  int64_t facing = 0;
  for (uint32_t t = 0; t < scan.num_triangles; ++t) {
    if (std::isnan(angle[t])) continue;
    sum += angle[t];
    sum2 += dist[t] * dist[t];
    facing += angle[t] < 0.5 * M_PI ? 1 : -1;
    ++e.faces_used;
  }
  if (e.faces_used == 0) return e;
  e.flipped = facing < 0;
  // Σ (π − a) = n π − Σ a.
  e.normal_error = (e.flipped ? e.faces_used * M_PI - sum : sum) / e.faces_used;
  e.distance = std::sqrt(sum2 / e.faces_used) / unit;
  e.normal_error_coarse =
      coarse_normal_error(reference, scan, positions, angle, nearest, e.flipped, e.reference_faces_used);
  return e;
}

}  // namespace fq
