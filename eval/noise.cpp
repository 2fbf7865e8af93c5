#include "eval/noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <string_view>
#include <utility>
#include <vector>

#include "common/pair_table.h"
#include "eval/error_metrics.h"
#include "kernels/frame_prep.h"
#include "kernels/grid_build.h"

namespace fq {

namespace {

/// Standard normal draws, two per Box–Muller step; only the 64-bit engine's output is
/// used, which the standard fixes bit for bit.
class NormalSource {
 public:
  explicit NormalSource(uint64_t seed) : rng_(seed) {}

  double next() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    // u1 in (0, 1] so that log(u1) is finite; u2 in [0, 1).
    const double u1 = 1.0 - uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  /// 53 random bits into [0, 1), exactly representable.
  double uniform() { return double(rng_() >> 11) * 0x1.0p-53; }

  std::mt19937_64 rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// Noise standard deviation in mesh units; 0 when there is nothing meaningful to add.
double noise_std(const Mesh& mesh, double sigma_mean_edges) {
  if (!(sigma_mean_edges > 0.0) || !std::isfinite(sigma_mean_edges)) return 0.0;
  const double std_dev = sigma_mean_edges * mean_edge_length(mesh.view());
  return std_dev > 0.0 && std::isfinite(std_dev) ? std_dev : 0.0;
}

double length(const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/// Moves every vertex by offsets[v] along its unit normal (not at all without one).
void move_along(Mesh& mesh, const std::vector<double>& normals, const std::vector<double>& offsets) {
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const double* nv = &normals[3 * size_t(v)];
    const double len = length(nv);
    if (!(len > 0.0)) continue;
    for (int k = 0; k < 3; ++k) {
      float& c = mesh.positions[3 * size_t(v) + k];
      c = float(double(c) + offsets[v] * nv[k] / len);
    }
  }
}

constexpr std::pair<NoiseKind, const char*> kNoiseKindNames[] = {{NoiseKind::kIso, "iso"},
                                                                 {NoiseKind::kNormal, "normal"},
                                                                 {NoiseKind::kDepth, "depth"},
                                                                 {NoiseKind::kCorrelated, "correlated"},
                                                                 {NoiseKind::kRipple, "ripple"}};

/// Depth noise grows as 1 / |cos| of the angle to the view, up to 4 × at grazing angles
/// (a scanner drops the steepest parts rather than measure them worse still).
constexpr double kGrazingFloor = 0.25;

}  // namespace

void add_normal_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed) {
  const double std_dev = noise_std(mesh, sigma_mean_edges);
  if (std_dev == 0.0) return;
  const std::vector<double> normals = area_vertex_normals(mesh.view());
  NormalSource normal(seed);
  std::vector<double> offsets(mesh.num_vertices());
  for (double& d : offsets) d = std_dev * normal.next();
  move_along(mesh, normals, offsets);
}

void add_depth_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed) {
  const double std_dev = noise_std(mesh, sigma_mean_edges);
  if (std_dev == 0.0) return;
  const std::vector<double> normals = area_vertex_normals(mesh.view());
  NormalSource normal(seed);
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const double len = length(&normals[3 * size_t(v)]), draw = normal.next();
    if (!(len > 0.0)) continue;
    const double cosine = std::fabs(normals[3 * size_t(v) + 2]) / len;
    float& z = mesh.positions[3 * size_t(v) + 2];
    z = float(double(z) + std_dev * draw / std::max(cosine, kGrazingFloor));
  }
}

void add_correlated_noise(Mesh& mesh, double sigma_mean_edges, double length_mean_edges, uint64_t seed) {
  const double std_dev = noise_std(mesh, sigma_mean_edges);
  if (std_dev == 0.0 || !(length_mean_edges > 0.0) || !std::isfinite(length_mean_edges)) return;
  const uint32_t n = mesh.num_vertices();
  // The smoothing kernel's standard deviation in mesh units: a Gaussian of std s smoothing white
  // draws gives a field correlated as exp(−d² / (4 s²)), so s = length / √2.
  const double kernel = length_mean_edges * std_dev / sigma_mean_edges / std::numbers::sqrt2;
  NormalSource normal(seed);
  std::vector<double> white(n);
  for (double& w : white) w = normal.next();
  std::vector<Vec3> points(n);
  for (uint32_t v = 0; v < n; ++v)
    points[v] = {mesh.positions[3 * size_t(v)], mesh.positions[3 * size_t(v) + 1],
                 mesh.positions[3 * size_t(v) + 2]};
  CpuGrid grid;
  build_grid(points.data(), n, float(kernel), grid);
  std::vector<Point4> sorted(n);
  for (uint32_t k = 0; k < n; ++k)
    sorted[k] = {points[grid.order[k]].x, points[grid.order[k]].y, points[grid.order[k]].z, 0.f};
  const GridView g = grid.view(sorted.data());
  const double inv2 = -0.5 / (kernel * kernel);
  std::vector<double> offsets(n);
  for (uint32_t v = 0; v < n; ++v) {
    // Σ k w / √(Σ k²): unit variance whatever the sampling around v.
    double sum = 0.0, norm2 = 0.0;
    for_each_neighbor(g, points[v], float(3.0 * std::numbers::sqrt2 * kernel),
                      [&](uint32_t j, const Point4&, Vec3, float d2) {
                        const double k = std::exp(double(d2) * inv2);
                        sum += k * white[grid.order[j]];
                        norm2 += k * k;
                      });
    offsets[v] = norm2 > 0.0 ? std_dev * sum / std::sqrt(norm2) : 0.0;
  }
  move_along(mesh, area_vertex_normals(mesh.view()), offsets);
}

void add_ripple_noise(Mesh& mesh, double sigma_mean_edges, double period_mean_edges, uint64_t seed) {
  const double std_dev = noise_std(mesh, sigma_mean_edges);
  if (std_dev == 0.0 || !(period_mean_edges > 0.0) || !std::isfinite(period_mean_edges)) return;
  const double period = period_mean_edges * std_dev / sigma_mean_edges;  // in mesh units
  std::mt19937_64 rng(seed);
  const double phase = 2.0 * std::numbers::pi * (double(rng() >> 11) * 0x1.0p-53);
  std::vector<double> offsets(mesh.num_vertices());
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v)
    offsets[v] = std_dev * std::numbers::sqrt2 *
                 std::sin(2.0 * std::numbers::pi * mesh.positions[3 * size_t(v)] / period + phase);
  move_along(mesh, area_vertex_normals(mesh.view()), offsets);
}

bool parse_noise_kind(const char* name, NoiseKind& kind) {
  const std::optional<NoiseKind> k = first_of(kNoiseKindNames, std::string_view(name));
  if (k) kind = *k;
  return k.has_value();
}

const char* noise_kind_name(NoiseKind kind) { return second_of(kNoiseKindNames, kind).value_or("?"); }

void add_noise(Mesh& mesh, NoiseKind kind, double sigma_mean_edges, double length_mean_edges, uint64_t seed) {
  switch (kind) {
    case NoiseKind::kIso:
      add_gaussian_noise(mesh, sigma_mean_edges, seed);
      break;
    case NoiseKind::kNormal:
      add_normal_noise(mesh, sigma_mean_edges, seed);
      break;
    case NoiseKind::kDepth:
      add_depth_noise(mesh, sigma_mean_edges, seed);
      break;
    case NoiseKind::kCorrelated:
      add_correlated_noise(mesh, sigma_mean_edges, length_mean_edges, seed);
      break;
    case NoiseKind::kRipple:
      add_ripple_noise(mesh, sigma_mean_edges, length_mean_edges, seed);
      break;
  }
}

void add_gaussian_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed) {
  const double std_dev = noise_std(mesh, sigma_mean_edges);
  if (std_dev == 0.0) return;
  NormalSource normal(seed);
  for (float& c : mesh.positions) c = float(double(c) + std_dev * normal.next());
}

}  // namespace fq
