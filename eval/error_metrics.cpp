#include "eval/error_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace fq {

namespace {

using D3 = std::array<double, 3>;

D3 load(const float* positions, uint32_t v) {
  const float* p = positions + 3 * size_t(v);
  return {p[0], p[1], p[2]};
}
D3 sub(const D3& a, const D3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
D3 cross(const D3& a, const D3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Below this |cross| / (longest edge)^2 (about twice the sine of the smallest angle) a
// triangle's normal is numerical noise from float coordinates, not a direction.
constexpr double kDegenerateRatio = 1e-9;

/// Unnormalized face normal, or false when the face is degenerate.
bool face_normal(const float* positions, const uint32_t* tri, D3& n) {
  const D3 a = load(positions, tri[0]), b = load(positions, tri[1]), c = load(positions, tri[2]);
  const D3 e0 = sub(b, a), e1 = sub(c, a), e2 = sub(c, b);
  n = cross(e0, e1);
  const double longest2 = std::max({dot(e0, e0), dot(e1, e1), dot(e2, e2)});
  const double len = std::sqrt(dot(n, n));
  return longest2 > 0.0 && std::isfinite(len) && len > kDegenerateRatio * longest2;
}

}  // namespace

Status check_same_connectivity(const MeshView& reference, const MeshView& candidate) {
  if (reference.num_vertices != candidate.num_vertices)
    return invalid_input("vertex counts differ: reference has " + std::to_string(reference.num_vertices) +
                         ", mesh has " + std::to_string(candidate.num_vertices));
  if (reference.num_triangles != candidate.num_triangles)
    return invalid_input("triangle counts differ: reference has " + std::to_string(reference.num_triangles) +
                         ", mesh has " + std::to_string(candidate.num_triangles));
  for (uint64_t i = 0; i < uint64_t(reference.num_triangles) * 3; ++i) {
    if (reference.triangles[i] != candidate.triangles[i])
      return invalid_input("connectivity differs from the reference at triangle " + std::to_string(i / 3));
  }
  return {};
}

double bbox_diagonal(const MeshView& mesh) {
  if (mesh.num_vertices == 0) return std::numeric_limits<double>::quiet_NaN();
  D3 lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    const D3 r = load(mesh.positions, v);
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], r[k]);
      hi[k] = std::max(hi[k], r[k]);
    }
  }
  const D3 ext = sub(hi, lo);
  return std::sqrt(dot(ext, ext));
}

double rmse_over_diagonal(const MeshView& reference, const float* positions) {
  const double diag = bbox_diagonal(reference);
  if (!(diag > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  double sum2 = 0.0;
  for (uint32_t v = 0; v < reference.num_vertices; ++v) {
    const D3 d = sub(load(positions, v), load(reference.positions, v));
    sum2 += dot(d, d);
  }
  return std::sqrt(sum2 / reference.num_vertices) / diag;
}

std::array<double, 3> face_area_normal(const float* positions, const uint32_t* tri) {
  const D3 a = load(positions, tri[0]);
  return cross(sub(load(positions, tri[1]), a), sub(load(positions, tri[2]), a));
}

std::vector<double> area_vertex_normals(const MeshView& mesh) {
  std::vector<double> normals(3 * size_t(mesh.num_vertices), 0.0);
  for (size_t t = 0; t < 3 * size_t(mesh.num_triangles); t += 3) {
    const uint32_t* tri = &mesh.triangles[t];
    const std::array<double, 3> c = face_area_normal(mesh.positions, tri);
    for (int corner = 0; corner < 3; ++corner)
      for (int k = 0; k < 3; ++k) normals[3 * size_t(tri[corner]) + k] += c[k];  // area-weighted
  }
  return normals;
}

double face_normal_angle(const float* pa, const uint32_t* ta, const float* pb, const uint32_t* tb) {
  D3 na, nb;
  if (!face_normal(pa, ta, na) || !face_normal(pb, tb, nb)) return std::numeric_limits<double>::quiet_NaN();
  // atan2 of |cross| and dot keeps full precision for tiny and near-pi angles, where
  // acos of a normalized dot product loses it.
  const D3 c = cross(na, nb);
  return std::atan2(std::sqrt(dot(c, c)), dot(na, nb));
}

MfneResult mean_face_normal_error(const MeshView& reference, const float* positions) {
  MfneResult r;
  double sum = 0.0;
  for (uint32_t t = 0; t < reference.num_triangles; ++t) {
    const uint32_t* tri = reference.triangles + 3 * size_t(t);
    const double angle = face_normal_angle(reference.positions, tri, positions, tri);
    if (std::isnan(angle)) {
      ++r.faces_skipped;
      continue;
    }
    sum += angle;
    ++r.faces_used;
  }
  r.mean_radians = r.faces_used ? sum / r.faces_used : std::numeric_limits<double>::quiet_NaN();
  return r;
}

}  // namespace fq
