// RMSE/diagonal and mean face normal error on cases whose answer is known by hand.
#include "eval/error_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "tests/support/test_meshes.h"

namespace fq {
namespace {

/// Rotation of every vertex by `angle` about the unit axis (ax, ay, az) through the origin.
std::vector<float> rotated(const std::vector<float>& p, double angle, double ax, double ay, double az) {
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  const double r[3][3] = {{t * ax * ax + c, t * ax * ay - s * az, t * ax * az + s * ay},
                          {t * ax * ay + s * az, t * ay * ay + c, t * ay * az - s * ax},
                          {t * ax * az - s * ay, t * ay * az + s * ax, t * az * az + c}};
  std::vector<float> out(p.size());
  for (size_t v = 0; v < p.size() / 3; ++v) {
    for (int i = 0; i < 3; ++i)
      out[3 * v + i] = float(r[i][0] * p[3 * v] + r[i][1] * p[3 * v + 1] + r[i][2] * p[3 * v + 2]);
  }
  return out;
}

TEST(Metrics, TranslationGivesItsLengthOverTheDiagonal) {
  const Mesh cube = test::make_cube(3, 1.0f);  // bbox [-1, 1]^3, diagonal 2 sqrt(3)
  std::vector<float> moved = cube.positions;
  for (size_t v = 0; v < moved.size() / 3; ++v) {
    moved[3 * v] += 0.03f;
    moved[3 * v + 1] += 0.04f;
  }
  EXPECT_NEAR(rmse_over_diagonal(cube.view(), moved.data()), 0.05 / (2 * std::sqrt(3.0)), 1e-6);
  EXPECT_EQ(rmse_over_diagonal(cube.view(), cube.positions.data()), 0.0);
}

TEST(Metrics, OneMovedVertexAveragesOverAllVertices) {
  const Mesh cube = test::make_cube(2, 1.0f);
  std::vector<float> moved = cube.positions;
  moved[3 * 5 + 2] += 0.5f;
  const double expected = std::sqrt(0.25 / cube.num_vertices()) / (2 * std::sqrt(3.0));
  EXPECT_NEAR(rmse_over_diagonal(cube.view(), moved.data()), expected, 1e-7);
}

TEST(Metrics, RmseIsNanWithoutScale) {
  Mesh point;
  point.positions = {1, 2, 3, 1, 2, 3};
  EXPECT_TRUE(std::isnan(rmse_over_diagonal(point.view(), point.positions.data())));
  EXPECT_TRUE(std::isnan(rmse_over_diagonal(MeshView{}, nullptr)));
}

TEST(Metrics, RigidRotationTurnsEveryCubeNormalByTheSameAngle) {
  const Mesh cube = test::make_cube(2, 1.0f);
  const double angle = 0.3;
  const double n = std::sqrt(3.0);
  const std::vector<float> turned = rotated(cube.positions, angle, 1 / n, 1 / n, 1 / n);
  const MfneResult r = mean_face_normal_error(cube.view(), turned.data());
  // A normal at angle a from the rotation axis turns by phi with
  // cos(phi) = cos(angle) + (1 - cos(angle)) cos^2(a); every cube normal has cos^2(a) = 1/3.
  const double phi = std::acos(std::cos(angle) + (1 - std::cos(angle)) / 3);
  EXPECT_NEAR(r.mean_radians, phi, 1e-5);
  EXPECT_EQ(r.faces_used, cube.num_triangles());
  EXPECT_EQ(r.faces_skipped, 0u);
}

TEST(Metrics, SingleFaceTiltedByKnownAngle) {
  const Mesh tri = test::make_single_triangle();  // in z = 0
  for (double angle : {1e-4, 0.1, 1.0, 2.5}) {
    const std::vector<float> turned = rotated(tri.positions, angle, 1, 0, 0);
    // The axis lies in the triangle's plane, so the normal turns by the full angle.
    EXPECT_NEAR(mean_face_normal_error(tri.view(), turned.data()).mean_radians, angle, 1e-5) << angle;
  }
}

TEST(Metrics, FlippedFaceIsPi) {
  const Mesh tri = test::make_single_triangle();
  std::vector<float> mirrored = tri.positions;
  std::swap_ranges(mirrored.begin() + 3, mirrored.begin() + 6,
                   mirrored.begin() + 6);  // swap vertices 1 and 2
  EXPECT_NEAR(mean_face_normal_error(tri.view(), mirrored.data()).mean_radians, std::numbers::pi, 1e-6);
}

TEST(Metrics, DegenerateFacesAreSkippedAndCounted) {
  Mesh mesh = test::make_cube(2, 1.0f);
  const uint32_t good = mesh.num_triangles();
  const uint32_t added = test::append_zero_area_faces(mesh, 3);
  MfneResult r = mean_face_normal_error(mesh.view(), mesh.positions.data());
  EXPECT_EQ(r.faces_skipped, added);
  EXPECT_EQ(r.faces_used, good);
  EXPECT_NEAR(r.mean_radians, 0.0, 1e-12);

  // Degenerate in the candidate only: collapse the single triangle onto a line.
  const Mesh tri = test::make_single_triangle();
  std::vector<float> flat = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  r = mean_face_normal_error(tri.view(), flat.data());
  EXPECT_EQ(r.faces_skipped, 1u);
  EXPECT_EQ(r.faces_used, 0u);
  EXPECT_TRUE(std::isnan(r.mean_radians));
}

TEST(Metrics, ConnectivityCheckNamesTheDifference) {
  const Mesh a = test::make_cube(2, 1.0f);
  const Mesh b = test::make_cube(3, 1.0f);
  Status s = check_same_connectivity(a.view(), b.view());
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("vertex counts differ"), std::string::npos) << s.message();

  Mesh c = a;
  std::swap(c.triangles[6], c.triangles[7]);
  s = check_same_connectivity(a.view(), c.view());
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("triangle 2"), std::string::npos) << s.message();

  Mesh d = a;
  d.triangles.resize(d.triangles.size() - 3);
  EXPECT_FALSE(check_same_connectivity(a.view(), d.view()).ok());
  EXPECT_TRUE(check_same_connectivity(a.view(), a.view()).ok());
}

}  // namespace
}  // namespace fq
