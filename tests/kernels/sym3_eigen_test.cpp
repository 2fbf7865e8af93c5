// Jacobi eigen-decomposition (kernels/sym3_eigen.h) on random symmetric matrices and on
// the degenerate spectra that quadrics produce (rank 1, rank 2, repeated eigenvalues).
#include "kernels/sym3_eigen.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

namespace fq {
namespace {

using Mat3 = std::array<std::array<float, 3>, 3>;

float frobenius(const Mat3& a) {
  float s = 0.f;
  for (const auto& row : a)
    for (float x : row) s += x * x;
  return std::sqrt(s);
}

// A v_k = lambda_k v_k, V orthonormal, V diag(lambda) V^T = A, sum lambda = trace.
void expect_decomposes(const Mat3& a) {
  const Sym3Eigen e = sym3_eigen(a[0][0], a[0][1], a[0][2], a[1][1], a[1][2], a[2][2]);
  const float scale = std::max(frobenius(a), 1e-20f);
  for (int k = 0; k < 3; ++k) {
    for (int r = 0; r < 3; ++r) {
      float av = 0.f;
      for (int c = 0; c < 3; ++c) av += a[r][c] * e.vectors[c][k];
      EXPECT_NEAR(av, e.values[k] * e.vectors[r][k], 2e-6f * scale) << "k=" << k << " r=" << r;
    }
    for (int l = 0; l < 3; ++l) {
      float d = 0.f;
      for (int r = 0; r < 3; ++r) d += e.vectors[r][k] * e.vectors[r][l];
      EXPECT_NEAR(d, k == l ? 1.f : 0.f, 2e-6f);
    }
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      float m = 0.f;
      for (int k = 0; k < 3; ++k) m += e.vectors[r][k] * e.values[k] * e.vectors[c][k];
      EXPECT_NEAR(m, a[r][c], 2e-6f * scale);
    }
  }
  EXPECT_NEAR(e.values[0] + e.values[1] + e.values[2], a[0][0] + a[1][1] + a[2][2], 2e-6f * scale);
}

Mat3 outer_sum(std::initializer_list<std::array<float, 3>> vs) {
  Mat3 a{};
  for (const auto& v : vs)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[r][c] += v[r] * v[c];
  return a;
}

TEST(KernelSym3Eigen, RandomSymmetricPositiveDefinite) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int k = 0; k < 500; ++k) {
    Mat3 m;
    for (auto& row : m)
      for (float& x : row) x = u(rng);
    Mat3 a{};  // M M^T + 0.01 I
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        for (int j = 0; j < 3; ++j) a[r][c] += m[r][j] * m[c][j];
        if (r == c) a[r][c] += 0.01f;
      }
    SCOPED_TRACE(k);
    expect_decomposes(a);
    const Sym3Eigen e = sym3_eigen(a[0][0], a[0][1], a[0][2], a[1][1], a[1][2], a[2][2]);
    for (float v : e.values) EXPECT_GT(v, 0.f);
  }
}

TEST(KernelSym3Eigen, RandomIndefinite) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(-10.f, 10.f);
  for (int k = 0; k < 200; ++k) {
    Mat3 a;
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) a[r][c] = a[c][r] = u(rng);
    SCOPED_TRACE(k);
    expect_decomposes(a);
  }
}

TEST(KernelSym3Eigen, DegenerateSpectra) {
  expect_decomposes(Mat3{});                                           // zero
  expect_decomposes(Mat3{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});          // identity (triple)
  expect_decomposes(Mat3{{{3, 0, 0}, {0, -2, 0}, {0, 0, 5e-7f}}});     // diagonal
  expect_decomposes(outer_sum({{0.6f, 0.f, 0.8f}}));                   // one plane: rank 1
  expect_decomposes(outer_sum({{0.6f, 0.f, 0.8f}, {0.f, 1.f, 0.f}}));  // a line: rank 2
  expect_decomposes(outer_sum({{0.48f, 0.6f, 0.64f}, {0.48f, 0.6f, 0.64f}, {0.f, 0.8f, -0.6f}}));
}

TEST(KernelSym3Eigen, Rank1HasOneNonZeroEigenvalue) {
  const Mat3 a = outer_sum({{2.f / 3.f, -1.f / 3.f, 2.f / 3.f}});
  const Sym3Eigen e = sym3_eigen(a[0][0], a[0][1], a[0][2], a[1][1], a[1][2], a[2][2]);
  std::array<float, 3> v{e.values[0], e.values[1], e.values[2]};
  std::sort(v.begin(), v.end());
  EXPECT_NEAR(v[0], 0.f, 1e-6f);
  EXPECT_NEAR(v[1], 0.f, 1e-6f);
  EXPECT_NEAR(v[2], 1.f, 1e-6f);
}

}  // namespace
}  // namespace fq
