#include "kernels/noise_estimate.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/refine_math.h"
#include "kernels/sym3_eigen.h"

namespace fq {

namespace {

/// Added to the mean weight E[(1 − (n·d)²) |n·d|] (at most 0.385; a range scan's 0.3–0.35).
constexpr double kWeightFloor = 0.01;

bool usable(const NoiseSample& s) { return std::isfinite(s.height) && norm2(s.normal) > 0.f; }

/// The directional part of `e` (noise_estimate.h, NoiseEstimate). Every fitted sample counts:
/// unlike the correlation of neighbours, which creases and corners would read as detail, a
/// crease's large residual has no relation to the slide along one direction shared by the whole
/// frame; it only widens the covariance's sampling error, which the significance margin holds.
void estimate_directional(const NoiseSample* samples, uint32_t count, NoiseEstimate& e) {
  // Each sample's displacement as the fit and the slide see it, e·(n·d) n + e·(d − (n·d) n) = e·d
  // for noise along d: their spread's largest axis is d (on a flat frame the slides alone would
  // give only d's part within the plane).
  OuterSum spread;
  uint32_t used = 0;
  for (uint32_t k = 0; k < count; ++k)
    if (usable(samples[k])) {
      spread.add(samples[k].height * samples[k].normal - samples[k].slide, 1.f);
      ++used;
    }
  if (used < 2) return;
  const Sym3Eigen eig = spread.eigen();
  int top = 0;
  for (int k = 1; k < 3; ++k)
    if (eig.values[k] > eig.values[top]) top = k;
  const Vec3 d{eig.vectors[0][top], eig.vectors[1][top], eig.vectors[2][top]};
  if (!(norm2(d) > 0.f)) return;
  e.direction = (1.0f / std::sqrt(norm2(d))) * d;
  // Covariance terms c_k = −(slide·d) sign(n·d) e_v, and their weights (1 − (n·d)²) |n·d|.
  double sum = 0.0, sum2 = 0.0, weight = 0.0, aligned = 0.0;
  for (uint32_t k = 0; k < count; ++k) {
    const NoiseSample& s = samples[k];
    if (!usable(s)) continue;
    const double nd = dot(s.normal, e.direction);
    const double c = -double(dot(s.slide, e.direction)) * (nd < 0.0 ? -1.0 : 1.0) * s.height;
    sum += c;
    sum2 += c * c;
    weight += (1.0 - nd * nd) * std::fabs(nd);
    aligned += nd * nd;
  }
  const double mean = sum / used, spread_of_mean = std::sqrt(std::max(0.0, sum2 / used - mean * mean) / used);
  e.alignment = float(std::sqrt(aligned / used));
  // A direction the frame is seen edge-on from (n·d ≈ 0 everywhere) puts no directional noise
  // along the normals and the covariance says nothing: kWeightFloor keeps the ratio bounded there.
  const double w = weight / used + kWeightFloor;
  // Only the part of the covariance beyond kDirectionalSignificance standard errors counts.
  const double kept = std::max(0.0, mean - kDirectionalSignificance * spread_of_mean);
  e.directional = float(std::sqrt(kept / w));
}

}  // namespace

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
  estimate_directional(samples, count, e);
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
