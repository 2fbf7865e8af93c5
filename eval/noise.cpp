#include "eval/noise.h"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "kernels/frame_prep.h"

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

}  // namespace

void add_normal_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed) {
  const double std_dev = noise_std(mesh, sigma_mean_edges);
  if (std_dev == 0.0) return;
  const uint32_t n = mesh.num_vertices();
  std::vector<double> normals(3 * size_t(n), 0.0);
  const float* p = mesh.positions.data();
  for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const uint32_t* tri = &mesh.triangles[t];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = double(p[3 * size_t(tri[1]) + k]) - p[3 * size_t(tri[0]) + k];
      e2[k] = double(p[3 * size_t(tri[2]) + k]) - p[3 * size_t(tri[0]) + k];
    }
    const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (int corner = 0; corner < 3; ++corner)
      for (int k = 0; k < 3; ++k) normals[3 * size_t(tri[corner]) + k] += c[k];  // area-weighted
  }
  NormalSource normal(seed);
  for (uint32_t v = 0; v < n; ++v) {
    const double* nv = &normals[3 * size_t(v)];
    const double len = std::sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
    const double d = std_dev * normal.next();
    if (!(len > 0.0)) continue;
    for (int k = 0; k < 3; ++k) {
      float& c = mesh.positions[3 * size_t(v) + k];
      c = float(double(c) + d * nv[k] / len);
    }
  }
}

void add_gaussian_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed) {
  const double std_dev = noise_std(mesh, sigma_mean_edges);
  if (std_dev == 0.0) return;
  NormalSource normal(seed);
  for (float& c : mesh.positions) c = float(double(c) + std_dev * normal.next());
}

}  // namespace fq
