// Minimizers of a quadric (kernels/quadric_solve.h): exact corners when the quadric has
// full rank, a Tikhonov pull that only shortens the step along the constrained directions
// and never moves along flat ones, finite steps on every singular quadric, and the
// normal-constrained step.
#include "kernels/quadric_solve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace fq {
namespace {

constexpr float kTol = 1e-5f;

void expect_vec_near(Vec3 got, Vec3 want, float tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

// Sum of w_k * plane(n_k through point_k), in the frame whose origin is `origin`.
Quadric planes(std::initializer_list<std::pair<Vec3, Vec3>> normal_point, Vec3 origin,
               std::initializer_list<float> weights = {}) {
  Quadric q = zero_quadric();
  auto w = weights.begin();
  for (const auto& [n, p] : normal_point) {
    add_scaled(q, plane_quadric(normalized_or_zero(n), p, origin), w != weights.end() ? *w++ : 1.f);
  }
  return q;
}

TEST(KernelQuadricSolve, ThreeOrthogonalPlanesMeetAtTheirCorner) {
  const Quadric q =
      planes({{{1, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {0, 2, 0}}, {{0, 0, 1}, {0, 0, -0.5f}}}, {0, 0, 0});
  expect_vec_near(minimizer_step(q, 0.f), {1, 2, -0.5f}, kTol);
}

TEST(KernelQuadricSolve, RotatedWeightedCornerSeenFromAnOffsetOrigin) {
  // Orthonormal frame rotated about (1,1,1); unequal weights make A non-diagonal with
  // distinct eigenvalues, so the eigen-solver is exercised.
  const Vec3 n1 = normalized_or_zero({2, -1, 2}), n2 = normalized_or_zero({2, 2, -1});
  const Vec3 n3 = cross(n1, n2);
  const Vec3 corner{0.3f, -1.2f, 0.8f}, origin{1.f, 0.5f, -0.25f};
  const Quadric q = planes({{n1, corner}, {n2, corner}, {n3, corner}}, origin, {1.f, 2.f, 3.f});
  expect_vec_near(minimizer_step(q, 0.f), corner - origin, 2e-5f);
}

TEST(KernelQuadricSolve, TikhonovStepOntoOnePlaneIsAlongItsNormal) {
  const Vec3 n = normalized_or_zero({1, -2, 3}), point{0.4f, 0.2f, 1.f}, origin{0, 0, 0};
  const Quadric q = planes({{n, point}}, origin);
  const float d = dot(n, origin - point);  // signed distance of the origin
  // eps = 0: the flat directions are cut, the step lands exactly on the plane.
  expect_vec_near(minimizer_step(q, 0.f), -d * n, kTol);
  // eps = 0.05: tr(A) = 1, the normal component shrinks by 1 / (1 + eps/3) and nothing
  // moves along the plane.
  const Vec3 step = minimizer_step(q, 0.05f);
  expect_vec_near(step, (-d / (1.f + 0.05f / 3.f)) * n, kTol);
  const Vec3 tangential = step - dot(step, n) * n;
  EXPECT_LT(std::sqrt(norm2(tangential)), kTol);
}

TEST(KernelQuadricSolve, TikhonovStepSolvesTheRegularizedSystem) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int k = 0; k < 100; ++k) {
    Quadric q = zero_quadric();
    for (int p = 0; p < 4; ++p) {
      add_scaled(
          q, plane_quadric(normalized_or_zero({u(rng), u(rng), u(rng)}), {u(rng), u(rng), u(rng)}, {0, 0, 0}),
          0.1f + std::fabs(u(rng)));
    }
    const float eps = 0.05f, reg = eps * trace_a(q) / 3.f;
    const Vec3 step = minimizer_step(q, eps);
    const Vec3 residual = mul_a(q, step) + reg * step + b_of(q);  // (A + reg I) s + b
    EXPECT_LT(std::sqrt(norm2(residual)), 1e-4f * (1.f + std::sqrt(norm2(b_of(q))))) << k;
  }
}

TEST(KernelQuadricSolve, ZeroAndConstantQuadricsDoNotMove) {
  EXPECT_EQ(norm2(minimizer_step(zero_quadric(), 0.f)), 0.f);
  EXPECT_EQ(norm2(minimizer_step(zero_quadric(), 0.05f)), 0.f);
  Quadric constant = zero_quadric();
  constant.c = 4.f;
  EXPECT_EQ(norm2(minimizer_step(constant, 0.f)), 0.f);
  Quadric tiny = planes({{{0, 0, 1}, {0, 0, 1}}}, {0, 0, 0});
  divide(tiny, 1e14f);  // trace below kMinTrace: no information
  EXPECT_EQ(norm2(minimizer_step(tiny, 0.f)), 0.f);
  EXPECT_EQ(norm2(constrained_step(tiny, {0, 0, 1}, 0.f)), 0.f);
  EXPECT_EQ(norm2(constrained_step(zero_quadric(), {0, 0, 1}, 0.05f)), 0.f);
}

TEST(KernelQuadricSolve, TwoPlanesGoToTheNearestPointOfTheirLine) {
  // x = 1 and y = 2 meet in a line along z: no step along z.
  const Quadric q = planes({{{1, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {0, 2, 0}}}, {0, 0, 0});
  expect_vec_near(minimizer_step(q, 0.f), {1, 2, 0}, kTol);
  const float shrink = 1.f / (1.f + 0.05f * 2.f / 3.f);  // tr(A) = 2
  expect_vec_near(minimizer_step(q, 0.05f), {shrink, 2.f * shrink, 0}, kTol);
}

TEST(KernelQuadricSolve, NearlyParallelPlanesGiveABoundedStep) {
  // Two planes 1e-4 rad apart, offset by 0.1: their exact intersection is ~1000 away.
  // The eigenvalue cut (eps = 0) and the Tikhonov pull (eps > 0) both keep the step
  // near the planes instead.
  const float a = 1e-4f;
  const Quadric q =
      planes({{{0, 0, 1}, {0, 0, 1}}, {{std::sin(a), 0, std::cos(a)}, {0, 0, 1.1f}}}, {0, 0, 0});
  for (float eps : {0.f, 0.05f}) {
    const Vec3 step = minimizer_step(q, eps);
    ASSERT_TRUE(is_finite(step));
    EXPECT_LT(std::sqrt(norm2(step)), 2.f) << eps;
    EXPECT_NEAR(step.z, 1.05f, 0.05f) << eps;
  }
}

TEST(KernelQuadricSolve, ConstrainedStepAlongThePlaneNormal) {
  const Quadric q = planes({{{0, 0, 1}, {0, 0, 1}}}, {0, 0, 0});
  expect_vec_near(constrained_step(q, {0, 0, 1}, 0.f), {0, 0, 1}, kTol);
  expect_vec_near(constrained_step(q, {0, 0, 1}, 0.05f), {0, 0, 1.f / (1.f + 0.05f / 3.f)}, kTol);
}

TEST(KernelQuadricSolve, ConstrainedStepFollowsTheGivenDirection) {
  // Direction 60 degrees off the plane normal: the line meets z = 1 at lambda = 2.
  const Quadric q = planes({{{0, 0, 1}, {0, 0, 1}}}, {0, 0, 0});
  const Vec3 n{std::sin(1.0471976f), 0.f, 0.5f};
  expect_vec_near(constrained_step(q, n, 0.f), 2.f * n, 1e-4f);
}

TEST(KernelQuadricSolve, ConstrainedStepIsZeroWithoutCurvatureOrDirection) {
  const Quadric q = planes({{{0, 0, 1}, {0, 0, 1}}}, {0, 0, 0});
  EXPECT_EQ(norm2(constrained_step(q, {1, 0, 0}, 0.f)), 0.f);    // moving along the plane
  EXPECT_EQ(norm2(constrained_step(q, {1, 0, 0}, 0.05f)), 0.f);  // gains nothing
  EXPECT_EQ(norm2(constrained_step(q, {0, 0, 0}, 0.05f)), 0.f);  // no normal
}

TEST(KernelQuadricSolve, ConstrainedStepMinimizesOnItsLine) {
  const Quadric q = planes({{{1, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {0, 2, 0}}, {{1, 1, 1}, {0, 0, 0.5f}}},
                           {0, 0, 0}, {1.f, 0.5f, 2.f});
  const Vec3 n = normalized_or_zero({0.3f, 0.4f, 1.f});
  const Vec3 s = constrained_step(q, n, 0.f);
  EXPECT_LT(std::sqrt(norm2(cross(s, n))), kTol);  // parallel to n
  const float best = evaluate(q, s);
  for (float dl : {-0.01f, 0.01f}) EXPECT_LE(best, evaluate(q, s + dl * n));
}

}  // namespace
}  // namespace fq
