#include "eval/surface_flicker.h"

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

double norm3(const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/// Scales every 3-vector of `v` to unit length in place (zero ones stay zero); returns the
/// lengths before.
std::vector<double> normalize_all(std::vector<double>& v) {
  std::vector<double> length(v.size() / 3);
  for (size_t i = 0; i < length.size(); ++i) {
    double* n = &v[3 * i];
    length[i] = norm3(n);
    for (int k = 0; k < 3; ++k) n[k] = length[i] > 0.0 ? n[k] / length[i] : 0.0;
  }
  return length;
}

/// The unit barycentric mix of triangle t's unit vertex normals (zero when they cancel).
void smooth_normal(const MeshView& mesh, const std::vector<double>& vertex_normals, uint32_t t,
                   const double weights[3], double* out) {
  const uint32_t* tri = mesh.triangles + 3 * size_t(t);
  for (int k = 0; k < 3; ++k) out[k] = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) out[k] += weights[c] * vertex_normals[3 * size_t(tri[c]) + k];
  const double len = norm3(out);
  for (int k = 0; k < 3; ++k) out[k] = len > 0.0 ? out[k] / len : 0.0;
}

/// sqrt(Σ a_i x_i / Σ a_i) over the vertices, or the plain weighted mean when `root` is false.
template <class F>
double weighted(const std::vector<double>& area, F&& x, bool root) {
  double sum = 0.0, weight = 0.0;
  for (size_t i = 0; i < area.size(); ++i) {
    if (!(area[i] > 0.0)) continue;
    sum += area[i] * x(i);
    weight += area[i];
  }
  if (!(weight > 0.0)) return kNaN;
  return root ? std::sqrt(sum / weight) : sum / weight;
}

bool comparable(const SurfaceSample& before, const SurfaceSample& now) {
  return !now.height.empty() && before.vertices() == now.vertices();
}

}  // namespace

SurfaceSample sample_surface(const MeshView& clean, const MeshView& result, int threads) {
  SurfaceSample s;
  const double edge = mean_edge_length(clean);
  if (clean.num_triangles == 0 || result.num_triangles == 0 || !(edge > 0.0)) return s;
  const uint32_t n = clean.num_vertices;
  s.mean_edge = edge;
  s.clean_normal = area_vertex_normals(clean);
  // A vertex's share of the surface: a third of each incident triangle (|cross| / 2 / 3).
  s.area.assign(n, 0.0);
  for (uint32_t t = 0; t < clean.num_triangles; ++t) {
    const std::array<double, 3> c = face_area_normal(clean.positions, clean.triangles + 3 * size_t(t));
    const double third = norm3(c.data()) / 6.0;
    for (int k = 0; k < 3; ++k) s.area[clean.triangles[3 * size_t(t) + k]] += third;
  }
  const std::vector<double> clean_length = normalize_all(s.clean_normal);
  std::vector<double> result_normals = area_vertex_normals(result);
  normalize_all(result_normals);
  s.height.assign(n, 0.0);
  s.result_normal.assign(3 * size_t(n), 0.0);
  s.hit.assign(n, 0);
  const TriangleIndex index(result, 2.0 * edge);
  const double reach = kSampleReach * edge;
  parallel_for(n, threads_or_all(threads), [&](uint32_t v) {
    if (!(clean_length[v] > 0.0)) {
      s.area[v] = 0.0;  // no normal to sample along: the vertex does not count
      return;
    }
    const float* p = clean.positions + 3 * size_t(v);
    const double* nc = &s.clean_normal[3 * size_t(v)];
    const Point3d c{p[0], p[1], p[2]}, dir{nc[0], nc[1], nc[2]};
    const LineHit h = index.nearest_line_hit(c, dir, reach);
    double offset = 0.0;
    uint32_t triangle = h.triangle;
    double weights[3] = {h.weights[0], h.weights[1], h.weights[2]};
    if (triangle != UINT32_MAX) {
      offset = h.s;
      s.hit[v] = 1;
    } else {
      // The line misses (a hole, a boundary, a fold beyond reach): the closest point of the
      // result, and how far along n_c it lies.
      const ClosestPoint q = index.closest(c, index.max_reach() + edge);
      triangle = q.triangle;
      offset = (q.point.x - c.x) * dir.x + (q.point.y - c.y) * dir.y + (q.point.z - c.z) * dir.z;
      index.barycentric(triangle, q.point, weights);
    }
    s.height[v] = offset / edge;
    smooth_normal(result, result_normals, triangle, weights, &s.result_normal[3 * size_t(v)]);
  });
  return s;
}

double height_rms(const SurfaceSample& s) {
  return weighted(
      s.area, [&](size_t i) { return s.height[i] * s.height[i]; }, true);
}

double smooth_normal_error(const SurfaceSample& s) {
  return weighted(
      s.area,
      [&](size_t i) {
        const double* a = &s.result_normal[3 * i];
        const double* b = &s.clean_normal[3 * i];
        const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        // atan2 keeps the digits of small angles that acos of the dot product loses.
        return std::atan2(norm3(c), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
      },
      false);
}

double surface_flicker(const SurfaceSample& before, const SurfaceSample& now) {
  if (!comparable(before, now)) return kNaN;
  return weighted(
      now.area,
      [&](size_t i) {
        const double d = now.height[i] - before.height[i];
        return d * d;
      },
      true);
}

double shading_flicker(const SurfaceSample& before, const SurfaceSample& now) {
  if (!comparable(before, now)) return kNaN;
  return weighted(
      now.area,
      [&](size_t i) {
        double sum = 0.0;
        for (size_t k = 3 * i; k < 3 * i + 3; ++k) {
          const double d = (now.result_normal[k] - before.result_normal[k]) -
                           (now.clean_normal[k] - before.clean_normal[k]);
          sum += d * d;
        }
        return sum;
      },
      true);
}

SurfaceFrameMetrics SurfaceFlickerSeries::add(SurfaceSample sample) {
  SurfaceFrameMetrics m;
  m.height_rms = height_rms(sample);
  m.smooth_normal_error = smooth_normal_error(sample);
  height_rms_.push_back(m.height_rms);
  normal_error_.push_back(m.smooth_normal_error);
  if (before_ && comparable(*before_, sample)) {
    m.surface_flicker = surface_flicker(*before_, sample);
    m.shading_flicker = shading_flicker(*before_, sample);
    surface_flicker_.push_back(*m.surface_flicker);
    shading_flicker_.push_back(*m.shading_flicker);
  }
  before_ = std::move(sample);
  return m;
}

double SurfaceFlickerSeries::mean(const std::vector<double>& x) {
  double sum = 0.0;
  size_t count = 0;
  for (double v : x) {
    if (!std::isfinite(v)) continue;
    sum += v;
    ++count;
  }
  return count ? sum / double(count) : kNaN;
}

}  // namespace fq
