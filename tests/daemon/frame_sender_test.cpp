// The producer side's frames (clients/common/frame_sender.h): the chunk count build_frame picks
// when the producer leaves it open, by the frame's size.
#include "clients/common/frame_sender.h"

#include <gtest/gtest.h>

#include "tests/support/test_meshes.h"
#include "wire/fq.pb.h"

namespace fq::client {
namespace {

TEST(FrameSender, AutoChunksGrowWithTheFrameAndStopAtTheCap) {
  EXPECT_EQ(auto_chunks(0), 1u);
  EXPECT_EQ(auto_chunks(1), 1u);
  EXPECT_EQ(auto_chunks(kAutoChunkVertices), 1u);
  EXPECT_EQ(auto_chunks(kAutoChunkVertices + 1), 2u);
  EXPECT_EQ(auto_chunks(134345), 9u);  // igea
  EXPECT_EQ(auto_chunks(kMaxAutoChunks * kAutoChunkVertices), kMaxAutoChunks);
  EXPECT_EQ(auto_chunks(435545), kMaxAutoChunks);  // dragon
  EXPECT_EQ(auto_chunks(4'000'000'000u), kMaxAutoChunks);
  for (uint32_t v = 1; v < 40 * kAutoChunkVertices; v += 997) EXPECT_LE(auto_chunks(v), auto_chunks(v + 997));
}

TEST(FrameSender, ChunksZeroSplitsTheFrameByItsSize) {
  const Mesh small = test::make_plane_grid(40, 40);    // 1,681 vertices
  const Mesh large = test::make_plane_grid(200, 200);  // 40,401 vertices: 3 chunks
  for (const Mesh* m : {&small, &large}) {
    FrameSpec spec;
    spec.chunks = 0;
    std::vector<std::string> parts;
    ASSERT_TRUE(build_frame(m->view(), spec, 7, parts).ok());
    const uint32_t expected = auto_chunks(m->num_vertices());
    ASSERT_EQ(parts.size(), 2 + size_t(expected));  // topic, header, chunks
    wire::FrameHeader h;
    ASSERT_TRUE(h.ParseFromString(parts[1]));
    EXPECT_EQ(h.chunk_count(), expected);
    EXPECT_EQ(h.vertex_count(), m->num_vertices());
  }
  EXPECT_EQ(auto_chunks(large.num_vertices()), 3u);
  // A count the producer gives is kept.
  FrameSpec fixed;
  fixed.chunks = 5;
  std::vector<std::string> parts;
  ASSERT_TRUE(build_frame(large.view(), fixed, 0, parts).ok());
  EXPECT_EQ(parts.size(), 7u);
}

}  // namespace
}  // namespace fq::client
