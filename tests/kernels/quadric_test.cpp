// Quadric algebra (kernels/quadric.h): a plane quadric is the squared distance to the
// plane, sums and weights evaluate linearly, and moving a quadric's frame does not move
// the function it describes.
#include "kernels/quadric.h"

#include <gtest/gtest.h>

#include <random>

namespace fq {
namespace {

class KernelQuadric : public ::testing::Test {
 protected:
  Vec3 random_point(float scale = 2.f) {
    std::uniform_real_distribution<float> u(-scale, scale);
    return {u(rng_), u(rng_), u(rng_)};
  }
  Vec3 random_unit() {
    for (;;) {
      const Vec3 v = random_point(1.f);
      if (norm2(v) > 0.05f && norm2(v) <= 1.f) return normalized_or_zero(v);
    }
  }
  Quadric random_plane_quadric(Vec3 origin) { return plane_quadric(random_unit(), random_point(), origin); }

  std::mt19937 rng_{12345};
};

float plane_distance(Vec3 n, Vec3 point, Vec3 x) { return dot(n, x - point); }

TEST_F(KernelQuadric, PlaneQuadricIsSquaredDistance) {
  for (int k = 0; k < 200; ++k) {
    const Vec3 n = random_unit(), point = random_point(), origin = random_point();
    const Quadric q = plane_quadric(n, point, origin);
    const Vec3 y = random_point();
    const float d = plane_distance(n, point, origin + y);
    EXPECT_NEAR(evaluate(q, y), d * d, 1e-4f * (1.f + d * d));
  }
}

TEST_F(KernelQuadric, PlaneQuadricVanishesOnThePlaneAndHasUnitTrace) {
  const Vec3 n = normalized_or_zero({1, 2, 2}), point{0.5f, -1, 3}, origin{1, 1, 1};
  const Quadric q = plane_quadric(n, point, origin);
  EXPECT_NEAR(trace_a(q), 1.f, 1e-6f);
  const Vec3 tangent = normalized_or_zero(cross(n, {0, 0, 1}));
  for (float s : {-3.f, 0.f, 2.5f}) EXPECT_NEAR(evaluate(q, point - origin + s * tangent), 0.f, 1e-5f);
  EXPECT_NEAR(evaluate(q, point - origin + 2.f * n), 4.f, 1e-5f);
}

TEST_F(KernelQuadric, SumAndWeightsEvaluateLinearly) {
  for (int k = 0; k < 50; ++k) {
    const Vec3 origin = random_point();
    const Quadric q1 = random_plane_quadric(origin), q2 = random_plane_quadric(origin),
                  q3 = random_plane_quadric(origin);
    Quadric acc = zero_quadric();
    add_scaled(acc, q1, 1.f);
    add_scaled(acc, q2, 0.25f);
    add_scaled(acc, q3, 3.f);
    const Vec3 y = random_point();
    const float want = evaluate(q1, y) + 0.25f * evaluate(q2, y) + 3.f * evaluate(q3, y);
    EXPECT_NEAR(evaluate(acc, y), want, 1e-4f * (1.f + want));
  }
}

TEST_F(KernelQuadric, DivideDividesEveryValue) {
  Quadric q = random_plane_quadric({0, 0, 0});
  const Vec3 y{0.3f, -0.7f, 1.1f};
  const float before = evaluate(q, y);
  divide(q, 8.0f);
  EXPECT_NEAR(evaluate(q, y), 0.125f * before, 1e-6f * (1.f + before));
  EXPECT_EQ(evaluate(zero_quadric(), y), 0.f);
}

// Normalizing by a denormal weight sum stays finite (1 / w would be inf).
TEST_F(KernelQuadric, DivideByADenormalWeightSumStaysFinite) {
  const float w = 1e-40f;  // denormal
  Quadric q = random_plane_quadric({0, 0, 0});
  Quadric acc = zero_quadric();
  add_scaled(acc, q, w);
  divide(acc, w);
  const Vec3 y{0.3f, -0.7f, 1.1f};
  EXPECT_TRUE(std::isfinite(evaluate(acc, y)));
  EXPECT_NEAR(evaluate(acc, y), evaluate(q, y), 0.05f * (1.f + evaluate(q, y)));
}

// The frame of `moved` has its origin at t in q's frame: moved(y) == q(t + y).
TEST_F(KernelQuadric, AddTranslatedAgreesWithShiftedEvaluation) {
  for (int k = 0; k < 100; ++k) {
    const Vec3 origin = random_point();
    Quadric q = zero_quadric();
    for (int p = 0; p < 3; ++p) add_scaled(q, random_plane_quadric(origin), 0.5f + p);
    const Vec3 t = random_point();
    Quadric moved = zero_quadric();
    add_translated(moved, q, t, evaluate(q, t), 1.f);
    EXPECT_NEAR(trace_a(moved), trace_a(q), 1e-5f);
    for (int s = 0; s < 5; ++s) {
      const Vec3 y = random_point();
      const float want = evaluate(q, t + y);
      EXPECT_NEAR(evaluate(moved, y), want, 2e-4f * (1.f + want));
    }
  }
}

TEST_F(KernelQuadric, AddTranslatedIsWeightedAndAccumulates) {
  const Quadric q1 = random_plane_quadric({0, 0, 0}), q2 = random_plane_quadric({1, 0, 0});
  const Vec3 t1{0.2f, 0.1f, -0.4f}, t2{-1.f, 0.5f, 0.f};
  Quadric acc = zero_quadric();
  add_translated(acc, q1, t1, evaluate(q1, t1), 2.f);
  add_translated(acc, q2, t2, evaluate(q2, t2), 0.5f);
  const Vec3 y{0.7f, -0.3f, 0.9f};
  const float want = 2.f * evaluate(q1, t1 + y) + 0.5f * evaluate(q2, t2 + y);
  EXPECT_NEAR(evaluate(acc, y), want, 1e-4f * (1.f + want));
}

// A plane quadric built directly in a shifted frame equals the translated one.
TEST_F(KernelQuadric, PlaneQuadricInAnotherFrameEqualsTranslation) {
  const Vec3 n = random_unit(), point = random_point(), a = random_point(), b = random_point();
  const Quadric qa = plane_quadric(n, point, a);
  Quadric moved = zero_quadric();
  add_translated(moved, qa, b - a, evaluate(qa, b - a), 1.f);
  const Quadric qb = plane_quadric(n, point, b);
  EXPECT_NEAR(moved.b0, qb.b0, 1e-5f);
  EXPECT_NEAR(moved.b1, qb.b1, 1e-5f);
  EXPECT_NEAR(moved.b2, qb.b2, 1e-5f);
  EXPECT_NEAR(moved.c, qb.c, 1e-4f);
}

TEST(KernelQuadricEvaluate, NeverNegative) {
  // c slightly too small for A and b: the exact value at the minimizer is -1e-3.
  Quadric q = plane_quadric({0, 0, 1}, {0, 0, 1}, {0, 0, 0});
  q.c -= 1e-3f;
  EXPECT_EQ(evaluate(q, {0, 0, 1}), 0.f);
}

}  // namespace
}  // namespace fq
