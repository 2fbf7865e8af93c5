// The surface-based temporal measures (eval/surface_flicker.h) and the flicker split
// (eval/flicker.h) on planes whose answers are known by construction.
#include "eval/surface_flicker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "eval/flicker.h"
#include "kernels/frame_prep.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::make_plane_grid;

// The clean frame of every test: [0,10]^2 at z = 0, normals +z.
Mesh clean_plane() { return make_plane_grid(10, 10); }

Mesh lifted(Mesh m, double dz) {
  for (uint32_t v = 0; v < m.num_vertices(); ++v) m.positions[3 * v + 2] += float(dz);
  return m;
}

// Rotated by `angle` about the line y = 5, z = 0 (the x axis through the middle).
Mesh tilted(Mesh m, double angle) {
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    float* p = &m.positions[3 * size_t(v)];
    const double y = p[1] - 5.0, z = p[2];
    p[1] = float(5.0 + std::cos(angle) * y - std::sin(angle) * z);
    p[2] = float(std::sin(angle) * y + std::cos(angle) * z);
  }
  return m;
}

double clean_edge() { return mean_edge_length(clean_plane().view()); }

TEST(SurfaceSample, APlaneLiftedAlongTheNormalHasThatHeightEverywhere) {
  const Mesh clean = clean_plane(), result = lifted(clean_plane(), 0.25);
  const SurfaceSample s = sample_surface(clean.view(), result.view(), 2);
  ASSERT_EQ(s.vertices(), clean.num_vertices());
  EXPECT_DOUBLE_EQ(s.mean_edge, clean_edge());
  for (uint32_t v = 0; v < s.vertices(); ++v) {
    EXPECT_NEAR(s.height[v], 0.25 / s.mean_edge, 1e-9) << v;
    EXPECT_EQ(s.hit[v], 1) << v;
    EXPECT_NEAR(s.result_normal[3 * v + 2], 1.0, 1e-12) << v;
  }
  EXPECT_NEAR(height_rms(s), 0.25 / s.mean_edge, 1e-9);
  EXPECT_NEAR(smooth_normal_error(s), 0.0, 1e-12);
  // Areas: a third of each incident triangle, so they add up to the plane's 100.
  double area = 0;
  for (double a : s.area) area += a;
  EXPECT_NEAR(area, 100.0, 1e-9);
}

TEST(SurfaceSample, TheSameSurfaceMeshedAnotherWayHasNoHeightAndNoNormalError) {
  const Mesh clean = clean_plane();
  const Mesh result = make_plane_grid(14, 14, 10.f / 14.f);  // other vertices, other triangles
  const SurfaceSample s = sample_surface(clean.view(), result.view(), 2);
  EXPECT_NEAR(height_rms(s), 0.0, 1e-7);
  EXPECT_NEAR(smooth_normal_error(s), 0.0, 1e-12);
}

TEST(SurfaceSample, ATiltedResultHasTheTiltForNormalError) {
  const double angle = 0.1;
  const Mesh clean = clean_plane(), result = tilted(clean_plane(), angle);
  const SurfaceSample s = sample_surface(clean.view(), result.view(), 2);
  EXPECT_NEAR(smooth_normal_error(s), angle, 1e-6);
  // On the axis the result meets the clean plane; 4 away it is 4 tan(angle) above it.
  const uint32_t on_axis = 5 * 11 + 3, high = 9 * 11 + 3;
  EXPECT_NEAR(s.height[on_axis], 0.0, 1e-7);
  EXPECT_NEAR(s.height[high] * s.mean_edge, 4.0 * std::tan(angle), 1e-5);
}

TEST(SurfaceSample, TheNearestOfTwoSheetsIsTheOneSampled) {
  const Mesh clean = clean_plane(), above = lifted(clean_plane(), 0.5), below = lifted(clean_plane(), -0.3);
  Mesh both = above;
  for (float x : below.positions) both.positions.push_back(x);
  for (uint32_t i : below.triangles) both.triangles.push_back(i + above.num_vertices());
  const SurfaceSample s = sample_surface(clean.view(), both.view(), 2);
  for (uint32_t v = 0; v < s.vertices(); ++v) EXPECT_NEAR(s.height[v] * s.mean_edge, -0.3, 1e-6) << v;
}

TEST(SurfaceSample, WhereTheLineMissesTheClosestPointGivesTheHeight) {
  // The result covers x in [0, 4] only, 0.2 above: vertices beyond x = 4 see no crossing
  // within reach and take the closest point, on the patch's edge x = 4 at the same height.
  const Mesh clean = clean_plane(), patch = lifted(make_plane_grid(4, 10), 0.2);
  const SurfaceSample s = sample_surface(clean.view(), patch.view(), 2);
  const uint32_t inside = 5 * 11 + 2, outside = 5 * 11 + 7;
  EXPECT_EQ(s.hit[inside], 1);
  EXPECT_EQ(s.hit[outside], 0);
  EXPECT_NEAR(s.height[inside] * s.mean_edge, 0.2, 1e-6);
  EXPECT_NEAR(s.height[outside] * s.mean_edge, 0.2, 1e-6);
  EXPECT_NEAR(s.result_normal[3 * outside + 2], 1.0, 1e-12);
}

TEST(SurfaceFlicker, AConstantOffsetDoesNotFlickerTwoOffsetsFlickerByTheirDifference) {
  const Mesh clean = clean_plane();
  const SurfaceSample a = sample_surface(clean.view(), lifted(clean, 0.1).view(), 2);
  const SurfaceSample b = sample_surface(clean.view(), lifted(clean, 0.1).view(), 2);
  const SurfaceSample c = sample_surface(clean.view(), lifted(clean, -0.3).view(), 2);
  EXPECT_NEAR(surface_flicker(a, b), 0.0, 1e-9);
  EXPECT_NEAR(surface_flicker(b, c), 0.4 / clean_edge(), 1e-6);
  EXPECT_NEAR(shading_flicker(b, c), 0.0, 1e-12) << "parallel planes shade alike";
}

TEST(SurfaceFlicker, ShadingFlickerIsTheChordOfTheResultsTurnAndIgnoresTheCleanOnes) {
  const double angle = 0.1;
  const Mesh clean = clean_plane(), clean_turned = tilted(clean, angle);
  const SurfaceSample flat = sample_surface(clean.view(), clean.view(), 2);
  const SurfaceSample turned = sample_surface(clean.view(), tilted(clean, angle).view(), 2);
  EXPECT_NEAR(shading_flicker(flat, turned), 2.0 * std::sin(angle / 2), 1e-6);
  // The clean frame turns and the result with it: nothing the clean sequence does not do.
  const SurfaceSample follows = sample_surface(clean_turned.view(), clean_turned.view(), 2);
  EXPECT_NEAR(shading_flicker(flat, follows), 0.0, 1e-6);
  EXPECT_NEAR(surface_flicker(flat, follows), 0.0, 1e-6);
}

TEST(SurfaceFlicker, TheSeriesAveragesOverTransitionsAndSkipsUntrackedFrames) {
  const Mesh clean = clean_plane();
  const double edge = clean_edge();
  SurfaceFlickerSeries series;
  const SurfaceFrameMetrics first = series.add(sample_surface(clean.view(), lifted(clean, 0.1).view(), 2));
  EXPECT_FALSE(first.surface_flicker);
  EXPECT_NEAR(first.height_rms, 0.1 / edge, 1e-6);
  series.add(sample_surface(clean.view(), lifted(clean, 0.3).view(), 2));  // SF 0.2
  series.add(sample_surface(clean.view(), lifted(clean, 0.3).view(), 2));  // SF 0
  EXPECT_EQ(series.frames(), 3u);
  EXPECT_EQ(series.transitions(), 2u);
  EXPECT_NEAR(series.mean_surface_flicker(), 0.1 / edge, 1e-6);
  EXPECT_NEAR(series.mean_height_rms(), (0.1 + 0.3 + 0.3) / 3 / edge, 1e-6);
  // A clean frame of other vertices breaks the chain: no pair measure against it.
  const Mesh other = make_plane_grid(5, 5, 2.f);
  const SurfaceFrameMetrics untracked = series.add(sample_surface(other.view(), other.view(), 2));
  EXPECT_FALSE(untracked.surface_flicker);
  EXPECT_EQ(series.transitions(), 2u);
}

TEST(FlickerParts, MotionAcrossTheSurfaceIsNormalMotionAlongItTangential) {
  const Mesh clean = clean_plane();
  const uint32_t n = clean.num_vertices();
  const std::vector<double> up = [&] {
    std::vector<double> z(3 * size_t(n), 0.0);
    for (uint32_t v = 0; v < n; ++v) z[3 * v + 2] = 1.0;
    return z;
  }();
  const Mesh raised = lifted(clean, 0.3);
  Mesh slid = clean;
  for (uint32_t v = 0; v < n; ++v) slid.positions[3 * size_t(v)] += 0.4f;
  const float* c = clean.positions.data();
  const FlickerParts across = flicker_parts(raised.positions.data(), c, c, c, up.data(), n, 2.0);
  EXPECT_NEAR(across.normal, 0.15, 1e-7);
  EXPECT_NEAR(across.tangential, 0.0, 1e-7);
  EXPECT_NEAR(across.total, flicker(raised.positions.data(), c, c, c, n, 2.0), 1e-12);
  const FlickerParts along = flicker_parts(slid.positions.data(), c, c, c, up.data(), n, 2.0);
  EXPECT_NEAR(along.normal, 0.0, 1e-7);
  EXPECT_NEAR(along.tangential, 0.2, 1e-6);
}

}  // namespace
}  // namespace fq
