// The meshes made in code are what their comments promise: counts, closedness,
// orientation and exact positions (other tests rely on all of these).
#include "tests/support/test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

namespace fq::test {
namespace {

// Directed edge -> uses. Closed and consistently oriented: every directed edge once and
// its reverse once.
bool closed_and_oriented(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (size_t t = 0; t < m.triangles.size(); t += 3) {
    for (int e = 0; e < 3; ++e) ++uses[{m.triangles[t + e], m.triangles[t + (e + 1) % 3]}];
  }
  for (const auto& [edge, count] : uses) {
    if (count != 1) return false;
    if (uses.count({edge.second, edge.first}) != 1) return false;
  }
  return true;
}

// Six times the signed volume: positive when the normals point outward.
double signed_volume6(const Mesh& m) {
  double v = 0.0;
  for (size_t t = 0; t < m.triangles.size(); t += 3) {
    const Vec3 a = vertex(m, m.triangles[t]), b = vertex(m, m.triangles[t + 1]),
               c = vertex(m, m.triangles[t + 2]);
    v += dot(a, cross(b, c));
  }
  return v;
}

TEST(KernelTestMeshes, PlaneGridCountsAndFlatness) {
  const Mesh m = make_plane_grid(4, 3, 0.5f);
  EXPECT_EQ(m.num_vertices(), 20u);
  EXPECT_EQ(m.num_triangles(), 24u);
  for (uint32_t i = 0; i < m.num_vertices(); ++i) EXPECT_EQ(vertex(m, i).z, 0.f);
  EXPECT_FLOAT_EQ(vertex(m, 19).x, 2.0f);
  EXPECT_FLOAT_EQ(vertex(m, 19).y, 1.5f);
  for (size_t t = 0; t < m.triangles.size(); t += 3) {  // every normal is +z
    const Vec3 a = vertex(m, m.triangles[t]), b = vertex(m, m.triangles[t + 1]),
               c = vertex(m, m.triangles[t + 2]);
    EXPECT_GT(cross(b - a, c - a).z, 0.f);
  }
}

TEST(KernelTestMeshes, CubeIsClosedOutwardAndOnTheCube) {
  for (int n : {1, 3, 8}) {
    const Mesh m = make_cube(n, 2.0f);
    EXPECT_EQ(m.num_vertices(), uint32_t(6 * n * n + 2)) << n;
    EXPECT_EQ(m.num_triangles(), uint32_t(12 * n * n)) << n;
    EXPECT_TRUE(closed_and_oriented(m)) << n;
    EXPECT_NEAR(signed_volume6(m), 6.0 * 64.0, 1e-3) << n;  // volume 4^3
    for (uint32_t i = 0; i < m.num_vertices(); ++i) {
      const Vec3 p = vertex(m, i);
      const float linf = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
      EXPECT_FLOAT_EQ(linf, 2.0f);
    }
  }
}

TEST(KernelTestMeshes, IcosphereIsClosedOutwardAndOnTheSphere) {
  for (int s : {0, 1, 3}) {
    const Mesh m = make_icosphere(s, 3.0f);
    const uint32_t f = 20u << (2 * s);
    EXPECT_EQ(m.num_triangles(), f);
    EXPECT_EQ(m.num_vertices(), f / 2 + 2);
    EXPECT_TRUE(closed_and_oriented(m));
    EXPECT_GT(signed_volume6(m), 0.0);
    for (uint32_t i = 0; i < m.num_vertices(); ++i) EXPECT_NEAR(std::sqrt(norm2(vertex(m, i))), 3.0, 1e-5);
  }
}

TEST(KernelTestMeshes, DegenerateBuilders) {
  Mesh cube = make_cube(2);
  const Mesh soup = make_triangle_soup(cube);
  EXPECT_EQ(soup.num_vertices(), 3 * cube.num_triangles());
  EXPECT_EQ(soup.num_triangles(), cube.num_triangles());
  const uint32_t before = cube.num_triangles();
  EXPECT_EQ(append_zero_area_faces(cube, 5), 10u);
  EXPECT_EQ(cube.num_triangles(), before + 10);
  for (uint32_t t = before; t < cube.num_triangles(); ++t) {
    const Vec3 a = vertex(cube, cube.triangles[3 * t]), b = vertex(cube, cube.triangles[3 * t + 1]),
               c = vertex(cube, cube.triangles[3 * t + 2]);
    EXPECT_EQ(norm2(cross(b - a, c - a)), 0.f) << t;
  }
  const uint32_t id = append_isolated_vertex(cube, {5, 5, 5});
  EXPECT_EQ(id, cube.num_vertices() - 1);
  EXPECT_EQ(make_non_manifold_fin().num_triangles(), 3u);
}

}  // namespace
}  // namespace fq::test
