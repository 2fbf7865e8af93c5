// The registry's snapshots, without sockets.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "daemon/stream_registry.h"

namespace fq::daemon {
namespace {

TEST(StreamRegistry, SnapshotsOfOneAndOfAllStreamsAgree) {
  DaemonConfig c;
  StreamRegistry r(c);
  StreamSettings s;
  const std::string engine = "engine";
  for (const std::string id : {"a", "b"}) {
    ASSERT_TRUE(r.settings(id, s));
    for (int i = 1; i <= 100; ++i) {
      r.record(id, engine, double(i) * (id == "a" ? 1 : 2));
    }
  }
  std::vector<StreamSnapshot> all, one;
  ASSERT_TRUE(r.snapshot("", all));
  ASSERT_TRUE(r.snapshot("b", one));
  ASSERT_EQ(all.size(), 2u);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(all[1].stream_id, "b");
  EXPECT_EQ(one[0].stages.at("engine").p95_ms, all[1].stages.at("engine").p95_ms);
  EXPECT_EQ(one[0].stages.at("engine").p95_ms, 190.0);
  EXPECT_EQ(all[0].stages.at("engine").p99_ms, 99.0);
  EXPECT_EQ(all[0].stages.at("engine").count, 100u);
  EXPECT_FALSE(r.snapshot("c", one));
}

TEST(StageMetrics, ACopysSummaryIsTheWindowsSummary) {
  StageMetrics m;
  for (int i = 0; i < 4500; ++i) m.add(i % 3 ? "decode" : "receive_to_publish", double((i * 7919) % 1000));
  SampleCopy copy;
  m.copy_samples(copy);
  m.copy_samples(copy);  // a reused copy is replaced, not appended to
  const auto expected = m.summary();
  const auto got = copy.summary();
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [stage, p] : expected) {
    EXPECT_EQ(got.at(stage).p50_ms, p.p50_ms) << stage;
    EXPECT_EQ(got.at(stage).p95_ms, p.p95_ms) << stage;
    EXPECT_EQ(got.at(stage).p99_ms, p.p99_ms) << stage;
    EXPECT_EQ(got.at(stage).count, p.count) << stage;
  }
  EXPECT_EQ(copy.samples.size(), 2048u + 1500u);  // decode's window is full, the other holds 1500
}

}  // namespace
}  // namespace fq::daemon
