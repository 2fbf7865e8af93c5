// The registry's per-result accounting and its snapshots, without sockets.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "daemon/stream_registry.h"

namespace fq::daemon {
namespace {

TEST(StreamRegistry, OneResultsCountersAndSamplesLandTogether) {
  DaemonConfig c;
  StreamRegistry r(c);
  StreamSettings s;
  ASSERT_TRUE(r.settings("cam0", s));
  const std::string decode = "decode", total = "receive_to_publish";
  const Counter late[] = {Counter::kOut, Counter::kLate};
  const StageSample samples[] = {{&decode, 2.0}, {&total, 30.0}};
  r.record_result("cam0", late, samples);
  const Counter ok[] = {Counter::kOut};
  const StageSample more[] = {{&decode, 4.0}, {&total, 10.0}};
  r.record_result("cam0", ok, more);
  r.record_result("unknown", ok, more);  // not registered: nothing is made for it

  std::vector<StreamSnapshot> snaps;
  ASSERT_TRUE(r.snapshot("", snaps));
  ASSERT_EQ(snaps.size(), 1u);
  const StreamSnapshot& snap = snaps[0];
  EXPECT_EQ(snap.stream_id, "cam0");
  EXPECT_EQ(snap.counters.frames_out, 2u);
  EXPECT_EQ(snap.counters.late, 1u);
  EXPECT_EQ(snap.counters.errors, 0u);
  ASSERT_EQ(snap.stages.count("decode"), 1u);
  EXPECT_EQ(snap.stages.at("decode").count, 2u);
  EXPECT_EQ(snap.stages.at("decode").p50_ms, 2.0);
  EXPECT_EQ(snap.stages.at("decode").p99_ms, 4.0);
  EXPECT_EQ(snap.stages.at("receive_to_publish").p50_ms, 10.0);
  EXPECT_EQ(snap.histograms.at("receive_to_publish").count(), 2u);
  EXPECT_FALSE(r.snapshot("unknown", snaps));
}

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
