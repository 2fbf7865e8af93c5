// The decode queue on its own: bounded in frames and bytes (a push waits for room), one frame
// per stream (the older one is handed back), a frame over the byte bound let in alone, and
// close() releasing a waiting push.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "daemon/pipeline/decode_queue.h"

namespace fq::daemon {
namespace {

FramePtr frame(const std::string& stream, size_t bytes, uint64_t arrival = 0) {
  auto f = std::make_unique<FrameJob>();
  f->stream_id = stream;
  f->arrival = arrival;
  f->chunks.emplace_back(bytes);
  return f;
}

TEST(DecodeQueue, AStreamKeepsOnlyItsNewestFrame) {
  DecodeQueue q;
  FramePtr older;
  ASSERT_TRUE(q.push(frame("a", 10, 1), older));
  EXPECT_FALSE(older);
  ASSERT_TRUE(q.push(frame("b", 10, 2), older));
  ASSERT_TRUE(q.push(frame("a", 10, 3), older));
  ASSERT_TRUE(older);
  EXPECT_EQ(older->arrival, 1u);  // the oldest of the stream gives way
  EXPECT_EQ(q.frames(), 2u);
  EXPECT_EQ(q.bytes(), 20u);
  EXPECT_EQ((*q.pop())->arrival, 2u);
  EXPECT_EQ((*q.pop())->arrival, 3u);
}

// Pushes `f` on a thread of its own; done() once the push returned.
class Pusher {
 public:
  Pusher(DecodeQueue& q, FramePtr f) : thread_([this, &q, f = std::move(f)]() mutable {
    FramePtr older;
    result_ = q.push(std::move(f), older);
    done_ = true;
  }) {}
  ~Pusher() { thread_.join(); }
  bool done() const { return done_; }
  bool result() const { return result_; }

 private:
  std::atomic<bool> done_{false};
  bool result_ = false;
  std::thread thread_;
};

TEST(DecodeQueue, APushWaitsForRoomInFramesAndInBytes) {
  DecodeQueue q;
  q.set_bounds(2, 1000);
  FramePtr older;
  ASSERT_TRUE(q.push(frame("a", 100), older));
  ASSERT_TRUE(q.push(frame("b", 100), older));
  {
    Pusher third(q, frame("c", 100));  // over the frame bound
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // gives it time to (wrongly) get in
    EXPECT_FALSE(third.done());
    EXPECT_EQ(q.frames(), 2u);
    ASSERT_TRUE(q.pop());
  }  // joined: room was made, so it got in
  EXPECT_EQ(q.frames(), 2u);
  q.set_bounds(8, 250);
  {
    Pusher big(q, frame("d", 100));  // 200 + 100 bytes: over the byte bound
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_FALSE(big.done());
    ASSERT_TRUE(q.pop());
  }
  EXPECT_EQ(q.bytes(), 200u);
}

TEST(DecodeQueue, AFrameOverTheByteBoundGoesAloneAndCloseReleasesAWaitingPush) {
  DecodeQueue q;
  q.set_bounds(8, 50);
  FramePtr older;
  ASSERT_TRUE(q.push(frame("huge", 1000), older));  // alone: let in
  Pusher waiting(q, frame("next", 10));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(waiting.done());
  q.close();
  while (!waiting.done()) std::this_thread::yield();
  EXPECT_FALSE(waiting.result());
  EXPECT_TRUE(q.pop());   // what was queued is still handed out
  EXPECT_FALSE(q.pop());  // then nothing
}

}  // namespace
}  // namespace fq::daemon
