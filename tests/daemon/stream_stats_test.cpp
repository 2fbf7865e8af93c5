// fqsub's drops by reason (clients/common/stream_stats.h): a sequence gap is one reason it cannot
// split further; error results of a stopped frame are counted by the reason fqd's error starts with.
#include "clients/common/stream_stats.h"

#include <gtest/gtest.h>

namespace fq::client {
namespace {

ReceivedResult result(const std::string& stream, uint64_t sequence, const std::string& error = "") {
  ReceivedResult r;
  r.topic = stream;
  r.header.set_stream_id(stream);
  r.header.set_sequence(sequence);
  r.header.set_status(error.empty() ? wire::OK : wire::ERROR);
  r.header.set_error(error);
  r.receive_ns = static_cast<int64_t>(sequence) * 1'000'000;
  return r;
}

TEST(StreamStats, DropsSplitIntoGapsAndTheReasonsOfStoppedFrames) {
  StreamStats s;
  s.add(result("cam0", 1), true);
  s.add(result("cam0", 4), true);  // 2 and 3 never came
  s.add(result("cam1", 10), true);
  s.add(result("cam1", 11, "preempted: the engine stopped the frame to serve a stream"), true);
  s.add(result("cam1", 12, "time_limit: the engine stopped the frame after caps.engine_time_limit_s = 1 s"),
        true);
  s.add(result("cam1", 13, "cancelled: fqd is stopping"), true);
  s.add(result("cam1", 14, "frame: not a valid Draco mesh"), true);  // a bad frame: an error, no drop
  s.add(result("cam1", 16), true);                                   // 15 never came
  const std::map<std::string, uint64_t> expected{
      {"gap", 3}, {"preempted", 1}, {"time_limit", 1}, {"stopping", 1}};
  EXPECT_EQ(s.drops_by_reason(), expected);
  EXPECT_EQ(s.drops(), 6u);
  EXPECT_EQ(s.errors(), 4u);
  EXPECT_NE(s.status_line().find("drops 6 (gap 3, preempted 1, stopping 1, time_limit 1)"), std::string::npos)
      << s.status_line();
  const nlohmann::json j = s.to_json();
  EXPECT_EQ(j.at("drops"), 6);
  EXPECT_EQ(j.at("drops_by_reason").at("gap"), 3);
  EXPECT_EQ(j.at("drops_by_reason").at("time_limit"), 1);
}

TEST(StreamStats, NoDropsSaysZeroWithoutReasons) {
  StreamStats s;
  s.add(result("cam0", 1), true);
  s.add(result("cam0", 2), true);
  EXPECT_EQ(s.drops(), 0u);
  EXPECT_NE(s.status_line().find("drops 0  errors 0"), std::string::npos) << s.status_line();
  EXPECT_TRUE(s.to_json().at("drops_by_reason").empty());
}

}  // namespace
}  // namespace fq::client
