// The stream registry and the Stream objects it owns, without sockets: which streams are
// pinned, what expiry frees, and that a metrics snapshot holds no lock a frame waits for.
#include "daemon/stream/stream_registry.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "daemon/control/stats_log.h"

namespace fq::daemon {
namespace {

constexpr int64_t kSecond = 1'000'000'000;

TEST(StreamRegistry, SetParamsForAnUnknownIdDoesNotPinIt) {
  DaemonConfig c;
  StreamRegistry r(c);
  StreamSettings s;
  s.budget_ms = 250.0;
  ASSERT_TRUE(r.set_settings("ghost", s));
  StreamSettings back;
  ASSERT_TRUE(r.find("ghost", back));
  EXPECT_EQ(back.budget_ms, 250.0);
  // A control client that names ids no producer sends cannot keep max_streams filled.
  EXPECT_EQ(r.expire_idle(wall_ns() + 10 * kSecond, 1.0), std::vector<std::string>{"ghost"});
  EXPECT_TRUE(r.list().empty());
}

TEST(StreamRegistry, ReloadLiftsThePinOfAStreamNoLongerConfigured) {
  DaemonConfig c;
  c.streams["cam1"] = StreamSettings{};
  c.streams["cam2"] = StreamSettings{};
  StreamRegistry r(c);
  const int64_t later = wall_ns() + 10 * kSecond;
  EXPECT_TRUE(r.expire_idle(later, 1.0).empty()) << "configured streams are pinned";
  std::map<std::string, StreamSettings> fresh{{"cam2", StreamSettings{}}, {"cam3", StreamSettings{}}};
  r.reload(StreamSettings{}, fresh);
  EXPECT_EQ(r.list(), (std::vector<std::string>{"cam1", "cam2", "cam3"}));
  EXPECT_EQ(r.expire_idle(later, 1.0), std::vector<std::string>{"cam1"});
  EXPECT_EQ(r.list(), (std::vector<std::string>{"cam2", "cam3"}));
}

// Expiry is one erase; a frame still in flight keeps its stream (and what the stream holds)
// until it is done, and then nothing is left.
TEST(StreamRegistry, TheLastFrameInFlightFreesAnExpiredStream) {
  DaemonConfig c;
  StreamRegistry r(c);
  const int64_t now = wall_ns();
  auto frame = std::make_unique<FrameJob>();
  frame->stream = r.admit("cam", now);
  ASSERT_NE(frame->stream, nullptr);
  const std::weak_ptr<Stream> watch = frame->stream;
  frame->stream->count(&StreamCounters::frames_in);
  EXPECT_EQ(r.expire_idle(now + 10 * kSecond, 1.0), std::vector<std::string>{"cam"});
  EXPECT_EQ(r.find("cam"), nullptr);
  ASSERT_FALSE(watch.expired()) << "the frame in flight still has its stream";
  frame->stream->count(&StreamCounters::frames_out);
  EXPECT_EQ(frame->stream->samples().counters.frames_out, 1u);
  frame.reset();
  EXPECT_TRUE(watch.expired());
  // The id comes back as a new stream with counters of its own.
  const StreamPtr again = r.admit("cam", now + 11 * kSecond);
  EXPECT_EQ(again->samples().counters.frames_in, 0u);
}

TEST(StreamRegistry, MaxStreamsBoundsTheRegisteredStreams) {
  DaemonConfig c;
  c.caps.max_streams = 2;
  StreamRegistry r(c);
  const int64_t now = wall_ns();
  EXPECT_NE(r.admit("a", now), nullptr);
  EXPECT_NE(r.admit("b", now), nullptr);
  EXPECT_EQ(r.admit("c", now), nullptr);
  StreamSettings s;
  EXPECT_FALSE(r.set_settings("c", s));
  EXPECT_NE(r.admit("a", now), nullptr) << "a registered stream is always found";
}

TEST(StreamRegistry, AStreamOnlySetParamsMadeGivesItsSlotToAProducer) {
  DaemonConfig c;
  c.caps.max_streams = 3;
  c.streams["pinned"] = c.defaults;  // configured: never given up
  StreamRegistry r(c);
  const int64_t now = wall_ns();
  StreamSettings s;
  ASSERT_TRUE(r.set_settings("ctl0", s));
  ASSERT_TRUE(r.set_settings("ctl1", s));
  EXPECT_FALSE(r.set_settings("ctl2", s)) << "control requests do not take each other's slots";
  // A frame of a new stream takes the slot of a stream no frame has found; one that a frame
  // has found keeps its slot.
  ASSERT_NE(r.admit("ctl1", now), nullptr);
  ASSERT_NE(r.admit("cam", now), nullptr);
  EXPECT_EQ(r.find("ctl0"), nullptr);
  EXPECT_NE(r.find("ctl1"), nullptr);
  EXPECT_NE(r.find("pinned"), nullptr);
  EXPECT_EQ(r.admit("cam2", now), nullptr) << "every slot is a fed or configured stream's";
}

// A snapshot copies each stream's counters and samples under its lock and computes the
// percentiles after: while it computes them, a frame of the same stream counts, records and
// is admitted. (Before, the registry's lock was held over every stream's percentiles.)
TEST(StreamRegistry, ASnapshotHoldsNoLockAFrameWaitsFor) {
  DaemonConfig c;
  StreamRegistry r(c);
  const int64_t now = wall_ns();
  const StreamPtr cam = r.admit("cam", now);
  for (int i = 0; i < 3000; ++i) cam->record("engine", 1.0 + i % 100);
  bool frame_done = false;
  std::future<bool> frame;  // outlives the snapshot: a frame that waits is let go after it
  std::vector<StreamSnapshot> snaps;
  ASSERT_TRUE(r.snapshot("", snaps, [&] {
    // A frame on another thread, while the percentiles are still to be computed. The wait is
    // a bound against a deadlock, not a measurement: the frame takes microseconds.
    frame = std::async(std::launch::async, [&] {
      const StreamPtr s = r.admit("cam", now + 1);
      s->count(&StreamCounters::frames_in);
      s->record("engine", 500.0);
      return s->settings().budget_ms > 0.0;
    });
    frame_done = frame.wait_for(std::chrono::seconds(30)) == std::future_status::ready && frame.get();
  }));
  EXPECT_TRUE(frame_done) << "the frame waited for the snapshot";
  ASSERT_EQ(snaps.size(), 1u);
  EXPECT_EQ(snaps[0].counters.frames_in, 0u) << "the snapshot is of the samples before the frame";
  EXPECT_EQ(snaps[0].stages.at("engine").count, 3000u);
  EXPECT_GE(snaps[0].stages.at("engine").p99_ms, 99.0);
  std::vector<StreamSnapshot> after;
  ASSERT_TRUE(r.snapshot("cam", after));
  EXPECT_EQ(after[0].counters.frames_in, 1u);
  EXPECT_EQ(after[0].stages.at("engine").count, 3001u);
}

TEST(StatsLog, AnExpiredStreamLeavesThePreviousCounters) {
  std::map<std::string, StreamCounters> previous;
  StreamSnapshot a, b;
  a.stream_id = "a";
  b.stream_id = "b";
  a.counters.frames_in = b.counters.frames_in = 5;
  EXPECT_EQ(StatsLog::lines({a, b}, 1.0, previous).size(), 2u);
  EXPECT_EQ(previous.size(), 2u);
  a.counters.frames_in = 9;
  EXPECT_EQ(StatsLog::lines({a}, 1.0, previous).size(), 1u);  // b expired
  EXPECT_EQ(previous.size(), 1u);
  EXPECT_EQ(previous.at("a").frames_in, 9u);
}

}  // namespace
}  // namespace fq::daemon
