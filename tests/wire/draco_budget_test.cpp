// The decoded-size budget read from a Draco chunk's header, before Draco allocates.
#include "wire/draco_budget.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/wire/wire_test_meshes.h"
#include "wire/frame_codec.h"

namespace fq::wire {
namespace {

std::string one_chunk(const Mesh& m, int speed) {
  CodecOptions o;
  o.encode_speed = o.decode_speed = speed;
  std::vector<std::string> out;
  EXPECT_TRUE(encode_frame(m.view(), nullptr, 1, o, out).ok());
  return out.empty() ? std::string() : out[0];
}

class DracoBudget : public ::testing::TestWithParam<int> {};

TEST_P(DracoBudget, ReadsTheCountsOfGenuineChunks) {
  const Mesh m = test_wire::make_bumpy_grid(30, 20);
  const std::string chunk = one_chunk(m, GetParam());
  const StatusOr<ChunkCounts> c = read_chunk_counts(chunk);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->faces, m.num_triangles());
  EXPECT_GE(c->points, m.num_vertices());
  EXPECT_LE(c->points, 3ull * m.num_triangles());
  EXPECT_TRUE(check_chunk_budget(chunk, ChunkBudget{}).ok());
}

TEST_P(DracoBudget, RefusesAForgedFaceCountBeforeDecoding) {
  const std::string chunk = one_chunk(test_wire::make_bumpy_grid(30, 20), GetParam());
  const std::string bomb = test_wire::forge_face_count(chunk, 300'000'000);
  ASSERT_NE(bomb, chunk) << "the face count field was not found";
  const StatusOr<ChunkCounts> c = read_chunk_counts(bomb);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->faces, 300'000'000u);
  const Status s = check_chunk_budget(bomb, ChunkBudget{});
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("300000000 faces"), std::string::npos) << s.message();
}

TEST_P(DracoBudget, RefusesCountsItsBytesCannotCarry) {
  const Mesh m = test_wire::make_bumpy_grid(30, 20);
  const std::string chunk = one_chunk(m, GetParam());
  // Within the absolute caps, but far beyond what a chunk of this size could hold.
  ChunkBudget tight;
  tight.max_items_per_byte = 1;
  const std::string forged = test_wire::forge_face_count(chunk, 100 * chunk.size());
  const Status s = check_chunk_budget(forged, tight);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("bytes can carry"), std::string::npos) << s.message();
}

INSTANTIATE_TEST_SUITE_P(Speeds, DracoBudget, ::testing::Values(0, 10),
                         [](const auto& i) { return i.param == 0 ? "edgebreaker" : "sequential"; });

TEST(DracoBudget, RefusesMalformedHeaders) {
  const std::string chunk = one_chunk(test_wire::make_bumpy_grid(8, 8), 10);
  EXPECT_FALSE(read_chunk_counts("").ok());
  EXPECT_FALSE(read_chunk_counts("PLY not draco").ok());
  EXPECT_FALSE(read_chunk_counts(chunk.substr(0, 9)).ok());   // header cut short
  EXPECT_FALSE(read_chunk_counts(chunk.substr(0, 12)).ok());  // metadata cut short
  std::string v1 = chunk;
  v1[5] = 1;  // bitstream 1.x
  const Status s = read_chunk_counts(v1).status();
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("not supported"), std::string::npos) << s.message();
}

TEST(DracoBudget, MetadataCountsBeyondTheBytesAreRefused) {
  const std::string chunk = one_chunk(test_wire::make_bumpy_grid(8, 8), 10);
  ASSERT_GT(chunk.size(), 11u);
  // Header (9 bytes), flags with the metadata bit, then 2^32 - 1 attribute metadata entries.
  const std::string forged = chunk.substr(0, 9) + std::string("\x00\x80", 2) +
                             std::string("\xff\xff\xff\xff\x0f", 5) + chunk.substr(11);
  const Status s = read_chunk_counts(forged).status();
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("metadata"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace fq::wire
