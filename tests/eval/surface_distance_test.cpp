// distance_to_surface against distances known by construction, and against brute force.
#include "eval/surface_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::make_icosphere;
using test::make_plane_grid;

// Plane [0,10]^2 at z = 0, diagonal of the bounding box = 10 sqrt(2).
const double kPlaneDiag = 10.0 * std::sqrt(2.0);

TEST(SurfaceDistance, PointsOnTheSurfaceAreAtZero) {
  const Mesh plane = make_plane_grid(10, 10);
  const SurfaceDistance d = distance_to_surface(plane.view(), plane.positions.data(), plane.num_vertices());
  EXPECT_EQ(d.rms_over_diagonal, 0.0);
  EXPECT_EQ(d.max_over_diagonal, 0.0);
}

TEST(SurfaceDistance, SlidingAlongThePlaneCostsNothingLiftingCostsTheHeight) {
  const Mesh plane = make_plane_grid(10, 10);
  std::vector<float> slid = plane.positions, lifted = plane.positions;
  for (uint32_t v = 0; v < plane.num_vertices(); ++v) {
    // Tangential motion that stays inside the plane's square.
    slid[3 * v + 0] = std::clamp(slid[3 * v + 0] + 0.4f, 0.f, 10.f);
    lifted[3 * v + 2] = (v % 2) ? 0.3f : -0.3f;
  }
  const SurfaceDistance s = distance_to_surface(plane.view(), slid.data(), plane.num_vertices());
  EXPECT_NEAR(s.rms_over_diagonal, 0.0, 1e-7);
  const SurfaceDistance l = distance_to_surface(plane.view(), lifted.data(), plane.num_vertices());
  EXPECT_NEAR(l.rms_over_diagonal, 0.3 / kPlaneDiag, 1e-7);
  EXPECT_NEAR(l.max_over_diagonal, 0.3 / kPlaneDiag, 1e-7);
}

TEST(SurfaceDistance, PointsBeyondTheBorderMeasureToTheEdgeOrCorner) {
  const Mesh plane = make_plane_grid(10, 10);
  const float pts[] = {-3.f, 5.f,  4.f,   // closest to the edge x = 0: distance 5
                       13.f, 14.f, 0.f};  // closest to the corner (10, 10): distance 5
  const SurfaceDistance d = distance_to_surface(plane.view(), pts, 2);
  EXPECT_NEAR(d.max_over_diagonal, 5.0 / kPlaneDiag, 1e-6);
  EXPECT_NEAR(d.rms_over_diagonal, 5.0 / kPlaneDiag, 1e-6);
}

// Brute force: the distance to a one-triangle mesh is the distance to that triangle, so
// the minimum over single-triangle meshes checks the grid search (radius bound, widening).
double brute_force_distance(const Mesh& mesh, const float* p) {
  double best = INFINITY;
  for (uint32_t t = 0; t < mesh.num_triangles(); ++t) {
    const uint32_t tri[3] = {0, 1, 2};
    float pos[9];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) pos[3 * k + c] = mesh.positions[3 * mesh.triangles[3 * t + k] + c];
    const MeshView one{pos, 3, tri, 1};
    float diag2 = 0.f;  // undo the one-triangle mesh's own diagonal normalization
    for (int c = 0; c < 3; ++c) {
      const float lo = std::min({pos[c], pos[3 + c], pos[6 + c]}),
                  hi = std::max({pos[c], pos[3 + c], pos[6 + c]});
      diag2 += (hi - lo) * (hi - lo);
    }
    best = std::min(best, distance_to_surface(one, p, 1).max_over_diagonal * std::sqrt(double(diag2)));
  }
  return best;
}

TEST(SurfaceDistance, MatchesBruteForceNearAndFarFromASphere) {
  const Mesh sphere = make_icosphere(2);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-3.f, 3.f);
  std::vector<float> pts(3 * 60);
  for (float& x : pts) x = u(rng);
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (uint32_t v = 0; v < sphere.num_vertices(); ++v)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], sphere.positions[3 * v + c]);
      hi[c] = std::max(hi[c], sphere.positions[3 * v + c]);
    }
  const double diag =
      std::sqrt(double(hi[0] - lo[0]) * (hi[0] - lo[0]) + double(hi[1] - lo[1]) * (hi[1] - lo[1]) +
                double(hi[2] - lo[2]) * (hi[2] - lo[2]));
  for (int i = 0; i < 60; ++i) {
    const double fast = distance_to_surface(sphere.view(), &pts[3 * i], 1).max_over_diagonal * diag;
    EXPECT_NEAR(fast, brute_force_distance(sphere, &pts[3 * i]), 1e-5) << "point " << i;
  }
}

}  // namespace
}  // namespace fq
