// The POSITIONS result form: a frame's positions as Draco point clouds over vertex ranges.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/wire/wire_test_meshes.h"
#include "wire/frame_codec.h"

namespace fq::wire {
namespace {

std::vector<std::string_view> views(const std::vector<std::string>& chunks) {
  return {chunks.begin(), chunks.end()};
}

std::vector<float> positions_round_trip(const Mesh& m, uint32_t chunks, const CodecOptions& o) {
  std::vector<std::string> encoded;
  const Status es = encode_positions(m.positions.data(), m.num_vertices(), chunks, o, encoded);
  EXPECT_TRUE(es.ok()) << es.message();
  EXPECT_EQ(encoded.size(), std::min(chunks, m.num_vertices()));
  std::vector<float> out;
  const Status ds = decode_positions(views(encoded), m.num_vertices(), o, out);
  EXPECT_TRUE(ds.ok()) << ds.message();
  return out;
}

/// The MESH form of the same frame, decoded: same grid, so the same floats are expected.
std::vector<float> mesh_form_positions(const Mesh& m, uint32_t chunks, const CodecOptions& o) {
  std::vector<std::string> encoded;
  EXPECT_TRUE(encode_frame(m.view(), nullptr, chunks, o, encoded).ok());
  Mesh out;
  EXPECT_TRUE(decode_frame(views(encoded), m.num_vertices(), o, out, nullptr).ok());
  return out.positions;
}

void check_same_as_mesh_form(const Mesh& m) {
  for (int speed : {0, 5, 10}) {  // below 10, Draco would pick its reordering k-d tree coder
    for (uint32_t chunks : {1u, 2u, 7u}) {
      SCOPED_TRACE("speed " + std::to_string(speed) + ", chunks " + std::to_string(chunks));
      CodecOptions o;
      o.threads = 2;
      o.encode_speed = o.decode_speed = speed;
      const std::vector<float> got = positions_round_trip(m, chunks, o);
      ASSERT_EQ(got.size(), m.positions.size());
      EXPECT_EQ(got, mesh_form_positions(m, chunks, o));  // vertex order kept, one grid: bit for bit
    }
  }
}

TEST(PositionChunks, SameVerticesInTheSameOrderAsTheMeshForm) {
  check_same_as_mesh_form(test_wire::make_bumpy_grid(40, 30));
}

TEST(PositionChunks, RealMeshSameAsTheMeshForm) {
  const auto m = test_wire::load_shared_mesh("bunny.ply");
  if (!m) GTEST_SKIP() << "bunny.ply not found (set FQ_MESH_DIR)";
  check_same_as_mesh_form(*m);
}

TEST(PositionChunks, WithinHalfAQuantizationStep) {
  const Mesh m = test_wire::make_bumpy_grid(20, 10);
  CodecOptions o;
  o.position_bits = 12;
  const std::vector<float> got = positions_round_trip(m, 3, o);
  float lo = m.positions[0], hi = m.positions[0];
  for (float v : m.positions) lo = std::min(lo, v), hi = std::max(hi, v);
  // The grid's range is the largest side of the box, at most the spread of all coordinates.
  const float half_step = 0.5f * (hi - lo) / 4095.f * 1.01f;
  for (size_t i = 0; i < got.size(); ++i) ASSERT_LE(std::abs(got[i] - m.positions[i]), half_step) << i;
}

TEST(PositionChunks, MoreChunksThanVerticesIsClamped) {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  EXPECT_EQ(positions_round_trip(m, 9, CodecOptions{}), positions_round_trip(m, 1, CodecOptions{}));
}

TEST(PositionChunks, BadInputIsRefusedWithAMessage) {
  std::vector<std::string> out;
  const Mesh m = test_wire::make_bumpy_grid(4, 4);
  EXPECT_EQ(encode_positions(m.positions.data(), m.num_vertices(), 0, CodecOptions{}, out).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(encode_positions(m.positions.data(), 0, 1, CodecOptions{}, out).code(),
            StatusCode::kInvalidInput);
  Mesh bad = m;
  bad.positions[7] = NAN;
  const Status nan = encode_positions(bad.positions.data(), bad.num_vertices(), 2, CodecOptions{}, out);
  EXPECT_NE(nan.message().find("vertex 2 has a non-finite coordinate"), std::string::npos) << nan.message();

  ASSERT_TRUE(encode_positions(m.positions.data(), m.num_vertices(), 2, CodecOptions{}, out).ok());
  std::vector<float> pos;
  const Status count = decode_positions(views(out), m.num_vertices() + 1, CodecOptions{}, pos);
  EXPECT_NE(count.message().find("chunks carry 25 points, the frame has 26 vertices"), std::string::npos)
      << count.message();
  std::vector<std::string> mesh_chunks;
  ASSERT_TRUE(encode_frame(m.view(), nullptr, 1, CodecOptions{}, mesh_chunks).ok());
  const Status mesh = decode_positions(views(mesh_chunks), 0, CodecOptions{}, pos);
  EXPECT_NE(mesh.message().find("not a point cloud"), std::string::npos) << mesh.message();
  const std::string garbage = "not draco at all";
  EXPECT_EQ(decode_positions({garbage}, 0, CodecOptions{}, pos).code(), StatusCode::kInvalidInput);
  EXPECT_EQ(decode_positions({}, 0, CodecOptions{}, pos).code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace fq::wire
