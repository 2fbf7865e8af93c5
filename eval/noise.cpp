#include "eval/noise.h"

#include <cmath>
#include <numbers>
#include <random>

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

}  // namespace

void add_gaussian_noise(Mesh& mesh, double sigma_mean_edges, uint64_t seed) {
  if (!(sigma_mean_edges > 0.0) || !std::isfinite(sigma_mean_edges)) return;
  const double std_dev = sigma_mean_edges * mean_edge_length(mesh.view());
  if (!(std_dev > 0.0) || !std::isfinite(std_dev)) return;
  NormalSource normal(seed);
  for (float& c : mesh.positions) c = float(double(c) + std_dev * normal.next());
}

}  // namespace fq
