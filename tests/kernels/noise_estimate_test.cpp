// The noise estimate (kernels/noise_estimate.h) on surfaces whose noise and detail are known:
// a plane's residual is its noise, white noise correlates between neighbours as the fits'
// weights predict, and smooth detail that a quadratic cannot follow is not taken for noise.
#include "kernels/noise_estimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "kernels/refine_plan.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

struct Frame {
  std::vector<Vec3> x;
  std::vector<uint32_t> tris, offsets, faces;
  FanView view() const { return {tris.data(), offsets.data(), faces.data()}; }
};

/// Where grid_frame's noise goes: along one unit direction (a range scan's line of sight; the
/// default, z, is the plane's normal) or along each axis independently.
struct NoiseAlong {
  Vec3 direction{0.f, 0.f, 1.f};
  bool every_axis = false;
};

// A mesh's positions and its vertex-to-triangle fans.
Frame frame_of(const Mesh& m) {
  Frame f;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) f.x.push_back(test::vertex(m, v));
  f.tris = m.triangles;
  f.offsets.assign(m.num_vertices() + 1, 0);
  for (uint32_t v : f.tris) ++f.offsets[v + 1];
  for (size_t i = 1; i < f.offsets.size(); ++i) f.offsets[i] += f.offsets[i - 1];
  f.faces.resize(f.tris.size());
  std::vector<uint32_t> cursor(f.offsets.begin(), f.offsets.end() - 1);
  for (uint32_t t = 0; t < m.num_triangles(); ++t)
    for (int k = 0; k < 3; ++k) f.faces[cursor[f.tris[3 * t + k]]++] = t;
  return f;
}

// A plane grid of 1-unit edges, heights from `height(x, y)` plus white noise of `sigma` units.
Frame grid_frame(int n, double sigma, double (*height)(double, double), uint32_t seed,
                 NoiseAlong along = {}) {
  const Mesh m = test::make_plane_grid(n, n, 1.f);
  Frame f = frame_of(m);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  auto draw = [&] { return float(sigma > 0 ? noise(rng) : 0.0); };
  for (Vec3& p : f.x) {
    const Vec3 on{p.x, p.y, float(height(p.x, p.y))};
    p = along.every_axis ? on + Vec3{draw(), draw(), draw()} : on + draw() * along.direction;
  }
  return f;
}

double flat(double, double) { return 0.0; }
// Bumps 8 edges across, 0.3 edges high: smooth, but no quadratic over two rings follows them.
double bumps(double x, double y) { return 0.3 * std::sin(2 * M_PI * x / 8) * std::sin(2 * M_PI * y / 8); }

NoiseEstimate estimate(const Frame& f) {
  const uint32_t n = static_cast<uint32_t>(f.x.size());
  const uint32_t stride = noise_sample_stride(n), count = noise_sample_count(n);
  std::vector<NoiseSample> s(count);
  for (uint32_t k = 0; k < count; ++k) s[k] = noise_sample(f.view(), f.x.data(), k * stride);
  return estimate_noise(s.data(), count);
}

TEST(KernelNoiseEstimate, AFlatPlanesResidualIsItsNoise) {
  EXPECT_EQ(estimate(grid_frame(60, 0.0, flat, 1)).noise, 0.f);
  for (double sigma : {0.02, 0.1, 0.3}) {
    const NoiseEstimate e = estimate(grid_frame(80, sigma, flat, 2));
    SCOPED_TRACE(sigma);
    EXPECT_NEAR(e.residual, sigma, 0.1 * sigma);
    EXPECT_NEAR(e.noise, sigma, 0.15 * sigma);
  }
}

// For white noise the neighbours' residuals correlate as the weights say (a few percent of
// sampling error over ~4000 pairs).
TEST(KernelNoiseEstimate, WhiteNoiseCorrelatesAsTheWeightsPredict) {
  const NoiseEstimate e = estimate(grid_frame(80, 0.1, flat, 3));
  EXPECT_LT(e.white, -0.1f);
  EXPECT_NEAR(e.correlation, e.white, 0.05f);
}

TEST(KernelNoiseEstimate, SmoothDetailIsNotTakenForNoise) {
  const NoiseEstimate clean = estimate(grid_frame(80, 0.0, bumps, 4));
  EXPECT_GT(clean.residual, 0.01f);                  // the quadratics cannot follow the bumps...
  EXPECT_GT(clean.correlation, kDetailCorrelation);  // ...but neighbours agree on them
  EXPECT_EQ(clean.noise, 0.f);
  const NoiseEstimate noisy = estimate(grid_frame(80, 0.1, bumps, 5));
  EXPECT_NEAR(noisy.noise, 0.1, 0.025);
  EXPECT_GT(noisy.residual, noisy.noise);
}

TEST(KernelNoiseEstimate, SamplesSpreadOverTheFrame) {
  EXPECT_EQ(noise_sample_count(0), 0u);
  EXPECT_EQ(noise_sample_count(10), 10u);
  EXPECT_EQ(noise_sample_stride(kNoiseSamples), 1u);
  EXPECT_EQ(noise_sample_stride(kNoiseSamples + 1), 2u);
  const uint32_t n = 1000003;
  EXPECT_LE(noise_sample_count(n), kNoiseSamples);
  EXPECT_LT((noise_sample_count(n) - 1) * noise_sample_stride(n), n);
}

// A vertex with too few neighbours for six coefficients gives no sample, not garbage.
TEST(KernelNoiseEstimate, TinyMeshesGiveNoSample) {
  const Frame f = grid_frame(1, 0.0, flat, 6);  // 4 vertices
  const NoiseSample s = noise_sample(f.view(), f.x.data(), 0);
  EXPECT_TRUE(std::isnan(s.z_v));
  EXPECT_EQ(estimate(f).noise, 0.f);
}

// Noise along one direction d, 37° off the plane's normal here: it moves vertices within the
// plane by 0.6 of itself, which the slides show, and along the normal by 0.8, which the fits show;
// the estimate finds d, the noise along it and the share of it along the normal.
TEST(KernelNoiseEstimate, NoiseAlongOneDirectionIsReadAlongIt) {
  const Vec3 d{0.6f, 0.f, 0.8f};
  for (double sigma : {0.05, 0.1, 0.2}) {
    SCOPED_TRACE(sigma);
    const NoiseEstimate e = estimate(grid_frame(80, sigma, flat, 7, {d}));
    EXPECT_NEAR(e.directional, sigma, 0.25 * sigma);
    EXPECT_GT(std::fabs(dot(e.direction, d)), 0.95f);
    EXPECT_NEAR(e.alignment, 0.8f, 0.05f);
    EXPECT_NEAR(e.noise, 0.8 * sigma, 0.2 * sigma);  // its part along the normal
  }
}

// Noise along the normal of a frame seen head-on is noise along one direction, the normal, with
// nothing of it within the surface; noise along every axis alike has no direction of its own (its
// slides and residuals are independent). Neither is read as sliding vertices within the surface.
TEST(KernelNoiseEstimate, NormalAndIsotropicNoiseSlideNothingAlongOneDirection) {
  for (bool every_axis : {false, true}) {
    SCOPED_TRACE(every_axis);
    for (double (*height)(double, double) : {flat, bumps}) {
      const NoiseEstimate e = estimate(grid_frame(80, 0.1, height, 8, {Vec3{0.f, 0.f, 1.f}, every_axis}));
      EXPECT_LT(tangential_noise(e), 0.02f);
      EXPECT_LE(normal_noise(e), e.noise);  // σ̂ sees all of the part along the normals
      EXPECT_GT(e.noise, 0.05f);
    }
  }
}

// A clean height field sampled on a regular grid seen from above, as a range scan samples it:
// every vertex's 1-ring mean lies straight below or above it (along the line of sight), so the
// slides share one direction. Shape alone couples them to the residuals only weakly (a pure
// sinusoid's curvature and its fits' residual both follow its height: 0.03 along z here, almost
// none of it within the surface); noise along a slanted line of sight stands far above that.
TEST(KernelNoiseEstimate, AScansSamplingAloneIsNotNoise) {
  const NoiseEstimate clean = estimate(grid_frame(80, 0.0, bumps, 9));
  EXPECT_LT(clean.directional, 0.04f);
  EXPECT_LT(tangential_noise(clean), 0.01f);
  const Vec3 slanted{0.6f, 0.f, 0.8f};
  const NoiseEstimate depth = estimate(grid_frame(80, 0.1, bumps, 11, {slanted}));
  EXPECT_NEAR(depth.directional, 0.1, 0.03);
  EXPECT_GT(tangential_noise(depth), 0.04f);
  EXPECT_GT(std::fabs(dot(depth.direction, slanted)), 0.9f);
}

// A clean cube: at its creases the quadratic cannot follow the surface, and the residuals and
// slides there both follow the creases' shape; read with every sample they covary as noise along
// the cube's diagonal would (0.04–0.07 mean edges, turned or not). Samples past the residual's
// cut do not count, and nothing is read (float rounding: under 1e-7).
TEST(KernelNoiseEstimate, ACubesCreasesAreNotNoiseAlongOneDirection) {
  for (int n : {16, 32}) {
    Frame f = frame_of(test::make_cube(n));
    EXPECT_LT(estimate(f).directional, 1e-3f) << n;
    // Turned about a generic axis: the diagonals are no longer the frame's axes.
    const float c = std::cos(0.7f), s = std::sin(0.7f);
    for (Vec3& p : f.x)
      p = Vec3{c * p.x - s * p.y, s * c * p.x + c * c * p.y - s * p.z, s * s * p.x + s * c * p.y + c * p.z};
    EXPECT_LT(estimate(f).directional, 1e-3f) << n << " turned";
  }
}

}  // namespace
}  // namespace fq
