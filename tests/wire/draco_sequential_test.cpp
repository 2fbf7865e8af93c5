// The codec writes Draco's sequential format itself (wire/draco_sequential.h). These tests
// hold it to Draco's own encoder: for the same chunk and options, draco::Encoder's bytes and
// ours must be identical, in every index width, at several speeds, with and without labels,
// for meshes and for the positions form's point clouds.
#include "wire/draco_sequential.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/point_cloud/point_cloud.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "tests/wire/wire_test_meshes.h"
#include "wire/frame_chunk.h"
#include "wire/frame_split.h"

namespace fq::wire::detail {
namespace {

CodecOptions speeds(int encode, int decode) {
  CodecOptions o;
  o.encode_speed = encode;
  o.decode_speed = decode;
  return o;
}

/// Labels 0..k-1 that vary over the mesh, so their deltas are not all zero.
std::vector<uint32_t> some_labels(uint32_t n) {
  std::vector<uint32_t> labels(n);
  for (uint32_t v = 0; v < n; ++v) labels[v] = (v / 7) % 13 + (v % 3) * 100;
  return labels;
}

/// Every sequential part of `mesh` cut into `chunks` (all of them at speed 10), by Draco
/// (build_chunk + encode_chunk) and by write_sequential_chunk: the same bytes.
void expect_same_chunks(const Mesh& mesh, uint32_t chunks, const CodecOptions& o, bool with_labels) {
  const MeshView view = mesh.view();
  const std::vector<uint32_t> labels = some_labels(view.num_vertices);
  const uint32_t* l = with_labels ? labels.data() : nullptr;
  const Box box = bounding_box(view);
  const std::vector<Part> parts = split_parts(view, box, chunks);
  ChunkScratch ours_scratch, draco_scratch;
  size_t compared = 0;
  for (size_t i = 0; i < parts.size(); ++i) {
    SCOPED_TRACE("chunk " + std::to_string(i));
    if (!sequential_chunk(view, o, parts[i])) {
      EXPECT_NE(o.encode_speed, 10) << "every chunk is sequential at speed 10";
      continue;
    }
    ++compared;
    draco::Mesh m;
    ASSERT_TRUE(build_chunk(view, l, true, o, parts[i], draco_scratch, m));
    std::string by_draco, ours;
    ASSERT_TRUE(encode_chunk(m, true, o, box, by_draco).ok());
    ASSERT_TRUE(write_sequential_chunk(view, l, parts[i], o, box, ours_scratch, ours).ok());
    ASSERT_EQ(ours.size(), by_draco.size());
    EXPECT_TRUE(ours == by_draco) << "first difference at byte "
                                  << std::mismatch(ours.begin(), ours.end(), by_draco.begin()).first -
                                         ours.begin();
  }
  EXPECT_GT(compared, 0u);
}

TEST(DracoSequential, MeshChunksAreDracosBytes) {
  const Mesh grid = test_wire::make_bumpy_grid(60, 40);  // 2,501 points: uint16 indices
  for (bool labels : {false, true}) {
    expect_same_chunks(grid, 1, speeds(10, 10), labels);
    expect_same_chunks(grid, 7, speeds(10, 10), labels);
    expect_same_chunks(grid, 7, speeds(10, 3), labels);  // symbol coder level from the larger speed
  }
}

TEST(DracoSequential, EveryIndexWidthIsDracos) {
  expect_same_chunks(test_wire::make_bumpy_grid(8, 6), 1, speeds(10, 10), true);      // < 256 points: uint8
  expect_same_chunks(test_wire::make_bumpy_grid(300, 250), 1, speeds(10, 10), true);  // 75,551: varint
  // 2^21 points and more: uint32 indices.
  expect_same_chunks(test_wire::make_bumpy_grid(1500, 1400), 1, speeds(10, 10), false);
}

TEST(DracoSequential, ForcedSequentialChunksBelowSpeedTenAreDracos) {
  // A face that repeats a vertex makes a chunk sequential at any speed (edgebreaker drops it).
  Mesh m = test_wire::make_bumpy_grid(20, 20);
  m.triangles[4] = m.triangles[3];
  for (int speed : {0, 5, 9}) expect_same_chunks(m, 3, speeds(speed, speed), true);
}

TEST(DracoSequential, RealMeshChunksAreDracos) {
  const auto mesh = test_wire::load_shared_mesh("bunny.ply");
  if (!mesh) GTEST_SKIP() << "bunny.ply not found (FQ_MESH_DIR)";
  expect_same_chunks(*mesh, 8, speeds(10, 10), true);
}

TEST(DracoSequential, PointCloudsAreDracos) {
  const Mesh grid = test_wire::make_bumpy_grid(90, 70);
  const Box box = bounding_box(grid.view());
  for (int speed : {0, 5, 10}) {
    for (uint32_t n : {1u, 100u, grid.num_vertices()}) {
      SCOPED_TRACE("speed " + std::to_string(speed) + ", " + std::to_string(n) + " points");
      const CodecOptions o = speeds(speed, speed);
      draco::PointCloud pc;
      pc.set_num_points(n);
      draco::GeometryAttribute ga;
      ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 3 * sizeof(float), 0);
      draco::PointAttribute* pos = pc.attribute(pc.AddAttribute(ga, true, n));
      std::memcpy(pos->GetAddress(draco::AttributeValueIndex(0)), grid.positions.data(),
                  3 * sizeof(float) * n);
      std::string by_draco, ours;
      ASSERT_TRUE(encode_on_grid(pc, draco::POINT_CLOUD_SEQUENTIAL_ENCODING, o, box, by_draco).ok());
      SequentialScratch scratch;
      ASSERT_TRUE(write_point_cloud(grid.positions.data(), n, o, box, scratch, ours).ok());
      EXPECT_TRUE(ours == by_draco);
    }
  }
}

TEST(DracoSequential, QuantizerRoundsAsDraco) {
  Box box;
  box.hi[0] = box.hi[1] = box.hi[2] = 2.f;
  const PositionQuantizer q(box, 4);  // 15 steps over [0, 2]
  EXPECT_EQ(q(0.f, 0), 0);
  EXPECT_EQ(q(2.f, 1), 15);
  EXPECT_EQ(q(1.f, 2), 8);  // 7.5 rounds up, as floor(x + 0.5)
  EXPECT_EQ(q(2.f / 15.f * 2.49f, 0), 2);
  Box flat;  // a zero extent quantizes on a range of 1, as the codec hands Draco
  const PositionQuantizer f(flat, 4);
  EXPECT_EQ(f(0.5f, 0), 8);
}

}  // namespace
}  // namespace fq::wire::detail
