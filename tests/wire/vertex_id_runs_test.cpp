// Vertex id runs: the ids of a sequentially coded chunk as (gap, run length) varints.
#include "wire/vertex_id_runs.h"

#include <gtest/gtest.h>

#include <vector>

namespace fq::wire::detail {
namespace {

/// The runs of `ids`, written as build_chunk writes them: one id at a time.
std::vector<uint8_t> runs_of(const std::vector<uint32_t>& ids) {
  IdRunWriter w;
  for (uint32_t id : ids) w.add(id);
  return w.finish();
}

std::vector<uint32_t> round_trip(const std::vector<uint32_t>& ids) {
  const std::vector<uint8_t> runs = runs_of(ids);
  std::vector<uint32_t> back;
  EXPECT_TRUE(decode_id_runs(runs.data(), runs.size(), ids.size(), 1u << 24, back));
  return back;
}

TEST(VertexIdRuns, RoundTrips) {
  EXPECT_EQ(round_trip({}), std::vector<uint32_t>{});
  EXPECT_EQ(round_trip({0}), std::vector<uint32_t>{0});
  const std::vector<uint32_t> mixed{3, 4, 5, 9, 200, 201, 70000, 70001, 70002, (1u << 24) - 1};
  EXPECT_EQ(round_trip(mixed), mixed);
}

TEST(VertexIdRuns, ConsecutiveIdsAreOneRun) {
  std::vector<uint32_t> ids(100000);
  for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = 1000 + i;
  EXPECT_EQ(runs_of(ids).size(), 2u + 3u);  // gap 1000 (2 bytes), length 100000 (3 bytes)
  EXPECT_EQ(round_trip(ids), ids);
}

TEST(VertexIdRuns, RejectsMalformedOrMismatchedRuns) {
  std::vector<uint32_t> ids;
  const auto decode = [&](const std::vector<uint8_t>& b, size_t count, uint32_t limit = 1u << 24) {
    return decode_id_runs(b.data(), b.size(), count, limit, ids);
  };
  EXPECT_TRUE(decode({2, 3}, 3));  // 2, 3, 4
  EXPECT_EQ(ids, (std::vector<uint32_t>{2, 3, 4}));
  EXPECT_FALSE(decode({2, 3}, 2));                               // more ids than points
  EXPECT_FALSE(decode({2, 3}, 4));                               // fewer
  EXPECT_FALSE(decode({2, 0}, 0));                               // empty run
  EXPECT_FALSE(decode({2}, 1));                                  // truncated pair
  EXPECT_FALSE(decode({0x80}, 1));                               // truncated varint
  EXPECT_FALSE(decode({0xff, 0xff, 0xff, 0xff, 0x1f, 1}, 1));    // more than 32 bits
  EXPECT_FALSE(decode({0, 0xff, 0xff, 0xff, 0xff, 0x0f}, 100));  // a run far beyond the point count
  EXPECT_FALSE(decode({9, 1}, 1, 9));                            // id 9 at limit 9
  EXPECT_TRUE(decode({8, 1}, 1, 9));
}

}  // namespace
}  // namespace fq::wire::detail
