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

/// A sample with directional terms whose fit followed the surface: |z_v| within `cut`.
bool usable(const NoiseSample& s, double cut) {
  return std::isfinite(s.height) && norm2(s.normal) > 0.f && std::fabs(s.z_v) <= cut;
}

/// Residuals beyond kResidualCut × their scale are creases, corners or detail the quadratic does
/// not follow, for the correlation of neighbours and the directional part alike.
constexpr double kResidualCut = 3.5;
/// Rounds of the directional part's cut (estimate_directional); it settles in two or three.
constexpr int kCutRounds = 4;

/// The directional part of `e` (noise_estimate.h, NoiseEstimate) from the samples whose residual
/// is within `cut`.
void directional_within(const NoiseSample* samples, uint32_t count, double cut, NoiseEstimate& e) {
  e.directional = e.alignment = 0.f;
  e.direction = Vec3{0.f, 0.f, 0.f};
  // Each sample's displacement as the fit and the slide see it, e·(n·d) n + e·(d − (n·d) n) = e·d
  // for noise along d: their spread's largest axis is d (on a flat frame the slides alone would
  // give only d's part within the plane).
  OuterSum spread;
  uint32_t used = 0;
  for (uint32_t k = 0; k < count; ++k)
    if (usable(samples[k], cut)) {
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
    if (!usable(s, cut)) continue;
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

/// The directional part of `e`, from the samples whose fit followed the surface. At a crease or a
/// corner the quadratic does not, and its residual and the slide there both follow the crease's
/// shape, not noise: on a clean cube (creases, a regular triangulation) they covary as noise along
/// its diagonal would, 0.04–0.07 mean edges read with every sample. The cut is kResidualCut × the
/// noise the residuals hold: at first the residual's scale, then with the directional noise's part
/// along the normals, √(residual² + (σ_d ρ)²), until it settles. The residual's scale alone would
/// trim the tails that noise along one direction gives the residuals (the raw scan bun000 read
/// 0.089 with it, 0.108 settled, 0.115 with every sample), while a clean cube, whose residual is 0,
/// keeps no sample and reads nothing.
void estimate_directional(const NoiseSample* samples, uint32_t count, NoiseEstimate& e) {
  double cut = kResidualCut * e.residual;
  for (int round = 0; round < kCutRounds; ++round) {
    directional_within(samples, count, cut, e);
    const double along_normals = double(e.directional) * e.alignment;
    const double wider =
        kResidualCut * std::sqrt(double(e.residual) * e.residual + along_normals * along_normals);
    if (!(wider > 1.01 * cut)) break;
    cut = wider;
  }
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
  const double cut = kResidualCut * e.residual;
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
