// The ingest thread as an object over a real PULL socket: a message that cannot be a frame is
// refused before any stream exists for it (from a producer without CURVE counted and dropped,
// a bad stream id handed to the publisher), and the thread ends, closing its socket, when the
// context is shut down.
#include "daemon/pipeline/ingest.h"

#include <gtest/gtest.h>

#include <array>
#include <zmq_addon.hpp>

#include "daemon/config/config.h"

namespace fq::daemon {
namespace {

// Without CURVE anyone who can connect is a producer: a message without a frame is counted
// and dropped unanswered, while a topic that is no stream id is still answered as refused.
TEST(Ingest, DropsJunkFromAProducerWithoutCurveAndEndsWhenItsContextShutsDown) {
  const DaemonConfig config;
  StreamRegistry registry(config);
  LiveCaps caps(config.caps);
  Pipeline p(config, registry, caps);
  zmq::context_t ctx;
  zmq::socket_t pull(ctx, zmq::socket_type::pull);
  pull.bind("inproc://ingest");
  Ingest ingest(std::move(pull), p);
  ingest.start();

  zmq::socket_t push(ctx, zmq::socket_type::push);
  push.connect("inproc://ingest");
  std::array<zmq::const_buffer, 2> junk = {zmq::str_buffer("cam0"), zmq::str_buffer("no header")};
  ASSERT_TRUE(zmq::send_multipart(push, junk));
  std::array<zmq::const_buffer, 2> bad_id = {zmq::str_buffer("cam\x1b"), zmq::str_buffer("no header")};
  ASSERT_TRUE(zmq::send_multipart(push, bad_id));

  // One ingest thread takes them in order: the first job published is the bad id's.
  std::optional<FramePtr> refused = p.publish_queue.pop();
  ASSERT_TRUE(refused && *refused);
  EXPECT_TRUE((*refused)->refused);
  EXPECT_EQ((*refused)->stream_id, "cam\\x1b");
  EXPECT_EQ(registry.refusals().get(Refusal::kBadStreamId), 1u);
  EXPECT_EQ(registry.refusals().get(Refusal::kMalformed), 1u) << "the junk is counted, not answered";
  EXPECT_FALSE(registry.find("cam0")) << "junk never makes a stream";

  push.close();
  ctx.shutdown();
  ingest.join();
  ctx.close();  // returns only once the ingest thread closed its socket
}

}  // namespace
}  // namespace fq::daemon
