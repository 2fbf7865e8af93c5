#include "kernels/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fq {

NoiseEstimate estimate_noise(const NoiseSample* samples, uint32_t count) {
  NoiseEstimate e;
  std::vector<float> a;
  a.reserve(count);
  for (uint32_t k = 0; k < count; ++k)
    if (std::isfinite(samples[k].z_v)) a.push_back(std::fabs(samples[k].z_v));
  if (a.empty()) return e;
  auto mid = a.begin() + a.size() / 2;
  std::nth_element(a.begin(), mid, a.end());
  // 1.4826 = 1 / 0.6745, the median absolute value of a standard normal.
  e.residual = 1.4826f * *mid;
  // Correlation over the pairs within 3.5 sigma: creases and corners are not the surface's detail.
  const double cut = 3.5 * e.residual;
  double zz = 0.0, zu = 0.0, w = 0.0;
  uint32_t pairs = 0;
  for (uint32_t k = 0; k < count; ++k) {
    const NoiseSample& s = samples[k];
    if (!std::isfinite(s.z_v) || !std::isfinite(s.z_u) || !std::isfinite(s.white_correlation)) continue;
    if (std::fabs(s.z_v) > cut || std::fabs(s.z_u) > cut) continue;
    zz += 0.5 * (double(s.z_v) * s.z_v + double(s.z_u) * s.z_u);
    zu += double(s.z_v) * s.z_u;
    w += s.white_correlation;
    ++pairs;
  }
  if (pairs == 0 || !(zz > 0.0)) {
    e.noise = e.residual;
    return e;
  }
  e.correlation = float(zu / zz);
  e.white = float(w / pairs);
  const float share =
      std::clamp((kDetailCorrelation - e.correlation) / (kDetailCorrelation - e.white), 0.f, 1.f);
  e.noise = e.residual * std::sqrt(share);
  return e;
}

}  // namespace fq
