// The decode queue on its own: bounded in frames and bytes (a full queue sheds the newest place
// of the connection holding most), one place per stream (a newer frame takes the older one's
// place, which is handed back), connections served in turn by bytes and the streams of each in
// turn, a frame over the byte bound let in alone, and close() releasing a waiting push.
#include "daemon/pipeline/decode_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

namespace fq::daemon {
namespace {

FramePtr frame(const std::string& stream, size_t bytes, uint64_t arrival = 0, int64_t connection = -1) {
  auto f = std::make_unique<FrameJob>();
  f->stream_id = stream;
  f->arrival = arrival;
  f->connection = connection;
  f->chunks.emplace_back(bytes);
  return f;
}

std::string pop_id(DecodeQueue& q) {
  std::optional<FramePtr> f = q.pop();
  return f ? (*f)->stream_id + std::to_string((*f)->arrival) : std::string("none");
}

TEST(DecodeQueue, ANewerFrameTakesItsStreamsPlace) {
  DecodeQueue q;
  std::vector<FramePtr> dropped;
  ASSERT_TRUE(q.push(frame("a", 10, 1), dropped));
  ASSERT_TRUE(q.push(frame("b", 10, 2), dropped));
  EXPECT_TRUE(dropped.empty());
  ASSERT_TRUE(q.push(frame("a", 10, 3), dropped));
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0]->arrival, 1u);  // the older frame of the stream gives way
  EXPECT_EQ(q.frames(), 2u);
  EXPECT_EQ(q.bytes(), 20u);
  // "a" keeps its place before "b": a stream that keeps sending still reaches the front.
  EXPECT_EQ(pop_id(q), "a3");
  EXPECT_EQ(pop_id(q), "b2");
}

TEST(DecodeQueue, TheStreamsOfAConnectionAndTheConnectionsAreServedInTurn) {
  DecodeQueue q;
  std::vector<FramePtr> dropped;
  // One connection of heavy frames on three streams, one of light frames on one.
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(q.push(frame("h" + std::to_string(i), 1000, 0, 1), dropped));
  ASSERT_TRUE(q.push(frame("light", 10, 1, 2), dropped));
  // By bytes: the light connection's frame goes first, and again each time one comes.
  EXPECT_EQ(pop_id(q), "light1");
  ASSERT_TRUE(q.push(frame("light", 10, 2, 2), dropped));
  EXPECT_EQ(pop_id(q), "light2");
  // A stream that keeps sending does not hold the front of its connection's lane.
  ASSERT_TRUE(q.push(frame("h0", 1000, 3, 1), dropped));  // takes h0's place
  EXPECT_EQ(pop_id(q), "h03");
  ASSERT_TRUE(q.push(frame("h0", 1000, 4, 1), dropped));  // a new place, after h1 and h2
  EXPECT_EQ(pop_id(q), "h10");
  EXPECT_EQ(pop_id(q), "h20");
  EXPECT_EQ(pop_id(q), "h04");
  EXPECT_EQ(q.frames(), 0u);
}

TEST(DecodeQueue, AFullQueueShedsTheNewestPlaceOfTheConnectionHoldingMost) {
  DecodeQueue q;
  q.set_bounds(3, 1000);
  std::vector<FramePtr> dropped;
  ASSERT_TRUE(q.push(frame("a", 100, 1, 1), dropped));
  ASSERT_TRUE(q.push(frame("b", 100, 2, 1), dropped));
  ASSERT_TRUE(q.push(frame("c", 100, 3, 1), dropped));
  // Over the frame bound: connection 2 holds less, so connection 1's newest place gives way.
  ASSERT_TRUE(q.push(frame("d", 100, 4, 2), dropped));
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0]->stream_id, "c");
  EXPECT_EQ(q.frames(), 3u);
  // Connection 1 holds most with its new frame counted: the new frame itself gives way.
  dropped.clear();
  ASSERT_TRUE(q.push(frame("e", 100, 5, 1), dropped));
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0]->stream_id, "e");
  EXPECT_EQ(q.frames(), 3u);
  // In bytes: 300 queued, a bound of 350; a 150-byte frame of connection 3 sheds the newest of
  // connection 1, which holds 200 bytes.
  q.set_bounds(8, 350);
  dropped.clear();
  ASSERT_TRUE(q.push(frame("f", 150, 6, 3), dropped));
  EXPECT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0]->stream_id, "b");
  EXPECT_LE(q.bytes(), 350u);
  EXPECT_EQ(q.frames(), 3u);
}

TEST(DecodeQueue, OneDecoderIsKeptForSmallFramesWhileTheyCome) {
  DecodeQueue q;
  q.set_decoders(2);
  std::vector<FramePtr> dropped;
  const size_t large = DecodeQueue::kSmallFrameBytes + 1;
  ASSERT_TRUE(q.push(frame("small", 10, 0, 2), dropped));  // a small frame came just now
  EXPECT_EQ(pop_id(q), "small0");
  for (int i = 0; i < 2; ++i) ASSERT_TRUE(q.push(frame("large" + std::to_string(i), large, 1, 1), dropped));
  std::optional<FramePtr> first = q.pop();  // one decoder on a large frame
  ASSERT_TRUE(first);
  // The other is kept: a pop does not hand the second large frame out...
  std::string got;
  std::atomic<bool> popped{false};
  std::thread waiter([&] {
    got = pop_id(q);
    popped = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // gives it time to (wrongly) pop
  EXPECT_FALSE(popped);
  // ...but a small frame, at once.
  ASSERT_TRUE(q.push(frame("small", 10, 2, 2), dropped));
  waiter.join();
  EXPECT_EQ(got, "small2");
  // The second large frame once the first is decoded.
  popped = false;
  std::thread after([&] {
    got = pop_id(q);
    popped = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(popped);
  q.decoded(**first);
  after.join();
  EXPECT_EQ(got, "large11");
}

// Pushes `f` on a thread of its own; done() once the push returned.
class Pusher {
 public:
  Pusher(DecodeQueue& q, FramePtr f)
      : thread_([this, &q, f = std::move(f)]() mutable {
          std::vector<FramePtr> dropped;
          result_ = q.push(std::move(f), dropped);
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

TEST(DecodeQueue, AFrameOverTheByteBoundGoesAloneAndCloseReleasesAWaitingPush) {
  DecodeQueue q;
  q.set_bounds(8, 50);
  std::vector<FramePtr> dropped;
  ASSERT_TRUE(q.push(frame("huge", 1000), dropped));  // alone: let in
  {
    Pusher second(q, frame("huge2", 1000, 0, 2));                // waits for an empty queue
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // gives it time to (wrongly) get in
    EXPECT_FALSE(second.done());
    EXPECT_EQ(pop_id(q), "huge0");
  }  // joined: the queue emptied, so it got in
  EXPECT_EQ(q.frames(), 1u);
  ASSERT_TRUE(q.pop());
  ASSERT_TRUE(q.push(frame("huge", 1000), dropped));
  Pusher waiting(q, frame("next", 1000, 0, 2));
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
