// The ring table and its blocks (kernels/vertex_ring.h) against ring_mean over the fan, bit for
// bit: on a closed surface, a grid with a boundary, a non-manifold fin and triangles that repeat
// a vertex (degenerate: a triangle listed once per corner, each time without the vertex itself);
// with values of both signs, and all -0.0 (the value the blocks pad with: it must change nothing);
// and a mean of one lane of an array of structs (Lane) against that lane of the structs' mean.
#include "kernels/vertex_ring.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "kernels/temporal_math.h"
#include "kernels/vertex_faces.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::make_icosphere;
using test::make_non_manifold_fin;
using test::make_plane_grid;

uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }

void expect_same_ring_means(const Mesh& mesh, int threads, bool negative_zeros = false) {
  const uint32_t n = mesh.num_vertices();
  std::vector<uint32_t> vf_offsets, vf_faces, corners;
  build_vertex_faces(mesh.triangles.data(), mesh.triangles.size() / 3, n, vf_offsets, vf_faces);
  const FanView fan{mesh.triangles.data(), vf_offsets.data(), vf_faces.data()};
  const RingView ring = build_vertex_ring(fan, n, corners, threads);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<float> e(n);
  std::vector<Vec3> x(n);
  for (uint32_t v = 0; v < n; ++v) {
    e[v] = negative_zeros ? -0.f : u(rng);
    x[v] = negative_zeros ? Vec3{-0.f, -0.f, -0.f} : Vec3{u(rng), u(rng), u(rng)};
  }
  // The block table reads the pad past the n values.
  std::vector<uint32_t> rows, slots;
  std::vector<float> inv_count, block_e = e;
  std::vector<Vec3> block_x = x;
  std::vector<Point4> block_p(n);  // x and e, one to a lane
  for (uint32_t v = 0; v < n; ++v) block_p[v] = Point4{x[v].x, x[v].y, x[v].z, e[v]};
  set_ring_pad(block_e, n);
  set_ring_pad(block_x, n);
  set_ring_pad(block_p, n);
  const BlockRing blocks = build_block_ring(ring, n, rows, slots, inv_count, threads);
  for (uint32_t b = 0; b * kRingBlock < n; ++b) {
    float be[kRingBlock];
    Vec3 bx[kRingBlock];
    block_ring_means(blocks, block_e.data(), b, be);
    block_ring_means(blocks, block_x.data(), b, bx);
    Point4 bp[kRingBlock];
    block_ring_means(blocks, block_p.data(), b, bp);
    for (uint32_t j = 0; j < kRingBlock && b * kRingBlock + j < n; ++j) {
      const uint32_t v = b * kRingBlock + j;
      const float q = ring_mean(fan, e.data(), v);
      EXPECT_EQ(bits(be[j]), bits(q)) << "block table, vertex " << v;
      EXPECT_EQ(bits(bp[j].w), bits(q)) << "block table, lanes, vertex " << v;
      const Vec3 p = ring_mean(fan, x.data(), v);
      for (const Vec3& got : {bx[j], xyz(bp[j])}) {
        EXPECT_EQ(bits(got.x), bits(p.x)) << "block table, vertex " << v;
        EXPECT_EQ(bits(got.y), bits(p.y)) << "block table, vertex " << v;
        EXPECT_EQ(bits(got.z), bits(p.z)) << "block table, vertex " << v;
      }
    }
  }
  for (uint32_t v = 0; v < n; ++v) {
    const float a = ring_mean(fan, e.data(), v), b = ring_mean(ring, e.data(), v);
    EXPECT_EQ(bits(a), bits(b)) << "vertex " << v;
    const Vec3 p = ring_mean(fan, x.data(), v), q = ring_mean(ring, x.data(), v);
    EXPECT_EQ(bits(p.x), bits(q.x)) << "vertex " << v;
    EXPECT_EQ(bits(p.y), bits(q.y)) << "vertex " << v;
    EXPECT_EQ(bits(p.z), bits(q.z)) << "vertex " << v;
  }
}

/// The neighbours in v's slots of the table.
uint32_t ring_size(const RingView& r, uint32_t v) {
  uint32_t count = 0;
  for (uint32_t k = 2 * r.vf_offsets[v]; k < 2 * r.vf_offsets[v + 1]; ++k)
    count += r.corners[k] != RingView::kNoCorner;
  return count;
}

TEST(KernelVertexRing, GivesRingMeanBitForBitOnAClosedSurface) {
  const Mesh sphere = make_icosphere(3);
  expect_same_ring_means(sphere, 1);
  expect_same_ring_means(sphere, 4);
}

TEST(KernelVertexRing, GivesRingMeanBitForBitOnABoundaryAndANonManifoldFin) {
  expect_same_ring_means(make_plane_grid(7, 5), 2);
  expect_same_ring_means(make_non_manifold_fin(), 2);
}

TEST(KernelVertexRing, CountsADegenerateTrianglesCornersAsTheFanDoes) {
  Mesh m = make_plane_grid(4, 4);
  const uint32_t a = m.triangles[0], b = m.triangles[1];
  m.triangles.insert(m.triangles.end(), {a, a, b, b, b, b});  // a repeated corner, then all three
  expect_same_ring_means(m, 2);
  expect_same_ring_means(m, 2, true);
  std::vector<uint32_t> vf_offsets, vf_faces, corners;
  build_vertex_faces(m.triangles.data(), m.triangles.size() / 3, m.num_vertices(), vf_offsets, vf_faces);
  const FanView fan{m.triangles.data(), vf_offsets.data(), vf_faces.data()};
  const RingView ring = build_vertex_ring(fan, m.num_vertices(), corners, 1);
  // b's fan lists {a, a, b} once and {b, b, b} three times (once a corner); its ring has two
  // corners per proper triangle, a twice from {a, a, b} and nothing from {b, b, b}.
  const uint32_t proper = (vf_offsets[b + 1] - vf_offsets[b]) - 4;
  EXPECT_EQ(ring_size(ring, b), 2 * proper + 2);
  EXPECT_EQ(ring_size(ring, a), 2 * (vf_offsets[a + 1] - vf_offsets[a] - 2) + 2)
      << "a: b from {a, a, b} twice";
}

// The CUDA engine's ring means of track B's 64-byte lanes run a thread a lane (Lane); each lane's
// mean must be that lane of the whole struct's, bit for bit, for the two engines to agree.
void expect_lane_means_as_the_structs(const Mesh& mesh) {
  const uint32_t n = mesh.num_vertices();
  std::vector<uint32_t> vf_offsets, vf_faces, corners;
  build_vertex_faces(mesh.triangles.data(), mesh.triangles.size() / 3, n, vf_offsets, vf_faces);
  const FanView fan{mesh.triangles.data(), vf_offsets.data(), vf_faces.data()};
  const RingView ring = build_vertex_ring(fan, n, corners, 1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  const auto p4 = [&] { return Point4{u(rng), u(rng), u(rng), u(rng)}; };
  std::vector<MotionLanes> e(n);
  for (MotionLanes& l : e) l = {{p4(), p4(), p4()}, p4()};
  static_assert(sizeof(MotionLanes) == 4 * sizeof(Point4));
  const auto* lanes = reinterpret_cast<const Point4*>(e.data());
  for (uint32_t v = 0; v < n; ++v) {
    const MotionLanes whole = ring_mean(ring, e.data(), v);
    const auto* expected = reinterpret_cast<const Point4*>(&whole);
    for (uint32_t k = 0; k < 4; ++k) {
      const Point4 got = ring_mean_of<Point4>(ring, Lane<Point4, 4>{lanes + k}, v);
      const Point4 want = expected[k];
      ASSERT_EQ(bits(got.x), bits(want.x)) << "vertex " << v << " lane " << k;
      ASSERT_EQ(bits(got.y), bits(want.y)) << "vertex " << v << " lane " << k;
      ASSERT_EQ(bits(got.z), bits(want.z)) << "vertex " << v << " lane " << k;
      ASSERT_EQ(bits(got.w), bits(want.w)) << "vertex " << v << " lane " << k;
    }
  }
  // And a lane is not another: the test sees a wrong stride.
  const Point4 first = ring_mean_of<Point4>(ring, Lane<Point4, 4>{lanes}, 0);
  EXPECT_NE(bits(first.x), bits(ring_mean(ring, e.data(), 0).offset.x));
}

TEST(KernelVertexRing, AMeanOfOneLaneOfAStructIsThatLaneOfTheStructsMean) {
  expect_lane_means_as_the_structs(make_icosphere(3));
  expect_lane_means_as_the_structs(make_non_manifold_fin());
}

}  // namespace
}  // namespace fq
