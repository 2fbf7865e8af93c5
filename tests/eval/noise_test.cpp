// Gaussian noise: amplitude in mean edge lengths, Gaussian statistics, seed determinism.
#include "eval/noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/frame_prep.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

struct Stats {
  double mean = 0, std = 0, within_one_std = 0;
};

Stats displacement_stats(const std::vector<float>& before, const std::vector<float>& after) {
  Stats s;
  const size_t n = before.size();
  for (size_t i = 0; i < n; ++i) s.mean += double(after[i]) - before[i];
  s.mean /= n;
  for (size_t i = 0; i < n; ++i) {
    const double d = double(after[i]) - before[i] - s.mean;
    s.std += d * d;
  }
  s.std = std::sqrt(s.std / (n - 1));
  for (size_t i = 0; i < n; ++i) s.within_one_std += std::abs(double(after[i]) - before[i]) <= s.std;
  s.within_one_std /= n;
  return s;
}

TEST(Noise, NormalNoiseMovesAPlaneOnlyAlongItsNormal) {
  const Mesh clean = test::make_plane_grid(100, 100, 0.01f);
  const double edge = mean_edge_length(clean.view());
  Mesh noisy = clean;
  add_normal_noise(noisy, 0.3, 42);
  std::vector<float> z0, z1;
  for (uint32_t v = 0; v < clean.num_vertices(); ++v) {
    EXPECT_EQ(noisy.positions[3 * v], clean.positions[3 * v]);
    EXPECT_EQ(noisy.positions[3 * v + 1], clean.positions[3 * v + 1]);
    z0.push_back(clean.positions[3 * v + 2]);
    z1.push_back(noisy.positions[3 * v + 2]);
  }
  const Stats s = displacement_stats(z0, z1);
  EXPECT_NEAR(s.std / edge, 0.3, 0.01);
  EXPECT_NEAR(s.within_one_std, 0.6827, 0.015);
  Mesh again = clean;
  add_normal_noise(again, 0.3, 42);
  EXPECT_EQ(again.positions, noisy.positions);
}

TEST(Noise, StandardDeviationIsSigmaTimesMeanEdge) {
  const Mesh clean = test::make_plane_grid(100, 100, 0.01f);  // 30,603 coordinates
  const double edge = mean_edge_length(clean.view());
  for (double sigma : {0.1, 0.5}) {
    Mesh noisy = clean;
    add_gaussian_noise(noisy, sigma, 42);
    const Stats s = displacement_stats(clean.positions, noisy.positions);
    // Standard errors: of the mean sigma*l/sqrt(n) ~ 0.6%, of the std ~ 0.4%.
    EXPECT_NEAR(s.std, sigma * edge, 0.03 * sigma * edge) << sigma;
    EXPECT_NEAR(s.mean, 0.0, 0.03 * sigma * edge) << sigma;
    EXPECT_NEAR(s.within_one_std, 0.6827, 0.015) << "not Gaussian-shaped";
  }
}

TEST(Noise, IsIsotropicPerAxis) {
  const Mesh clean = test::make_icosphere(4, 1.0f);  // 2,562 vertices
  Mesh noisy = clean;
  add_gaussian_noise(noisy, 0.2, 3);
  const double target = 0.2 * mean_edge_length(clean.view());
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> a, b;
    for (uint32_t v = 0; v < clean.num_vertices(); ++v) {
      a.push_back(clean.positions[3 * v + axis]);
      b.push_back(noisy.positions[3 * v + axis]);
    }
    EXPECT_NEAR(displacement_stats(a, b).std, target, 0.06 * target) << "axis " << axis;
  }
}

TEST(Noise, SameSeedSameMeshOtherSeedOtherMesh) {
  const Mesh clean = test::make_icosphere(2, 1.0f);
  Mesh a = clean, b = clean, c = clean;
  add_gaussian_noise(a, 0.3, 7);
  add_gaussian_noise(b, 0.3, 7);
  add_gaussian_noise(c, 0.3, 8);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_NE(a.positions, c.positions);
  EXPECT_NE(a.positions, clean.positions);
  EXPECT_EQ(a.triangles, clean.triangles);
}

TEST(Noise, DrawsArePinned) {
  // mt19937_64 is fully specified and Box-Muller is ours, so these values hold with any
  // standard library (up to libm rounding in log/sin/cos, hence the tolerance).
  Mesh m = test::make_single_triangle();
  const std::vector<float> before = m.positions;
  const double edge = mean_edge_length(m.view());
  add_gaussian_noise(m, 1.0, 12345);
  const double expected[3] = {-0.7626909, 0.5508932, -1.4227289};
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR((double(m.positions[i]) - before[i]) / edge, expected[i], 1e-5) << i;
}

TEST(Noise, ZeroOrInvalidSigmaLeavesTheMeshAlone) {
  const Mesh clean = test::make_icosphere(1, 1.0f);
  for (double sigma : {0.0, -1.0, std::nan("")}) {
    Mesh m = clean;
    add_gaussian_noise(m, sigma, 1);
    EXPECT_EQ(m.positions, clean.positions) << sigma;
  }
  Mesh no_faces;
  no_faces.positions = {1, 2, 3};
  add_gaussian_noise(no_faces, 1.0, 1);  // no edge, no amplitude
  EXPECT_EQ(no_faces.positions, (std::vector<float>{1, 2, 3}));
}

}  // namespace
}  // namespace fq
