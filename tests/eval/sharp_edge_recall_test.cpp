// Sharp-edge recall on a hand-made cube whose 12 creases are single mesh edges: each face is
// a fan of 4 triangles around its centre, so the two vertices opposite a crease are the
// centres of the two faces that meet there.
#include "eval/sharp_edge_recall.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "tests/support/test_meshes.h"

namespace fq {
namespace {

constexpr uint32_t kCorners = 8;  // vertices 0..7 corners, 8..13 face centres (face f = 8 + f)

// Face f: axis f / 2, side + for even f. Corner c has coordinate bit k set for +half on axis k.
Mesh fan_cube(float half) {
  Mesh m;
  for (uint32_t c = 0; c < kCorners; ++c)
    for (int k = 0; k < 3; ++k) m.positions.push_back((c >> k) & 1u ? half : -half);
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    for (int k = 0; k < 3; ++k) m.positions.push_back(k == axis ? (f % 2 == 0 ? half : -half) : 0.f);
  }
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
    const uint32_t side = f % 2 == 0 ? 1u << axis : 0u;
    // The face's corners in order around it (u, v plane), turned so that normals point out.
    std::array<uint32_t, 4> ring = {side, side | 1u << u, side | 1u << u | 1u << v, side | 1u << v};
    if (f % 2 == 1) std::swap(ring[1], ring[3]);
    for (int k = 0; k < 4; ++k) {
      for (uint32_t id : {uint32_t(kCorners + f), ring[k], ring[(k + 1) % 4]}) m.triangles.push_back(id);
    }
  }
  return m;
}

// Every vertex labelled by the face it is the centre of; corners by `corner_label`.
std::vector<uint32_t> face_labels(uint32_t corner_label = 99) {
  std::vector<uint32_t> labels(kCorners, corner_label);
  for (uint32_t f = 0; f < 6; ++f) labels.push_back(f);
  return labels;
}

TEST(SharpEdgeRecall, HandMadeCubeHasTwelveCreasesOfKnownLength) {
  const Mesh cube = fan_cube(1.5f);
  const SharpEdgeRecall r = sharp_edge_recall(cube.view(), face_labels().data());
  EXPECT_EQ(r.sharp_edges, 12u);
  EXPECT_NEAR(r.sharp_length, 12 * 3.0, 1e-9);
  EXPECT_EQ(r.separated_edges, 12u);
  EXPECT_DOUBLE_EQ(r.recall, 1.0);
}

TEST(SharpEdgeRecall, OneLabelSeparatesNothing) {
  const Mesh cube = fan_cube(1.f);
  const std::vector<uint32_t> same(cube.num_vertices(), 7);
  const SharpEdgeRecall r = sharp_edge_recall(cube.view(), same.data());
  EXPECT_EQ(r.sharp_edges, 12u);
  EXPECT_EQ(r.separated_edges, 0u);
  EXPECT_EQ(r.recall, 0.0);
}

TEST(SharpEdgeRecall, MergingTwoAdjacentFacesLosesTheirCreaseOnly) {
  const Mesh cube = fan_cube(1.f);
  std::vector<uint32_t> labels = face_labels();
  labels[kCorners + 2] = labels[kCorners + 0];  // +y takes the label of +x: one shared crease
  const SharpEdgeRecall adjacent = sharp_edge_recall(cube.view(), labels.data());
  EXPECT_EQ(adjacent.separated_edges, 11u);
  EXPECT_NEAR(adjacent.recall, 11.0 / 12.0, 1e-12);

  labels = face_labels();
  labels[kCorners + 1] = labels[kCorners + 0];  // -x and +x never meet
  EXPECT_DOUBLE_EQ(sharp_edge_recall(cube.view(), labels.data()).recall, 1.0);
}

TEST(SharpEdgeRecall, CornerLabelsDoNotMatter) {
  // Corners lie on the creases: only the vertices beside a crease decide.
  const Mesh cube = fan_cube(1.f);
  std::vector<uint32_t> labels = face_labels();
  for (uint32_t c = 0; c < kCorners; ++c) labels[c] = c % 3;
  EXPECT_DOUBLE_EQ(sharp_edge_recall(cube.view(), labels.data()).recall, 1.0);
}

TEST(SharpEdgeRecall, ThresholdSelectsCreasesByAngle) {
  const Mesh cube = fan_cube(1.f);
  // Cube creases are 90 degrees: a threshold above that finds none and gives NaN.
  const SharpEdgeRecall none = sharp_edge_recall(cube.view(), face_labels().data(), 91.0);
  EXPECT_EQ(none.sharp_edges, 0u);
  EXPECT_TRUE(std::isnan(none.recall));
  EXPECT_EQ(sharp_edge_recall(cube.view(), face_labels().data(), 89.0).sharp_edges, 12u);
}

TEST(SharpEdgeRecall, SmoothSphereHasNoCreaseAndOpenBordersAreSkipped) {
  const Mesh sphere = test::make_icosphere(3);
  const std::vector<uint32_t> labels(sphere.num_vertices(), 0);
  EXPECT_EQ(sharp_edge_recall(sphere.view(), labels.data()).sharp_edges, 0u);
  // A plane's border edges have one triangle: no dihedral angle, never sharp.
  const Mesh plane = test::make_plane_grid(4, 4);
  EXPECT_EQ(
      sharp_edge_recall(plane.view(), std::vector<uint32_t>(plane.num_vertices(), 0).data()).sharp_edges, 0u);
}

TEST(SharpEdgeRecall, RefinedCubeFindsEveryCreaseSegment) {
  const int n = 5;
  const Mesh cube = test::make_cube(n, 1.f);
  const std::vector<uint32_t> labels(cube.num_vertices(), 0);
  const SharpEdgeRecall r = sharp_edge_recall(cube.view(), labels.data());
  EXPECT_EQ(r.sharp_edges, 12u * n);
  EXPECT_NEAR(r.sharp_length, 12 * 2.0, 1e-5);
}

}  // namespace
}  // namespace fq
