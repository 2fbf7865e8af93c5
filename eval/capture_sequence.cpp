#include "eval/capture_sequence.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

#include "eval/noise.h"

namespace fq {

Mesh capture_frame(const Mesh& clean, double degrees, double noise_sigma, uint64_t seed) {
  const uint32_t n = clean.num_vertices();
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (uint32_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(clean.positions[3 * v + k]));
      hi[k] = std::max(hi[k], double(clean.positions[3 * v + k]));
    }
  const double cx = 0.5 * (lo[0] + hi[0]), cz = 0.5 * (lo[2] + hi[2]);
  const double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
  Mesh turned = clean;
  for (uint32_t v = 0; v < n; ++v) {
    const double x = clean.positions[3 * v] - cx, z = clean.positions[3 * v + 2] - cz;
    turned.positions[3 * v] = float(cx + c * x + s * z);
    turned.positions[3 * v + 2] = float(cz - s * x + c * z);
  }
  add_gaussian_noise(turned, noise_sigma, seed);
  std::vector<uint32_t> source_of(n), new_id(n);
  std::iota(source_of.begin(), source_of.end(), 0u);
  std::shuffle(source_of.begin(), source_of.end(), std::mt19937_64(seed ^ 0x9e3779b97f4a7c15ull));
  Mesh out;
  out.positions.resize(3 * size_t(n));
  for (uint32_t v = 0; v < n; ++v) {
    new_id[source_of[v]] = v;
    std::copy_n(&turned.positions[3 * size_t(source_of[v])], 3, &out.positions[3 * size_t(v)]);
  }
  out.triangles.resize(clean.triangles.size());
  for (size_t i = 0; i < clean.triangles.size(); ++i) out.triangles[i] = new_id[clean.triangles[i]];
  return out;
}

}  // namespace fq
