// Broken and unusual meshes: each one either filters and clusters with an ok status and
// all-finite output, or is refused with a clear kInvalidInput status. Never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "kernels/frame_prep.h"
#include "tests/support/param_values.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::vertex;

Params filter_and_cluster() {
  Params p;
  p.cluster = true;
  return p;
}

// Runs the engine, expects ok, all-finite positions and labels in range.
FrameResult expect_ok(const Mesh& mesh, const Params& p = filter_and_cluster()) {
  CpuEngine engine(2);
  FrameResult out;
  const Status s = engine.process(mesh.view(), p, out);
  EXPECT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(out.positions.size(), mesh.positions.size());
  EXPECT_TRUE(test::all_finite(out.positions));
  if (p.cluster) {
    EXPECT_EQ(out.labels.size(), mesh.num_vertices());
    EXPECT_GE(out.num_clusters, 1u);
    for (uint32_t l : out.labels) EXPECT_LT(l, out.num_clusters);
  }
  return out;
}

// Runs the engine, expects kInvalidInput with `needle` in the message, then checks the
// same engine still processes a good mesh.
void expect_invalid_input(const MeshView& mesh, const std::string& needle) {
  CpuEngine engine(2);
  FrameResult out;
  const Status s = engine.process(mesh, filter_and_cluster(), out);
  EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << s.message();
  EXPECT_NE(s.message().find(needle), std::string::npos) << "message: " << s.message();
  const Mesh good = test::make_icosphere(1);
  EXPECT_TRUE(engine.process(good.view(), filter_and_cluster(), out).ok());
}

TEST(KernelDegenerateInput, EmptyMeshIsRefused) { expect_invalid_input(MeshView{}, "no vertices"); }

TEST(KernelDegenerateInput, PointCloudIsRefused) {
  Mesh cloud = test::make_icosphere(1);
  cloud.triangles.clear();
  expect_invalid_input(cloud.view(), "no triangles");
}

TEST(KernelDegenerateInput, OutOfRangeIndexIsRefused) {
  Mesh m = test::make_cube(2);
  m.triangles[7] = m.num_vertices();
  expect_invalid_input(m.view(), "references vertex");
  m.triangles[7] = std::numeric_limits<uint32_t>::max();
  expect_invalid_input(m.view(), "references vertex");
}

TEST(KernelDegenerateInput, NonFiniteCoordinateIsRefused) {
  Mesh m = test::make_cube(2);
  m.positions[13] = std::numeric_limits<float>::quiet_NaN();
  expect_invalid_input(m.view(), "vertex 4 has a non-finite coordinate");
  m.positions[13] = -std::numeric_limits<float>::infinity();
  expect_invalid_input(m.view(), "non-finite");
}

TEST(KernelDegenerateInput, AllEdgesOfZeroLengthAreRefused) {
  Mesh m = test::make_cube(1);
  for (size_t i = 0; i < m.positions.size(); ++i) m.positions[i] = float(i % 3);  // every vertex at (0,1,2)
  expect_invalid_input(m.view(), "degenerate");
}

// One triangle: one plane, nothing to move along it or off it.
TEST(KernelDegenerateInput, SingleTriangleStaysInItsPlace) {
  const Mesh tri = test::make_single_triangle();
  const FrameResult out = expect_ok(tri);
  EXPECT_LT(test::max_displacement(tri.positions, out.positions), 1e-5);
  EXPECT_EQ(out.num_clusters, 1u);
}

// Every face collinear: edges have length (so the mesh is not refused) but no face has
// area, so no vertex carries a quadric and nothing moves.
TEST(KernelDegenerateInput, AllFacesWithoutAreaLeaveTheMeshInPlace) {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
  m.triangles = {0, 1, 2, 1, 2, 3, 0, 1, 3};
  Params constrained = filter_and_cluster(), bilateral = filter_and_cluster();
  constrained.filtering.constrained = true;
  bilateral.filtering.method = FilterMethod::kBilateral;
  for (const Params& p : {filter_and_cluster(), constrained, bilateral}) {
    const FrameResult out = expect_ok(m, p);
    EXPECT_LT(test::max_displacement(m.positions, out.positions), 1e-6);
  }
}

// Coordinates near the ends of float's range: the engine works in normalized units, so
// the result is the unit-scale result, scaled.
TEST(KernelDegenerateInput, ExtremeScalesGiveTheScaledResult) {
  Mesh unit = test::make_icosphere(2);
  add_gaussian_noise(unit, 0.2, 10);
  const FrameResult want = expect_ok(unit);
  for (float scale : {1e-30f, 1e30f}) {
    Mesh m = unit;
    for (float& x : m.positions) x *= scale;
    const FrameResult got = expect_ok(m);
    EXPECT_EQ(got.labels, want.labels) << scale;
    for (size_t i = 0; i < m.positions.size(); ++i)
      ASSERT_NEAR(got.positions[i] / scale, want.positions[i], 1e-5) << scale;
  }
}

TEST(KernelDegenerateInput, NonManifoldFinIsProcessed) {
  expect_ok(test::make_non_manifold_fin());
  Mesh m = test::make_cube(4);
  // A fin standing on a cube edge: that edge now has three triangles.
  const uint32_t a = m.triangles[0], b = m.triangles[1];
  const uint32_t tip = test::append_isolated_vertex(m, 1.5f * (0.5f * (vertex(m, a) + vertex(m, b))));
  m.triangles.insert(m.triangles.end(), {a, b, tip});
  expect_ok(m);
}

TEST(KernelDegenerateInput, ZeroAreaFacesAreHarmless) {
  Mesh m = test::make_plane_grid(12, 12);
  add_gaussian_noise(m, 0.1, 5);
  const uint32_t first_added_vertex = m.num_vertices();
  ASSERT_EQ(test::append_zero_area_faces(m, 40), 80u);
  const FrameResult out = expect_ok(m);
  // The midpoint vertices touch only zero-area faces (no weight of their own); they are
  // moved by their neighbours' quadrics, so they end near the plane.
  for (uint32_t v = first_added_vertex; v < m.num_vertices(); ++v)
    EXPECT_LT(std::fabs(vertex(out.positions, v).z), 0.5f);
}

// Coincident vertices with different indices (a triangle soup) are welded by the engine
// (kernels/seam_weld.h): the filtered surface is the welded mesh's and copies of a vertex stay
// exactly together, for the paper's filter and for qf+, which refines along the connectivity
// that the soup gets back.
TEST(KernelDegenerateInput, DuplicatedVerticesGiveTheWeldedResult) {
  Mesh welded = test::make_icosphere(2);
  add_gaussian_noise(welded, 0.15, 6);
  const Mesh soup = test::make_triangle_soup(welded);
  Params p;  // filter only (cluster_test.cpp checks the soup's clusters)
  for (FilterMethod method : {FilterMethod::kQuadric, FilterMethod::kQuadricRefined}) {
    p.filtering.method = method;
    const FrameResult w = expect_ok(welded, p), s = expect_ok(soup, p);
    EXPECT_EQ(s.welded_vertices, soup.num_vertices() - welded.num_vertices());
    const double me = mean_edge_length(welded.view());
    for (uint32_t corner = 0; corner < soup.num_vertices(); ++corner) {
      const Vec3 got = vertex(s.positions, corner), want = vertex(w.positions, welded.triangles[corner]);
      ASSERT_LT(std::sqrt(norm2(got - want)) / me, 1e-3) << corner;
    }
    for (uint32_t corner = 0; corner < soup.num_vertices(); ++corner) {
      for (uint32_t other = corner + 1; other < soup.num_vertices(); ++other) {
        if (welded.triangles[corner] != welded.triangles[other]) continue;
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(s.positions[3 * size_t(corner) + c], s.positions[3 * size_t(other) + c]) << corner;
      }
    }
  }
  expect_ok(soup);  // and clustering works on it
}

TEST(KernelDegenerateInput, IsolatedVertices) {
  Mesh m = test::make_plane_grid(10, 10);
  add_gaussian_noise(m, 0.1, 8);
  const Mesh without = m;
  const double me = mean_edge_length(m.view());
  // Far away: no neighbour, no quadric, it stays (up to the normalization round trip).
  const uint32_t far = test::append_isolated_vertex(m, {40.f, 40.f, 40.f});
  // Just above the plane: the paper's filter moves it by its neighbours' quadrics; "qf+",
  // which works on triangles, leaves it where it is. Neither moves the plane.
  const uint32_t near = test::append_isolated_vertex(m, {5.f, 5.f, 0.4f});
  Params qf = filter_and_cluster();
  qf.filtering.method = FilterMethod::kQuadric;
  for (const Params& p : {qf, filter_and_cluster()}) {
    SCOPED_TRACE(test::mode_name(p.filtering.method));
    const FrameResult out = expect_ok(m, p), ref = expect_ok(without, p);
    EXPECT_LT(std::sqrt(norm2(vertex(out.positions, far) - Vec3{40.f, 40.f, 40.f})), 1e-4);
    if (p.filtering.method == FilterMethod::kQuadric)
      EXPECT_LT(std::fabs(vertex(out.positions, near).z), 0.15f);
    else
      EXPECT_NEAR(vertex(out.positions, near).z, 0.4f, 1e-6f);
    for (uint32_t v = 0; v < without.num_vertices(); ++v) {
      ASSERT_LT(std::sqrt(norm2(vertex(out.positions, v) - vertex(ref.positions, v))) / me, 1e-4) << v;
    }
  }
}

// A mesh whose extent is beyond float range in mean edges (1e-10 edges and one unreferenced
// vertex at 1e30) once gave all -inf with an ok status; frames wider than
// kMaxExtentInEdges are now refused.
TEST(KernelDegenerateInput, ExtentBeyondFloatRangeIsRefusedOrFinite) {
  Mesh m = test::make_plane_grid(10, 10, 1e-10f);
  test::append_isolated_vertex(m, {1e30f, 1e30f, 1e30f});
  CpuEngine engine(2);
  FrameResult out;
  const Status s = engine.process(m.view(), filter_and_cluster(), out);
  if (s.ok()) {
    EXPECT_TRUE(test::all_finite(out.positions));
  } else {
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << s.message();
  }
}

// One vertex far from the rest (1e7 units from a grid of unit edges) is refused by name;
// the span is printed to 4 significant digits, so that an engine whose mean edge differs in
// its last bits (the CUDA engine sums in another order) prints the same message.
TEST(KernelDegenerateInput, FarOutlierIsRefusedWithItsSpan) {
  Mesh m = test::make_plane_grid(10, 10, 1.0f);
  test::append_isolated_vertex(m, {1e7f, 0.f, 0.f});
  CpuEngine engine(2);
  FrameResult out;
  const Status s = engine.process(m.view(), filter_and_cluster(), out);
  ASSERT_EQ(s.code(), StatusCode::kInvalidInput) << s.message();
  EXPECT_EQ(s.message().rfind("mesh spans ", 0), 0u) << s.message();
  const std::string span = s.message().substr(11, s.message().find(' ', 11) - 11);
  EXPECT_NE(span.find("e+06"), std::string::npos) << span;
  EXPECT_LE(span.size(), std::string("8.888e+06").size()) << span;
  EXPECT_NE(s.message().find("far outlier vertex"), std::string::npos) << s.message();
  expect_invalid_input(m.view(), "mean edge lengths (at most 1e6 supported)");
}

}  // namespace
}  // namespace fq
