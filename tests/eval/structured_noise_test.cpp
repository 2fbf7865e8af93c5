// The structured noise families (depth, correlated, ripple): amplitude, direction and
// correlation as documented in eval/noise.h, on planes where each is known by construction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "eval/noise.h"
#include "kernels/frame_prep.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::make_plane_grid;

// Offsets along z of a plane z = 0 after the noise, in mean edges; x and y must not move.
std::vector<double> z_offsets(const Mesh& before, const Mesh& after) {
  const double edge = mean_edge_length(before.view());
  std::vector<double> dz;
  for (uint32_t v = 0; v < before.num_vertices(); ++v) {
    EXPECT_EQ(after.positions[3 * size_t(v)], before.positions[3 * size_t(v)]);
    EXPECT_EQ(after.positions[3 * size_t(v) + 1], before.positions[3 * size_t(v) + 1]);
    dz.push_back((double(after.positions[3 * size_t(v) + 2]) - before.positions[3 * size_t(v) + 2]) / edge);
  }
  return dz;
}

double rms(const std::vector<double>& x) {
  double s = 0;
  for (double v : x) s += v * v;
  return std::sqrt(s / x.size());
}

// Correlation of the offsets of grid neighbours one step apart along x.
double neighbour_correlation(const std::vector<double>& dz, int nx, int ny) {
  double xy = 0, xx = 0;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double a = dz[size_t(j) * (nx + 1) + i], b = dz[size_t(j) * (nx + 1) + i + 1];
      xy += a * b;
      xx += 0.5 * (a * a + b * b);
    }
  return xy / xx;
}

TEST(StructuredNoise, DepthNoiseIsSigmaFacingTheScannerAndFourTimesAtGrazing) {
  const Mesh plane = make_plane_grid(80, 80);
  Mesh noisy = plane;
  add_depth_noise(noisy, 0.1, 3);
  EXPECT_NEAR(rms(z_offsets(plane, noisy)), 0.1, 0.005);
  // The same plane standing up (normal along x): the scanner sees it edge on, and the depth
  // noise along z is at the grazing floor's 4 × sigma, still along z only.
  Mesh wall = plane;
  for (uint32_t v = 0; v < wall.num_vertices(); ++v)
    std::swap(wall.positions[3 * size_t(v)], wall.positions[3 * size_t(v) + 2]);
  Mesh noisy_wall = wall;
  add_depth_noise(noisy_wall, 0.1, 3);
  const double edge = mean_edge_length(wall.view());
  double s = 0;
  for (uint32_t v = 0; v < wall.num_vertices(); ++v) {
    EXPECT_EQ(noisy_wall.positions[3 * size_t(v)], wall.positions[3 * size_t(v)]);
    const double d =
        (double(noisy_wall.positions[3 * size_t(v) + 2]) - wall.positions[3 * size_t(v) + 2]) / edge;
    s += d * d;
  }
  EXPECT_NEAR(std::sqrt(s / wall.num_vertices()), 0.4, 0.02);
}

TEST(StructuredNoise, CorrelatedNoiseKeepsSigmaAndCorrelatesOverItsLength) {
  const int n = 80;
  const Mesh plane = make_plane_grid(n, n);
  Mesh white = plane, short_range = plane, long_range = plane;
  add_normal_noise(white, 0.1, 5);
  add_correlated_noise(short_range, 0.1, 1.0, 5);
  add_correlated_noise(long_range, 0.1, 3.0, 5);
  const std::vector<double> w = z_offsets(plane, white), a = z_offsets(plane, short_range),
                            b = z_offsets(plane, long_range);
  // Every vertex has standard deviation sigma; a field correlated over 3 edges has few
  // independent values on an 80-edge plane, so its sample RMS is looser.
  EXPECT_NEAR(rms(a), 0.1, 0.01);
  EXPECT_NEAR(rms(b), 0.1, 0.03);
  // Correlation length L: exp(−d² / (2 L²)) one grid step apart, d = 3 / (2 + √2) = 0.879 mean
  // edges (the plane's mean edge is (2 + √2) / 3 of its step): 0.68 at L = 1, 0.96 at L = 3.
  EXPECT_LT(std::fabs(neighbour_correlation(w, n, n)), 0.05);
  EXPECT_NEAR(neighbour_correlation(a, n, n), 0.68, 0.06);
  EXPECT_GT(neighbour_correlation(b, n, n), 0.93);
}

TEST(StructuredNoise, RipplesAreStripesAlongXWithRmsSigma) {
  const Mesh plane = make_plane_grid(80, 80);
  Mesh noisy = plane;
  add_ripple_noise(noisy, 0.1, 4.0, 9);
  const std::vector<double> dz = z_offsets(plane, noisy);
  EXPECT_NEAR(rms(dz), 0.1, 0.005);
  // Constant along y: each column of the grid has one offset.
  for (int j = 1; j <= 80; ++j)
    for (int i = 0; i <= 80; ++i) EXPECT_NEAR(dz[size_t(j) * 81 + i], dz[i], 1e-5);
  // Another seed shifts the stripes' phase.
  Mesh other = plane;
  add_ripple_noise(other, 0.1, 4.0, 10);
  EXPECT_NE(z_offsets(plane, other)[0], dz[0]);
}

TEST(StructuredNoise, KindsByNameAndTheOldFamiliesUnchanged) {
  const Mesh plane = make_plane_grid(20, 20);
  for (const char* name : {"iso", "normal", "depth", "correlated", "ripple"}) {
    NoiseKind k;
    ASSERT_TRUE(parse_noise_kind(name, k));
    EXPECT_STREQ(noise_kind_name(k), name);
  }
  NoiseKind k;
  EXPECT_FALSE(parse_noise_kind("gaussian", k));
  Mesh a = plane, b = plane;
  add_noise(a, NoiseKind::kNormal, 0.2, 2.0, 7);
  add_normal_noise(b, 0.2, 7);
  EXPECT_EQ(a.positions, b.positions);
  Mesh c = plane, d = plane;
  add_noise(c, NoiseKind::kIso, 0.2, 2.0, 7);
  add_gaussian_noise(d, 0.2, 7);
  EXPECT_EQ(c.positions, d.positions);
}

}  // namespace
}  // namespace fq
