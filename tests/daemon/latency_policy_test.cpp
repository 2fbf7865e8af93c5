// FrameSlots (the latency policy) and the percentile helper, without sockets.
#include "daemon/pipeline/latency_policy.h"

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <memory>
#include <thread>

#include "daemon/pipeline/work_queue.h"
#include "daemon/stream/stage_metrics.h"
#include "daemon/stream/stream.h"

namespace fq::daemon {
namespace {

// One test's streams: a frame goes to the slots with its stream (the slot lives in it).
struct Streams {
  std::map<std::string, StreamPtr> by_id;

  FramePtr frame(const std::string& stream, uint64_t arrival, int64_t receive_ns, double budget_ms = 1e6) {
    StreamPtr& s = by_id[stream];
    if (!s) s = std::make_shared<Stream>(stream, StreamSettings{}, receive_ns);
    auto f = std::make_unique<FrameJob>();
    f->stream_id = stream;
    f->stream = s;
    f->arrival = arrival;
    f->receive_ns = receive_ns;
    f->settings.budget_ms = budget_ms;
    return f;
  }
};

TEST(FrameSlots, NewerFrameReplacesTheWaitingOne) {
  Streams streams;
  FrameSlots slots;
  const int64_t now = wall_ns();
  EXPECT_EQ(slots.offer(streams.frame("a", 0, now)), nullptr);
  FramePtr loser = slots.offer(streams.frame("a", 1, now));
  ASSERT_NE(loser, nullptr);
  EXPECT_EQ(loser->arrival, 0u);
  FramePtr out;
  std::vector<FramePtr> stale;
  ASSERT_TRUE(slots.take(out, stale));
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->arrival, 1u);
  EXPECT_EQ(out->ticket, 0u);
  EXPECT_TRUE(stale.empty());
}

TEST(FrameSlots, TheStreamOfLeastEngineTimeGoesFirst) {
  Streams streams;
  FrameSlots slots;
  const int64_t now = wall_ns();
  // "hog" has used two seconds of engine time; it is served after "light" though it came first.
  YieldRequest run;
  ASSERT_EQ(slots.offer(streams.frame("hog", 0, now)), nullptr);
  FramePtr out;
  std::vector<FramePtr> stale;
  ASSERT_TRUE(slots.take(out, stale, std::chrono::milliseconds::max(), &run));
  slots.finish(&run, 2.0);
  ASSERT_EQ(slots.offer(streams.frame("hog", 1, now)), nullptr);
  ASSERT_EQ(slots.offer(streams.frame("light", 2, now)), nullptr);
  YieldRequest light_run;
  ASSERT_TRUE(slots.take(out, stale, std::chrono::milliseconds::max(), &light_run));
  EXPECT_EQ(out->stream_id, "light");
  ASSERT_TRUE(slots.take(out, stale, std::chrono::milliseconds::max(), &run));
  EXPECT_EQ(out->stream_id, "hog");
  slots.finish(&light_run, 0.01);
  EXPECT_FALSE(run.requested) << "nobody waits";
}

int64_t steady_now() { return CancelToken::Clock::now().time_since_epoch().count(); }

// One engine runs a frame of `runner` (its stream's frames cost `cost_s` and come every
// `interval_s`, its budget `budget_ms`, `preempted_before`: its last run was stopped); then a
// frame of "light" (10 ms every 200 ms: it asks for 5 % of the engine) with a budget of
// `light_budget_ms` comes. Whether and when the run is asked to yield.
struct Scene {
  Streams streams;
  FrameSlots slots;
  YieldRequest run;

  void start(double cost_s, double budget_ms, bool preempted_before = false, double interval_s = 0.2) {
    const int64_t now = wall_ns();
    const auto ago = [&](double s) { return now - static_cast<int64_t>(s * 1e9); };
    FramePtr out;
    std::vector<FramePtr> stale;
    YieldRequest first;
    ASSERT_EQ(slots.offer(streams.frame("light", 0, ago(0.2))), nullptr);
    ASSERT_TRUE(slots.take(out, stale, std::chrono::milliseconds::max(), &first));
    slots.finish(&first, 0.01);
    ASSERT_EQ(slots.offer(streams.frame("runner", 1, ago(interval_s))), nullptr);
    ASSERT_TRUE(slots.take(out, stale, std::chrono::milliseconds::max(), &first));
    slots.finish(&first, cost_s, preempted_before);
    ASSERT_EQ(slots.offer(streams.frame("runner", 2, now, budget_ms)), nullptr);
    ASSERT_TRUE(slots.take(out, stale, std::chrono::milliseconds::max(), &run));
    ASSERT_EQ(out->stream_id, "runner");
  }
  void light_comes(double light_budget_ms) {
    ASSERT_EQ(slots.offer(streams.frame("light", 3, wall_ns(), light_budget_ms)), nullptr);
  }
};

TEST(FrameSlots, ARunIsStoppedOnlyWhenItMissesItsBudgetAndAWaitingFrameWouldMissItsOwn) {
  const int64_t slice_ns = static_cast<int64_t>(FrameSlots::kSliceS * 1e9);
  {
    // Frames of 2 s every 0.2 s against a 1 s budget, a light frame with 0.5 s: stopped after
    // a slice.
    Scene s;
    s.start(2.0, 1000);
    s.light_comes(500);
    EXPECT_TRUE(s.run.requested);
    EXPECT_LE(s.run.after_ns, steady_now() + slice_ns);
  }
  {
    // The same run within its own budget (3 s): never stopped, however light the waiting frame.
    Scene s;
    s.start(2.0, 3000);
    s.light_comes(500);
    EXPECT_FALSE(s.run.requested);
  }
  {
    // The waiting frame keeps its budget behind the run (5 s): the run goes on, unless it is
    // still running at the light frame's latest start.
    Scene s;
    s.start(2.0, 1000);
    s.light_comes(5000);
    EXPECT_TRUE(!s.run.requested || s.run.after_ns - steady_now() > 4'500'000'000);
  }
  {
    // Guaranteed progress: the stream's last run was preempted, so this one is not.
    Scene s;
    s.start(2.0, 1000, true);
    s.light_comes(500);
    EXPECT_FALSE(s.run.requested);
  }
  {
    // The engine has room for both (0.3 s every 0.4 s and 5 %): though both budgets (100 ms)
    // are missed, the light stream waits.
    Scene s;
    s.start(0.3, 100, false, 0.4);
    s.light_comes(100);
    EXPECT_FALSE(s.run.requested);
  }
  {
    // A stream whose frames were never seen to cost asks for nothing yet: its run goes on.
    Scene s;
    s.start(0.0, 300);
    s.light_comes(500);
    EXPECT_FALSE(s.run.requested);
  }
}

uint64_t preempted_others(const Scene& s, const std::string& stream) {
  return s.streams.by_id.at(stream)->samples().counters.preempted_others;
}

// A run of "runner" that `light` asks to yield (the first case above), or, within its own
// budget, that nobody does.
std::unique_ptr<Scene> scene(double runner_budget_ms) {
  auto s = std::make_unique<Scene>();
  s->start(2.0, runner_budget_ms);
  s->light_comes(500);
  return s;
}

TEST(FrameSlots, AStoppedRunIsCountedOnTheStreamItWasStoppedFor) {
  {
    // Stopped for "light": the stop is light's, not the runner's.
    auto s = scene(1000);
    ASSERT_TRUE(s->run.requested);
    s->slots.finish(&s->run, 0.15, true);
    EXPECT_EQ(preempted_others(*s, "light"), 1u);
    EXPECT_EQ(preempted_others(*s, "runner"), 0u);
  }
  {
    // Asked to yield, but it ran to its end first: nothing was stopped, nothing is counted.
    auto s = scene(1000);
    ASSERT_TRUE(s->run.requested);
    s->slots.finish(&s->run, 0.05, false);
    EXPECT_EQ(preempted_others(*s, "light"), 0u);
  }
  {
    // Withdrawn after it was seen due (light's frame went to another engine): the run still
    // stops, and the stop is still light's.
    auto s = scene(1000);
    ASSERT_TRUE(s->run.requested);
    FramePtr out;
    std::vector<FramePtr> stale;
    YieldRequest other;
    ASSERT_TRUE(s->slots.take(out, stale, std::chrono::milliseconds::max(), &other));
    ASSERT_EQ(out->stream_id, "light");
    EXPECT_FALSE(s->run.requested);
    s->slots.finish(&s->run, 0.15, true);
    s->slots.finish(&other, 0.01);
    EXPECT_EQ(preempted_others(*s, "light"), 1u);
  }
  {
    // Never asked to yield (within its budget): a run stopped otherwise is nobody's preemption.
    auto s = scene(3000);
    ASSERT_FALSE(s->run.requested);
    s->slots.finish(&s->run, 0.15, true);
    EXPECT_EQ(preempted_others(*s, "light"), 0u);
  }
}

TEST(FrameSlots, AnOlderFrameDecodedLateLosesToTheNewerOne) {
  Streams streams;
  FrameSlots slots;
  const int64_t now = wall_ns();
  EXPECT_EQ(slots.offer(streams.frame("a", 5, now)), nullptr);
  FramePtr loser = slots.offer(streams.frame("a", 4, now));
  ASSERT_NE(loser, nullptr);
  EXPECT_EQ(loser->arrival, 4u);
  FramePtr out;
  std::vector<FramePtr> stale;
  ASSERT_TRUE(slots.take(out, stale));
  EXPECT_EQ(out->arrival, 5u);
  // Once 5 was taken, 3 is behind it as well.
  FramePtr late = slots.offer(streams.frame("a", 3, now));
  ASSERT_NE(late, nullptr);
  EXPECT_EQ(late->arrival, 3u);
}

TEST(FrameSlots, StaleFramesAreSetAsideAndOldestStreamGoesFirstWithTickets) {
  Streams streams;
  FrameSlots slots;
  const int64_t now = wall_ns();
  slots.offer(streams.frame("old", 0, now - 50'000'000, 10.0));  // 50 ms old, 10 ms budget
  slots.offer(streams.frame("b", 0, now - 2'000'000));
  slots.offer(streams.frame("c", 0, now - 1'000'000));
  FramePtr out;
  std::vector<FramePtr> stale;
  ASSERT_TRUE(slots.take(out, stale));
  ASSERT_EQ(stale.size(), 1u);
  EXPECT_EQ(stale[0]->stream_id, "old");
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->stream_id, "b");
  EXPECT_TRUE(out->ticketed);
  slots.offer(streams.frame("b", 1, now));
  FramePtr next;
  stale.clear();
  ASSERT_TRUE(slots.take(next, stale));
  EXPECT_EQ(next->stream_id, "c");
  ASSERT_TRUE(slots.take(next, stale));
  EXPECT_EQ(next->stream_id, "b");
  EXPECT_EQ(next->ticket, 1u);
}

TEST(FrameSlots, CloseHandsOutWhatIsWaitingThenStops) {
  Streams streams;
  FrameSlots slots;
  slots.offer(streams.frame("a", 0, wall_ns()));
  slots.close();
  FramePtr out;
  std::vector<FramePtr> stale;
  EXPECT_TRUE(slots.take(out, stale));
  EXPECT_NE(out, nullptr);
  out.reset();
  EXPECT_FALSE(slots.take(out, stale));
}

// The engine workers wake without frames (to give idle engines' buffers back).
TEST(FrameSlots, ATakeWithAWaitReturnsEmptyHandedWhenNothingComes) {
  Streams streams;
  FrameSlots slots;
  FramePtr out;
  std::vector<FramePtr> stale;
  EXPECT_TRUE(slots.take(out, stale, std::chrono::milliseconds(10)));
  EXPECT_EQ(out, nullptr);
  EXPECT_TRUE(stale.empty());
  slots.offer(streams.frame("a", 0, wall_ns()));
  EXPECT_TRUE(slots.take(out, stale, std::chrono::milliseconds(10)));
  EXPECT_NE(out, nullptr);
  slots.close();
  out.reset();
  EXPECT_FALSE(slots.take(out, stale, std::chrono::milliseconds(10)));
}

// Idle wake-ups of the publisher (to read subscription messages).
TEST(WorkQueue, PopForTimesOutEmptyHanded) {
  WorkQueue<int> q;
  bool timed_out = false;
  EXPECT_FALSE(q.pop_for(std::chrono::milliseconds(10), timed_out).has_value());
  EXPECT_TRUE(timed_out);
  ASSERT_TRUE(q.push(7));
  EXPECT_EQ(q.pop_for(std::chrono::milliseconds(10), timed_out), 7);
  EXPECT_FALSE(timed_out);
  q.close();
  EXPECT_FALSE(q.pop_for(std::chrono::milliseconds(10), timed_out).has_value());
  EXPECT_FALSE(timed_out) << "closed and empty is not a time-out";
}

TEST(WorkQueue, ABoundedQueueNeverHoldsMoreThanItsCapacity) {
  WorkQueue<int> q(1);
  ASSERT_TRUE(q.push(1));
  bool pushed = true;
  std::thread producer([&] { pushed = q.push(2); });  // waits for room
  EXPECT_EQ(q.size(), 1u);
  EXPECT_EQ(q.pop(), 1);
  producer.join();
  EXPECT_TRUE(pushed);
  EXPECT_EQ(q.size(), 1u);
  std::thread blocked([&] { pushed = q.push(3); });  // full again: waits until close
  q.close();
  blocked.join();
  EXPECT_FALSE(pushed);
  EXPECT_EQ(q.pop(), 2);  // what was queued is still handed out
  EXPECT_EQ(q.pop(), std::nullopt);
}

TEST(Metrics, NearestRankPercentiles) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);
  EXPECT_DOUBLE_EQ(percentile(v, 0.5), 50.0);
  EXPECT_DOUBLE_EQ(percentile(v, 0.99), 99.0);
  EXPECT_DOUBLE_EQ(percentile(v, 1.0), 100.0);
  EXPECT_DOUBLE_EQ(percentile({}, 0.5), 0.0);
  SampleWindow w;
  for (size_t i = 0; i < SampleWindow::kWindow + 10; ++i) w.add(1.0);
  EXPECT_EQ(w.summary().count, SampleWindow::kWindow + 10);
  EXPECT_DOUBLE_EQ(w.summary().p99_ms, 1.0);
}

}  // namespace
}  // namespace fq::daemon
